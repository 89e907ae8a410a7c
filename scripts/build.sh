#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Configures and builds limn into build/ (RelWithDebInfo; LIMN_BUILD_DIR overrides).
# Arguments go to CMake's configure step (e.g. -DLIMN_BUILD_PERF=ON); the
# build's parallel jobs are LIMN_BUILD_JOBS (default: every CPU, nproc).
set -euo pipefail
cd "$(dirname "$0")/.."
dir=${LIMN_BUILD_DIR:-build}
cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo "$@" >/dev/null
cmake --build "$dir" -j "${LIMN_BUILD_JOBS:-$(nproc)}"
