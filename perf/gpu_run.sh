#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The GPU measurement of issue 17, item 3, as one prepared run (for the device
# machine: one call, about 6-8 minutes on a 16-core host with one GPU).
#   bash perf/gpu_run.sh [OUT_DIR]            (default: $OUT, else out/gpu-run)
# 1. builds limn with -DLIMN_BUILD_PERF=ON into build-gpu (skipped when LIMN
#    names a built limn);
# 2. `limn bench` at each size of GPU_RUN_SIZES in both kernel shapes
#    (LIMN_KERNEL_SHAPE=cpu|gpu, docs/performance.md "Kernel shapes"): the
#    whole job, the solve loop's GB/s and a STREAM triad on the same device in
#    the same run (limn_device_triad: the device's measured bandwidth);
# 3. the solve suite: `limn interpolate --report` on Loop and Catmull-Clark
#    meshes of GPU_RUN_LEVELS (2.6M, 6.3M and 10.5M vertices by default), for
#    each method:precision of GPU_RUN_METHODS, in both shapes; the loop's GB/s
#    from the report by the byte model of docs/performance.md (useful bytes:
#    CSR nonzeros, not SELL's padding) over seconds.iterations;
# 4. summary.json and summary.md in OUT_DIR: every run, and each solve's
#    fraction of the best triad (the target: >= 0.6 at >= 4M vertices).
# Environment (defaults for the GPU machine; tested on PoCL with small ones):
#   LIMN             a built limn (skip the build)
#   GPU_RUN_DEVICE   the --device of every run                   [opencl]
#   GPU_RUN_SIZES    bench sizes                     [2M 4M 8M 16M]
#   GPU_RUN_LEVELS   meshes, SCHEME:LEVELS   [loop:9 catmark:10 loop:10]
#   GPU_RUN_METHODS  METHOD:PRECISION[:TOL]
#                           [chebyshev:double chebyshev:float cg:double]
#                    (TOL: the run's --tol; a smooth refined mesh meets the
#                    default 1e-6 in 1-2 iterations, too few to time a loop)
#   GPU_RUN_TRIAD    triad bytes per array                          [1G]
#   GPU_RUN_SHAPES   kernel shapes                              [gpu cpu]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
out=${1:-${OUT:-$root/out/gpu-run}}
device=${GPU_RUN_DEVICE:-opencl}
sizes=${GPU_RUN_SIZES:-2M 4M 8M 16M}
levels=${GPU_RUN_LEVELS:-loop:9 catmark:10 loop:10}
methods=${GPU_RUN_METHODS:-chebyshev:double chebyshev:float cg:double}
triad=${GPU_RUN_TRIAD:-1G}
shapes=${GPU_RUN_SHAPES:-gpu cpu}
mkdir -p "$out"
log=$out/run.log
: >"$log"
say() { echo "gpu_run: $*" | tee -a "$log"; }
start=$SECONDS

if [[ -z ${LIMN:-} ]]; then
    say "building limn (build-gpu, -DLIMN_BUILD_PERF=ON)"
    cmake -S "$root" -B "$root/build-gpu" -DCMAKE_BUILD_TYPE=Release -DLIMN_BUILD_PERF=ON \
        >>"$log" 2>&1
    cmake --build "$root/build-gpu" -j "$(nproc)" --target limn_cli >>"$log" 2>&1
    LIMN=$root/build-gpu/limn
fi
limn=$LIMN
"$limn" devices | tee "$out/devices.txt" | tee -a "$log"
nvidia-smi --query-gpu=name,memory.total,clocks.max.memory --format=csv >"$out/gpu.txt" 2>&1 ||
    echo "(no nvidia-smi)" >"$out/gpu.txt"

# 1b. the device against the C reference backend: the same output bytes for
# commands whose results are products only (docs/performance.md "Kernel
# shapes": A.P bit-identical, only norms and dots may differ in the last
# digits, so CG and the stop tests are left out), in each shape
bytes_mesh=$(mktemp -d "${TMPDIR:-/tmp}/limn_gpu_bytes_XXXXXX")
"$limn" subdivide "$root/data/spot_control_mesh.obj" -o "$bytes_mesh/spot3.ply" --levels 3 \
    --device reference -q >>"$log" 2>&1
