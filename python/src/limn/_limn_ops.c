/* SPDX-License-Identifier: MIT */
/* The context's operations: interpolate, subdivide, the series (smooth,
   denoise, sharpen, bands, morph) and texture; reports as dicts with the keys
   of the CLI's JSON reports. */
#include "_limn.h"

#include <string.h>

/* (Mesh, report) or NULL with the exception (out and report dropped). */
static PyObject *mesh_and_report(LimnContext *c, limn_status st, limn_mesh *out, PyObject *rep)
{
    limn_py_leave(c);
    if (limn_py_check(c, st) < 0 || !rep) {
        limn_mesh_destroy(out);
        Py_XDECREF(rep);
        return NULL;
    }
    PyObject *m = limn_py_mesh_new(out);
    if (!m) {
        Py_DECREF(rep);
        return NULL;
    }
    return Py_BuildValue("(NN)", m, rep);
}

static PyObject *seconds_dict(const char *const *names, const double *values, int n)
{
    PyObject *d = PyDict_New();
    for (int i = 0; d && i < n; i++)
        if (SET_NUM(d, names[i], values[i]) < 0)
            Py_CLEAR(d);
    return d;
}

/* ----------------------------------------------------------- interpolate */

static int interpolate_method_keys(PyObject *d, const limn_report *r)
{
    const char *method = r->method ? r->method : "";
    int e = 0;
    if (strcmp(method, "weighted") == 0)
        e |= SET_NUM(d, "omega", r->omega);
    if (strcmp(method, "chebyshev") == 0) {
        e |= SET_NUM(d, "spectrum_lower", r->spectrum_lower);
        e |= SET_INT(d, "restarts", r->restarts);
    }
    return e;
}

static int interpolate_seconds(PyObject *d, const limn_report *r)
{
    double setup = r->seconds_opencl_platform + r->seconds_opencl_context +
                   r->seconds_opencl_build + r->seconds_opencl_kernels;
    static const char *const s_names[] = {"topology", "stencil", "solve", "iterations",
                                          "opencl_setup"};
    const double s[] = {r->seconds_topology, r->seconds_stencil, r->seconds_solve,
                        r->seconds_iterations, setup};
    static const char *const o_names[] = {"platform", "context", "build", "kernels"};
    const double o[] = {r->seconds_opencl_platform, r->seconds_opencl_context,
                        r->seconds_opencl_build, r->seconds_opencl_kernels};
    return limn_py_set(d, "seconds", seconds_dict(s_names, s, 5)) |
           limn_py_set(d, "opencl_setup", seconds_dict(o_names, o, 4));
}

static PyObject *interpolate_report(LimnContext *c, const limn_report *r, double tol)
{
    PyObject *d = PyDict_New();
    if (!d)
        return NULL;
    int t, h;
    const char *ts, *hs;
    limn_context_threads(c->ctx, &t, &ts);
    int e = SET_INT(d, "vertices", r->vertices) | SET_INT(d, "faces", r->faces) |
            SET_STR(d, "scheme", limn_scheme_name(r->scheme)) | SET_NUM(d, "alpha", r->alpha) |
            SET_STR(d, "method", r->method) | SET_INT(d, "iterations", r->iterations) |
            SET_NUM(d, "products", r->products) | SET_STR(d, "method_reason", r->method_reason) |
            SET_STR(d, "precision", r->precision ? r->precision : "double") |
            SET_STR(d, "precision_reason", r->precision_reason) |
            SET_NUM(d, "products_float", r->products_float) | interpolate_method_keys(d, r) |
            SET_NUM(d, "tolerance", tol) | SET_NUM(d, "max_rel_error", r->max_rel_error) |
            SET_NUM(d, "mean_rel_error", r->mean_rel_error) |
            SET_NUM(d, "max_abs_error", r->max_abs_error) |
            SET_NUM(d, "mean_abs_error", r->mean_abs_error) |
            SET_NUM(d, "bbox_diagonal", r->bbox_diagonal) |
            SET_INT(d, "stencil_nonzeros", r->stencil_nonzeros) |
            SET_STR(d, "vertex_order", r->reordered ? "rcm" : "input") |
            SET_STR(d, "device", r->device) | SET_INT(d, "threads", t) |
            SET_STR(d, "threads_source", ts);
    if (limn_context_host_threads(c->ctx, &h, &hs) == LIMN_OK)
        e |= SET_INT(d, "host_threads", h) | SET_STR(d, "host_threads_source", hs);
    e |= interpolate_seconds(d, r);
    if (e)
        Py_CLEAR(d);
    return d;
}

