# SPDX-License-Identifier: MIT
"""Every operation gives the CLI's bits on every shared small mesh: the CLI
writes binary PLY (doubles, lossless), read back with limn.read(repair=False),
compared with the arrays of the Python call on limn.read(path)'s arrays
(with the CLI's repair). The reference backend on every mesh; the default
OpenCL device (PoCL) on two."""

import json

import numpy as np
import pytest

import limn
from conftest import MESHES, SPOT

SMALL = [m for m in MESHES]
IDS = [m.name for m in SMALL]
OPENCL = [m for m in SMALL if m.name in ("spot_control_mesh.obj", "bun_zipper_res4.ply")]


def same_bits(a, b):
    a, b = np.ascontiguousarray(a), np.ascontiguousarray(b)
    return a.shape == b.shape and a.dtype == b.dtype and a.tobytes() == b.tobytes()


def read_back(path):
    V, F = limn.read(path, repair=False, faces="offsets")
    return V, F


def faces_equal(F_py, F_cli):
    off, idx = F_cli
    if isinstance(F_py, tuple):
        return np.array_equal(F_py[0], off) and np.array_equal(F_py[1], idx)
    return np.array_equal(F_py.reshape(-1), idx) and np.all(np.diff(off) == F_py.shape[1])


def cli_or_error(cli, args, call):
    """Runs both; when the CLI refuses, the Python call raises limn.Error
    with the CLI's message."""
    r = cli(*args, check=False)
    if r.returncode == 0:
        return call(), True
    with pytest.raises(limn.Error) as e:
        call()
    assert e.value.message in r.stderr, (e.value.message, r.stderr)
    REFUSED.append((args[0], str(args[1]), e.value.status_name))
    return None, False


REFUSED = []  # (operation, mesh, status) the CLI and Python both refused


def device_args(device):
    return ["--device", device] if device else []


def run_interpolate(cli, tmp_path, mesh, device):
    V, F = limn.read(mesh)
    out = tmp_path / "p.ply"
    res, ok = cli_or_error(cli, ["interpolate", mesh, "-o", out, *device_args(device)],
                           lambda: limn.interpolate(V, F, device=device))
    if ok:
        P, report = res
        assert same_bits(P, read_back(out)[0])
        assert report["iterations"] >= 0 and report["max_rel_error"] <= 1e-6
        # limn.write makes the CLI's very file
        mine = tmp_path / "mine.ply"
        limn.write(mine, P, F)
        assert mine.read_bytes() == out.read_bytes()


@pytest.mark.parametrize("mesh", SMALL, ids=IDS)
def test_interpolate(cli, tmp_path, mesh):
    run_interpolate(cli, tmp_path, mesh, "reference")


@pytest.mark.parametrize("mesh", OPENCL, ids=[m.name for m in OPENCL])
def test_interpolate_opencl(cli, tmp_path, mesh):
    run_interpolate(cli, tmp_path, mesh, None)


def run_subdivide(cli, tmp_path, mesh, device, limit):
    V, F = limn.read(mesh)
    out = tmp_path / "s.ply"
    extra = ["--limit"] if limit else []
    res, ok = cli_or_error(cli, ["subdivide", mesh, "-o", out, "--levels", 2, *extra,
                                 *device_args(device)],
                           lambda: limn.subdivide(V, F, 2, limit=limit, device=device))
    if ok:
        V2, F2 = res
        W, G = read_back(out)
        assert same_bits(V2, W) and faces_equal(F2, G)


@pytest.mark.parametrize("mesh", SMALL, ids=IDS)
def test_subdivide(cli, tmp_path, mesh):
    run_subdivide(cli, tmp_path, mesh, "reference", limit=mesh.name.startswith("s"))


@pytest.mark.parametrize("mesh", OPENCL, ids=[m.name for m in OPENCL])
def test_subdivide_opencl(cli, tmp_path, mesh):
    run_subdivide(cli, tmp_path, mesh, None, limit=True)


SERIES = {
    "smooth": (["--terms", 3], lambda V, F, d: limn.smooth(V, F, 3, device=d)),
    "denoise": ([], lambda V, F, d: limn.denoise(V, F, device=d)),
    "denoise-products": (["--products", 5, "--no-keep-volume"],
                         lambda V, F, d: limn.denoise(V, F, products=5, keep_volume=False,
                                                      device=d)),
    "denoise-paper": (["--m", 1, "--steps", 4],
                      lambda V, F, d: limn.denoise(V, F, m=1, steps=4, device=d)),
    "sharpen": (["--from", 1, "--to", 3], lambda V, F, d: limn.sharpen(V, F, 1, 3, device=d)),
}


