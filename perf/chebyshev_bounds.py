#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""How the Chebyshev iteration's lower bound a was chosen (host/solve/solve_chebyshev.c).

    bash scripts/build.sh -DLIMN_BUILD_PERF=ON      # builds build/perf/export_operator
    python3 perf/chebyshev_bounds.py [--build build] [MESH:SCHEME ...]

For each mesh (default: the shared medium meshes) it exports limn's operator A
and prints the stencil products needed to reach max |M - A P| <= 1e-6 x bbox
diagonal by: the seeds' iteration; Chebyshev on [lambda_min, 1] with the exact
lambda_min (ARPACK shift-invert); Chebyshev on the regular-lattice prior
(0.85/4 Loop, 0.85/9 Catmull-Clark) with and without one seeds' step first;
and Chebyshev with a Lanczos estimate from the first K seeds' steps (Ritz
values of the Krylov space the residuals span, D^-1 inner product), the
estimate the issue suggested. Needs numpy and scipy (pip install numpy scipy).
"""
import os
import sys

import numpy as np
import scipy.linalg as sla
import scipy.sparse.linalg as spla

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from perf_args import exported_operators, operator_args  # noqa: E402
from scipy_anchor import load  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHARED = os.environ.get("LIMN_SHARED_MESHES", os.path.join(ROOT, "..", "shared", "meshes"))
DEFAULT = ["armadillo_43k.obj:loop", "bunny_closed.off:loop", "fertility.off:loop",
           "horse.ply:loop", "bun_zipper.ply:loop", "beast.obj:catmark",
           "blub_quadrangulated.obj:catmark", "bob_quad.obj:catmark", "horse.ply:catmark"]


def max_norm(r):
    return float(np.sqrt((r * r).sum(axis=1)).max())


def paper(A, M, tol, P=None, count=0):
    P = M.copy() if P is None else P
    while True:
        R = M - A @ P
        count += 1
        if max_norm(R) <= tol or count > 5000:
            return count, P
        P = P + R


def chebyshev(A, M, tol, a, P=None, count=0):
    """Saad Alg. 12.1 on [a, 1], from P (default M); returns products."""
    theta, delta = (1 + a) / 2, (1 - a) / 2
    sigma = theta / delta
    P = M.copy() if P is None else P
    R = M - A @ P
    count += 1
    if max_norm(R) <= tol:
        return count
    rho = 1 / sigma
    D = R / theta
    while count < 5000:
        P = P + D
        R = M - A @ P
        count += 1
        if max_norm(R) <= tol:
            return count
        rho_next = 1 / (2 * sigma - rho)
        D = rho_next * rho * D + (2 * rho_next / delta) * R
        rho = rho_next
    return count


def ritz_lambda_min(A, M, K, dinv):
    """K seeds' steps; the moments <r_i, r_j>_{D^-1} = mu_{i+j} give the Ritz
    values of E - A on span{r_0..r_{K-1}}; returns 1 - the largest, and P."""
    P, rs = M.copy(), []
    for i in range(K + 1):
        R = M - A @ P
        rs.append(R)
        if i < K:
            P = P + R
    w = dinv[:, None]
    mu = np.zeros(2 * K + 1)
    for i in range(K + 1):
        mu[2 * i] = (w * rs[i] * rs[i]).sum()
        if i < K:
            mu[2 * i + 1] = (w * rs[i] * rs[i + 1]).sum()
    G = np.array([[mu[i + j] for j in range(K)] for i in range(K)])
    H = np.array([[mu[i + j + 1] for j in range(K)] for i in range(K)])
    return 1 - sla.eigh(H, G, eigvals_only=True).max(), P


def main():
    args, exporter = operator_args(__doc__, DEFAULT)
    print("| mesh | scheme | lambda_min | paper | cheb exact | cheb prior | 1 paper + cheb prior "
          "| Lanczos K=4 estimate | cheb on it (incl. 4 probes) |")
    print("|---|---|---:|---:|---:|---:|---:|---:|---:|")
    for name, scheme, out in exported_operators(args.meshes, exporter, SHARED):
        A, M, _, scale = load(out)
        tol = 1e-6 * float(np.linalg.norm(M.max(0) - M.min(0)))
        lmin = float(np.real(spla.eigs(A, k=1, sigma=0, which="LM",
                                       return_eigenvectors=False)[0]))
        prior = 0.25 * 0.85 if scheme == "loop" else 0.85 / 9
        n_paper, _ = paper(A, M, tol)
        P1 = M + (M - A @ M)  # one seeds' step
        lz, P4 = ritz_lambda_min(A, M, 4, 1 / scale)
        print(f"| {os.path.basename(name)} | {scheme} | {lmin:.3f} | {n_paper} | "
              f"{chebyshev(A, M, tol, lmin)} | {chebyshev(A, M, tol, prior)} | "
              f"{chebyshev(A, M, tol, prior, P1, 1)} | {lz:.3f} | "
              f"{chebyshev(A, M, tol, min(prior, 0.9 * lz), P4, 4)} |", flush=True)


if __name__ == "__main__":
    main()
