#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# docs/mpi.md "Set-up, 2026-12-07 (session 32)": issue 14's set-up comparison
# on a mesh perf/mpi_scaling.py --pipeline does not make (e.g. igea refined
# four times, 34.4M vertices): one warm-up run each, then ROUNDS rounds taking
# turns (odd rounds one core first) of `limn interpolate MESH --precision
# double` as one rank bound to a core and as 2 ranks bound to a core each,
# each run's set-up summed as mpi_scaling.py sums it (one rank: load +
# topology + stencil + opening the device; 2 ranks: the worst rank's load +
# partition + local rows), then a cmp of the two outputs.
#
#   bash perf/mpi_setup_pairs.sh MESH [ROUNDS=3] [LIMN=build/limn]
set -euo pipefail
mesh=${1:?usage: mpi_setup_pairs.sh MESH [ROUNDS] [LIMN]}
rounds=${2:-3}
limn=${3:-build/limn}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
one() {
    mpirun -np 1 --bind-to core "$limn" interpolate "$mesh" -o "$dir/one.ply" \
        --report "$dir/one.json" --precision double -q >/dev/null
    python3 -c "import json, sys; s = json.load(open(sys.argv[1]))['seconds']
print('one core', round(s['load'] + s.get('topology', 0) + s.get('stencil', 0)
                        + s.get('opencl_setup', 0), 2))" "$dir/one.json"
}
two() {
    mpirun -np 2 --bind-to core "$limn" interpolate "$mesh" -o "$dir/two.ply" \
        --report "$dir/two.json" --precision double -q >/dev/null
    python3 -c "import json, sys; r = json.load(open(sys.argv[1]))['mpi']['per_rank']
print('2 ranks', round(max(x['seconds_load'] + x['seconds_partition'] + x['seconds_distribute']
                           for x in r), 2), 'peak MiB', [x['peak_rss_bytes'] >> 20 for x in r])" \
        "$dir/two.json"
}
one >/dev/null
two >/dev/null
for i in $(seq "$rounds"); do
    if [ $((i % 2)) = 1 ]; then one; two; else two; one; fi
done
cmp "$dir/one.ply" "$dir/two.ply" && echo "same bytes"