/* interpolate(mesh, scheme, alpha, tol, max_iter, reorder, method, precision) */
static PyObject *ctx_interpolate(LimnContext *c, PyObject *args)
{
    limn_mesh *mesh;
    limn_interpolate_options o;
    limn_interpolate_options_default(&o);
    int scheme, method, precision;
    if (!PyArg_ParseTuple(args, "O&iddipii", limn_py_mesh_arg, &mesh, &scheme, &o.alpha, &o.tolerance,
                          &o.max_iterations, &o.reorder, &method, &precision) ||
        limn_py_enter(c) < 0)
        return NULL;
    o.scheme = (limn_scheme)scheme;
    o.method = (limn_method)method;
    o.precision = (limn_precision)precision;
    limn_report r = {.size = sizeof r};
    limn_mesh *out = NULL;
    limn_status st;
    CALL(c, st, limn_interpolate(c->ctx, mesh, &o, &out, &r));
    PyObject *rep = st || c->exc_type ? Py_NewRef(Py_None) : interpolate_report(c, &r, o.tolerance);
    return mesh_and_report(c, st, out, rep);
}

/* ----------------------------------------------------------- subdivide */

static PyObject *subdivide_report(const limn_subdivide_report *r)
{
    PyObject *d = PyDict_New();
    if (!d)
        return NULL;
    static const char *const names[] = {"plan", "apply", "limit"};
    const double s[] = {r->seconds_plan, r->seconds_apply, r->seconds_limit};
    int e = SET_INT(d, "vertices", r->input_vertices) | SET_INT(d, "faces", r->input_faces) |
            SET_INT(d, "output_vertices", r->vertices) | SET_INT(d, "output_faces", r->faces) |
            SET_STR(d, "scheme", limn_scheme_name(r->scheme)) | SET_NUM(d, "alpha", r->alpha) |
            SET_INT(d, "levels", r->levels) | SET_BOOL(d, "limit", r->limit) |
            SET_INT(d, "stencil_nonzeros", r->stencil_nonzeros) |
            SET_INT(d, "estimated_bytes", r->estimated_bytes) | SET_STR(d, "device", r->device) |
            limn_py_set(d, "seconds", seconds_dict(names, s, 3));
    if (e)
        Py_CLEAR(d);
    return d;
}

/* subdivide(mesh, scheme, alpha, levels, limit, max_memory) */
static PyObject *ctx_subdivide(LimnContext *c, PyObject *args)
{
    limn_mesh *mesh;
    limn_subdivide_options o;
    limn_subdivide_options_default(&o);
    int scheme;
    unsigned long long max_memory;
    if (!PyArg_ParseTuple(args, "O&idipK", limn_py_mesh_arg, &mesh, &scheme, &o.alpha, &o.levels,
                          &o.limit, &max_memory) ||
        limn_py_enter(c) < 0)
        return NULL;
    o.scheme = (limn_scheme)scheme;
    o.max_memory = (size_t)max_memory;
    limn_subdivide_report r = {.size = sizeof r};
    limn_mesh *out = NULL;
    limn_status st;
    CALL(c, st, limn_subdivide(c->ctx, mesh, &o, &out, &r));
    PyObject *rep = st || c->exc_type ? Py_NewRef(Py_None) : subdivide_report(&r);
    return mesh_and_report(c, st, out, rep);
}