: >"$out/bytes.txt"
while IFS='|' read -r name args; do
    [[ -n $name ]] || continue
    # shellcheck disable=SC2086 # args is a list of words
    "$limn" $args -o "$bytes_mesh/ref.ply" --device reference -q >>"$log" 2>&1 ||
        { echo "$name: reference failed" >>"$out/bytes.txt"; continue; }
    for shape in $shapes; do
        # shellcheck disable=SC2086
        if ! LIMN_KERNEL_SHAPE=$shape "$limn" $args -o "$bytes_mesh/dev.ply" --device "$device" \
            -q >>"$log" 2>&1; then
            echo "$name, $shape shape: FAILED" >>"$out/bytes.txt"
        elif cmp -s "$bytes_mesh/ref.ply" "$bytes_mesh/dev.ply"; then
            echo "$name, $shape shape: same bytes" >>"$out/bytes.txt"
        else
            echo "$name, $shape shape: DIFFERENT bytes" >>"$out/bytes.txt"
        fi
    done
done <<EOF_BYTES
interpolate paper double|interpolate $bytes_mesh/spot3.ply --method paper --precision double --tol 1e-10 --max-iter 2000
interpolate chebyshev double|interpolate $bytes_mesh/spot3.ply --method chebyshev --precision double --tol 1e-12
interpolate paper float|interpolate $bytes_mesh/spot3.ply --method paper --precision float --tol 1e-6
subdivide --limit|subdivide $root/data/spot_control_mesh.obj --levels 3 --limit
smooth 6 terms|smooth $bytes_mesh/spot3.ply --terms 6
denoise eq. 8|denoise $bytes_mesh/spot3.ply --m 2 --steps 3 --no-keep-volume
sharpen|sharpen $bytes_mesh/spot3.ply --from 2 --to 4 --steps 2
EOF_BYTES
rm -rf "$bytes_mesh"
say "backends: $(grep -c 'same bytes' "$out/bytes.txt") same, $(grep -vc 'same bytes' "$out/bytes.txt") not"

# 2. limn bench per size and shape
for n in $sizes; do
    for shape in $shapes; do
        say "bench $n, $shape shape"
        LIMN_KERNEL_SHAPE=$shape "$limn" bench --vertices "$n" --device "$device" \
            --triad-bytes "$triad" --repeat 5 -q --json "$out/bench-$n-$shape.json" >>"$log" 2>&1
    done
done