def run_series(cli, tmp_path, mesh, op, device):
    V, F = limn.read(mesh)
    args, call = SERIES[op]
    out, rep = tmp_path / "o.ply", tmp_path / "o.json"
    res, ok = cli_or_error(cli, [op.split("-")[0], mesh, "-o", out, "--report", rep, *args,
                                 *device_args(device)], lambda: call(V, F, device))
    if ok:
        V2, report = res
        assert same_bits(V2, read_back(out)[0])
        cli_report = json.loads(rep.read_text())
        for key in ("scheme", "products", "stencil_nonzeros", "bbox_diagonal", "vertices",
                    "mean_rel_displacement"):
            assert report[key] == cli_report[key], key
        for key in ("form", "sigma_estimate", "keep_volume", "volume_output"):  # denoise
            if key in cli_report and not (key == "volume_output" and not cli_report["closed"]):
                assert report[key] == cli_report[key], key


@pytest.mark.parametrize("op", sorted(SERIES))
@pytest.mark.parametrize("mesh", SMALL, ids=IDS)
def test_series(cli, tmp_path, mesh, op):
    run_series(cli, tmp_path, mesh, op, "reference")


@pytest.mark.parametrize("op", sorted(SERIES))
@pytest.mark.parametrize("mesh", OPENCL, ids=[m.name for m in OPENCL])
def test_series_opencl(cli, tmp_path, mesh, op):
    run_series(cli, tmp_path, mesh, op, None)


@pytest.mark.parametrize("mesh", SMALL, ids=IDS)
def test_bands(cli, tmp_path, mesh):
    V, F = limn.read(mesh)
    prefix = tmp_path / "b"
    res, ok = cli_or_error(cli, ["bands", mesh, "--count", 3, "-o", prefix, "--device",
                                 "reference"], lambda: limn.bands(V, F, 3, device="reference"))
    if ok:
        bands, remainder, energy = res
        for i, band in enumerate(bands):
            assert same_bits(band, read_back(str(prefix) + "_band%d.ply" % i)[0])
        assert same_bits(remainder, read_back(str(prefix) + "_remainder.ply")[0])
        e = json.loads((tmp_path / "b_energy.json").read_text())
        assert list(energy) == e["bands"] + [e["remainder"]]


@pytest.mark.parametrize("mesh", SMALL, ids=IDS)
def test_morph(cli, tmp_path, mesh):
    V, F = limn.read(mesh)
    target = tmp_path / "to.ply"
    V_to = V * 1.25 + 0.1
    limn.write(target, V_to, F)
    pattern = tmp_path / "f%02d.ply"
    res, ok = cli_or_error(cli, ["morph", mesh, target, "-o", pattern, "--frames", 4,
                                 "--device", "reference"],
                           lambda: list(limn.morph(V, V_to, F, frames=4, device="reference")))
    if ok:
        assert [f.index for f in res] == [0, 1, 2, 3]
        for f in res:
            assert same_bits(f.V, read_back(str(pattern) % f.index)[0])
        assert same_bits(res[0].V, V)


@pytest.mark.parametrize("mesh", SMALL, ids=IDS)
def test_texture(cli, tmp_path, mesh):
    V, F = limn.read(mesh)
    out = tmp_path / "t.ply"
    res, ok = cli_or_error(cli, ["texture", mesh, "-o", out, "--levels", 1, "--colors",
                                 "#ff0000,#00ff00,#0000ff", "--seed", 7, "--device", "reference"],
                           lambda: limn.texture(V, F, 1, ["#ff0000", "#00ff00", "#0000ff"], 7,
                                                device="reference"))
    if ok:
        V2, F2, rgb = res
        W, G, c = limn.read(out, repair=False, faces="offsets", colors=True)
        assert same_bits(V2, W) and faces_equal(F2, G) and same_bits(rgb, c)


def test_most_cases_ran():
    """The comparisons above mostly compared results, not refusals (alpha 0
    is singular on some meshes: both refuse with one message)."""
    print("refused by both:", REFUSED)
    assert len(REFUSED) <= len(SMALL) * 2
