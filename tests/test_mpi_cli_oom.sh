#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# `mpirun -np 2 limn COMMAND` on slices (the distributed pipeline: slices
# read, repaired, local rows, the solve or the filter, the parallel writes
# staged with the report, then all committed) with memory running out on
# one rank: limn_cli_faults (tests/alloc_fail_env.c) with
# LIMN_TEST_ALLOC_RANK=R fails the K-th allocation of rank R alone, for
# every one of the first 16 K (the arguments, the checks of the outputs)
# and then every STRIDE-th up to that rank's count in a run with nothing
# failing (each run is a launch: ~2 s here). Jobs (LIMN_TEST_JOBS, NAME:RANK
# or NAME:RANK:STRIDE, STRIDE default LIMN_TEST_STRIDE or 7): interpolate on
# rank 1 then 0; denoise, bands and morph on rank 0 (the rank that writes
# the report and the energy file after the parallel writes). Each run finds
# old bytes of its own in every file the run with nothing failing wrote.
# Every run must end with exit status 1 and a message ("error: " and
# words), every old file as it was and nothing beside them, or 0 with the
# same files as the run with nothing failing (the same bytes but in the
# reports); never another status, never a hang (timeout 60 s a run).
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
# shellcheck source=tests/oom_outputs.sh
source "$(dirname "$0")/oom_outputs.sh"

# args NAME OUTDIR: the command line of job NAME writing into OUTDIR
args() {
    local o=$2
    case $1 in
    interpolate) echo interpolate "$mesh" -o "$o/result.ply" --report "$o/r.json" --precision double ;;
    denoise) echo denoise "$mesh" -o "$o/result.ply" --report "$o/r.json" ;;
    bands) echo bands "$mesh" --count 2 -o "$o/b" --report "$o/r.json" ;;
    morph) echo morph "$mesh" "$mesh" -o "$o/f%02d.ply" --frames 3 --report "$o/r.json" ;;
    esac
}

# run NAME OUTDIR [env...]: one launch, its exit status
run() {
    local name=$1 out=$2
    shift 2
    # shellcheck disable=SC2046 # the paths hold no blanks (mktemp)
    env "$@" timeout 60 "$mpiexec" -np 2 "${flags[@]}" "$bin" $(args "$name" "$out") -q \
        >/dev/null 2>"$work/err"
}

for job in ${LIMN_TEST_JOBS:-interpolate:1 interpolate:0 denoise:0:30 bands:0:40 morph:0:40}; do
    IFS=: read -r name victim stride <<<"$job"
    stride=${stride:-${LIMN_TEST_STRIDE:-7}}
    rm -rf "$work/ref" "$work/count" && mkdir "$work/ref"
    if ! run "$name" "$work/ref" LIMN_TEST_ALLOC_FAIL=0 LIMN_TEST_ALLOC_RANK="$victim" \
        LIMN_TEST_ALLOC_COUNT="$work/count"; then
        echo "FAIL: $name, nothing failing: $(head -c 300 "$work/err")"
        exit 1
    fi
    n=$(cat "$work/count")
    refused=0
    tried=0
    for ((k = 1; k <= n; k = k < 16 ? k + 1 : k + stride)); do
        rm -rf "$work/out" && mkdir "$work/out" && old_files
        run "$name" "$work/out" LIMN_TEST_ALLOC_FAIL=$k LIMN_TEST_ALLOC_RANK="$victim"
        rc=$?
        runs=$((runs + 1))
        tried=$((tried + 1))
        if [ $rc -eq 0 ] && same_outputs; then
            continue
        elif [ $rc -eq 1 ] && grep -q 'error: [^ ]' "$work/err" && old_kept; then
            refused=$((refused + 1))
        else
            echo "FAIL: $name, rank $victim's allocation $k failing: exit $rc," \
                 "$(ls -A "$work/out" | tr '\n' ' ')left, old bytes $(old_kept &&
                 echo kept || echo not kept): $(head -c 300 "$work/err")"
            failures=$((failures + 1))
        fi
    done
    printf '  %s, rank %d: %d of its %d allocations failing in turn: %d refused, %d worked around\n' \
        "$name" "$victim" "$tried" "$n" "$refused" $((tried - refused))
done
echo "test_mpi_cli_oom: $runs runs, $failures failures"
[ $failures -eq 0 ]
