# SPDX-License-Identifier: MIT
"""The GIL is released around every limn call, progress callbacks take it
back, an exception in one is raised by the operation, and two threads calling
limn at once on separate meshes get the results of sequential calls."""

import threading

import numpy as np
import pytest

import limn
from limn import _core
from conftest import MESHES, SPOT

pytestmark = pytest.mark.filterwarnings("ignore::limn.LimnWarning")


def two_meshes():
    names = [m for m in MESHES if m.name in ("cow.obj", "suzanne.obj")]
    paths = names if len(names) == 2 else [SPOT, SPOT]
    return [limn.read(p) for p in paths]


def work(V, F, device, progress=None):
    P, rep = limn.interpolate(V, F, device=device, progress=progress)
    D, _ = limn.denoise(V, F, steps=6, device=device, progress=progress)
    return P, D


@pytest.mark.parametrize("device", ["reference", None], ids=["reference", "opencl"])
def test_two_threads_at_once_give_sequential_results(device):
    meshes = two_meshes()
    want = [work(V, F, device) for V, F in meshes]
    barrier = threading.Barrier(2, timeout=120)
    met = [False, False]
    events = []
    got = [None, None]
    errors = []

    def run(i):
        def progress(stage, fraction):
            events.append((i, stage, fraction))
            if not met[i]:  # both operations are in flight before either goes on
                met[i] = True
                barrier.wait()
        try:
            got[i] = work(*meshes[i], device, progress)
        except BaseException as e:  # reported below, not lost in the thread
            errors.append(e)

    threads = [threading.Thread(target=run, args=(i,)) for i in (0, 1)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors, errors
    assert met == [True, True]
    for i in (0, 1):
        assert got[i][0].tobytes() == want[i][0].tobytes()
        assert got[i][1].tobytes() == want[i][1].tobytes()
    assert {e[0] for e in events} == {0, 1}


def test_callbacks_come_without_the_gil_held():
    """Every progress callback is entered by a thread that does not hold the
    GIL: the call released it (the trampoline counts such entries)."""
    V, F = limn.read(SPOT)
    calls = []
    with _core.context("reference", None, lambda s, f: calls.append(s)) as (ctx, _):
        before = ctx.calls_without_gil()
        mesh = _core.make_mesh(ctx, V, F)
        ctx.denoise(mesh, 0, 0.0, 2, 4, False)
        after = ctx.calls_without_gil()
    assert len(calls) >= 4 and after - before == len(calls)


class Stop(Exception):
    pass


@pytest.mark.parametrize("op", ["interpolate", "denoise", "morph", "bands"])
def test_exception_in_progress_is_raised(op):
    V, F = limn.read(SPOT)
    calls = []

    def progress(stage, fraction):
        calls.append(stage)
        raise Stop("from the callback")

    run = {
        "interpolate": lambda: limn.interpolate(V, F, device="reference", progress=progress),
        "denoise": lambda: limn.denoise(V, F, steps=5, device="reference", progress=progress),
        "morph": lambda: list(limn.morph(V, V * 2, F, frames=20, device="reference",
                                         progress=progress)),
        "bands": lambda: limn.bands(V, F, 5, device="reference", progress=progress),
    }[op]
    with pytest.raises(Stop, match="from the callback"):
        run()
    assert len(calls) == 1  # never called again once it raised
    # the pooled context is clean afterwards
    P, rep = limn.interpolate(V, F, device="reference")
    assert rep["max_rel_error"] <= 1e-6


def test_progress_reports_stages():
    V, F = limn.read(SPOT)
    seen = []
    limn.interpolate(V, F, device="reference", progress=lambda s, f: seen.append((s, f)))
    stages = {s for s, _ in seen}
    assert "solve" in stages and all(0.0 <= f <= 1.0 for _, f in seen)
    assert np.isfinite([f for _, f in seen]).all()
