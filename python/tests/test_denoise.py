# SPDX-License-Identifier: MIT
"""limn.denoise: the default form (limn_denoise_sure: the SURE-fitted
polynomial of degree `products` in A, the volume kept on closed meshes) and
the paper's eq. 8 with m / steps. The default's result is checked against an
independent route: it must lie in y + span{(E - A)^i y, i = 1..N}, the
vectors rebuilt from limn.bands (the remainder after i bands is (E - A)^i y)
and fitted by numpy's least squares."""

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


def test_default_is_the_sure_polynomial_of_degree_products():
    V, F = noisy_spot()
    N = 6
    V2, rep = limn.denoise(V, F, products=N, keep_volume=False, **REF)
    assert rep["form"] == "sure" and rep["degree"] == N and rep["products"] == N
    assert rep["sigma_estimate"] > 0 and rep["keep_volume"] is False
    bands, _, _ = limn.bands(V, F, N, **REF)
    r, rest = [], V.copy()
    for b in bands:  # (E - A)^{i+1} y = (E - A)^i y - A (E - A)^i y
        rest = rest - b
        r.append(rest.ravel())
    R = np.stack(r, axis=1)
    delta = (V2 - V).ravel()
    d, *_ = np.linalg.lstsq(R, delta, rcond=None)
    assert np.linalg.norm(R @ d - delta) <= 1e-9 * np.linalg.norm(delta)
    assert np.linalg.norm(delta) > 0


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
