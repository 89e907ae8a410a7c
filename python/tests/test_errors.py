# SPDX-License-Identifier: MIT
"""Bad input raises with the message: limn.Error (the library's message and
status) for what the library refuses, ValueError for shapes, dtypes and option
values found in Python; nothing is written on failure."""

import numpy as np
import pytest

import limn
from conftest import SPOT

pytestmark = pytest.mark.filterwarnings("ignore::limn.LimnWarning")

REF = {"device": "reference"}
TETRA_V = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
TETRA_F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])


def test_index_out_of_range_is_a_limn_error():
    F = TETRA_F.copy()
    F[2, 1] = 9
    with pytest.raises(limn.Error) as e:
        limn.interpolate(TETRA_V, F, **REF)
    assert e.value.status == 1 and e.value.status_name == "LIMN_ERR_ARGUMENT"
    assert "face index 7 is 9 but there are 4 vertices" in e.value.message
    assert "LIMN_ERR_ARGUMENT" in str(e.value)


def test_negative_and_huge_indices_are_value_errors():
    F = TETRA_F.copy()
    F[1, 0] = -1
    with pytest.raises(ValueError, match="negative"):
        limn.subdivide(TETRA_V, F, 1, **REF)
    with pytest.raises(ValueError, match="beyond uint32"):
        limn.subdivide(TETRA_V, TETRA_F + 2**33, 1, **REF)
    with pytest.raises(ValueError, match="integers"):
        limn.subdivide(TETRA_V, TETRA_F.astype(float), 1, **REF)


def test_face_too_small_is_a_limn_error():
    with pytest.raises(limn.Error, match="face 1 has 2 vertices"):
        limn.smooth(TETRA_V, [[0, 1, 2], [0, 1]], 2, **REF)


def test_nan_coordinate_names_the_vertex():
    V = TETRA_V.copy()
    V[3, 1] = np.nan
    for call in (lambda: limn.interpolate(V, TETRA_F, **REF),
                 lambda: limn.denoise(V, TETRA_F, **REF)):
        with pytest.raises(limn.Error) as e:
            call()
        assert "vertex 3" in e.value.message and e.value.status == 1


@pytest.mark.parametrize("V", [np.zeros((4, 2)), np.zeros(12), np.zeros((4, 3, 1)),
                               np.array([["a", "b", "c"]] * 4), np.zeros((4, 3), complex)])
def test_wrong_positions(V):
    with pytest.raises(ValueError, match="V must"):
        limn.interpolate(V, TETRA_F, **REF)


def test_wrong_faces():
    with pytest.raises(ValueError, match="shape"):
        limn.interpolate(TETRA_V, np.zeros(12, dtype=int), **REF)
    with pytest.raises(ValueError, match="offsets"):
        limn.interpolate(TETRA_V, (np.array([0, 3, 5]), np.arange(6)), **REF)
    with pytest.raises(ValueError, match="index sequences"):
        limn.interpolate(TETRA_V, 7, **REF)


@pytest.mark.parametrize("call, match", [
    (lambda: limn.interpolate(TETRA_V, TETRA_F, scheme="bspline"), "scheme"),
    (lambda: limn.interpolate(TETRA_V, TETRA_F, alpha=1.5), "alpha"),
    (lambda: limn.interpolate(TETRA_V, TETRA_F, tol=0), "tol"),
    (lambda: limn.interpolate(TETRA_V, TETRA_F, tol=float("nan")), "tol"),
    (lambda: limn.interpolate(TETRA_V, TETRA_F, method="newton"), "method"),
    (lambda: limn.interpolate(TETRA_V, TETRA_F, precision="half"), "precision"),
    (lambda: limn.interpolate(TETRA_V, TETRA_F, method="cg", precision="float"), "cg"),
    (lambda: limn.interpolate(TETRA_V, TETRA_F, max_iter=0), "max_iter"),
    (lambda: limn.interpolate(TETRA_V, TETRA_F, max_iter=2.5), "max_iter"),
    (lambda: limn.subdivide(TETRA_V, TETRA_F, 17), "levels"),
    (lambda: limn.smooth(TETRA_V, TETRA_F, 0), "terms"),
    (lambda: limn.denoise(TETRA_V, TETRA_F, steps=0), "steps"),
    (lambda: limn.sharpen(TETRA_V, TETRA_F, -1, 2), "from_"),
    (lambda: limn.bands(TETRA_V, TETRA_F, -1), "count"),
    (lambda: limn.morph(TETRA_V, TETRA_V, TETRA_F, frames=1), "frames"),
    (lambda: limn.morph(TETRA_V, TETRA_V, TETRA_F, p=1.0), "p="),
    (lambda: limn.texture(TETRA_V, TETRA_F, 9, ["#fff"]), "levels"),
    (lambda: limn.texture(TETRA_V, TETRA_F, 1, ["#ggg"]), "colour"),
    (lambda: limn.interpolate(TETRA_V, TETRA_F, device=3), "device"),
    (lambda: limn.interpolate(TETRA_V, TETRA_F, fallback="cpu"), "fallback"),
    (lambda: limn.interpolate(TETRA_V, TETRA_F, progress=5), "progress"),
    (lambda: limn.write("/tmp/x.ply", TETRA_V, TETRA_F, format="vrml"), "format"),
])
def test_bad_option_values(call, match):
    with pytest.raises(ValueError, match=match):
        call()


def test_library_refusals_carry_status_and_message(tmp_path):
    with pytest.raises(limn.Error) as e:
        limn.read(tmp_path / "missing.obj")
    assert e.value.status_name == "LIMN_ERR_IO" and "missing.obj" in e.value.message
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n")
    with pytest.raises(limn.Error) as e:
        limn.read(bad)
    assert e.value.status_name == "LIMN_ERR_FORMAT" and "bad.obj:4" in e.value.message
    V, F = limn.read(SPOT)
    with pytest.raises(limn.Error) as e:  # V_to has one vertex more: not the same topology
        limn.morph(V, np.vstack([V, [[0.0, 0, 0]]]), F, frames=3, **REF)
    assert e.value.status_name == "LIMN_ERR_TOPOLOGY" and e.value.message
    with pytest.raises(limn.Error) as e:
        limn.interpolate(V, F, device="opencl:no-such-device-name")
    assert "no-such-device-name" in e.value.message and e.value.status_name == "LIMN_ERR_DEVICE"


def test_nothing_written_on_failure(tmp_path):
    V = TETRA_V.copy()
    V[0, 0] = np.inf
    target = tmp_path / "t.ply"
    with pytest.raises(limn.Error, match="vertex 0"):
        limn.write(target, V, TETRA_F)
    assert not target.exists() and list(tmp_path.iterdir()) == []
    with pytest.raises(limn.Error):
        limn.write(tmp_path / "no" / "dir.ply", TETRA_V, TETRA_F)


def test_no_convergence_is_a_limn_error():
    V, F = limn.read(SPOT)
    with pytest.raises(limn.Error) as e:
        limn.interpolate(V, F, method="paper", max_iter=2, **REF)
    assert e.value.status_name == "LIMN_ERR_NO_CONVERGENCE" and e.value.message
