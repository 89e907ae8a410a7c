#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""SciPy anchors for the interpolation A P = M on limn's own operator (exported
by perf/export_operator): the seeds' iteration on a SciPy CSR matrix, conjugate
gradients on the symmetric form, and a SuperLU direct solve where it fits.
Prints one JSON line per method.

    python3 perf/scipy_anchor.py OPERATOR.bin [--tol 1e-6] [--superlu-max 200000]

CG treatment of the rows that break symmetry (DESIGN.md §1): the limit operator
is block triangular — pinned rows (corners, non-manifold, isolated) are the
identity, crease/boundary rows touch only crease and pinned vertices, smooth
rows touch anything. So: P = M on pinned rows; the crease block A_CC (weights
(1,4,1)/6 along the curves, symmetric) is solved first with the pinned values
moved to the right-hand side; then the smooth block, scaled by D^-1 so that
D^-1 A_SS is symmetric, with the crease and pinned values moved to the
right-hand side. Each stage stops when its true max residual |M - A P| (free
from CG's residual: r_true = D r) is below tol * bbox diagonal.
"""
import argparse
import json
import sys
import time

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla


def load(path):
    with open(path, "rb") as f:
        n, nnz = np.frombuffer(f.read(16), dtype="<u8")
        n, nnz = int(n), int(nnz)
        ro = np.frombuffer(f.read(4 * (n + 1)), dtype="<u4").astype(np.int64)
        col = np.frombuffer(f.read(4 * nnz), dtype="<u4").astype(np.int64)
        w = np.frombuffer(f.read(8 * nnz), dtype="<f8")
        m = np.frombuffer(f.read(24 * n), dtype="<f8").reshape(n, 3).copy()
        rule = np.frombuffer(f.read(n), dtype="u1").copy()
        scale = np.frombuffer(f.read(8 * n), dtype="<f8").copy()
    return sp.csr_matrix((w, col, ro), shape=(n, n)), m, rule, scale


def max_err(A, P, M):
    return float(np.sqrt(((M - A @ P) ** 2).sum(axis=1)).max())


def paper(A, M, tol_abs, max_iter=5000):
    P = M.copy()
    t = time.perf_counter()
    for k in range(max_iter + 1):
        R = M - A @ P
        e = float(np.sqrt((R * R).sum(axis=1)).max())
        if e <= tol_abs:
            break
        P += R
    return P, k + 1, time.perf_counter() - t


def cg_block(S, b, scale_rows, tol_abs, x0, max_iter=5000):
    """Preconditioned CG on the symmetric system (D^-1 S) x = D^-1 b with the
    preconditioner D, from x0 (M: the paper's start), columns at once. The
    preconditioned operator is D D^-1 S = S itself (spectrum of A in (0, 1]),
    and the preconditioned residual z = D r = b - S x is the true residual,
    so the stop test max_i |z_i| <= tol costs nothing."""
    Dinv = 1.0 / scale_rows[:, None]
    x = x0.copy()
    z = b - S @ x            # true residual
    products = 1
    r = Dinv * z             # residual of the symmetric system
    p = z.copy()
    rz = (r * z).sum(axis=0)
    for k in range(max_iter):
        true = np.sqrt((z ** 2).sum(axis=1)).max() if len(b) else 0.0
        if true <= tol_abs:
            break
        q = S @ p            # D (D^-1 S) p
        products += 1
        alpha = rz / np.maximum((p * (Dinv * q)).sum(axis=0), 1e-300)
        x += alpha * p
        z -= alpha * q
        r = Dinv * z
        rz_new = (r * z).sum(axis=0)
        p = z + (rz_new / np.maximum(rz, 1e-300)) * p
        rz = rz_new
    return x, products


def cg(A, M, rule, scale, tol_abs):
    t = time.perf_counter()
    n = A.shape[0]
    pinned = (rule == 0) | (rule == 3)
    crease = rule == 2
    smooth = rule == 1
    P = np.zeros_like(M)
    P[pinned] = M[pinned]
    products = 0
    # crease block, pinned moved to the right-hand side
    if crease.any():
        Acc = A[crease][:, crease]
        b = M[crease] - A[crease][:, pinned] @ P[pinned]
        x, k = cg_block(Acc, b, np.full(crease.sum(), 1.0 / 6.0), tol_abs, M[crease])
        P[crease] = x
        products += k
    if smooth.any():
        Ass = A[smooth][:, smooth]
        b = M[smooth] - A[smooth][:, ~smooth] @ P[~smooth]
        x, k = cg_block(Ass, b, scale[smooth], tol_abs, M[smooth])
        P[smooth] = x
        products += k
    return P, products, time.perf_counter() - t


def symmetry_check(A, rule, scale):
    smooth = rule == 1
    S = sp.diags(1.0 / scale[smooth]) @ A[smooth][:, smooth]
    d = abs(S - S.T)
    return float(d.max()) if d.nnz else 0.0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("operator")
    ap.add_argument("--tol", type=float, default=1e-6)
    ap.add_argument("--superlu-max", type=int, default=200000)
    ap.add_argument("--label", default="")
    a = ap.parse_args()
    A, M, rule, scale = load(a.operator)
    n = A.shape[0]
    lo, hi = M.min(axis=0), M.max(axis=0)
    diag = float(np.linalg.norm(hi - lo))
    tol_abs = a.tol * diag
    base = {"label": a.label, "vertices": n, "nonzeros": int(A.nnz)}
    # one product, for the per-product time
    t = time.perf_counter()
    for _ in range(5):
        A @ M
    per = (time.perf_counter() - t) / 5
    print(json.dumps({**base, "impl": "scipy_csr_product", "seconds_per_product": per}))
    print(json.dumps({**base, "impl": "scipy_symmetry_check",
                      "max_asymmetry_of_Dinv_A_smooth": symmetry_check(A, rule, scale)}))
    P, k, sec = paper(A, M, tol_abs)
    print(json.dumps({**base, "impl": "scipy_paper", "products": k, "seconds": sec,
                      "max_rel_error": max_err(A, P, M) / diag}))
    P, k, sec = cg(A, M, rule, scale, tol_abs)
    print(json.dumps({**base, "impl": "scipy_cg", "products": k, "seconds": sec,
                      "max_rel_error": max_err(A, P, M) / diag}))
    if n <= a.superlu_max:
        t = time.perf_counter()
        lu = spla.splu(A.tocsc())
        P = lu.solve(M)
        sec = time.perf_counter() - t
        print(json.dumps({**base, "impl": "scipy_superlu", "products": 0, "seconds": sec,
                          "max_rel_error": max_err(A, P, M) / diag,
                          "lu_nonzeros": int(lu.L.nnz + lu.U.nnz)}))
    else:
        print(json.dumps({**base, "impl": "scipy_superlu", "skipped": f"n > {a.superlu_max}"}))


if __name__ == "__main__":
    sys.exit(main())
