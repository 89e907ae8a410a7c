#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# `mpirun -np 2 limn interpolate` and `limn denoise` (the distributed
# pipeline: slices read, repaired, local rows, the solve or the filter, the
# parallel write staged with the report, then both committed) with memory
# running out on one rank: limn_cli_faults (tests/alloc_fail_env.c) with
# LIMN_TEST_ALLOC_RANK=R fails the K-th allocation of rank R alone, for every
# K up to that rank's count in a run with nothing failing: interpolate with R
# = 1 then 0, denoise with R = 0 (the rank that writes the report after the
# mesh). Each run starts with old bytes in the mesh and the report it names.
# Every run must end with exit status 1 and a message, both old files as
# they were and nothing beside them, or 0 with the same mesh bytes as the
# run with nothing failing; never another status, never a hang (timeout 60 s
# a run).
#   test_mpi_cli_oom.sh MPIEXEC BIN MESH [MPIEXEC FLAGS...]
set -uo pipefail
shopt -s nullglob
mpiexec=$1
bin=$2
mesh=$3
shift 3
flags=("$@")
work=$(mktemp -d "${TMPDIR:-/tmp}/limn_mpi_cli_oom.XXXXXX")
trap 'rm -rf "$work"' EXIT
failures=0
runs=0
run() { # COMMAND OUTDIR [env...]: one launch, its exit status
    local cmd=$1 out=$2
    local extra=(--precision double)
    [ "$cmd" = interpolate ] || extra=()
    shift 2
    env "$@" timeout 60 "$mpiexec" -np 2 "${flags[@]}" "$bin" "$cmd" "$mesh" \
        -o "$out/result.ply" --report "$out/r.json" "${extra[@]}" -q >/dev/null 2>"$work/err"
}
old_files() { # OUTDIR: the outputs a run finds, with bytes of their own
    printf 'an old mesh\n' >"$1/result.ply"
    printf 'an old report\n' >"$1/r.json"
}
kept() { # OUTDIR: the old files as they were, nothing beside them
    [ "$(cat "$1/result.ply")" = "an old mesh" ] && [ "$(cat "$1/r.json")" = "an old report" ] &&
        [ "$(ls -A "$1" | wc -l)" -eq 2 ]
}
mkdir -p "$work/ref"
for job in ${LIMN_TEST_JOBS:-interpolate:1 interpolate:0 denoise:0}; do
    cmd=${job%%:*}
    victim=${job##*:}
    rm -f "$work/ref"/* "$work/count"
    if ! run "$cmd" "$work/ref" LIMN_TEST_ALLOC_FAIL=0 LIMN_TEST_ALLOC_RANK=$victim \
        LIMN_TEST_ALLOC_COUNT="$work/count"; then
        echo "FAIL: $cmd, nothing failing: $(head -c 300 "$work/err")"
        exit 1
    fi
    n=$(cat "$work/count")
    refused=0
    tried=0
    # every allocation of the first 16 (the arguments, the checks of the
    # outputs), then every STRIDE-th (each run is a launch: ~2 s here)
    for ((k = 1; k <= n; k = k < 16 ? k + 1 : k + ${LIMN_TEST_STRIDE:-7})); do
        rm -rf "$work/out" && mkdir "$work/out" && old_files "$work/out"
        run "$cmd" "$work/out" LIMN_TEST_ALLOC_FAIL=$k LIMN_TEST_ALLOC_RANK=$victim
        rc=$?
        runs=$((runs + 1))
        tried=$((tried + 1))
        if [ $rc -eq 0 ]; then
            cmp -s "$work/ref/result.ply" "$work/out/result.ply" || {
                echo "FAIL: $cmd, rank $victim's allocation $k failing: exit 0 with other bytes"
                failures=$((failures + 1))
            }
        elif [ $rc -eq 1 ] && grep -q 'error: [^ ]' "$work/err" && kept "$work/out"; then
            refused=$((refused + 1))
        else
            echo "FAIL: $cmd, rank $victim's allocation $k failing: exit $rc," \
                 "$(ls -A "$work/out" | tr '\n' ' ')left, old bytes $(kept "$work/out" &&
                 echo kept || echo lost): $(head -c 300 "$work/err")"
            failures=$((failures + 1))
        fi
    done
    printf '  %s, rank %d: %d of its %d allocations failing in turn: %d refused, %d worked around\n' \
        "$cmd" "$victim" "$tried" "$n" "$refused" $((tried - refused))
done
echo "test_mpi_cli_oom: $runs runs, $failures failures"
[ $failures -eq 0 ]
