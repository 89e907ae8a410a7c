# SPDX-License-Identifier: MIT
"""The forms of input: mixed polygon faces (list, (offsets, indices), the
read result), float32, non-contiguous and integer V, no copy of C-contiguous
float64, faces returned in each form, and trimesh meshes in and out."""

import numpy as np
import pytest

import limn
from limn import _core
from conftest import SPOT

pytestmark = pytest.mark.filterwarnings("ignore::limn.LimnWarning")

REF = {"device": "reference"}


def spot():
    return limn.read(SPOT)  # mixed: 4 triangles, 160 quads, 16 pentagons


def test_mixed_faces_every_form_same_result():
    V, (off, idx) = spot()
    assert len(set(np.diff(off))) == 3
    as_list = [list(map(int, idx[a:b])) for a, b in zip(off[:-1], off[1:])]
    as_arrays = [idx[a:b] for a, b in zip(off[:-1], off[1:])]
    want, _ = limn.interpolate(V, (off, idx), **REF)
    ragged = np.empty(len(as_arrays), dtype=object)  # a ragged object array, as from pandas
    ragged[:] = as_arrays
    for F in (as_list, as_arrays, ragged, (off.astype(np.uint32), idx.astype(np.int32)),
              limn.read(SPOT, faces="list")[1]):
        P, _ = limn.interpolate(V, F, **REF)
        assert P.tobytes() == want.tobytes()


def test_faces_forms_returned():
    V, F = limn.read(SPOT, faces="offsets")
    listed = limn.read(SPOT, faces="list")[1]
    assert len(listed) == 180 and all(np.array_equal(listed[i], F[1][F[0][i]:F[0][i + 1]])
                                      for i in range(180))
    with pytest.raises(ValueError, match="one size"):
        limn.read(SPOT, faces="array")
    V2, F2 = limn.subdivide(V, F, 1, **REF)  # Catmull-Clark: quads after one step
    assert F2.shape == (4 * 3 + 160 * 4 + 16 * 5, 4) and F2.dtype == np.int64 and V2.shape == (188 + 180 + 366, 3)


def test_float32_input_equals_its_float64():
    V, F = spot()
    V32 = V.astype(np.float32)
    P32, _ = limn.interpolate(V32, F, **REF)
    P64, _ = limn.interpolate(V32.astype(np.float64), F, **REF)
    assert P32.dtype == np.float64 and P32.tobytes() == P64.tobytes()


def test_non_contiguous_input():
    V, F = spot()
    wide = np.zeros((V.shape[0], 7))
    wide[:, 2:5] = V
    strided = wide[:, 2:5]
    fortran = np.asfortranarray(V)
    assert not strided.flags.c_contiguous and not fortran.flags.c_contiguous
    want, _ = limn.interpolate(V, F, **REF)
    for W in (strided, fortran, V.tolist()):
        assert limn.interpolate(W, F, **REF)[0].tobytes() == want.tobytes()
    off, idx = F
    back = np.zeros(2 * idx.size, dtype=np.int64)
    back[::2] = idx
    assert limn.smooth(V, (off, back[::2]), 2, **REF)[0].tobytes() == \
        limn.smooth(V, F, 2, **REF)[0].tobytes()


def test_no_copy_of_c_contiguous_float64():
    V, _ = spot()
    assert _core.positions(V) is V
    assert _core.positions(V.astype(np.float32)) is not V


def test_uniform_array_faces_and_int_positions():
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])  # integers are accepted
    F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]], dtype=np.int32)
    V2, F2 = limn.subdivide(V, F, 2, **REF)
    assert F2.shape == (64, 3) and V2.shape == (34, 3) and V2.dtype == np.float64


def test_write_read_round_trip(tmp_path):
    V, F = spot()
    for ext in ("ply", "obj", "off"):
        path = tmp_path / ("m." + ext)
        limn.write(path, V, F)
        W, G = limn.read(path, repair=False)
        assert W.tobytes() == V.tobytes()
        assert np.array_equal(G[0], F[0]) and np.array_equal(G[1], F[1])
    rgb = (np.arange(V.shape[0] * 3) % 256).astype(np.uint8).reshape(-1, 3)
    limn.write(tmp_path / "c.ply", V, F, colors=rgb)
    assert np.array_equal(limn.read(tmp_path / "c.ply", colors=True)[2], rgb)
    rep = limn.write(tmp_path / "f.ply", V, F, precision="float")
    assert 0 < rep["max_error"] < 1e-6 * rep["bbox_diagonal"]


def test_trimesh_in_and_out():
    import trimesh  # installed by scripts/test_python.sh: a missing one fails, never skips
    box = trimesh.creation.icosphere(subdivisions=1)
    P, report = limn.interpolate(box.vertices, box.faces, **REF)
    assert report["scheme"] == "loop"
    V2, F2 = limn.subdivide(P, box.faces, 2, limit=True, **REF)
    smooth = trimesh.Trimesh(V2, F2, process=False)
    assert smooth.is_watertight and len(smooth.faces) == 16 * len(box.faces)
    # the limit surface passes through the input's vertices (to the tolerance)
    err = np.abs(V2[: len(box.vertices)] - box.vertices).max()
    assert err <= 1e-6 * np.linalg.norm(np.ptp(box.vertices, axis=0)) * 1.01


def test_version_is_the_library_and_the_package():
    import importlib.metadata
    assert limn.__version__ == importlib.metadata.version("limn")
    assert limn.__version__.count(".") == 2


def test_every_listed_device_runs_and_agrees_with_the_reference():
    V, F = spot()
    devices = limn.devices()
    assert devices[-1]["spec"] == "reference"
    want, _ = limn.interpolate(V, F, device="reference")
    for d in devices:
        if d["usable"]:
            P, rep = limn.interpolate(V, F, device=d["spec"])
            assert P.tobytes() == want.tobytes(), d["spec"]  # the backends are bit-identical
