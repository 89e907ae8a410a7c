#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Every kernel family of limn under Oclgrind (an OpenCL device simulator that
# checks each memory access): `oclgrind --check-api --data-races limn ...` for
# every --method and --precision, subdivide, the series commands and texture,
# on small meshes. Each run must print no Oclgrind diagnostic and write the
# same bytes as the same command on the default device (PoCL): FP_CONTRACT
# is off in every kernel and reductions are finished on the host in item
# order, so the results do not depend on the device. Oclgrind's Debian
# package installs no ICD file: its wrapper preloads its runtime, which is
# then the only platform limn sees. (--uninitialized is not used: it reports
# buffers filled by clEnqueueFillBuffer.) Then the gpu kernel shape, every
# method, precision and series command once (gpu_cases, below). Exit 77
# (skipped) without oclgrind.
#   tests/test_oclgrind.sh LIMN DATA_DIR
set -euo pipefail
limn=${1:?usage: test_oclgrind.sh LIMN DATA_DIR}
data=${2:?usage: test_oclgrind.sh LIMN DATA_DIR}
if ! command -v oclgrind >/dev/null; then
    echo "test_oclgrind: oclgrind is not installed (apt-get install oclgrind): skipped"
    exit 77
fi
work=$(mktemp -d /tmp/limn_oclgrind_XXXXXX)
trap 'rm -rf "$work"' EXIT
start=$SECONDS

spot=$data/spot_control_mesh.obj
# A small triangle mesh for Loop: the icosahedron of data/ refined once (42 vertices).
"$limn" subdivide "$data/icosahedron.obj" -o "$work/tri.obj" --levels 1 -q
# morph's target: spot smoothed (same faces, same vertex order)
"$limn" smooth "$spot" -o "$work/spot_smooth.obj" --terms 2 -q

# name | arguments (OUT: the output path, or prefix for bands, or frame pattern);
# the paper and weighted iterations to 1e-4 (~40 steps instead of ~150: the
# kernels are the same, Oclgrind runs each launch ~1000x slower than PoCL)
cases=(
    "paper-double|interpolate $spot -o OUT.ply --method paper --precision double --tol 1e-4"
    "weighted-double|interpolate $spot -o OUT.ply --method weighted --precision double --tol 1e-4"
    "chebyshev-double|interpolate $spot -o OUT.ply --method chebyshev --precision double"
    "cg-double|interpolate $spot -o OUT.ply --method cg --precision double"
    "sgs-double|interpolate $spot -o OUT.ply --method sgs --precision double"
    "paper-float|interpolate $spot -o OUT.ply --method paper --precision float --tol 1e-4"
    "weighted-float|interpolate $spot -o OUT.ply --method weighted --precision float --tol 1e-4"
    "chebyshev-float|interpolate $spot -o OUT.ply --method chebyshev --precision float"
    "loop-chebyshev-double|interpolate $work/tri.obj -o OUT.ply --method chebyshev --precision double"
    "loop-sgs-double|interpolate $work/tri.obj -o OUT.ply --method sgs --precision double"
    "loop-chebyshev-float|interpolate $work/tri.obj -o OUT.ply --method chebyshev --precision float"
    "subdivide|subdivide $spot -o OUT.ply --levels 2"
    "subdivide-limit|subdivide $work/tri.obj -o OUT.ply --levels 1 --limit"
    "smooth|smooth $spot -o OUT.ply --terms 3"
    "denoise|denoise $spot -o OUT.ply --m 2 --steps 2"
    "sharpen|sharpen $spot -o OUT.ply --from 1 --to 2 --steps 1"
    "bands|bands $spot --count 2 -o OUT"
    "morph|morph $spot $work/spot_smooth.obj -o OUT/f%02d.ply --frames 3"
    "texture|texture $work/tri.obj -o OUT.ply --colors #ff0000,#00ff00,#0000ff --levels 1"
)