/* ----------------------------------------------------------- series */

static PyObject *series_report(const limn_series_report *r)
{
    PyObject *d = PyDict_New();
    if (!d)
        return NULL;
    static const char *const names[] = {"topology", "stencil", "compute"};
    const double s[] = {r->seconds_topology, r->seconds_stencil, r->seconds_compute};
    int e = SET_INT(d, "vertices", r->vertices) | SET_INT(d, "faces", r->faces) |
            SET_STR(d, "scheme", limn_scheme_name(r->scheme)) | SET_NUM(d, "alpha", r->alpha) |
            SET_STR(d, "device", r->device) |
            SET_INT(d, "stencil_nonzeros", r->stencil_nonzeros) |
            SET_INT(d, "products", r->products) | SET_NUM(d, "bbox_diagonal", r->bbox_diagonal) |
            limn_py_set(d, "seconds", seconds_dict(names, s, 3));
    if (e)
        Py_CLEAR(d);
    return d;
}

static PyObject *series_result(LimnContext *c, limn_status st, limn_mesh *out,
                               const limn_series_report *r)
{
    PyObject *rep = st || c->exc_type ? Py_NewRef(Py_None) : series_report(r);
    return mesh_and_report(c, st, out, rep);
}

/* The series options from (scheme, alpha). */
static limn_series_options series_options(int scheme, double alpha)
{
    limn_series_options o;
    limn_series_options_default(&o);
    o.scheme = (limn_scheme)scheme;
    o.alpha = alpha;
    return o;
}

typedef enum { FILTER_SMOOTH, FILTER_DENOISE, FILTER_SHARPEN } filter_kind;

/* smooth(mesh, scheme, alpha, terms), denoise(mesh, scheme, alpha, m, steps,
   keep_volume), sharpen(mesh, scheme, alpha, from, to, steps) */
static PyObject *filter(LimnContext *c, PyObject *args, filter_kind kind)
{
    static const char *const formats[] = {"O&idi", "O&idiip", "O&idiii"};
    limn_mesh *mesh;
    int scheme, a = 0, b = 0, d = 0;
    double alpha;
    if (!PyArg_ParseTuple(args, formats[kind], limn_py_mesh_arg, &mesh, &scheme, &alpha, &a, &b, &d) ||
        limn_py_enter(c) < 0)
        return NULL;
    limn_series_options o = series_options(scheme, alpha);
    limn_series_report r = {.size = sizeof r};
    limn_mesh *out = NULL;
    limn_status st;
    if (kind == FILTER_SMOOTH)
        CALL(c, st, limn_smooth(c->ctx, mesh, &o, a, &out, &r));
    else if (kind == FILTER_DENOISE)
        CALL(c, st, limn_denoise(c->ctx, mesh, &o, a, b, d, &out, &r));
    else
        CALL(c, st, limn_sharpen(c->ctx, mesh, &o, a, b, d, &out, &r));
    return series_result(c, st, out, &r);
}

static PyObject *ctx_smooth(LimnContext *c, PyObject *args)
{
    return filter(c, args, FILTER_SMOOTH);
}

static PyObject *ctx_denoise(LimnContext *c, PyObject *args)
{
    return filter(c, args, FILTER_DENOISE);
}

/* denoise_sure(mesh, scheme, alpha, products, keep_volume) -> (mesh, report):
   limn denoise's default; the report's "sigma_estimate" the noise estimate. */
