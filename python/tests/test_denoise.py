# SPDX-License-Identifier: MIT
"""limn.denoise: the default form (limn_denoise_sure: SURE-fitted
polynomials of degree `products` in A for the parts along and across the
vertex normals of A^k y, the volume kept on closed meshes) and the paper's
eq. 8 with m / steps. The default's result is checked against an
independent route: the vectors (E - A)^i y, i = 1..N, rebuilt from
limn.bands (the remainder after i bands is (E - A)^i y), the frame's normals
computed here from A^k y, k = min(N, 12); the result's displacement along
the normals must lie in the span of the vectors' normal parts and its
displacement across them in the span of their tangential parts (numpy's
least squares), and the whole displacement not in the vectors' span (not
one polynomial)."""

import math

import numpy as np
import pytest

import limn
from conftest import SPOT

REF = {"device": "reference"}


def noisy_spot(scale=0.01, seed=16):
    """spot (188 vertices, tri, quad and pentagon faces: F in limn's mixed form)
    with seeded Gaussian noise of scale x its bbox diagonal."""
    V, F = limn.read(SPOT)
    diag = float(np.linalg.norm(V.max(axis=0) - V.min(axis=0)))
    rng = np.random.default_rng(seed)
    return V + rng.normal(0.0, scale * diag, V.shape), F


def vertex_normals(X, F):
    """Unit vertex normals: each vertex's faces' Newell normals summed."""
    off, idx = F if isinstance(F, tuple) else (np.arange(0, F.size + 1, F.shape[1]), F.ravel())
    N = np.zeros_like(X)
    for f in range(len(off) - 1):
        c = idx[off[f]:off[f + 1]]
        p, q = X[c], X[np.roll(c, -1)]
        n = np.array([np.sum((p[:, 1] - q[:, 1]) * (p[:, 2] + q[:, 2])),
                      np.sum((p[:, 2] - q[:, 2]) * (p[:, 0] + q[:, 0])),
                      np.sum((p[:, 0] - q[:, 0]) * (p[:, 1] + q[:, 1]))])
        N[c] += n
    return N / np.linalg.norm(N, axis=1, keepdims=True)


def test_default_is_the_split_sure_polynomials_of_degree_products():
    V, F = noisy_spot()
    N = 6
    V2, rep = limn.denoise(V, F, products=N, keep_volume=False, **REF)
    assert rep["form"] == "sure" and rep["degree"] == N and rep["products"] == N
    assert rep["sigma_estimate"] > 0 and rep["keep_volume"] is False
    bands, _, _ = limn.bands(V, F, N, **REF)
    r, rest = [], V.copy()
    for b in bands:  # (E - A)^{i+1} y = (E - A)^i y - A (E - A)^i y
        rest = rest - b
        r.append(rest)
    k = min(N, 12)  # A^k y = (E - B)^k y = y + sum_j (-1)^j C(k, j) B^j y
    X = V + sum((-1) ** (j + 1) * math.comb(k, j + 1) * r[j] for j in range(k))
    n = vertex_normals(X, F)
    S = np.stack([np.sum(ri * n, axis=1) for ri in r], axis=1)  # normal parts
    T = np.stack([(ri - np.sum(ri * n, axis=1, keepdims=True) * n).ravel() for ri in r],
                 axis=1)  # tangential parts
    delta = V2 - V
    along = np.sum(delta * n, axis=1)
    across = (delta - along[:, None] * n).ravel()
    for basis, part in ((S, along), (T, across)):
        d, *_ = np.linalg.lstsq(basis, part, rcond=None)
        assert np.linalg.norm(basis @ d - part) <= 1e-8 * np.linalg.norm(part)
        assert np.linalg.norm(part) > 0
    # and not one polynomial: the whole displacement is not in y + span{B^i y}
    R = np.stack([ri.ravel() for ri in r], axis=1)
    d, *_ = np.linalg.lstsq(R, delta.ravel(), rcond=None)
    assert np.linalg.norm(R @ d - delta.ravel()) >= 1e-3 * np.linalg.norm(delta)


def test_default_keeps_a_closed_mesh_volume():
    V, F = noisy_spot()
    V2, rep = limn.denoise(V, F, **REF)
    assert rep["closed"] and rep["keep_volume"] is True and rep["degree"] == 12
    assert abs(rep["volume_change"]) < 1e-12
    V3, rep3 = limn.denoise(V, F, keep_volume=False, **REF)
    assert rep3["keep_volume"] is False and abs(rep3["volume_change"]) > 1e-6
    assert not np.array_equal(V2, V3)


def test_default_moves_with_a_translation():
    V, F = noisy_spot()
    t = np.array([3.0, -2.0, 0.5])
    a, _ = limn.denoise(V, F, products=8, **REF)
    b, _ = limn.denoise(V + t, F, products=8, **REF)
    assert np.max(np.abs((b - t) - a)) <= 1e-9 * np.max(np.abs(V))


def test_paper_form_still_reachable():
    V, F = noisy_spot()
    a, ra = limn.denoise(V, F, m=2, steps=3, **REF)
    b, rb = limn.denoise(V, F, 2, 3, **REF)  # positional, as before the default changed
    c, rc = limn.denoise(V, F, steps=3, **REF)  # m's default 2
    assert ra["form"] == "paper" and ra["m"] == 2 and ra["steps"] == 3
    assert ra["products"] == 9 and ra["keep_volume"] is False
    assert np.array_equal(a, b) and np.array_equal(a, c)
    d, _ = limn.denoise(V, F, **REF)
    assert not np.array_equal(a, d)


def test_bad_choices_are_value_errors():
    V, F = noisy_spot()
    with pytest.raises(ValueError, match="one or the other"):
        limn.denoise(V, F, products=4, m=2, **REF)
    for bad in (0, 65, 2.5):
        with pytest.raises(ValueError, match="products"):
            limn.denoise(V, F, products=bad, **REF)


def test_keep_volume_on_an_open_mesh_is_a_limn_error():
    V = np.array([[0.0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0.5, 0.5, 0.2]])
    F = np.array([[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]])
    _, rep = limn.denoise(V, F, **REF)  # open: not kept by default
    assert rep["keep_volume"] is False and not rep["closed"]
    with pytest.raises(limn.Error, match="closed mesh"):
        limn.denoise(V, F, keep_volume=True, **REF)
