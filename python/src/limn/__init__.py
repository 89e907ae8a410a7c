# SPDX-License-Identifier: MIT
"""limn: interpolating subdivision surfaces and mesh series, numpy in and out.

Every operation takes ``V``, an (n, 3) array of float32 or float64 (no copy
when already C-contiguous float64), and ``F``, the faces: an (m, k) integer
array for one polygon size, a list of index sequences for mixed polygons, or
a tuple ``(offsets, indices)`` of two 1-D integer arrays. Results are new
numpy arrays (faces as ``limn.read`` returns them: an (m, k) int64 array when
all faces have k corners, else ``(offsets, indices)``).

Every operation also takes ``device`` (None: LIMN_DEVICE etc., then the first
OpenCL device; "reference", "opencl", "opencl:P.D", "opencl:NAME"),
``fallback`` (None: the environment's LIMN_FALLBACK; "reference": run on the
C reference backend when the OpenCL device cannot be used, with a
LimnWarning; "none") and ``progress`` (None or a callable(stage, fraction)).
The GIL is released while the C library computes; a progress callback takes
it back, and an exception it raises is raised by the operation (the C API has
no cancellation: the call runs to its end without further callbacks, except
morph, which stops at the next frame). Failures of the library raise
``limn.Error`` (message and status); bad shapes, dtypes and option values
found before the call raise ValueError. docs/python.md has the tour.
"""

import collections
import os

import numpy as np

from . import _core, _limn
from ._core import Error, LimnWarning

__all__ = ["Error", "LimnWarning", "MorphFrame", "read", "write", "interpolate", "subdivide",
           "smooth", "denoise", "sharpen", "bands", "morph", "texture", "devices",
           "__version__"]

__version__ = _limn.version()

_FORMATS = ("obj", "ply", "ply-ascii", "ply-be", "off", "stl")


def _format(fmt):
    if fmt is None:
        return 0
    code = _limn.format_from_name(fmt) if isinstance(fmt, str) else -1
    if code < 0:
        raise ValueError("format=%r is not one of %s (or None: from the extension)"
                         % (fmt, ", ".join(_FORMATS)))
    return code


def _path(path):
    return os.fsencode(os.fspath(path))


def read(path, format=None, repair=True, drop_duplicate_faces=False, faces="auto",
         colors=False, max_memory=0, device=None):
    """Reads a mesh file (OBJ, PLY, OFF, STL) -> ``(V, F)`` (``(V, F, rgb)``
    with ``colors=True``; rgb is None when the file has no colours).

    ``repair=True`` runs the repair step the CLI runs after reading (faces
    using a vertex twice are mended, degenerate ones removed; warnings say
    what changed), so results equal the CLI's on the same file.
    ``faces``: "auto" (an (m, k) array when all faces have k corners, else
    ``(offsets, indices)``), "array", "offsets" or "list". ``max_memory``:
    the readers' limit in bytes (0: three quarters of physical memory)."""
    fmt = _format(format)
    mm = _core.size_value("max_memory", max_memory)
    with _core.context(device) as (ctx, _):
        mesh = ctx.read(_path(path), fmt, mm)
        if repair:
            ctx.repair(mesh, True, bool(drop_duplicate_faces))
        P, off, idx, rgb = _core.mesh_arrays(ctx, mesh, colors=colors)
    F = _core.faces_out(off, idx, faces)
    return (P, F, rgb) if colors else (P, F)


def write(path, V, F, colors=None, format=None, precision="double"):
    """Writes a mesh (format None: from the extension; "obj", "ply" binary,
    "ply-ascii", "ply-be", "off", "stl"), whole or not at all (a temporary
    file renamed over the target). ``colors``: (n, 3) RGB bytes (PLY).
    ``precision="float"`` writes float32 positions (PLY only). Returns the
    write report: max_error, mean_error, bbox_diagonal."""
    fmt = _format(format)
    if precision not in ("double", "float"):
        raise ValueError("precision=%r is not one of double, float" % (precision,))
    with _core.context("reference") as (ctx, _):
        mesh = _core.make_mesh(ctx, V, F)
        if colors is not None:
            ctx.set_colors(mesh, _core.colors_array(colors, mesh.counts()[0]))
        return ctx.write(mesh, _path(path), fmt, precision == "float")


