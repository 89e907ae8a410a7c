#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Builds the libFuzzer targets of tests/fuzz (clang-14, ASan + UBSan) and runs
# each reader's target for a bounded time, as many at once as there are cores,
# starting from the committed seeds (tests/fuzz/corpus/TARGET). New inputs go
# to BUILD/corpus/TARGET, crashes to BUILD/artifacts/TARGET/. Prints the
# executions per target; exits 1 when a target crashed (copy the artifact into
# tests/fuzz/regressions/TARGET/ and fix the reader: the replay test keeps it).
#
#   scripts/fuzz.sh [SECONDS_PER_TARGET] [TARGET...]
#     default 60 s, all targets; LIMN_FUZZ_DIR: build directory (build-fuzz)
set -euo pipefail
cd "$(dirname "$0")/.."
secs=${1:-60}
shift || true
targets=("$@")
[[ ${#targets[@]} -gt 0 ]] || targets=(obj off stl ply ply_le ply_be)
dir=${LIMN_FUZZ_DIR:-build-fuzz}
cc=$(command -v clang-14 || command -v clang || true)
cxx=$(command -v clang++-14 || command -v clang++ || true)
if [[ -z "$cc" || -z "$cxx" ]]; then
    echo "limn fuzz: clang is not installed (apt-get install clang-14 libclang-rt-14-dev)" >&2
    exit 1
fi

cmake -S . -B "$dir" -DCMAKE_C_COMPILER="$cc" -DCMAKE_CXX_COMPILER="$cxx" -DLIMN_FUZZ=ON \
      -DLIMN_BUILD_TESTS=OFF -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build "$dir" -j "$(nproc)" --target "${targets[@]/#/fuzz_}" >/dev/null

mkdir -p "$dir/logs"
run_one() {
    local t=$1 dict=tests/fuzz/dict/${1%%_*}.dict
    mkdir -p "$dir/corpus/$t" "$dir/artifacts/$t"
    "$dir/tests/fuzz/fuzz_$t" -max_total_time="$secs" -timeout=10 -rss_limit_mb=2048 \
        -malloc_limit_mb=512 -print_final_stats=1 -dict="$dict" \
        -artifact_prefix="$dir/artifacts/$t/" "$dir/corpus/$t" "tests/fuzz/corpus/$t" \
        >"$dir/logs/$t.log" 2>&1
}

echo "limn fuzz: ${#targets[@]} targets, ${secs} s each, $(nproc) at a time (clang: $cc)"
declare -A status
pids=()
names=()
for t in "${targets[@]}"; do
    run_one "$t" &
    pids+=($!)
    names+=("$t")
    if [[ ${#pids[@]} -ge $(nproc) ]]; then
        if wait "${pids[0]}"; then status[${names[0]}]=0; else status[${names[0]}]=$?; fi
        pids=("${pids[@]:1}")
        names=("${names[@]:1}")
    fi
done
for i in "${!pids[@]}"; do
    if wait "${pids[$i]}"; then status[${names[$i]}]=0; else status[${names[$i]}]=$?; fi
done

failed=0
printf '%-8s %12s %9s %8s %8s  %s\n' target executions exec/s corpus crashes result
for t in "${targets[@]}"; do
    log="$dir/logs/$t.log"
    execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
    rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
    corpus=$(find "$dir/corpus/$t" -type f | wc -l)
    crashes=$(find "$dir/artifacts/$t" -type f | wc -l)
    result=ok
    if [[ ${status[$t]} -ne 0 || $crashes -ne 0 ]]; then
        result="FAILED (exit ${status[$t]}; log $log)"
        failed=1
    fi
    printf '%-8s %12s %9s %8s %8s  %s\n' "$t" "${execs:-?}" "${rate:-?}" "$corpus" "$crashes" \
        "$result"
done
if [[ $failed -ne 0 ]]; then
    for t in "${targets[@]}"; do
        if [[ ${status[$t]} -ne 0 ]]; then
            echo "---- $t: last lines of $dir/logs/$t.log" >&2
            tail -40 "$dir/logs/$t.log" >&2
        fi
    done
    echo "limn fuzz: a target crashed: copy its artifact into tests/fuzz/regressions/TARGET/," \
         "fix the reader, and rerun" >&2
    exit 1
fi
