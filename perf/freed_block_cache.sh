#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# docs/mpi.md "Set-up, 2026-12-07 (session 28)": 2 ranks of limn interpolate
# on MESH, taking turns without and with perf/freed_block_cache.c preloaded;
# prints each run's worst rank's set-up (load + local rows, from --report)
# and peak RSS. Needs Open MPI and a build with MPI.
#   bash perf/freed_block_cache.sh [LIMN] [MESH] [ROUNDS]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
limn=${1:-$here/../build/limn}
mesh=${2:-/tmp/limn_read_bench/scanner_l2_f32.ply}
rounds=${3:-4}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cc -O2 -shared -fPIC -o "$work/freed_block_cache.so" "$here/freed_block_cache.c" -ldl -lpthread
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
for r in $(seq 1 "$rounds"); do
    for tag in plain cache; do
        pre=()
        [[ $tag == cache ]] && pre=(-x "LD_PRELOAD=$work/freed_block_cache.so" -x FREED_BLOCK_GROW=1)
        mpirun -np 2 --bind-to core "${pre[@]}" "$limn" interpolate "$mesh" -o "$work/out.ply" \
            --precision double -q --report "$work/report.json" >/dev/null
        python3 - "$tag" "$r" "$work/report.json" <<'PY'
import json, sys
ranks = json.load(open(sys.argv[3]))["mpi"]["per_rank"]
setup = max(x["seconds_load"] + x["seconds_distribute"] for x in ranks)
peak = max(x["peak_rss_bytes"] for x in ranks) >> 20
print(f"round {sys.argv[2]} {sys.argv[1]:5s}: set-up {setup:.3f} s, peak {peak} MiB")
PY
    done
done