def _mesh_result(ctx, mesh, form="auto"):
    P, off, idx, _ = _core.mesh_arrays(ctx, mesh)
    return P, _core.faces_out(off, idx, form)


def interpolate(V, F, scheme="auto", alpha=0.0, tol=1e-6, method="auto", precision="auto",
                max_iter=1000, reorder=True, device=None, fallback=None, progress=None):
    """Solves A P = V for the control mesh P whose subdivision limit surface
    passes through every vertex of (V, F) -> ``(P, report)``: P an (n, 3)
    float64 array (same faces as F), report a dict with the keys of
    ``limn interpolate --report`` (scheme, method, iterations, max_rel_error,
    device, seconds, ...). scheme: auto (Loop for triangle meshes, else
    Catmull-Clark), loop, catmark; alpha: Catmull-Clark alpha in [0, 1];
    tol: max |V - A P| / bbox diagonal; method: auto, paper, weighted,
    chebyshev, cg, sgs; precision: auto, double, float (not cg, sgs)."""
    args = (_core.choice("scheme", scheme, _core.SCHEMES), _core.alpha_value(alpha),
            _core.number("tol", tol, 0.0, open_lo=True),
            _core.integer("max_iter", max_iter, 1), bool(reorder),
            _core.choice("method", method, _core.METHODS),
            _core.choice("precision", precision, _core.PRECISIONS))
    if precision == "float" and method in ("cg", "sgs"):
        raise ValueError("precision='float' runs the chebyshev, paper or weighted iteration; "
                         "cg and sgs run in double")
    with _core.context(device, fallback, progress) as (ctx, state):
        mesh = _core.make_mesh(ctx, V, F)
        control, report = _core.run_with_fallback(
            ctx, state, lambda: ctx.interpolate(mesh, *args))
        P, _, _, _ = _core.mesh_arrays(ctx, control)
    return P, report


def subdivide(V, F, levels=1, limit=False, scheme="auto", alpha=0.0, max_memory=0,
              faces="auto", device=None, fallback=None, progress=None, report=False):
    """Refines (V, F) uniformly ``levels`` times (0..16) -> ``(V2, F2)``
    (``(V2, F2, report)`` with ``report=True``). Vertex i of V is vertex i of
    V2; Catmull-Clark gives quads after the first step, Loop triangles.
    ``limit=True`` moves the finest vertices onto the limit surface; alpha > 0
    uses the alpha vertex rule on the first step (the surface limn.interpolate
    matched). ``max_memory``: refuse above this predicted peak (bytes; 0:
    three quarters of physical memory)."""
    args = (_core.choice("scheme", scheme, _core.SCHEMES), _core.alpha_value(alpha),
            _core.integer("levels", levels, 0, 16), bool(limit),
            _core.size_value("max_memory", max_memory))
    with _core.context(device, fallback, progress) as (ctx, state):
        mesh = _core.make_mesh(ctx, V, F)
        surface, rep = _core.run_with_fallback(ctx, state, lambda: ctx.subdivide(mesh, *args))
        V2, F2 = _mesh_result(ctx, surface, faces)
    return (V2, F2, rep) if report else (V2, F2)


def _series_head(scheme, alpha):
    return _core.choice("scheme", scheme, _core.SCHEMES), _core.alpha_value(alpha)


def _displacement(ctx, a, b, rep):
    d = rep["bbox_diagonal"] if rep["bbox_diagonal"] > 0 else 1.0
    return ctx.compare(a, b)["mean_distance"] / d


def smooth(V, F, terms, scheme="auto", alpha=0.0, device=None, fallback=None, progress=None):
    """The partial sum of the first ``terms`` bands of the series of (V, F),
    (E - (E - A)^terms) V -> ``(V2, report)``: terms = 1 gives the limit
    points, more keeps more detail. report: the keys of
    ``limn smooth --report``."""
    head = _series_head(scheme, alpha)
    terms = _core.integer("terms", terms, 1)
    with _core.context(device, fallback, progress) as (ctx, _):
        mesh = _core.make_mesh(ctx, V, F)
        out, rep = ctx.smooth(mesh, *head, terms)
        rep["terms"] = terms
        rep["mean_rel_displacement"] = _displacement(ctx, mesh, out, rep)
        V2, _, _, _ = _core.mesh_arrays(ctx, out)
    return V2, rep


