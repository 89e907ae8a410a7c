#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The command line with memory running out anywhere (limn's and the CLI's
# own allocations, one at a time): BIN is the CLI built with the
# allocation-failure wrappers (limn_cli_faults, tests/alloc_fail_env.c).
# For each command, a run with nothing failing counts the allocations and
# keeps its outputs; then for every k the k-th fails, each run finding old
# bytes of its own in every file the run with nothing failing wrote: it must
# exit 1 with a message on standard error ("error: " and words) and leave
# every old file as it was and nothing beside them (the outputs appear
# together or not at all, and an existing one is never lost), or exit 0
# with the same files as the run with nothing failing, the same bytes but
# in the reports (where limn falls back).
# Never another exit status (a crash is 134 or 139).
# With KIND opencl the same sweep fails limn's OpenCL calls (cl_fail.h's:
# buffers, kernels, reads, writes, maps, fills, clFinish) one at a time,
# LIMN_TEST_CL_FAIL=K, in the commands that use the device: with no
# fallback, then (interpolate, subdivide) with LIMN_FALLBACK=reference.
#   test_cli_oom.sh BIN MESH [alloc|opencl]
set -uo pipefail
shopt -s nullglob
bin=$1
mesh=$2
kind=${3:-alloc}
fail_var=LIMN_TEST_ALLOC_FAIL
count_var=LIMN_TEST_ALLOC_COUNT
if [ "$kind" = opencl ]; then
    fail_var=LIMN_TEST_CL_FAIL
    count_var=LIMN_TEST_CL_COUNT
fi
work=$(mktemp -d "${TMPDIR:-/tmp}/limn_cli_oom.XXXXXX")
trap 'rm -rf "$work"' EXIT
failures=0
runs=0
# shellcheck source=tests/oom_outputs.sh
source "$(dirname "$0")/oom_outputs.sh"

# sweep NAME ARGS...: ARGS with @OUT@ for the output directory
sweep() {
    local name=$1
    shift
    mkdir -p "$work/ref" "$work/out"
    local args=("${@//@OUT@/$work/ref}")
    if ! env "$fail_var=0" "$count_var=$work/count" "$bin" "${args[@]}" \
        >/dev/null 2>"$work/err"; then
        echo "FAIL: $name with nothing failing: $(cat "$work/err")"
        failures=$((failures + 1))
        return
    fi
    local n refused=0
    n=$(cat "$work/count")
    for ((k = 1; k <= n; k++)); do
        rm -rf "$work/out" && mkdir "$work/out"
        old_files
        args=("${@//@OUT@/$work/out}")
        env "$fail_var=$k" "$bin" "${args[@]}" >/dev/null 2>"$work/err"
        local rc=$?
        runs=$((runs + 1))
        if [ $rc -eq 1 ]; then
            refused=$((refused + 1))
            if ! grep -q 'error: [^ ]' "$work/err" || ! old_kept; then
                echo "FAIL: $name, $kind call $k failing: exit 1, the old files not as they" \
                     "were ($(ls -A "$work/out" | tr '\n' ' ')), message" \
                     "'$(head -c 300 "$work/err")'"
                failures=$((failures + 1))
            fi
        elif [ $rc -eq 0 ]; then
            if ! same_outputs; then
                echo "FAIL: $name, $kind call $k failing: exit 0 with other outputs"
                failures=$((failures + 1))
            fi
        else
            echo "FAIL: $name, $kind call $k failing: exit status $rc: $(head -c 300 "$work/err")"
            failures=$((failures + 1))
        fi
    done
    rm -rf "$work/ref" "$work/out"
    printf '  %-28s %4d %s calls failing in turn: %4d refused, %d worked around\n' \
        "$name" "$n" "$kind" "$refused" $((n - refused))
}

export LIMN_FALLBACK=  # no fallback unless a sweep says so
if [ "$kind" = opencl ]; then
    sweep "interpolate --report" interpolate "$mesh" -o @OUT@/control.ply --report @OUT@/r.json -q
    sweep "denoise" denoise "$mesh" -o @OUT@/d.ply -q
    sweep "subdivide --limit" subdivide "$mesh" -o @OUT@/s.obj --levels 1 --limit -q
    sweep "bands" bands "$mesh" --count 2 -o @OUT@/b -q
    sweep "morph --frames 3" morph "$mesh" "$mesh" -o '@OUT@/f%02d.ply' --frames 3 -q
    sweep "texture --levels 1" texture "$mesh" -o @OUT@/t.ply --colors '#ff0000,#0000ff' \
        --levels 1 -q
    export LIMN_FALLBACK=reference
    sweep "interpolate, fallback" interpolate "$mesh" -o @OUT@/control.ply --report @OUT@/r.json -q
    sweep "subdivide, fallback" subdivide "$mesh" -o @OUT@/s.obj --levels 1 --limit -q
else
    sweep "interpolate --report" interpolate "$mesh" -o @OUT@/control.ply --report @OUT@/r.json -q
    sweep "denoise" denoise "$mesh" -o @OUT@/d.ply -q
    sweep "subdivide --limit" subdivide "$mesh" -o @OUT@/s.obj --levels 1 --limit -q
    sweep "bands" bands "$mesh" --count 2 -o @OUT@/b -q
    sweep "info" info "$mesh"
    sweep "morph --frames 3" morph "$mesh" "$mesh" -o '@OUT@/f%02d.ply' --frames 3 -q
    sweep "render --report" render "$mesh" -o @OUT@/p.png --report @OUT@/r.json --size 64x48 -q
    sweep "texture --levels 1" texture "$mesh" -o @OUT@/t.ply --colors '#ff0000,#0000ff' \
        --levels 1 -q
fi
echo "test_cli_oom ($kind): $runs runs, $failures failures"
[ $failures -eq 0 ]
