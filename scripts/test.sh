#!/usr/bin/env bash
# One command from a fresh Debian 12: install what is missing (test-only
# packages included), build, and run the whole test suite under CTest.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/deps.sh --test
bash scripts/build.sh -DLIMN_BUILD_TESTS=ON
ctest --test-dir build --output-on-failure
