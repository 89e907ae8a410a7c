#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The README's before/after pictures of the series commands, made with
# `limn render` (PNG, 400x300). Usage: bash perf/figures.sh [build/limn] [meshes dir]
#   docs/denoise_noisy.png, docs/denoise_limn.png: bunny_closed with seeded
#     Gaussian noise (sigma = 0.5 x mean edge) and after `limn denoise`;
#   docs/texture_mesh.png, docs/texture_spot.png: the Spot control mesh and
#     `limn texture` on it (3 levels).
set -euo pipefail
cd "$(dirname "$0")/.."
limn=${1:-build/limn}
meshes=${2:-${LIMN_SHARED_MESHES:-../shared/meshes}}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p docs

# noise on an OFF file (text), seeded: every coordinate + N(0, sigma^2)
python3 - "$meshes/medium/bunny_closed.off" "$tmp/noisy.off" 0.5 <<'PY'
import math, random, sys
src, dst, factor = sys.argv[1], sys.argv[2], float(sys.argv[3])
tok = open(src).read().split()
assert tok[0] == "OFF"
nv, nf = int(tok[1]), int(tok[2])
v = [[float(x) for x in tok[4 + 3 * i: 7 + 3 * i]] for i in range(nv)]
faces, k = [], 4 + 3 * nv
for _ in range(nf):
    n = int(tok[k]); faces.append([int(x) for x in tok[k + 1: k + 1 + n]]); k += 1 + n
edges = [(f[i], f[(i + 1) % len(f)]) for f in faces for i in range(len(f))]
mean = sum(math.dist(v[a], v[b]) for a, b in edges) / len(edges)
rng = random.Random(4)
with open(dst, "w") as out:
    out.write("OFF\n%d %d 0\n" % (nv, nf))
    for p in v:
        out.write("%.17g %.17g %.17g\n" % tuple(c + rng.gauss(0, factor * mean) for c in p))
    for f in faces:
        out.write("%d %s\n" % (len(f), " ".join(map(str, f))))
PY
"$limn" denoise "$tmp/noisy.off" -o "$tmp/denoised.ply" --m 1 --steps 6
"$limn" render "$tmp/noisy.off" -o docs/denoise_noisy.png --view 20,15 --flat -q
"$limn" render "$tmp/denoised.ply" -o docs/denoise_limn.png --view 20,15 --flat -q

"$limn" texture data/spot_control_mesh.obj -o "$tmp/spot_texture.ply" --levels 3 \
    --colors '#2b1d0e,#8c5a2b,#e8d3a9,#f7f1e3' --seed 7
"$limn" render data/spot_control_mesh.obj -o docs/texture_mesh.png --view 150,15 --flat -q
"$limn" render "$tmp/spot_texture.ply" -o docs/texture_spot.png --view 150,15 -q
ls -l docs/*.png
