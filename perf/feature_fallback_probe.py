#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Issue 16's organic clause, a per-mesh test not built: should
`--preserve-features` give way to the default on this mesh? A parametric
bootstrap (docs/series.md, "A per-mesh test by re-noising"):

    python3 perf/feature_fallback_probe.py ../shared/meshes/small/spot_quadrangulated.obj \
        ../shared/meshes/small/fandisk_quads.off --sigma 0.2 --sigma 0.5

For each mesh and sigma: seeded Gaussian noise (sigma x the mean edge length on
every coordinate, as feature_bench), then limn denoise's default (x_D) and
`--preserve-features` (x_F) on it. If x_F were the clean mesh, the default run
on x_F plus fresh noise of the same sigma would give back x_D up to its own
noise; so

    R = (|x_D - D(x_F + n1)|^2 - |D(x_F + n1) - D(x_F + n2)|^2) / |x_D - x_F|^2

(the second term the two draws' spread: twice the default's variance; with
--draws K both terms are means over K draws and K pairs of consecutive ones) is near
0 where the two results differ because the default rounded what the feature
mode kept, and near 1 where they differ because the feature mode moved the
mesh where the default would not (its flattening of coarse curved meshes). A
mesh with R above --tau would take the default. Prints R and both filters'
mean face-normal error against the clean mesh. The result: R separates the
organic and coarse meshes from the CAD ones at sigma 0.2-0.3 but for the
bevelled cube at 0.2, and not at 0.5 (spot 0.0-0.2, like fandisk): not
built. Needs numpy, scipy, plyfile and a built limn.
"""
import argparse
import os
import subprocess
import sys
import tempfile

import numpy as np
from plyfile import PlyData, PlyElement

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from normal_choice_oracle import angles, by_size, face_normals  # noqa: E402


def read_mesh(path):
    """Positions and faces of a .ply, .obj or .off (polygons only)."""
    if path.endswith(".ply"):
        data = PlyData.read(path)
        v = data["vertex"]
        faces = [np.asarray(f, dtype=np.int64) for f in data["face"].data["vertex_indices"]]
        return np.stack([v["x"], v["y"], v["z"]], 1).astype(float), faces
    positions, faces = [], []
    if path.endswith(".obj"):
        for line in open(path):
            t = line.split()
            if t and t[0] == "v":
                positions.append([float(x) for x in t[1:4]])
            elif t and t[0] == "f":
                faces.append(np.array([int(x.split("/")[0]) - 1 for x in t[1:]]))
        return np.array(positions), faces
    tokens = [line.split("#")[0].split() for line in open(path)]
    tokens = [t for t in tokens if t]
    if tokens[0][0].upper() == "OFF":
        tokens[0] = tokens[0][1:]
        if not tokens[0]:
            tokens = tokens[1:]
    nv, nf = int(tokens[0][0]), int(tokens[0][1])
    positions = [[float(x) for x in tokens[1 + i][:3]] for i in range(nv)]
    faces = [np.array([int(x) for x in t[1:1 + int(t[0])]]) for t in tokens[1 + nv:1 + nv + nf]]
    return np.array(positions), faces


def write_ply(path, positions, faces):
    v = np.array([tuple(p) for p in positions], dtype=[("x", "f8"), ("y", "f8"), ("z", "f8")])
    f = np.array([(list(x),) for x in faces], dtype=[("vertex_indices", "O")])
    PlyData([PlyElement.describe(v, "vertex"), PlyElement.describe(f, "face")]).write(path)


class Limn:
    def __init__(self, exe, work):
        self.exe, self.work, self.n = exe, work, 0

    def denoise(self, positions, faces, extra):
        self.n += 1
        src = os.path.join(self.work, f"in{self.n}.ply")
        dst = os.path.join(self.work, f"out{self.n}.ply")
        write_ply(src, positions, faces)
        subprocess.run([self.exe, "denoise", src, "-o", dst, "-q"] + extra, check=True,
                       stderr=subprocess.DEVNULL)
        return read_mesh(dst)[0]


def probe(limn, clean, faces, sigma, seed, draws):
    edges = [np.linalg.norm(clean[f] - clean[np.roll(f, -1)], axis=1) for f in faces]
    s = sigma * np.concatenate(edges).mean()
    rng = np.random.default_rng(seed)
    noisy = clean + s * rng.standard_normal(clean.shape)
    feat = ["--preserve-features"]
    x_d = limn.denoise(noisy, faces, [])
    x_f = limn.denoise(noisy, faces, feat)
    runs = [limn.denoise(x_f + s * rng.standard_normal(clean.shape), faces, [])
            for _ in range(draws + 1)]
    mismatch = np.mean([((x_d - d) ** 2).sum() for d in runs[:-1]])
    spread = np.mean([((a - b) ** 2).sum() for a, b in zip(runs[:-1], runs[1:])])
    r = (mismatch - spread) / ((x_d - x_f) ** 2).sum()
    groups, nf = by_size(faces), len(faces)
    n_clean = face_normals(clean, groups, nf)
    err = [angles(face_normals(x, groups, nf), n_clean).mean() for x in (x_d, x_f)]
    return r, err[0], err[1]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("meshes", nargs="+", help="clean meshes (.ply, .obj, .off)")
    ap.add_argument("--sigma", type=float, action="append", help="noise / mean edge (repeatable)")
    ap.add_argument("--seed", type=int, default=7)
    ap.add_argument("--draws", type=int, default=1, help="re-noised runs averaged (+1)")
    ap.add_argument("--tau", type=float, default=0.3, help="R above it: take the default")
    ap.add_argument("--limn", default=os.path.join(os.path.dirname(__file__), "..", "build", "limn"))
    args = ap.parse_args()
    print("| mesh | sigma | R | default ° | features ° | pick | better |")
    print("|---|---:|---:|---:|---:|---|---|")
    with tempfile.TemporaryDirectory() as work:
        limn = Limn(args.limn, work)
        for path in args.meshes:
            clean, faces = read_mesh(path)
            for sigma in args.sigma or [0.2, 0.3, 0.5]:
                r, e_d, e_f = probe(limn, clean, faces, sigma, args.seed, args.draws)
                pick = "default" if r > args.tau else "features"
                better = "default" if e_d < e_f else "features"
                print(f"| {os.path.basename(path)} | {sigma} | {r:.2f} | {e_d:.2f} | {e_f:.2f} | "
                      f"{pick} | {better} |", flush=True)


if __name__ == "__main__":
    main()
