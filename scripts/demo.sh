#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# One command from a fresh Debian 12: install what is missing, build, and
# interpolate the embedded Spot control mesh (Keenan Crane, public domain).
# Writes out/spot_control.ply (the control mesh) and out/spot_control.json.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/deps.sh
bash scripts/build.sh -DLIMN_BUILD_TESTS=OFF
mkdir -p out
build/limn interpolate "${1:-data/spot_control_mesh.obj}" -o "${2:-out/spot_control.ply}" \
    --report "${3:-out/spot_control.json}"
echo "wrote ${2:-out/spot_control.ply} and ${3:-out/spot_control.json}"