def _volumes(ctx, mesh, out, rep):
    a, b = ctx.measure(mesh), ctx.measure(out)
    closed = a["closed"]
    nan = float("nan")
    rep.update(closed=closed, volume_input=a["volume"] if closed else nan,
               volume_output=b["volume"] if closed else nan,
               volume_change=(b["volume"] - a["volume"]) / a["volume"] if closed else nan,
               area_input=a["area"], area_output=b["area"])
    if not closed:
        rep["volume_note"] = "not defined: the mesh is not closed"


def denoise(V, F, m=None, steps=None, keep_volume=None, scheme="auto", alpha=0.0, device=None,
            fallback=None, progress=None, products=None):
    """Smooths noise away -> ``(V2, report)``, as ``limn denoise``.

    By default (neither m nor steps given) limn denoise's default form: the
    polynomial E + sum_{i=1..products} d_i (E - A)^i of degree ``products``
    (default 12, 1..64; that many stencil products) in the limit operator A
    whose coefficients minimise Stein's unbiased estimate of the squared
    distance to the unknown clean mesh, for noise whose deviation is
    estimated from the mesh (report["sigma_estimate"]). keep_volume (default:
    whether the mesh is closed) scales the result back to the input's volume.

    With m or steps: Lai & Cheng 2011, eq. 8, T_{k+1} = sum_{i=0..m} (E - A)^i
    A T_k, ``steps`` times (defaults m = 2, steps = 3; keep_volume default
    False); products is then refused.

    report: the keys of ``limn denoise --report`` (form, volumes, areas, ...)."""
    head = _series_head(scheme, alpha)
    paper = m is not None or steps is not None
    if paper and products is not None:
        raise ValueError("denoise: products selects the default form and m / steps the "
                         "paper's: give one or the other")
    if paper:
        m = _core.integer("m", 2 if m is None else m, 0)
        steps = _core.integer("steps", 3 if steps is None else steps, 1)
    else:
        products = _core.integer("products", 12 if products is None else products, 1, 64)
    with _core.context(device, fallback, progress) as (ctx, _):
        mesh = _core.make_mesh(ctx, V, F)
        if paper:
            keep = bool(keep_volume)
            out, rep = ctx.denoise(mesh, *head, m, steps, keep)
            rep.update(form="paper", m=m, steps=steps)
        else:
            keep = ctx.measure(mesh)["closed"] if keep_volume is None else bool(keep_volume)
            out, rep = ctx.denoise_sure(mesh, *head, products, keep)
            rep.update(form="sure", degree=products)
        rep["keep_volume"] = keep
        _volumes(ctx, mesh, out, rep)
        rep["mean_rel_displacement"] = _displacement(ctx, mesh, out, rep)
        V2, _, _, _ = _core.mesh_arrays(ctx, out)
    return V2, rep


def sharpen(V, F, from_, to, steps=1, scheme="auto", alpha=0.0, device=None, fallback=None,
            progress=None):
    """Adds high-frequency detail (Lai & Cheng 2011, section 6): T_{k+1} =
    T_k + sum_{i=from_..to} (E - A)^i T_k, ``steps`` times, 0 <= from_ <= to
    (from_ = 0 adds the mesh itself) -> ``(V2, report)``."""
    head = _series_head(scheme, alpha)
    from_ = _core.integer("from_", from_, 0)
    to = _core.integer("to", to, 0)
    steps = _core.integer("steps", steps, 1)
    with _core.context(device, fallback, progress) as (ctx, _):
        mesh = _core.make_mesh(ctx, V, F)
        out, rep = ctx.sharpen(mesh, *head, from_, to, steps)
        rep.update({"from": from_, "to": to, "steps": steps})
        rep["mean_rel_displacement"] = _displacement(ctx, mesh, out, rep)
        V2, _, _, _ = _core.mesh_arrays(ctx, out)
    return V2, rep


def bands(V, F, count, scheme="auto", alpha=0.0, device=None, fallback=None, progress=None):
    """The bands of the series of (V, F): band i = (E - A)^i A V for
    i < count, and the remainder (E - A)^count V; they sum to V ->
    ``(bands, remainder, energies)``: a list of ``count`` (n, 3) arrays, an
    (n, 3) array and ``count + 1`` energies sum_v |band_i(v)|^2 (the
    remainder's last)."""
    head = _series_head(scheme, alpha)
    count = _core.integer("count", count, 0, 10000)
    with _core.context(device, fallback, progress) as (ctx, _):
        mesh = _core.make_mesh(ctx, V, F)
        n = mesh.counts()[0]
        out = np.empty((count + 1, n, 3), dtype=np.float64)
        energy = np.empty(count + 1, dtype=np.float64)
        ctx.bands(mesh, *head, count, out, energy)
    return [out[i] for i in range(count)], out[count], energy


