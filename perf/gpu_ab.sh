#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Two builds of limn side by side on one device (docs/performance.md "The
# solve's set-up on a discrete device"): `limn interpolate --method
# chebyshev` on an icosahedron refined 10 times (Loop, 10.5M vertices) and a
# cube refined 10 times (Catmull-Clark, 6.3M), in double at --tol 1e-12 and in
# float, the two builds alternated ROUNDS times; prints each run's solve, loop,
# finish (seconds.solve_finish, 0 where the build has none), set-up and first
# launches, and whether the two outputs are the same bytes.
#   LIMN_OLD=CMD LIMN_NEW=CMD bash perf/gpu_ab.sh [OUT_DIR]
# CMD: a command that runs limn (e.g. "env LD_LIBRARY_PATH=lib1 build1/limn").
# Environment: GPU_AB_LEVELS [10], GPU_AB_ROUNDS [2], GPU_AB_DEVICE [opencl].
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
out=${1:-${OUT:-$root/out/gpu-ab}}
levels=${GPU_AB_LEVELS:-10} rounds=${GPU_AB_ROUNDS:-2} device=${GPU_AB_DEVICE:-opencl}
mkdir -p "$out"
work=$(mktemp -d "${TMPDIR:-/tmp}/limn_gpu_ab_XXXXXX")
trap 'rm -rf "$work"' EXIT
cp "$root/data/icosahedron.obj" "$work/loop.obj"
printf 'v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n%s\n' \
    'f 1 4 3 2
f 5 6 7 8
f 1 2 6 5
f 2 3 7 6
f 3 4 8 7
f 4 1 5 8' >"$work/catmark.obj"
for m in loop catmark; do
    $LIMN_NEW subdivide "$work/$m.obj" -o "$work/$m.ply" --levels "$levels" -q
done
for r in $(seq "$rounds"); do
    for m in loop catmark; do
        for p in "double --tol 1e-12" "float"; do
            for v in old new; do
                cmd=$LIMN_OLD
                [[ $v == new ]] && cmd=$LIMN_NEW
                # shellcheck disable=SC2086 # cmd and p are lists of words
                $cmd interpolate "$work/$m.ply" -o "$work/$v.ply" --method chebyshev \
                    --precision $p --device "$device" -q --report "$work/r.json"
                python3 - "$work/r.json" "$r $m-$levels ${p%% *} $v" <<'PY' | tee -a "$out/ab.txt"
import json, sys
r = json.load(open(sys.argv[1]))
s, k = r["seconds"], r["opencl_setup"]
f = s.get("solve_finish", 0.0)
print(sys.argv[2], "solve %.3f loop %.4f finish %.3f set-up %.3f first-launches %.3f total %.2f "
      "iterations %d" % (s["solve"], s["iterations"], f, s["solve"] - s["iterations"] - f,
                         k["kernels"], s["total"], r["iterations"]))
PY
            done
            if cmp -s "$work/old.ply" "$work/new.ply"; then
                echo "  same bytes" | tee -a "$out/ab.txt"
            else
                echo "  DIFFERENT bytes" | tee -a "$out/ab.txt"
            fi
        done
    done
done
