#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# One command from a fresh Debian 12: install what is missing (test-only
# packages included), build, and run everything CI checks:
#   1. every reader's fuzz target for a bounded time (libFuzzer, ASan + UBSan;
#      LIMN_FUZZ_SECONDS per target, default 60; 0 skips);
#   2. the whole test suite once under ASan + UBSan (LIMN_SANITIZE_RUN=0 skips);
#   3. the whole test suite, plain (test_oclgrind among it: every kernel
#      family under Oclgrind, no diagnostic, PoCL's bytes);
#   4. the Python package (scripts/test_python.sh: pip install ./python in a
#      fresh venv under the build directory, pytest against the CLI;
#      LIMN_PYTHON_TESTS=0 skips).
# Build directories: LIMN_BUILD_DIR (build), LIMN_FUZZ_DIR (build-fuzz),
# LIMN_SANITIZE_DIR (build-sanitize).
# ctest runs LIMN_CTEST_JOBS tests at a time (default: the cores); each test
# that launches ranks asks for 2 or 3 (PROCESSORS), so on 2 cores it runs alone:
# ranks waiting in a collective spin, and beside other tests they slowed 2-4x (one
# timed out at 4 tests at once on 2 cores).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/deps.sh --test
export LIMN_CTEST_JOBS=${LIMN_CTEST_JOBS:-$(nproc)}
start=$SECONDS
bash scripts/build.sh -DLIMN_BUILD_TESTS=ON
if [[ "${LIMN_FUZZ_SECONDS:-60}" != 0 ]]; then
    echo "== limn: fuzzing every reader, ${LIMN_FUZZ_SECONDS:-60} s per target (scripts/fuzz.sh)"
    bash scripts/fuzz.sh "${LIMN_FUZZ_SECONDS:-60}"
fi
if [[ "${LIMN_SANITIZE_RUN:-1}" != 0 ]]; then
    echo "== limn: the whole test suite under AddressSanitizer + UBSan (scripts/sanitize.sh)"
    log=$(mktemp)
    if ! bash scripts/sanitize.sh >"$log" 2>&1; then
        cat "$log"
        echo "limn: the test suite failed under the sanitizers (see above)" >&2
        exit 1
    fi
    grep -E "Test +#|tests passed|Total Test time" "$log" | sed 's/^/  [asan+ubsan] /'
    rm -f "$log"
fi
echo "== limn: the whole test suite ($((SECONDS - start)) s so far)"
ctest --test-dir "${LIMN_BUILD_DIR:-build}" --output-on-failure -j "$LIMN_CTEST_JOBS"
if [[ "${LIMN_PYTHON_TESTS:-1}" != 0 ]]; then
    echo "== limn: the Python package (scripts/test_python.sh, $((SECONDS - start)) s so far)"
    bash scripts/test_python.sh
fi
