#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The pictures of docs/series.md "Keeping sharp features": fandisk and the
# chamfered puck with noise 0.3 x the mean edge, then limn denoise (default),
# bilateral normal filtering (Zheng et al.) and limn denoise --preserve-features.
#   bash perf/feature_figures.sh [BUILD_DIR=build] [MESHES=../shared/meshes]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build} meshes=${2:-../shared/meshes}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$build/perf/feature_bench" --meshes "$meshes" --device reference --out "$tmp" --sigma 0.3 \
    --write "$tmp" >/dev/null
for m in fandisk_quads part; do
    view=30,20
    [ "$m" = fandisk_quads ] && view=210,25
    for t in noisy default bnf features; do
        "$build/limn" render "$tmp/${m}_$t.ply" -o "docs/feature_${m%_quads}_$t.png" \
            --size 240x180 --flat --view "$view" -q
    done
done