# The gpu kernel shape (LIMN_KERNEL_SHAPE=gpu, docs/performance.md "Kernel
# shapes"): one row per work-item over the SELL table, partials reduced in
# local memory with barriers, which --data-races checks. Groups of 4 on both
# sides (Oclgrind's --max-wgsize, PoCL's POCL_MAX_WORK_GROUP_SIZE): several
# groups and SELL slices per launch on these small meshes, a group limit
# below the cpu shape's 8, and the same reduction tree on both, so the same
# bytes. Every method and precision, and every series command, once.
gpu_cases=(
    "gpu-paper-double|interpolate $spot -o OUT.ply --method paper --precision double --tol 1e-4"
    "gpu-weighted-double|interpolate $spot -o OUT.ply --method weighted --precision double --tol 1e-4"
    "gpu-chebyshev-double|interpolate $spot -o OUT.ply --method chebyshev --precision double"
    "gpu-cg-double|interpolate $spot -o OUT.ply --method cg --precision double"
    "gpu-sgs-double|interpolate $spot -o OUT.ply --method sgs --precision double"
    "gpu-paper-float|interpolate $work/tri.obj -o OUT.ply --method paper --precision float --tol 1e-4"
    "gpu-weighted-float|interpolate $work/tri.obj -o OUT.ply --method weighted --precision float --tol 1e-4"
    "gpu-chebyshev-float|interpolate $spot -o OUT.ply --method chebyshev --precision float"
    "gpu-subdivide-limit|subdivide $work/tri.obj -o OUT.ply --levels 1 --limit"
    "gpu-smooth|smooth $spot -o OUT.ply --terms 3"
    "gpu-denoise|denoise $spot -o OUT.ply --m 2 --steps 2"
    "gpu-sharpen|sharpen $spot -o OUT.ply --from 1 --to 2 --steps 1"
    "gpu-bands|bands $spot --count 2 -o OUT"
    "gpu-morph|morph $spot $work/spot_smooth.obj -o OUT/f%02d.ply --frames 3"
    "gpu-texture|texture $work/tri.obj -o OUT.ply --colors #ff0000,#00ff00,#0000ff --levels 1"
)

# run_case NAME ARGS SHAPE: the command on PoCL and under Oclgrind (SHAPE
# gpu: the gpu shape in groups of 4, above); 1 when it failed.
run_case() {
    local name=$1 args=$2 shape=$3 t0=$SECONDS bad=0 side out rc
    local -a pocl_env=() grind_opts=() stage_env=()
    if [[ $shape == gpu ]]; then
        pocl_env=(LIMN_KERNEL_SHAPE=gpu POCL_MAX_WORK_GROUP_SIZE=4)
        grind_opts=(--max-wgsize 4)
        stage_env=(LIMN_TEST_FAULT=small-staging)
    fi
    for side in pocl oclgrind; do
        mkdir -p "$work/$side/$name"
        out=$work/$side/$name/out
        [[ $args == morph* ]] && mkdir -p "$out"
        # shellcheck disable=SC2086 # the arguments are words on purpose
        set -- ${args//OUT/$out}
        rc=0
        if [[ $side == pocl ]]; then
            env "${pocl_env[@]}" "$limn" "$@" -q >"$work/$side/$name.log" 2>&1 || rc=$?
        else
            # the gpu shape's runs also stage every transfer through pinned
            # memory in 4 KiB chunks (Oclgrind is a discrete device to limn:
            # host/device/opencl/opencl_staging.h); the cpu shape's go direct
            env "${pocl_env[@]:0:1}" "${stage_env[@]}" \
                oclgrind --check-api --data-races "${grind_opts[@]}" "$limn" "$@" -q \
                >"$work/$side/$name.log" 2>&1 || rc=$?
        fi
        if [[ $rc -ne 0 ]]; then
            echo "FAIL $name ($side): exit $rc"
            cat "$work/$side/$name.log"
            bad=1
        fi
    done
    # Oclgrind's diagnostics ("Invalid read ...", "Data race ...", "OpenCL
    # runtime error detected", "OCLGRIND FATAL ERROR"); limn itself prints
    # nothing with -q unless it warns, and a warning is a failure here too
    if grep -Eiq 'oclgrind|invalid|error|race|warning' "$work/oclgrind/$name.log"; then
        echo "FAIL $name: Oclgrind reported:"
        cat "$work/oclgrind/$name.log"
        bad=1
    fi
    if ! diff -r "$work/pocl/$name" "$work/oclgrind/$name" >/dev/null; then
        echo "FAIL $name: Oclgrind's output differs from PoCL's:"
        diff -r "$work/pocl/$name" "$work/oclgrind/$name" | head -5
        bad=1
    fi
    files=$(find "$work/oclgrind/$name" -type f | wc -l)
    if [[ $files -eq 0 ]]; then
        echo "FAIL $name: no output"
        bad=1
    fi
    if [[ $bad -eq 0 ]]; then
        echo "ok   $name ($files file(s) identical, $((SECONDS - t0)) s)"
    fi
    return $bad
}

failed=0
for c in "${cases[@]}"; do
    run_case "${c%%|*}" "${c#*|}" cpu || failed=1
done
cpu_seconds=$((SECONDS - start))
for c in "${gpu_cases[@]}"; do
    run_case "${c%%|*}" "${c#*|}" gpu || failed=1
done
echo "test_oclgrind: ${#cases[@]} commands in the cpu shape in $cpu_seconds s," \
    "${#gpu_cases[@]} in the gpu shape in $((SECONDS - start - cpu_seconds)) s"
exit $failed