static PyObject *ctx_denoise_sure(LimnContext *c, PyObject *args)
{
    limn_mesh *mesh;
    int scheme, products, keep_volume;
    double alpha;
    if (!PyArg_ParseTuple(args, "O&idip", limn_py_mesh_arg, &mesh, &scheme, &alpha, &products,
                          &keep_volume) ||
        limn_py_enter(c) < 0)
        return NULL;
    limn_series_options o = series_options(scheme, alpha);
    limn_series_report r = {.size = sizeof r};
    limn_mesh *out = NULL;
    double sigma = 0.0;
    limn_status st;
    CALL(c, st, limn_denoise_sure(c->ctx, mesh, &o, products, keep_volume, &out, &sigma, &r));
    PyObject *rep = st || c->exc_type ? Py_NewRef(Py_None) : series_report(&r);
    if (rep && rep != Py_None && SET_NUM(rep, "sigma_estimate", sigma) < 0)
        Py_CLEAR(rep);
    return mesh_and_report(c, st, out, rep);
}

static PyObject *ctx_sharpen(LimnContext *c, PyObject *args)
{
    return filter(c, args, FILTER_SHARPEN);
}

/* bands(mesh, scheme, alpha, count, bands float64[(count+1)*n*3], energy float64[count+1]) */
static PyObject *ctx_bands(LimnContext *c, PyObject *args)
{
    limn_mesh *mesh;
    int scheme, count;
    double alpha;
    PyObject *bo, *eo;
    if (!PyArg_ParseTuple(args, "O&idiOO", limn_py_mesh_arg, &mesh, &scheme, &alpha, &count, &bo, &eo))
        return NULL;
    if (count < 0 || count > LIMN_MAX_TERMS) { /* the buffer sizes below need it */
        limn_py_raise(LIMN_ERR_ARGUMENT, "bands: count is outside 0..LIMN_MAX_TERMS (10000)");
        return NULL;
    }
    Py_ssize_t n = (Py_ssize_t)limn_mesh_vertex_count(mesh);
    Py_buffer b = {0}, e = {0};
    int ok = limn_py_buffer(bo, &b, 8, (Py_ssize_t)(count + 1) * 3 * n, 1, "bands") == 0 &&
             limn_py_buffer(eo, &e, 8, count + 1, 1, "energy") == 0 && limn_py_enter(c) == 0;
    limn_status st = LIMN_OK;
    limn_series_report r = {.size = sizeof r};
    if (ok) {
        limn_series_options o = series_options(scheme, alpha);
        CALL(c, st, limn_bands(c->ctx, mesh, &o, count, b.buf, e.buf, &r));
        limn_py_leave(c);
    }
    if (b.obj)
        PyBuffer_Release(&b);
    if (e.obj)
        PyBuffer_Release(&e);
    if (!ok || limn_py_check(c, st) < 0)
        return NULL;
    return series_report(&r);
}

/* ----------------------------------------------------------- morph */

typedef struct {
    LimnContext *c;
    double *positions; /* frames * 3n */
    double *stats;     /* frames * 4: volume, area, flipped faces, mean distance */
    size_t n;
    int frames;
} morph_sink;

/* limn_morph_frame_fn, without the GIL: copies the frame; stops the morph
   once a progress callback has raised (the exception is raised on return). */
static limn_status morph_frame(void *user, const limn_morph_frame *f)
{
    morph_sink *s = user;
    if (s->c->exc_type || f->index < 0 || f->index >= s->frames)
        return LIMN_ERR_ARGUMENT;
    memcpy(s->positions + (size_t)f->index * 3 * s->n, f->positions, 3 * s->n * sizeof(double));
    double *st = s->stats + 4 * (size_t)f->index;
    st[0] = f->volume;
    st[1] = f->area;
    st[2] = (double)f->flipped_faces;
    st[3] = f->mean_distance_to_target;
    return LIMN_OK;
}

/* morph(from, to, scheme, alpha, frames, m, p, linear, positions float64[frames*n*3],
   stats float64[frames*4]) */
