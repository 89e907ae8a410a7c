# SPDX-License-Identifier: MIT
"""limn's Python layer, the plumbing: errors, the context pool, option
values, and the conversion of vertex and face arrays to and from the C
library's layout (positions: n x 3 float64; faces: offsets + indices, uint32)."""

import contextlib
import math
import numbers
import os
import threading
import warnings as _warnings

import numpy as np

from . import _limn

STATUS_NAMES = {
    0: "LIMN_OK", 1: "LIMN_ERR_ARGUMENT", 2: "LIMN_ERR_IO", 3: "LIMN_ERR_FORMAT",
    4: "LIMN_ERR_TOPOLOGY", 5: "LIMN_ERR_MEMORY", 6: "LIMN_ERR_DEVICE",
    7: "LIMN_ERR_NO_CONVERGENCE", 8: "LIMN_ERR_SINGULAR",
}


class Error(Exception):
    """A failure reported by the C library: ``message`` is the library's
    message (limn_context_message: it names the file, line, vertex or face
    and the problem), ``status`` its limn_status code (an int) and
    ``status_name`` the code's name ("LIMN_ERR_TOPOLOGY")."""

    def __init__(self, message, status):
        super().__init__(message, status)
        self.message = message
        self.status = int(status)
        self.status_name = STATUS_NAMES.get(self.status, "LIMN_ERR_%d" % self.status)

    def __str__(self):
        return "%s (%s)" % (self.message, self.status_name)


class LimnWarning(UserWarning):
    """A warning of the C library (a repair made, the fall-back to the
    reference backend, colours not carried by subdivision, ...)."""


_limn.register_error(Error)

# ------------------------------------------------------------------ contexts
# A limn_context is used by one thread at a time and keeps its OpenCL device
# open (kernels compiled) between calls: each call takes an idle context of
# its (device, fallback, environment) from the pool, or makes one, and gives
# it back. Two threads never share one.

_ENV = ("LIMN_DEVICE", "LIMN_PLATFORM", "LIMN_DEVICE_TYPE", "LIMN_FALLBACK")
_pool = {}
_pool_lock = threading.Lock()
_POOL_KEEP = 8  # idle contexts kept per key


def _check_device(device):
    if device is not None and not isinstance(device, str):
        raise ValueError("device must be None or a string such as 'reference', 'opencl', "
                         "'opencl:0.0' or 'opencl:NAME', got %r" % (device,))


def _check_fallback(fallback):
    if fallback not in (None, "reference", "none"):
        raise ValueError("fallback must be None (the environment's LIMN_FALLBACK), "
                         "'reference' or 'none', got %r" % (fallback,))


@contextlib.contextmanager
def context(device=None, fallback=None, progress=None):
    """A pooled _limn.Context set to device and fallback; its warnings are
    issued as LimnWarning when the block ends."""
    _check_device(device)
    _check_fallback(fallback)
    if progress is not None and not callable(progress):
        raise ValueError("progress must be None or a callable(stage, fraction), got %r"
                         % (progress,))
    key = (device, fallback) + tuple(os.environ.get(k) for k in _ENV)
    with _pool_lock:
        idle = _pool.setdefault(key, [])
        ctx = idle.pop() if idle else None
    if ctx is None:
        ctx = _limn.Context()
        ctx.set_device(device)
        if fallback is not None:
            ctx.set_fallback(fallback)
    state = {"reusable": True}
    ctx.set_progress(progress)
    try:
        yield ctx, state
    finally:
        ctx.set_progress(None)
        for w in ctx.pop_warnings():
            for line in w.splitlines():
                _warnings.warn(line, LimnWarning, stacklevel=4)
        if state["reusable"]:
            with _pool_lock:
                if len(_pool[key]) < _POOL_KEEP:
                    _pool[key].append(ctx)


def run_with_fallback(ctx, state, fn):
    """fn(), and once more on the reference backend when it failed on the
    OpenCL device and the fall-back is allowed: the CLI's rule for
    interpolate and subdivide (limn_context_fall_back)."""
    try:
        return fn()
    except Error as e:
        if not ctx.fall_back(e.status):
            raise
    state["reusable"] = False  # now on the reference backend for good
    return fn()


