# SPDX-License-Identifier: MIT
"""No leak over 1,000 calls: Python memory (tracemalloc) and the process's
resident memory (which sees the C library's allocations) stay flat over
1,000 successful calls, 1,000 refused ones and 1,000 with a raising
progress callback."""

import gc
import os
import tracemalloc

import numpy as np
import pytest

import limn
from conftest import SPOT

pytestmark = pytest.mark.filterwarnings("ignore::limn.LimnWarning")



def rss_bytes():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def growth(call, n=1000, warm=200):
    """(Python bytes, resident bytes) gained over n calls after warm ones,
    the smaller of two windows of n: a leak grows both by n times its size,
    while a table the interpreter or the allocator resizes once (seen: one
    block of ~400 KB, once) lands in one. Cyclic garbage is collected first:
    it is not a leak."""
    tracemalloc.start()
    try:
        for _ in range(warm):
            call()
        seen = []
        for _ in range(2):
            gc.collect()
            base_py, base_rss = tracemalloc.get_traced_memory()[0], rss_bytes()
            for _ in range(n):
                call()
            gc.collect()
            seen.append((tracemalloc.get_traced_memory()[0] - base_py, rss_bytes() - base_rss))
        return min(s[0] for s in seen), min(s[1] for s in seen)
    finally:
        tracemalloc.stop()


def test_no_leak_over_1000_calls():
    V, F = limn.read(SPOT)  # one mesh: ~10 KB of C memory a call, 10 MB if kept
    bad = V.copy()
    bad[5, 2] = np.nan

    def ok():
        P, rep = limn.interpolate(V, F, device="reference")
        V2, F2 = limn.subdivide(P, F, 1, device="reference")
        assert rep["vertices"] == 188 and V2.shape[0] == 734

    def refused():
        with pytest.raises(limn.Error):
            limn.smooth(bad, F, 2, device="reference")

    def raising():
        def progress(stage, fraction):
            raise KeyError(stage)
        with pytest.raises(KeyError):
            limn.denoise(V, F, device="reference", progress=progress)

    for call in (ok, refused, raising):
        py, rss = growth(call)
        assert py < 256 * 1024, (call.__name__, py)
        assert rss < 4 * 1024 * 1024, (call.__name__, rss)
