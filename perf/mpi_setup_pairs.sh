#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# docs/mpi.md "Set-up, 2026-12-07 (session 32)": issue 14's set-up comparison
# on a mesh perf/mpi_scaling.py --pipeline does not make (e.g. igea refined
# four times, 34.4M vertices): one warm-up run each, then ROUNDS rounds taking
# turns (odd rounds one core first) of `limn interpolate MESH --precision
# double` as one rank bound to a core and as 2 ranks bound to a core each,
# each run's set-up summed by mpi_scaling.py's own single_row / ranks_row (one
# rank: load + topology + stencil + opening the device; 2 ranks: the worst
# rank's load + partition + local rows), then a cmp of the two outputs.
#
#   bash perf/mpi_setup_pairs.sh MESH [ROUNDS=3] [LIMN=build/limn]
set -euo pipefail
mesh=${1:?usage: mpi_setup_pairs.sh MESH [ROUNDS] [LIMN]}
rounds=${2:-3}
limn=${3:-build/limn}
here=$(cd "$(dirname "$0")" && pwd)
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
one() {
    mpirun -np 1 --bind-to core "$limn" interpolate "$mesh" -o "$dir/one.ply" \
        --report "$dir/one.json" --precision double -q >/dev/null
    python3 -c "import json, sys; sys.path.insert(0, sys.argv[2]); import mpi_scaling as m
print('one core', round(m.single_row(json.load(open(sys.argv[1])), 0, True)['setup'][0], 2))" \
        "$dir/one.json" "$here"
}
two() {
    mpirun -np 2 --bind-to core "$limn" interpolate "$mesh" -o "$dir/two.ply" \
        --report "$dir/two.json" --precision double -q >/dev/null
    python3 -c "import json, sys; sys.path.insert(0, sys.argv[2]); import mpi_scaling as m
row = m.ranks_row(json.load(open(sys.argv[1])), 0)
print('2 ranks', round(max(row['setup']), 2), 'peak MiB', [b >> 20 for b in row['peak_bytes']])" \
        "$dir/two.json" "$here"
}
one >/dev/null
two >/dev/null
for i in $(seq "$rounds"); do
    if [ $((i % 2)) = 1 ]; then one; two; else two; one; fi
done
cmp "$dir/one.ply" "$dir/two.ply" && echo "same bytes"