static PyObject *ctx_morph(LimnContext *c, PyObject *args)
{
    limn_mesh *from, *to;
    limn_morph_options o;
    limn_morph_options_default(&o);
    int scheme;
    PyObject *po, *so;
    if (!PyArg_ParseTuple(args, "O&O&idiidpOO", limn_py_mesh_arg, &from, limn_py_mesh_arg, &to, &scheme,
                          &o.series.alpha, &o.frames, &o.m, &o.p, &o.linear, &po, &so))
        return NULL;
    o.series.scheme = (limn_scheme)scheme;
    if (o.frames < 2 || o.frames > LIMN_MAX_FRAMES) {
        limn_py_raise(LIMN_ERR_ARGUMENT, "morph: frames is outside 2..LIMN_MAX_FRAMES (100000)");
        return NULL;
    }
    morph_sink s = {c, NULL, NULL, limn_mesh_vertex_count(from), o.frames};
    Py_buffer b = {0}, e = {0};
    int ok = limn_py_buffer(po, &b, 8, (Py_ssize_t)o.frames * 3 * (Py_ssize_t)s.n, 1,
                            "frames") == 0 &&
             limn_py_buffer(so, &e, 8, (Py_ssize_t)o.frames * 4, 1, "stats") == 0 &&
             limn_py_enter(c) == 0;
    limn_status st = LIMN_OK;
    limn_series_report r = {.size = sizeof r};
    if (ok) {
        s.positions = b.buf;
        s.stats = e.buf;
        CALL(c, st, limn_morph(c->ctx, from, to, &o, morph_frame, &s, &r));
        limn_py_leave(c);
    }
    if (b.obj)
        PyBuffer_Release(&b);
    if (e.obj)
        PyBuffer_Release(&e);
    if (!ok || limn_py_check(c, st) < 0)
        return NULL;
    return series_report(&r);
}

/* ----------------------------------------------------------- texture */

/* texture(mesh, scheme, alpha, levels, colours bytes, seed, frequency, tol, max_memory) */
static PyObject *ctx_texture(LimnContext *c, PyObject *args)
{
    limn_mesh *mesh;
    limn_texture_options o;
    limn_texture_options_default(&o);
    int scheme;
    Py_buffer colors;
    unsigned long long seed, max_memory;
    if (!PyArg_ParseTuple(args, "O&idiy*KddK", limn_py_mesh_arg, &mesh, &scheme, &o.series.alpha,
                          &o.levels, &colors, &seed, &o.frequency, &o.tolerance, &max_memory))
        return NULL;
    if (limn_py_enter(c) < 0) {
        PyBuffer_Release(&colors);
        return NULL;
    }
    o.series.scheme = (limn_scheme)scheme;
    o.colors = colors.buf;
    o.color_count = (size_t)colors.len / 3;
    o.seed = seed;
    o.max_memory = (size_t)max_memory;
    limn_series_report r = {.size = sizeof r};
    limn_mesh *out = NULL;
    limn_status st;
    CALL(c, st, limn_texture(c->ctx, mesh, &o, &out, &r));
    PyBuffer_Release(&colors);
    return series_result(c, st, out, &r);
}

PyMethodDef limn_py_ops_methods[] = {
    {"interpolate", (PyCFunction)ctx_interpolate, METH_VARARGS, "limn_interpolate"},
    {"subdivide", (PyCFunction)ctx_subdivide, METH_VARARGS, "limn_subdivide"},
    {"smooth", (PyCFunction)ctx_smooth, METH_VARARGS, "limn_smooth"},
    {"denoise", (PyCFunction)ctx_denoise, METH_VARARGS, "limn_denoise"},
    {"denoise_sure", (PyCFunction)ctx_denoise_sure, METH_VARARGS, "limn_denoise_sure"},
    {"sharpen", (PyCFunction)ctx_sharpen, METH_VARARGS, "limn_sharpen"},
    {"bands", (PyCFunction)ctx_bands, METH_VARARGS, "limn_bands"},
    {"morph", (PyCFunction)ctx_morph, METH_VARARGS, "limn_morph"},
    {"texture", (PyCFunction)ctx_texture, METH_VARARGS, "limn_texture"},
    {NULL, NULL, 0, NULL}};