MorphFrame = collections.namedtuple(
    "MorphFrame", "index V volume area flipped_faces mean_distance_to_target")
MorphFrame.__doc__ = ("One frame of limn.morph: its index, positions V (n, 3), signed "
                      "volume (NaN when not closed), area, faces flipped from V_from's, and "
                      "the mean distance to V_to over the bbox diagonal of V_to.")


def morph(V_from, V_to, F, frames=30, m=2, p=0.8, linear=False, scheme="auto", alpha=0.0,
          device=None, fallback=None, progress=None):
    """Morphs (V_from, F) into (V_to, F) (Lai & Cheng 2011, eq. 9):
    Q_0 = V_from, Q_{k+1} = V_to + p sum_{i=0..m} (E - A)^i A (Q_k - V_to);
    ``linear=True`` gives the linear blend instead. Computes every frame
    (frames x n x 3 doubles), then returns an iterator of ``MorphFrame``."""
    head = _series_head(scheme, alpha)
    frames = _core.integer("frames", frames, 2, 100000)
    m = _core.integer("m", m, 0)
    p = _core.number("p", p, 0.0, 1.0, open_lo=True, open_hi=True)
    with _core.context(device, fallback, progress) as (ctx, _):
        a = _core.make_mesh(ctx, V_from, F, "V_from")
        b = _core.make_mesh(ctx, V_to, F, "V_to")
        n = a.counts()[0]
        pos = np.empty((frames, n, 3), dtype=np.float64)
        stats = np.empty((frames, 4), dtype=np.float64)
        ctx.morph(a, b, *head, frames, m, p, bool(linear), pos, stats)
    return (MorphFrame(k, pos[k], float(stats[k, 0]), float(stats[k, 1]), int(stats[k, 2]),
                       float(stats[k, 3])) for k in range(frames))


def texture(V, F, levels=3, colors=("#202040", "#f0e0a0"), seed=1, frequency=4.0, tol=1e-6,
            max_memory=0, scheme="auto", alpha=0.0, faces="auto", device=None, fallback=None,
            progress=None):
    """Procedural texture (Lai & Cheng 2011, section 5): (V, F) refined
    ``levels`` times (0..8), noise interpolated per level, mapped through the
    colours -> ``(V2, F2, rgb)``: V2 on the limit surface, rgb (n2, 3) uint8.
    colors: '#rrggbb' / '#rgb' strings (or one comma-separated string) or a
    (k, 3) array of RGB bytes."""
    head = _series_head(scheme, alpha)
    args = (_core.integer("levels", levels, 0, 8), _core.palette(colors),
            _core.integer("seed", seed, 0, 2**64 - 1),
            _core.number("frequency", frequency, 0.0, open_lo=True),
            _core.number("tol", tol, 0.0, open_lo=True),
            _core.size_value("max_memory", max_memory))
    with _core.context(device, fallback, progress) as (ctx, _):
        mesh = _core.make_mesh(ctx, V, F)
        out, _rep = ctx.texture(mesh, *head, *args)
        P, off, idx, rgb = _core.mesh_arrays(ctx, out, colors=True)
    return P, _core.faces_out(off, idx, faces), rgb


def devices():
    """The compute devices: a list of dicts {"spec", "name", "usable", "line"}
    for each OpenCL device ("opencl:P.D"), then the reference backend. No
    OpenCL driver (no platform) gives just the reference backend."""
    out = []
    with _core.context() as (ctx, _):
        try:
            text = ctx.list_devices()
        except Error:
            text = ""  # no OpenCL platform: the reference backend still works
    for line in text.splitlines():
        if not line.strip():
            continue
        pd, _, rest = line.strip().partition(" ")
        out.append({"spec": "opencl:" + pd, "name": rest.strip().split("  ")[0],
                    "usable": "limn: usable" in line, "line": line.strip()})
    out.append({"spec": "reference", "name": "plain C backend", "usable": True,
                "line": "reference  plain C backend"})
    return out
