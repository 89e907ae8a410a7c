#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Builds limn and its tests with AddressSanitizer + UndefinedBehaviorSanitizer
# (-DLIMN_SANITIZE=ON) and runs the whole test suite once under them: any
# memory error, leak (PoCL's and LLVM's own are suppressed, tests/lsan.supp)
# or undefined behaviour fails the test that hit it.
#   LIMN_SANITIZE_DIR: build directory (default build-sanitize)
set -euo pipefail
cd "$(dirname "$0")/.."
dir=${LIMN_SANITIZE_DIR:-build-sanitize}
cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DLIMN_SANITIZE=ON \
      -DLIMN_BUILD_TESTS=ON >/dev/null
cmake --build "$dir" -j "$(nproc)" >/dev/null
export LSAN_OPTIONS="suppressions=$PWD/tests/lsan.supp:print_suppressions=0"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:halt_on_error=1"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
ctest --test-dir "$dir" --output-on-failure
