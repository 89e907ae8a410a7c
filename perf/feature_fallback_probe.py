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
mean face-normal error against the clean mesh, and Q: R with the default's own
result re-noised in place of the feature mode's and half the spread
subtracted (x_D's gap to its own re-run: how much the default would still
change its result). --per-face K: R summed over K rings of faces around each
face instead, the feature mode's normals where it is below --tau and the
default's elsewhere, then one least-squares fit of the positions to them
(normal_choice_oracle.py's); --family: the faces whose two normals differ by
more than t degrees take the feature mode's, a fit for each t, t picked by
Monte Carlo SURE. The results (docs/series.md): R separates the organic and
coarse meshes from the CAD ones at sigma 0.2-0.3 but for the bevelled cube at
0.2, and not at 0.5 (spot 0.0-0.2, like fandisk); none of the four was built.
Needs numpy, scipy, plyfile and a built limn.
"""
import argparse
import os
import subprocess
import sys
import tempfile

import numpy as np
from plyfile import PlyData, PlyElement

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from normal_choice_oracle import (angles, by_size, face_normals, face_rings,  # noqa: E402
                                  fit_to_normals, read_ply)

FEATURES = ["--preserve-features"]


def read_mesh(path):
    """Positions and faces of a .ply, .obj or .off (polygons only)."""
    if path.endswith(".ply"):
        return read_ply(path)
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


def renoised(limn, base, faces, s, rng, draws):
    """draws + 1 runs of the default on base plus fresh noise of deviation s."""
    return [limn.denoise(base + s * rng.standard_normal(base.shape), faces, [])
            for _ in range(draws + 1)]


def mismatch_spread(x_d, runs):
    """Per vertex: the mean squared gap from x_d to the runs, and between consecutive runs."""
    mismatch = np.mean([((x_d - d) ** 2).sum(1) for d in runs[:-1]], 0)
    spread = np.mean([((a - b) ** 2).sum(1) for a, b in zip(runs[:-1], runs[1:])], 0)
    return mismatch, spread


def per_face(groups, nf, per_vertex):
    """The sum of a per-vertex value over each face's corners."""
    out = np.zeros(nf)
    for ids, idx in groups.values():
        out[ids] = per_vertex[idx].sum(1)
    return out


class Case:
    """One noisy copy of a clean mesh and both filters' results on it."""

    def __init__(self, limn, clean, faces, sigma, seed):
        edges = [np.linalg.norm(clean[f] - clean[np.roll(f, -1)], axis=1) for f in faces]
        self.s = sigma * np.concatenate(edges).mean()
        self.rng = np.random.default_rng(seed)
        self.noisy = clean + self.s * self.rng.standard_normal(clean.shape)
        self.limn, self.faces = limn, faces
        self.x_d = limn.denoise(self.noisy, faces, [])
        self.x_f = limn.denoise(self.noisy, faces, FEATURES)
        self.groups, self.nf = by_size(faces), len(faces)
        self.n_clean = face_normals(clean, self.groups, self.nf)
        self.n_d = face_normals(self.x_d, self.groups, self.nf)
        self.n_f = face_normals(self.x_f, self.groups, self.nf)

    def error(self, x):
        return angles(face_normals(x, self.groups, self.nf), self.n_clean).mean()

    def fit(self, use_feature):
        return fit_choice(self.groups, self.x_d, self.n_d, self.n_f, use_feature)


def fit_choice(groups, x_d, n_d, n_f, use_feature):
    """The positions fitted to the feature mode's normals where use_feature, the
    default's elsewhere (normal_choice_oracle.py's fit, lam 0.1, from x_d)."""
    chosen = np.where(use_feature[:, None], n_f, n_d)
    return fit_to_normals(x_d, groups, chosen, 0.1)


def statistics(case, draws, rings_list, tau):
    """R, Q and, for each ring count, the fit with R per face below tau."""
    gap = ((case.x_d - case.x_f) ** 2).sum(1)
    runs = renoised(case.limn, case.x_f, case.faces, case.s, case.rng, draws)
    mis_f, spread_f = mismatch_spread(case.x_d, runs)
    runs = renoised(case.limn, case.x_d, case.faces, case.s, case.rng, draws)
    mis_d, spread_d = mismatch_spread(case.x_d, runs)
    r = (mis_f - spread_f).sum() / gap.sum()
    q = (mis_d - 0.5 * spread_d).sum() / gap.sum()
    local = []
    if rings_list:
        rings = face_rings(case.groups, len(case.x_d), case.nf)
        num = per_face(case.groups, case.nf, mis_f - spread_f)
        den = per_face(case.groups, case.nf, gap)
        for k in range(1, max(rings_list) + 1):
            num, den = rings @ num, rings @ den
            if k in rings_list:
                local.append(case.error(case.fit(num < tau * den)))
    return r, q, local


def sure_family(case, thresholds, probes):
    """The faces whose two normals differ by more than t degrees take the feature
    mode's, one fit each; t picked by Monte Carlo SURE (probes +-1 vectors through
    both filters and the fit). Returns the picked t and every t's normal error."""
    differ = angles(case.n_d, case.n_f)
    fits = [case.fit(differ > t) for t in thresholds]
    divergence = np.zeros(len(thresholds))
    eps = 0.05 * case.s
    for _ in range(probes):
        b = case.rng.choice([-1.0, 1.0], case.noisy.shape)
        x_d = case.limn.denoise(case.noisy + eps * b, case.faces, [])
        x_f = case.limn.denoise(case.noisy + eps * b, case.faces, FEATURES)
        n_d, n_f = (face_normals(x, case.groups, case.nf) for x in (x_d, x_f))
        for i, t in enumerate(thresholds):
            moved = fit_choice(case.groups, x_d, n_d, n_f, differ > t) - fits[i]
            divergence[i] += (b * moved).sum() / eps / probes
    risk = [((x - case.noisy) ** 2).sum() + 2 * case.s ** 2 * dv
            for x, dv in zip(fits, divergence)]
    return thresholds[int(np.argmin(risk))], [case.error(x) for x in fits]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("meshes", nargs="+", help="clean meshes (.ply, .obj, .off)")
    ap.add_argument("--sigma", type=float, action="append", help="noise / mean edge (repeatable)")
    ap.add_argument("--seed", type=int, default=7)
    ap.add_argument("--draws", type=int, default=1, help="re-noised runs averaged (+1)")
    ap.add_argument("--tau", type=float, default=0.3, help="R above it: take the default")
    ap.add_argument("--per-face", type=int, action="append", default=[],
                    help="also R per face summed over K rings, then the fit (repeatable)")
    ap.add_argument("--family", action="store_true",
                    help="also the threshold family picked by SURE (2 probes)")
    ap.add_argument("--limn", default=os.path.join(os.path.dirname(__file__), "..", "build", "limn"))
    args = ap.parse_args()
    thresholds = [0, 2, 4, 6, 8, 12, 16, 24, 360]
    extra = "".join(f" per face {k} rings ° |" for k in args.per_face)
    extra += " family: SURE's t, its ° (ends °) |" if args.family else ""
    print(f"| mesh | sigma | R | Q | default ° | features ° | pick | better |{extra}")
    print("|---|---:|---:|---:|---:|---:|---|---|" + "---:|" * (len(args.per_face) + args.family))
    with tempfile.TemporaryDirectory() as work:
        limn = Limn(args.limn, work)
        for path in args.meshes:
            clean, faces = read_mesh(path)
            for sigma in args.sigma or [0.2, 0.3, 0.5]:
                case = Case(limn, clean, faces, sigma, args.seed)
                r, q, local = statistics(case, args.draws, args.per_face, args.tau)
                e_d, e_f = case.error(case.x_d), case.error(case.x_f)
                row = [os.path.basename(path), sigma, f"{r:.2f}", f"{q:.2f}", f"{e_d:.2f}",
                       f"{e_f:.2f}", "default" if r > args.tau else "features",
                       "default" if e_d < e_f else "features"] + [f"{e:.2f}" for e in local]
                if args.family:
                    t, errs = sure_family(case, thresholds, 2)
                    row.append(f"{t}: {errs[thresholds.index(t)]:.2f} "
                               f"({errs[0]:.2f} .. {errs[-1]:.2f})")
                print("| " + " | ".join(str(c) for c in row) + " |", flush=True)


if __name__ == "__main__":
    main()
