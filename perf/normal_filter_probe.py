#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Issue 16's fandisk 0.2 miss, session 28's probes (docs/series.md, "A data
term in the normal filter, the range width per product, and one global
fit"): a re-implementation of `limn denoise --preserve-features` (bilateral
face-normal products, adaptive later rounds, Sun's sweeps with the
tangential pull) with (1) a data term, n <- normalise((1 - b) W n + b n0),
(2) the range width set before every product from the current normals, and
(3) the error of the filtered normals themselves and of one global
least-squares fit to them; and session 29's (4) the guide of Zhang et al.'s
guided normal filtering (2015): each face's guide the mean normal of the
most consistent patch containing it (vertex-ring or edge-ring patches), the
range kernel on the guides; and session 31's (5) L0 smoothing of the face
normals (Xu et al.'s image L0 gradient minimisation, 2011, on the faces'
edge graph, in the spirit of He and Schaefer's mesh L0 denoising, 2013):
min sum_f a_f |n_f - n0_f|^2 + lam sum_e l_e [n_f != n_g] by half-quadratic
splitting, then Sun's sweeps or one global fit; and session 32's (6) each
face's normal from a weighted plane fit to the vertices of its guided ring
(the bilateral weights, the range kernel on a guide: the noisy normals, BNF
products, the feature mode's result); and session 33's (7) the face operator
cut at creases: no weight between two faces of a ring unless they meet
around a shared vertex without crossing an edge marked crease (the clean
mesh's dihedrals, an oracle, or the feature mode's result's). On the meshes
`feature_bench --write` leaves:

    build/perf/feature_bench --meshes ../shared/meshes --sigma 0.2 --write /tmp/fb/0.2
    python3 perf/normal_filter_probe.py /tmp/fb/0.2 fandisk_quads [--only 7]

Prints the mean face-normal error (degrees, against the clean mesh) of each
setting. Needs numpy, scipy, plyfile.
"""
import argparse
import os
import sys

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spl
from scipy.sparse.csgraph import connected_components

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from normal_choice_oracle import (angles, by_size, face_rings, fit_to_normals,  # noqa: E402
                                  newell, read_ply)


class Mesh:
    def __init__(self, path):
        self.noisy, faces = read_ply(path)
        self.nv, self.nf = len(self.noisy), len(faces)
        self.groups = by_size(faces)
        ring = face_rings(self.groups, self.nv, self.nf).tocoo()
        self.ri, self.rj = ring.row, ring.col
        self.vi = np.concatenate([idx.ravel() for _, idx in self.groups.values()])
        self.fi = np.concatenate([np.repeat(ids, idx.shape[1]) for ids, idx in self.groups.values()])
        self.degree = np.bincount(self.vi, minlength=self.nv).astype(float)

    def faces(self, x):
        """Unit Newell normals, centroids and areas."""
        m = newell(x, self.groups, self.nf)
        length = np.linalg.norm(m, axis=1)
        c = np.zeros((self.nf, 3))
        for ids, idx in self.groups.values():
            c[ids] = x[idx].mean(1)
        return m / np.maximum(length, 1e-300)[:, None], c, 0.5 * length

    def spacing(self, c):
        d = np.sqrt(((c[self.ri] - c[self.rj]) ** 2).sum(1))
        return d[self.ri != self.rj].mean()

    def median_difference(self, n):
        d = np.sqrt(((n[self.ri] - n[self.rj]) ** 2).sum(1))
        return np.median(d[self.ri != self.rj])

    def product(self, n, c, a, sigma_r, sigma_s, guide=None, keep=None):
        """W n renormalised: the feature mode's bilateral rows (the range
        kernel on guide's normals when given; keep: 0 / 1 for each ring pair
        (ri, rj), the pairs a crease cuts set to 0)."""
        g = n if guide is None else guide
        d2 = ((c[self.ri] - c[self.rj]) ** 2).sum(1)
        r2 = ((g[self.ri] - g[self.rj]) ** 2).sum(1)
        w = a[self.rj] * np.exp(-d2 / (2 * sigma_s ** 2) - r2 / (2 * sigma_r ** 2))
        if keep is not None:
            w = w * keep
        W = sp.csr_matrix((w, (self.ri, self.rj)), shape=(self.nf, self.nf))
        return W @ n / np.asarray(W.sum(1))

    def sweeps(self, n, x, steps, tangential):
        """Sun et al.'s Jacobi sweeps plus the feature mode's tangential pull."""
        for _ in range(steps):
            _, c, a = self.faces(x)
            h = (n[self.fi] * (c[self.fi] - x[self.vi])).sum(1)
            d, m, t = np.zeros_like(x), np.zeros_like(x), np.zeros_like(x)
            np.add.at(d, self.vi, h[:, None] * n[self.fi])
            np.add.at(m, self.vi, a[self.fi][:, None] * n[self.fi])
            np.add.at(t, self.vi, c[self.fi] - x[self.vi])
            m /= np.maximum(np.linalg.norm(m, axis=1, keepdims=True), 1e-300)
            t -= (t * m).sum(1, keepdims=True) * m
            x = x + (d + tangential * t) / self.degree[:, None]
        return x


def unit(v):
    return v / np.linalg.norm(v, axis=1, keepdims=True)


def feature_mode(mesh, outer=3, products=10, sweeps=10, sigma_r=0.35, tangential=0.1,
                 beta=0.0, beta_later=None, per_product_gain=None, keep=None, later=None):
    """The feature mode's rounds; beta the data term's weight (beta_later in
    rounds 2.. when given); per_product_gain: the range width before every
    product, gain x the median difference (at most sigma_r, at least 0.05);
    keep: the ring pairs' 0 / 1 (crease_keep); later: rounds 2..'s products
    (ceil(products / 2) when None)."""
    x = mesh.noisy.copy()
    sigma_s = mesh.spacing(mesh.faces(x)[1])
    for k in range(outer):
        n, c, a = mesh.faces(x)
        start = n.copy()
        count = products if k == 0 else later or (products + 1) // 2
        width = sigma_r if k == 0 else max(1.5 * mesh.median_difference(n), 0.05)
        b = beta if k == 0 or beta_later is None else beta_later
        for _ in range(count):
            if per_product_gain:
                width = min(sigma_r, max(per_product_gain * mesh.median_difference(n), 0.05))
            m = mesh.product(n, c, a, width, sigma_s, keep=keep)
            n = unit((1 - b) * m + b * start)
        x = mesh.sweeps(n, x, sweeps, tangential)
    return x


def patch_guides(n, a, patches, pairs):
    """Each face's guide: the area-weighted mean normal of the patch with the
    least D x R among the patches around the faces of its own patch (D the
    largest normal difference in the patch, R the largest edge's share of the
    patch's summed edge differences; Zhang et al. 2015)."""
    nf = len(n)
    touching = [[] for _ in range(nf)]  # each face's edge pairs
    for i, j in pairs:
        touching[i].append((i, j))
        touching[j].append((i, j))
    score, mean = np.empty(nf), np.empty((nf, 3))
    for g, P in enumerate(patches):
        members = set(P.tolist())
        inside = {e for f in P for e in touching[f] if e[0] in members and e[1] in members}
        phi = np.array([np.linalg.norm(n[i] - n[j]) for i, j in inside] or [0.0])
        spread = np.sqrt(((n[P][:, None] - n[P][None]) ** 2).sum(2)).max()
        score[g] = spread * phi.max() / (1e-9 + phi.sum())
        mean[g] = unit((a[P][:, None] * n[P]).sum(0)[None])[0]
    return np.array([mean[P[np.argmin(score[P])]] for P in patches])


def guided_probe(mesh, clean_normals, error):
    """(4): the guides' own error, and guided products then 10 sweeps."""
    vertex_ring = ring_lists(mesh)[0]
    fi, gi, _ = edge_pairs(mesh)
    pairs = list(zip(fi.tolist(), gi.tolist()))
    edge_ring = [[f] for f in range(mesh.nf)]
    for i, j in pairs:
        edge_ring[i].append(j)
        edge_ring[j].append(i)
    n0, c, a = mesh.faces(mesh.noisy)
    sigma_s = mesh.spacing(c)
    for label, ring in (("vertex-ring", vertex_ring), ("edge-ring", edge_ring)):
        patches = [np.array(sorted(set(r))) for r in ring]
        print(f"  {label} patches: the guide's error from the clean normals "
              f"{angles(clean_normals, patch_guides(clean_normals, a, patches, pairs)).mean():.2f}, "
              f"from the noisy ones {angles(clean_normals, patch_guides(n0, a, patches, pairs)).mean():.2f}")
        for sigma_r in (0.2, 0.35):
            for products in (3, 5, 10):
                n = n0
                for _ in range(products):
                    g = patch_guides(n, a, patches, pairs)
                    n = unit(mesh.product(n, c, a, sigma_r, sigma_s, guide=g))
                print(f"    sigma_r {sigma_r}, {products} products: normals "
                      f"{angles(clean_normals, n).mean():.2f}, 10 sweeps "
                      f"{error(mesh.sweeps(n, mesh.noisy, 10, 0.1)):.2f}")


def edge_pairs(mesh):
    """The faces sharing each manifold edge (f, g) and the edge's two vertices."""
    owner = {}
    for ids, idx in mesh.groups.values():
        k = idx.shape[1]
        for c in range(k):
            for f, u, v in zip(ids, idx[:, c], idx[:, (c + 1) % k]):
                owner.setdefault((min(u, v), max(u, v)), []).append(f)
    pairs = [(fs[0], fs[1], u, v) for (u, v), fs in owner.items() if len(fs) == 2]
    a = np.array(pairs, dtype=np.int64).reshape(-1, 4)
    return a[:, 0], a[:, 1], a[:, 2:]


def l0_normals(n0, area, fi, gi, weight, lam, beta_max=1e4, kappa=2.0):
    """Half-quadratic L0 on the edge differences of the face normals: delta
    = the difference where |d|^2 beta > lam, else 0; then the normals from a
    sparse solve; beta from 2 lam doubling to beta_max."""
    nf, ne = len(n0), len(fi)
    rows = np.r_[np.arange(ne), np.arange(ne)]
    D = sp.csr_matrix((np.r_[np.ones(ne), -np.ones(ne)], (rows, np.r_[fi, gi])), shape=(ne, nf))
    W, A = sp.diags(weight), sp.diags(area)
    n, beta = n0.copy(), 2.0 * lam
    while beta < beta_max:
        d = D @ n
        delta = d * (((d ** 2).sum(1) * beta > lam)[:, None])
        M = (A + beta * (D.T @ W @ D)).tocsc()
        n = spl.splu(M).solve(A @ n0 + beta * (D.T @ (W @ delta)))
        beta *= kappa
    return unit(n)


def edge_lengths(mesh, ends):
    """The noisy mesh's length of each edge (edge_pairs' ends)."""
    return np.linalg.norm(mesh.noisy[ends[:, 0]] - mesh.noisy[ends[:, 1]], axis=1)


def l0_probe(mesh, clean_normals, error):
    fi, gi, ends = edge_pairs(mesh)
    n0, _, a = mesh.faces(mesh.noisy)
    length = edge_lengths(mesh, ends)
    for lam in (0.03, 0.1, 0.3, 0.5, 1.0, 4.0, 16.0):
        n = l0_normals(n0, a / a.mean(), fi, gi, length / length.mean(), lam)
        print(f"  lambda {lam}: normals {angles(n, clean_normals).mean():.2f}, "
              f"10 sweeps {error(mesh.sweeps(n, mesh.noisy, 10, 0.1)):.2f}, "
              f"30 sweeps {error(mesh.sweeps(n, mesh.noisy, 30, 0.1)):.2f}, "
              f"fit 0.1 {error(fit_to_normals(mesh.noisy, mesh.groups, n, 0.1)):.2f}", flush=True)


def ring_lists(mesh):
    """Each face's ring (the faces sharing a vertex with it, itself included)
    and each face's vertices."""
    order = np.argsort(mesh.ri, kind="stable")
    rj = mesh.rj[order]
    starts = np.searchsorted(mesh.ri[order], np.arange(mesh.nf + 1))
    rings = [rj[starts[f]:starts[f + 1]] for f in range(mesh.nf)]
    verts = [None] * mesh.nf
    for ids, idx in mesh.groups.values():
        for f, row in zip(ids, idx):
            verts[f] = row
    return rings, verts


def plane_normals(mesh, x, guide, rings, verts, sigma_r, sigma_s, two_rings=False, robust=0.0,
                  h=0.0):
    """Each face's normal from a weighted plane fit (least eigenvector of the
    weighted covariance) to the vertices of its ring's faces, each face j
    weighted as the bilateral filter weighs it (area, centroid distance, the
    range kernel on the guide); robust > 0: three reweightings of the points
    by exp(-r^2 / 2 (robust h)^2), r the distance to the last plane, h the
    mean edge length."""
    _, c, a = mesh.faces(x)
    out = np.empty((mesh.nf, 3))
    for f in range(mesh.nf):
        js = rings[f]
        if two_rings:
            js = np.unique(np.concatenate([rings[j] for j in js]))
        w = a[js] * np.exp(-((c[js] - c[f]) ** 2).sum(1) / (2 * sigma_s ** 2)
                           - ((guide[js] - guide[f]) ** 2).sum(1) / (2 * sigma_r ** 2))
        pts = np.concatenate([x[verts[j]] for j in js])
        pw = np.concatenate([np.full(len(verts[j]), wj / len(verts[j])) for j, wj in zip(js, w)])
        normal = guide[f]
        for it in range(1 + (3 if robust else 0)):
            q = pw
            if it:
                r = (pts - mu) @ normal
                q = pw * np.exp(-r * r / (2 * (robust * h) ** 2))
            mu = (q[:, None] * pts).sum(0) / q.sum()
            d = pts - mu
            _, vecs = np.linalg.eigh((d * q[:, None]).T @ d)
            normal = vecs[:, 0] if vecs[:, 0] @ guide[f] >= 0 else -vecs[:, 0]
        out[f] = normal
    return out


def plane_probe(mesh, clean, clean_normals, error):
    rings, verts = ring_lists(mesh)
    h = edge_lengths(mesh, edge_pairs(mesh)[2]).mean()
    n0, c0, a0 = mesh.faces(mesh.noisy)
    sigma_s = mesh.spacing(c0)
    print("  the clean normals as the guide (an oracle): plane fit on the noisy mesh, on the "
          "clean one (its bias), 10 bilateral products with that guide; then 10 sweeps of each")
    for sigma_r in (0.1, 0.2, 0.35):
        for two in (False, True):
            n = plane_normals(mesh, mesh.noisy, clean_normals, rings, verts, sigma_r, sigma_s, two)
            b = plane_normals(mesh, clean, clean_normals, rings, verts, sigma_r, sigma_s, two)
            m = n0
            for _ in range(10):
                m = unit(mesh.product(m, c0, a0, sigma_r, sigma_s, guide=clean_normals))
            print(f"    sigma_r {sigma_r} {'2' if two else '1'}-ring: "
                  f"{angles(n, clean_normals).mean():.2f}, {angles(b, clean_normals).mean():.2f}, "
                  f"{angles(m, clean_normals).mean():.2f}; sweeps "
                  f"{error(mesh.sweeps(n, mesh.noisy, 10, 0.1)):.2f}, "
                  f"{error(mesh.sweeps(m, mesh.noisy, 10, 0.1)):.2f}", flush=True)
    guides = {"noisy": n0}
    n = n0
    for _ in range(5):
        n = unit(mesh.product(n, c0, a0, 0.35, sigma_s))
    guides["bnf5"] = n
    for _ in range(5):
        n = unit(mesh.product(n, c0, a0, 0.35, sigma_s))
    guides["bnf10"] = n
    fm = feature_mode(mesh)
    guides["feature"] = mesh.faces(fm)[0]
    for name, g in guides.items():
        print(f"  guide {name}: {angles(g, clean_normals).mean():.2f}")
        for sigma_r in (0.2, 0.35):
            for two in (False, True):
                for robust in (0.0, 0.3):
                    n = plane_normals(mesh, mesh.noisy, g, rings, verts, sigma_r, sigma_s,
                                      two, robust, h)
                    m = n
                    for _ in range(2):  # rolling: the fit's normals as the next guide
                        m = plane_normals(mesh, mesh.noisy, m, rings, verts, sigma_r, sigma_s,
                                          two, robust, h)
                    print(f"    sigma_r {sigma_r} {'2' if two else '1'}-ring robust {robust}: "
                          f"normals {angles(n, clean_normals).mean():.2f}, 10 sweeps "
                          f"{error(mesh.sweeps(n, mesh.noisy, 10, 0.1)):.2f}; rolled twice "
                          f"{angles(m, clean_normals).mean():.2f}, 10 sweeps "
                          f"{error(mesh.sweeps(m, mesh.noisy, 10, 0.1)):.2f}", flush=True)


def crease_keep(mesh, fi, gi, ends, crease):
    """1 for the ring pairs (f, j) that meet around a shared vertex without
    crossing an edge marked crease (edge_pairs' order), 0 for the rest: the
    corners (v, f) of faces joined across each uncut edge at both its ends,
    and f, j kept when some vertex has both their corners in one component."""
    key = mesh.vi.astype(np.int64) * mesh.nf + mesh.fi
    order = np.argsort(key)

    def corner(v, f):
        return order[np.searchsorted(key[order], v.astype(np.int64) * mesh.nf + f)]

    uncut = ~crease
    f, g, e = fi[uncut], gi[uncut], ends[uncut]
    rows = np.r_[corner(e[:, 0], f), corner(e[:, 1], f)]
    cols = np.r_[corner(e[:, 0], g), corner(e[:, 1], g)]
    nc = len(key)
    graph = sp.csr_matrix((np.ones(len(rows)), (rows, cols)), shape=(nc, nc))
    _, label = connected_components(graph, directed=False)
    K = sp.csr_matrix((np.ones(nc), (mesh.fi, label)), shape=(mesh.nf, label.max() + 1))
    return (np.asarray((K @ K.T).tocsr()[mesh.ri, mesh.rj]).ravel() > 0).astype(float)


def dihedrals(n, fi, gi):
    """The angle in degrees between the normals of the faces across each edge."""
    return np.degrees(np.arccos(np.clip((n[fi] * n[gi]).sum(1), -1.0, 1.0)))


def cut_products(mesh, n, c, a, keep, sigma_r, sigma_s, count):
    for _ in range(count):
        n = unit(mesh.product(n, c, a, sigma_r, sigma_s, keep=keep))
    return n


def crease_probe(mesh, clean_normals, error):
    fi, gi, ends = edge_pairs(mesh)
    n0, c0, a0 = mesh.faces(mesh.noisy)
    sigma_s = mesh.spacing(c0)
    xf = feature_mode(mesh)
    nf_, cf, af = mesh.faces(xf)
    maps = {"clean": dihedrals(clean_normals, fi, gi), "feature": dihedrals(nf_, fi, gi)}
    print("  one round from the noisy normals, the operator cut at the edges whose dihedral (on "
          "the clean mesh: an oracle; on the feature mode's result) exceeds t; "
          "sigma_r/products: normals, 10 sweeps")
    for name, angle in maps.items():
        for t in (15, 20, 25, 30, 45):
            keep = crease_keep(mesh, fi, gi, ends, angle > t)
            row = []
            for sigma_r in (0.35, 0.7, 10.0):
                for count in (3, 5, 10, 20):
                    n = cut_products(mesh, n0, c0, a0, keep, sigma_r, sigma_s, count)
                    row.append(f"{sigma_r}/{count} {angles(clean_normals, n).mean():.2f} "
                               f"{error(mesh.sweeps(n, mesh.noisy, 10, 0.1)):.2f}")
            print(f"    {name} > {t} ({(angle > t).sum()} of {len(angle)} edges, "
                  f"{keep.mean():.2f} of the pairs kept): " + ", ".join(row), flush=True)
    print("  the feature mode's creases: (B) one cut round from the noisy normals (sigma_r 0.7, "
          "5 products, t 20, 25); (G) the feature mode again from the noisy mesh with the cut in "
          "every round (first-round products / sigma_r, 2 adaptive rounds of 3 or 5 products)")
    for t in (20, 25):
        keep = crease_keep(mesh, fi, gi, ends, maps["feature"] > t)
        xb = mesh.sweeps(cut_products(mesh, n0, c0, a0, keep, 0.7, sigma_s, 5), mesh.noisy, 10, 0.1)
        print(f"    (B) t {t}: {error(xb):.2f}", flush=True)
    for t, products, sigma_r, later in ((25, 5, 0.7, 3), (30, 3, 1.0, 5)):
        keep = crease_keep(mesh, fi, gi, ends, maps["feature"] > t)
        x = feature_mode(mesh, products=products, sigma_r=sigma_r, keep=keep, later=later)
        print(f"    (G) t {t}, {products} products at {sigma_r}, later rounds {later}: "
              f"{error(x):.2f}", flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("dir", help="a folder feature_bench --write filled")
    ap.add_argument("mesh", nargs="?", default="fandisk_quads")
    ap.add_argument("--only", type=int, choices=range(1, 8),
                    help="run only this section")
    args = ap.parse_args()
    mesh = Mesh(os.path.join(args.dir, f"{args.mesh}_noisy.ply"))
    clean = read_ply(os.path.join(args.dir, f"{args.mesh}_clean.ply"))[0]
    clean_normals = mesh.faces(clean)[0]

    def error(x):
        return angles(clean_normals, mesh.faces(x)[0]).mean()


    def want(section):
        return args.only in (None, section)

    print(f"noisy {error(mesh.noisy):.2f}, feature mode (re-implemented) {error(feature_mode(mesh)):.2f}")
    if want(1):
        print("(1) data term: beta, first-round products, later rounds' beta -> error")
        for beta in (0.05, 0.1, 0.2, 0.3):
            for products in (10, 20, 40):
                for later in (None, 0.0):
                    x = feature_mode(mesh, products=products, beta=beta, beta_later=later)
                    print(f"  {beta} {products} {'same' if later is None else 'none'}: {error(x):.2f}")
    if want(2):
        print("(2) range width per product: gain, products, rounds -> error")
        for gain in (1.0, 1.5, 2.0, 3.0):
            for products in (5, 10, 20):
                for outer in (1, 2, 3):
                    x = feature_mode(mesh, outer=outer, products=products, per_product_gain=gain)
                    print(f"  {gain} {products} {outer}: {error(x):.2f}")
    if want(3):
        print("(3) one round: the filtered normals, 10 sweeps, one global fit (lambda), 3 sweeps after")
        _, c, _ = mesh.faces(mesh.noisy)
        sigma_s = mesh.spacing(c)
        for products in (5, 10):
            n, c, a = mesh.faces(mesh.noisy)
            for _ in range(products):
                n = unit(mesh.product(n, c, a, 0.35, sigma_s))
            print(f"  {products} products: normals {angles(n, clean_normals).mean():.2f}, "
                  f"10 sweeps {error(mesh.sweeps(n, mesh.noisy, 10, 0.1)):.2f}")
            for lam in (0.001, 0.01, 0.03, 0.1, 0.3):
                x = fit_to_normals(mesh.noisy, mesh.groups, n, lam)
                print(f"    lambda {lam}: fit {error(x):.2f}, then 3 sweeps "
                      f"{error(mesh.sweeps(n, x, 3, 0.1)):.2f}")
    if want(4):
        print("(4) guided normal filtering's patch guides")
        guided_probe(mesh, clean_normals, error)
        for steps in (10, 30, 100):
            print(f"  clean normals, {steps} sweeps: {error(mesh.sweeps(clean_normals, mesh.noisy, steps, 0.0)):.2f}"
                  f" (pull 0.1: {error(mesh.sweeps(clean_normals, mesh.noisy, steps, 0.1)):.2f})")
    if want(5):
        print("(5) L0 smoothing of the face normals: lambda -> normals, sweeps, one global fit")
        l0_probe(mesh, clean_normals, error)
    if want(6):
        print("(6) plane fits to the vertices of each face's guided ring")
        plane_probe(mesh, clean, clean_normals, error)
    if want(7):
        print("(7) the face operator cut at creases (no pair weighted across a marked edge)")
        crease_probe(mesh, clean_normals, error)


if __name__ == "__main__":
    main()
