#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# `mpirun -np 2 limn interpolate` (the distributed pipeline: slices read,
# repaired, local rows, the solve, the parallel write and the report) with
# memory running out on one rank: limn_cli_faults (tests/alloc_fail_env.c)
# with LIMN_TEST_ALLOC_RANK=R fails the K-th allocation of rank R alone, for
# every K up to that rank's count in a run with nothing failing, R = 1 then
# 0. Every run must end with exit status 1 and a message, no output file
# and nothing beside it, or 0 with the same mesh bytes as the run with
# nothing failing; never another status, never a hang (timeout 60 s a run).
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
run() { # OUTDIR [env...]: one launch, its exit status
    local out=$1
    shift
    env "$@" timeout 60 "$mpiexec" -np 2 "${flags[@]}" "$bin" interpolate "$mesh" \
        -o "$out/control.ply" --report "$out/r.json" --precision double -q \
        >/dev/null 2>"$work/err"
}
mkdir -p "$work/ref"
for victim in ${LIMN_TEST_VICTIMS:-1 0}; do
    rm -f "$work/ref"/* "$work/count"
    if ! run "$work/ref" LIMN_TEST_ALLOC_FAIL=0 LIMN_TEST_ALLOC_RANK=$victim \
        LIMN_TEST_ALLOC_COUNT="$work/count"; then
        echo "FAIL: nothing failing: $(head -c 300 "$work/err")"
        exit 1
    fi
    n=$(cat "$work/count")
    refused=0
    tried=0
    # every allocation of the first 16 (the arguments, the checks of the
    # outputs), then every STRIDE-th (each run is a launch: ~2 s here)
    for ((k = 1; k <= n; k = k < 16 ? k + 1 : k + ${LIMN_TEST_STRIDE:-7})); do
        rm -rf "$work/out" && mkdir "$work/out"
        run "$work/out" LIMN_TEST_ALLOC_FAIL=$k LIMN_TEST_ALLOC_RANK=$victim
        rc=$?
        runs=$((runs + 1))
        tried=$((tried + 1))
        left=$(ls -A "$work/out" | wc -l)
        if [ $rc -eq 0 ]; then
            cmp -s "$work/ref/control.ply" "$work/out/control.ply" || {
                echo "FAIL: rank $victim's allocation $k failing: exit 0 with other bytes"
                failures=$((failures + 1))
            }
        elif [ $rc -eq 1 ] && [ -s "$work/err" ] && [ "$left" -eq 0 ]; then
            refused=$((refused + 1))
        else
            echo "FAIL: rank $victim's allocation $k failing: exit $rc, $left file(s) left:" \
                 "$(head -c 300 "$work/err")"
            failures=$((failures + 1))
        fi
    done
    printf '  rank %d: %d of its %d allocations failing in turn: %d refused, %d worked around\n' \
        "$victim" "$tried" "$n" "$refused" $((tried - refused))
done
echo "test_mpi_cli_oom: $runs runs, $failures failures"
[ $failures -eq 0 ]