# ------------------------------------------------------------------ options

SCHEMES = {"auto": 0, "loop": 1, "catmark": 2, "catmull-clark": 2}
METHODS = {"auto": 0, "paper": 1, "weighted": 2, "cg": 3, "chebyshev": 4, "sgs": 5}
PRECISIONS = {"auto": 0, "double": 1, "float": 2}


def choice(name, value, table):
    if not isinstance(value, str) or value not in table:
        raise ValueError("%s=%r is not one of %s" % (name, value, ", ".join(table)))
    return table[value]


def integer(name, value, lo, hi=2**31 - 1):
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise ValueError("%s must be an integer, got %r" % (name, value))
    value = int(value)
    if value < lo or value > hi:
        raise ValueError("%s=%d is outside %d..%d" % (name, value, lo, hi))
    return value


def number(name, value, lo=-math.inf, hi=math.inf, open_lo=False, open_hi=False):
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise ValueError("%s must be a number, got %r" % (name, value))
    value = float(value)
    bad = not math.isfinite(value) or value < lo or value > hi or \
        (open_lo and value == lo) or (open_hi and value == hi)
    if bad:
        raise ValueError("%s=%r is outside %s%g, %g%s" % (
            name, value, "(" if open_lo else "[", lo, hi, ")" if open_hi else "]"))
    return value


def alpha_value(alpha):
    return number("alpha", alpha, 0.0, 1.0)


def size_value(name, value):
    return integer(name, value, 0, 2**64 - 1)


# ------------------------------------------------------------------ arrays

def positions(V, name="V"):
    """V as a C-contiguous (n, 3) float64 array: no copy when it is one."""
    if isinstance(V, np.ndarray) and V.dtype == np.float64 and V.flags.c_contiguous \
            and V.ndim == 2 and V.shape[1] == 3:
        return V
    a = np.asarray(V)
    if a.dtype.kind not in "fiu" or a.dtype.itemsize > 8:
        raise ValueError("%s must hold real numbers (float32 or float64), got dtype %s"
                         % (name, a.dtype))
    if a.ndim != 2 or a.shape[1] != 3:
        raise ValueError("%s must have shape (n, 3), got %s" % (name, a.shape))
    return np.ascontiguousarray(a, dtype=np.float64)


def _index_array(a, name):
    a = np.asarray(a)
    if a.size == 0:
        return np.zeros(a.shape, dtype=np.uint32)
    if a.dtype.kind not in "iu":
        raise ValueError("%s must hold integers, got dtype %s" % (name, a.dtype))
    if a.dtype.kind == "i" and a.min() < 0:
        where = np.unravel_index(int(np.argmin(a)), a.shape)
        raise ValueError("%s: index %d at %s is negative" % (name, int(a.min()), where))
    if a.max() > 2**32 - 1:
        raise ValueError("%s: index %d is beyond uint32" % (name, int(a.max())))
    return np.ascontiguousarray(a, dtype=np.uint32)


def faces(F, name="F"):
    """F as (offsets, indices), uint32, from an (m, k) integer array, a list
    of index sequences (mixed polygons) or a tuple (offsets, indices) of two
    1-D arrays."""
    if isinstance(F, tuple) and len(F) == 2 and all(isinstance(x, np.ndarray) and x.ndim == 1
                                                    for x in F):
        off, idx = _index_array(F[0], name + " offsets"), _index_array(F[1], name + " indices")
        if off.size == 0 or off[0] != 0 or off[-1] != idx.size or np.any(np.diff(off.astype(np.int64)) < 0):
            raise ValueError("%s: offsets must start at 0, never decrease and end at the "
                             "number of indices (%d)" % (name, idx.size))
        return off, idx
    if isinstance(F, np.ndarray) and not (F.dtype == object and F.ndim == 1):
        if F.ndim != 2:
            raise ValueError("%s must have shape (m, k), be a list of index sequences or a "
                             "tuple (offsets, indices); got an array of shape %s"
                             % (name, F.shape))
        idx = _index_array(F, name).reshape(-1)
        m, k = F.shape
        return np.arange(0, m * k + 1, k, dtype=np.uint32) if k else \
            np.zeros(m + 1, dtype=np.uint32), idx
    try:
        rows = [np.asarray(f).reshape(-1) for f in F]
    except TypeError:
        raise ValueError("%s must be an (m, k) integer array, a list of index sequences or a "
                         "tuple (offsets, indices), got %r" % (name, type(F).__name__)) from None
    sizes = np.array([r.size for r in rows], dtype=np.int64)
    off = np.zeros(len(rows) + 1, dtype=np.int64)
    np.cumsum(sizes, out=off[1:])
    if off[-1] > 2**32 - 1:
        raise ValueError("%s: more than 2^32 - 1 indices" % name)
    idx = _index_array(np.concatenate(rows) if rows else np.zeros(0, np.int64), name)
    return off.astype(np.uint32), idx