# 3. the solve suite on generated meshes
work=$(mktemp -d "${TMPDIR:-/tmp}/limn_gpu_run_XXXXXX")
trap 'rm -rf "$work"' EXIT
# the base meshes: data/'s icosahedron (Loop) and a cube (Catmull-Clark)
cp "$root/data/icosahedron.obj" "$work/loop.obj"
cat >"$work/catmark.obj" <<'EOF'
v -1 -1 -1
v 1 -1 -1
v 1 1 -1
v -1 1 -1
v -1 -1 1
v 1 -1 1
v 1 1 1
v -1 1 1
f 1 4 3 2
f 5 6 7 8
f 1 2 6 5
f 2 3 7 6
f 3 4 8 7
f 4 1 5 8
EOF
for sl in $levels; do
    scheme=${sl%%:*} level=${sl#*:}
    mesh=$work/$scheme-$level.ply
    say "mesh: $scheme refined $level times"
    "$limn" subdivide "$work/$scheme.obj" -o "$mesh" --levels "$level" --device "$device" -q \
        >>"$log" 2>&1
    for mp in $methods; do
        method=${mp%%:*} precision=${mp#*:} tol=
        if [[ $precision == *:* ]]; then tol=${precision#*:} precision=${precision%%:*}; fi
        for shape in $shapes; do
            say "interpolate $scheme-$level --method $method --precision $precision${tol:+ --tol $tol}, $shape shape"
            LIMN_KERNEL_SHAPE=$shape "$limn" interpolate "$mesh" -o "$work/p.ply" \
                --method "$method" --precision "$precision" ${tol:+--tol "$tol" --max-iter 5000} \
                --device "$device" -q \
                --report "$out/solve-$scheme-$level-$method-$precision${tol:+-$tol}-$shape.json" \
                >>"$log" 2>&1 || say "  failed (see $log)"
        done
    done
    rm -f "$mesh" "$work/p.ply"
done

# 4. the summary
python3 - "$out" <<'EOF'
import glob, json, os, sys
out = sys.argv[1]

def loop_bytes(r):
    """docs/performance.md's byte model (host/cli/cli_bench.c bench_loop_bytes)."""
    nnz, n = float(r["stencil_nonzeros"]), float(r["vertices"])
    streams = {"chebyshev": 4, "sgs": 18}.get(r["method"], 3)
    nf = r.get("products_float", 0)
    if nf > 0:
        residual = 12 * nnz + (4 + 32 + 32 + 16) * n
        return residual * (r["products"] - nf) + (8 * nnz + (4 + streams * 16) * n) * nf
    return (12 * nnz + (4 + streams * 32) * n) * r["products"]

bench, solve = [], []
for p in sorted(glob.glob(os.path.join(out, "bench-*.json"))):
    b = json.load(open(p))
    b["shape"] = p.rsplit("-", 1)[1][:-5]
    bench.append(b)
triad = max([b["triad"]["gb_per_s"] for b in bench] or [0.0])
for p in sorted(glob.glob(os.path.join(out, "solve-*.json"))):
    r = json.load(open(p))
    secs = r["seconds"]["iterations"]
    gbs = loop_bytes(r) / secs / 1e9 if secs > 0 else 0.0
    solve.append({"file": os.path.basename(p), "shape": p.rsplit("-", 1)[1][:-5],
                  "vertices": r["vertices"], "method": r["method"],
                  "precision": r["precision"], "iterations": r["iterations"],
                  "seconds_iterations": secs, "gb_per_s": gbs,
                  "triad_fraction": gbs / triad if triad else None,
                  "max_rel_error": r["max_rel_error"], "device": r["device"]})
json.dump({"triad_gb_per_s_best": triad, "bench": bench, "solve": solve},
          open(os.path.join(out, "summary.json"), "w"), indent=1)
with open(os.path.join(out, "summary.md"), "w") as f:
    dev = bench[0]["device"] if bench else (solve[0]["device"] if solve else "?")
    f.write(f"Device: {dev}\n\nBest triad: {triad:.1f} GB/s\n\n")
    f.write("| bench | shape | vertices | method | precision | solve loop GB/s | of triad | total s |\n")
    f.write("|---|---|---:|---|---|---:|---:|---:|\n")
    for b in bench:
        f.write(f"| {b['vertices_requested']} | {b['shape']} | {b['vertices']} | {b['method']} | "
                f"{b['precision']} | {b['solve_loop']['gb_per_s']:.1f} | "
                f"{b['solve_loop']['triad_fraction']:.2f} | {b['seconds']['total']:.2f} |\n")
    f.write("\n| solve | shape | vertices | method | precision | iterations | loop s | GB/s | of triad | max rel error |\n")
    f.write("|---|---|---:|---|---|---:|---:|---:|---:|---:|\n")
    for s in solve:
        f.write(f"| {s['file'][6:-5]} | {s['shape']} | {s['vertices']} | {s['method']} | "
                f"{s['precision']} | {s['iterations']} | {s['seconds_iterations']:.4f} | "
                f"{s['gb_per_s']:.1f} | {s['triad_fraction'] or 0:.2f} | {s['max_rel_error']:.2e} |\n")
print(open(os.path.join(out, "summary.md")).read())
EOF
say "done in $((SECONDS - start)) s: $out/summary.md"
