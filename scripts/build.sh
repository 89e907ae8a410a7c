#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Configures and builds limn into build/ (RelWithDebInfo; LIMN_BUILD_DIR overrides).
set -euo pipefail
cd "$(dirname "$0")/.."
dir=${LIMN_BUILD_DIR:-build}
cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo "$@" >/dev/null
cmake --build "$dir" -j "$(nproc)"