def faces_out(off, idx, form):
    """Faces as the caller gets them: form "auto" an (m, k) int64 array when
    every face has k corners, else (offsets, indices); "array", "offsets",
    "list"."""
    if form not in ("auto", "array", "offsets", "list"):
        raise ValueError("faces=%r is not one of auto, array, offsets, list" % (form,))
    off = off.astype(np.int64)
    idx = idx.astype(np.int64)
    sizes = np.diff(off)
    uniform = sizes.size > 0 and bool(np.all(sizes == sizes[0]))
    if form == "list":
        return [idx[a:b] for a, b in zip(off[:-1], off[1:])]
    if form == "offsets" or (form == "auto" and not uniform):
        return off, idx
    if not uniform:
        raise ValueError("faces='array' needs faces of one size; these have %d to %d corners"
                         % (sizes.min(), sizes.max()))
    return idx.reshape(sizes.size, int(sizes[0]))


def make_mesh(ctx, V, F, name="V"):
    P = positions(V, name)
    off, idx = faces(F)
    return ctx.mesh_create(P, P.shape[0], off, off.size - 1, idx, idx.size)


def mesh_arrays(ctx, mesh, colors=False):
    """(P (n, 3) float64, offsets, indices[, rgb (n, 3) uint8]) of a C mesh."""
    n, m, k, has_colors = mesh.counts()
    P = np.empty((n, 3), dtype=np.float64)
    off = np.empty(m + 1, dtype=np.uint32)
    idx = np.empty(k, dtype=np.uint32)
    rgb = np.empty((n, 3), dtype=np.uint8) if colors and has_colors else None
    ctx.copy_out(mesh, P, off, idx, rgb)
    return P, off, idx, rgb


def colors_array(colors, n, name="colors"):
    c = np.asarray(colors)
    if c.dtype.kind not in "iu" or c.ndim != 2 or c.shape != (n, 3):
        raise ValueError("%s must be an (n, 3) integer array of RGB bytes with n = %d, got "
                         "dtype %s shape %s" % (name, n, c.dtype, c.shape))
    if c.size and (c.min() < 0 or c.max() > 255):
        raise ValueError("%s: values must be within 0..255" % name)
    return np.ascontiguousarray(c, dtype=np.uint8)


def palette(colors):
    """Texture colours: '#rrggbb' / '#rgb' strings or (k, 3) RGB bytes."""
    if isinstance(colors, str):
        colors = [s for s in colors.split(",") if s.strip()]
    items = list(colors)
    if items and all(isinstance(s, str) for s in items):
        rgb = []
        for s in items:
            h = s.strip().lstrip("#")
            if len(h) == 3:
                h = "".join(ch * 2 for ch in h)
            try:
                if len(h) != 6:
                    raise ValueError
                rgb.append([int(h[i:i + 2], 16) for i in (0, 2, 4)])
            except ValueError:
                raise ValueError("colour %r is not like #1a2b3c or #abc" % s) from None
        items = rgb
    c = np.asarray(items)
    if c.ndim != 2 or c.shape[1] != 3 or c.shape[0] < 1 or c.dtype.kind not in "iu":
        raise ValueError("colors must be '#hex' strings or a (k, 3) integer array, k >= 1")
    if c.min() < 0 or c.max() > 255:
        raise ValueError("colors: values must be within 0..255")
    return np.ascontiguousarray(c, dtype=np.uint8).tobytes()
