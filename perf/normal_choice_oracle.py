#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Issue 16's road not built: a choice per face between the normals of limn
denoise's default result and of `--preserve-features`, then one global
least-squares fit of the positions to the chosen normals. Measures the two
*oracle* choices (docs/series.md, "A choice per face of normals, then one
global least-squares fit") on the meshes `feature_bench --write DIR` leaves:

    build/perf/feature_bench --meshes ../shared/meshes --sigma 0.2 --write /tmp/fb/0.2
    python3 perf/normal_choice_oracle.py /tmp/fb/0.2

For each mesh: the mean face-normal error (degrees, against the clean mesh)
of the default, of the feature mode, and of the fit with (a) per face the
normal nearer the clean one, (b) per face the result nearer the clean mesh
in squared distance summed over `--rings` rings of faces. The fit solves
min sum_f sum_{v in f} (n_f . (x_v - c_f))^2 + lam |x - x_default|^2 (c_f
the face's centroid, linear in x) by a sparse direct solve. A selector that
needs no clean mesh and comes near (b) would meet issue 16's organic clause
(the oracles are what is known, not a method). Needs numpy, scipy, plyfile.
"""
import argparse
import glob
import os

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from plyfile import PlyData


def read_ply(path):
    data = PlyData.read(path)
    v = data["vertex"]
    positions = np.stack([v["x"], v["y"], v["z"]], 1).astype(float)
    faces = [np.asarray(f, dtype=np.int64) for f in data["face"].data["vertex_indices"]]
    return positions, faces


def by_size(faces):
    """{k: (face numbers, k-column index array)} for each face size k."""
    groups = {}
    for i, f in enumerate(faces):
        groups.setdefault(len(f), []).append(i)
    return {k: (np.array(ids), np.array([faces[i] for i in ids])) for k, ids in groups.items()}


def newell(positions, groups, nfaces):
    """Newell vectors: twice each face's vector area."""
    normals = np.zeros((nfaces, 3))
    for ids, idx in groups.values():
        p = positions[idx]
        q = np.roll(p, -1, axis=1)
        normals[ids] = np.stack([((p[..., 1] - q[..., 1]) * (p[..., 2] + q[..., 2])).sum(1),
                                 ((p[..., 2] - q[..., 2]) * (p[..., 0] + q[..., 0])).sum(1),
                                 ((p[..., 0] - q[..., 0]) * (p[..., 1] + q[..., 1])).sum(1)], 1)
    return normals


def face_normals(positions, groups, nfaces):
    """Unit Newell normals."""
    normals = newell(positions, groups, nfaces)
    return normals / np.linalg.norm(normals, axis=1, keepdims=True)


def angles(a, b):
    return np.degrees(np.arccos(np.clip((a * b).sum(1), -1.0, 1.0)))


def face_rings(groups, nvertices, nfaces):
    """The 0/1 matrix of faces sharing a vertex (each face with itself)."""
    rows, cols = [], []
    for ids, idx in groups.values():
        rows.append(idx.ravel())
        cols.append(np.repeat(ids, idx.shape[1]))
    incidence = sp.csr_matrix((np.ones(sum(len(r) for r in rows)),
                               (np.concatenate(rows), np.concatenate(cols))),
                              shape=(nvertices, nfaces))
    rings = (incidence.T @ incidence).tocsr()
    rings.data[:] = 1.0
    return rings


def fit_to_normals(base, groups, normals, lam):
    """argmin_x sum_f sum_{v in f} (n_f . (x_v - c_f))^2 + lam |x - base|^2."""
    n = len(base)
    rows, cols, vals, r0 = [], [], [], 0
    for ids, idx in groups.values():
        m, k = idx.shape
        w = np.eye(k)[None, :, :] - 1.0 / k                     # (1, k slot a, k slot b)
        nrm = normals[ids]                                       # (m, 3)
        val = w[:, :, :, None] * nrm[:, None, None, :]           # (m, a, b, 3)
        row = r0 + np.arange(m)[:, None] * k + np.arange(k)[None, :]
        row = np.broadcast_to(row[:, :, None, None], val.shape)
        col = 3 * idx[:, None, :, None] + np.arange(3)[None, None, None, :]
        col = np.broadcast_to(col, val.shape)
        rows.append(row.ravel())
        cols.append(col.ravel())
        vals.append(val.ravel())
        r0 += m * k
    mat = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                        shape=(r0, 3 * n))
    system = (mat.T @ mat + lam * sp.identity(3 * n)).tocsc()
    return spla.spsolve(system, lam * base.ravel()).reshape(n, 3)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("dir", help="a directory feature_bench --write filled")
    ap.add_argument("--lam", type=float, default=0.1, help="the fit's pull to the default")
    ap.add_argument("--rings", type=int, default=2, help="rings the distance oracle sums")
    args = ap.parse_args()
    print("| mesh | default ° | features ° | normal oracle ° | distance oracle ° |")
    print("|---|---:|---:|---:|---:|")
    for clean_path in sorted(glob.glob(os.path.join(args.dir, "*_clean.ply"))):
        name = os.path.basename(clean_path)[:-len("_clean.ply")]
        clean, faces = read_ply(clean_path)
        default, _ = read_ply(os.path.join(args.dir, name + "_default.ply"))
        feature, _ = read_ply(os.path.join(args.dir, name + "_features.ply"))
        groups = by_size(faces)
        nf = len(faces)
        n_clean = face_normals(clean, groups, nf)
        n_def = face_normals(default, groups, nf)
        n_feat = face_normals(feature, groups, nf)
        e_def, e_feat = angles(n_def, n_clean), angles(n_feat, n_clean)
        by_normal = np.where((e_feat < e_def)[:, None], n_feat, n_def)
        sq_feat = ((feature - clean) ** 2).sum(1)
        sq_def = ((default - clean) ** 2).sum(1)
        score = np.zeros(nf)
        for ids, idx in groups.values():
            score[ids] = (sq_feat[idx] - sq_def[idx]).sum(1)
        rings = face_rings(groups, len(clean), nf)
        for _ in range(args.rings):
            score = rings @ score
        by_distance = np.where((score < 0)[:, None], n_feat, n_def)
        errors = [e_def.mean(), e_feat.mean()]
        for chosen in (by_normal, by_distance):
            fitted = fit_to_normals(default, groups, chosen, args.lam)
            errors.append(angles(face_normals(fitted, groups, nf), n_clean).mean())
        print(f"| {name} | " + " | ".join(f"{e:.2f}" for e in errors) + " |", flush=True)


if __name__ == "__main__":
    main()
