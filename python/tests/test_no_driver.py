# SPDX-License-Identifier: MIT
"""Without an OpenCL driver (OCL_ICD_VENDORS naming an empty folder, in a
subprocess): import works, devices() lists the reference backend only, the
default device fails with a clear limn.Error, and the CLI's fall-back rule
holds (fallback="reference" or LIMN_FALLBACK=reference run on the reference
backend with a warning, the same bits as device="reference")."""

import os
import subprocess
import sys
import textwrap

from conftest import SPOT

SCRIPT = textwrap.dedent("""
    import warnings
    import limn
    V, F = limn.read(%r)
    assert [d["spec"] for d in limn.devices()] == ["reference"], limn.devices()
    want, _ = limn.interpolate(V, F, device="reference")
    if MODE == "none":
        try:
            limn.interpolate(V, F)
            raise SystemExit("no error without a driver")
        except limn.Error as e:
            assert e.status_name == "LIMN_ERR_DEVICE", e
            assert "no OpenCL platform" in e.message, e.message
        try:
            limn.subdivide(V, F, 1, fallback="none")
            raise SystemExit("no error without a driver")
        except limn.Error as e:
            assert e.status_name == "LIMN_ERR_DEVICE", e
    kw = {"fallback": "reference"} if MODE == "argument" else {}
    if MODE != "none":
        with warnings.catch_warnings(record=True) as w:
            warnings.simplefilter("always")
            P, rep = limn.interpolate(V, F, **kw)
            S = limn.subdivide(V, F, 1, **kw)
            D = limn.denoise(V, F, **kw)
        assert rep["device"].startswith("reference"), rep["device"]
        assert P.tobytes() == want.tobytes()
        assert any("reference backend" in str(x.message) for x in w), [str(x.message) for x in w]
    print("ok", MODE)
""") % str(SPOT)


def run(tmp_path, mode, extra_env):
    empty = tmp_path / "vendors"
    empty.mkdir(exist_ok=True)
    env = {k: v for k, v in os.environ.items()
           if k not in ("LIMN_FALLBACK", "LIMN_DEVICE", "LIMN_PLATFORM", "LIMN_DEVICE_TYPE")}
    env.update(OCL_ICD_VENDORS=str(empty), **extra_env)
    r = subprocess.run([sys.executable, "-c", "MODE = %r\n" % mode + SCRIPT], env=env,
                       capture_output=True, text=True, cwd=str(tmp_path))
    assert r.returncode == 0 and ("ok " + mode) in r.stdout, r.stdout + r.stderr


def test_no_driver_fails_clearly(tmp_path):
    run(tmp_path, "none", {})


def test_no_driver_fallback_argument(tmp_path):
    run(tmp_path, "argument", {})


def test_no_driver_fallback_environment(tmp_path):
    run(tmp_path, "environment", {"LIMN_FALLBACK": "reference"})
