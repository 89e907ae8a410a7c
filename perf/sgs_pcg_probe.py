#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""A probe for issue 5's open products target: conjugate gradients on the
symmetric form S = D^-1 A preconditioned by symmetric Gauss-Seidel (SSOR with
omega = 1), in the natural vertex order, counting iterations to
max |M - A P| <= 1e-6 x bbox diagonal. Closed manifold meshes only (one
smooth block). Not a solver of limn: it measures what a stronger
preconditioner would buy before anyone builds one on the device (which
needs a multicolour ordering).

    bash scripts/build.sh -DLIMN_BUILD_PERF=ON
    python3 perf/sgs_pcg_probe.py [--build build] [MESH:SCHEME ...]

Needs numpy and scipy. Each iteration applies S once and the two triangular
sweeps once (with Eisenstat's trick about one matrix pass in all).
"""
import os
import sys

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from perf_args import exported_operators, operator_args  # noqa: E402
from scipy_anchor import load  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHARED = os.environ.get("LIMN_SHARED_MESHES", os.path.join(ROOT, "..", "shared", "meshes"))
DEFAULT = ["armadillo_43k.obj:loop", "bunny_closed.off:loop", "blub_quadrangulated.obj:catmark"]


def max_norm(r):
    return float(np.sqrt((r * r).sum(axis=1)).max())


def sgs_pcg(A, M, scale, tol):
    S = (sp.diags(1 / scale) @ A).tocsr()
    S = ((S + S.T) / 2).tocsr()  # symmetric to rounding on closed manifold meshes
    b = sp.diags(1 / scale) @ M
    diag = S.diagonal()
    lower = (sp.diags(diag) + sp.tril(S, -1)).tocsr()
    upper = (sp.diags(diag) + sp.triu(S, 1)).tocsr()

    def precondition(r):
        y = spla.spsolve_triangular(lower, r, lower=True)
        return spla.spsolve_triangular(upper, diag[:, None] * y, lower=False)

    x = M.copy()
    r = b - S @ x
    z = precondition(r)
    p = z.copy()
    rz = float((r * z).sum())
    for k in range(1, 200):
        if max_norm(M - A @ x) <= tol:
            return k
        q = S @ p
        alpha = rz / float((p * q).sum())
        x += alpha * p
        r -= alpha * q
        z = precondition(r)
        rz_next = float((r * z).sum())
        p = z + (rz_next / rz) * p
        rz = rz_next
    return -1


def main():
    a, exporter = operator_args(__doc__, DEFAULT)
    print("| mesh | scheme | SGS-PCG iterations to 1e-6 |")
    print("|---|---|---:|")
    for name, scheme, out in exported_operators(a.meshes, exporter, SHARED):
        A, M, rule, scale = load(out)
        if (rule != 1).any():
            print(f"| {os.path.basename(name)} | {scheme} | (not closed manifold: skipped) |")
            continue
        tol = 1e-6 * float(np.linalg.norm(M.max(0) - M.min(0)))
        print(f"| {os.path.basename(name)} | {scheme} | {sgs_pcg(A, M, scale, tol)} |",
              flush=True)


if __name__ == "__main__":
    main()
