/* SPDX-License-Identifier: MIT */
/*
 * The mesh series (seed 000 §3, §6, §7; DESIGN.md §1): bands, partial sums,
 * denoising (eq. 8), sharpening and morphing (eq. 9). Every driver builds the
 * limit operator A once and runs the terms (E - A)^i x on the device with the
 * fused series_step (one stencil product per term, plus the running sum), so
 * nothing but stencil products and vector updates is ever computed: no matrix
 * power is formed.
 */
#include "base/abi.h"
#include "mesh/check.h"
#include "base/context.h"
#include "device/device.h"
#include "topology/measure.h"
#include "mesh/mesh.h"
#include "solve/operator.h"
#include "series/filter.h"
#include "series/series.h"
#include "series/sure.h"
#include "base/clock.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void limn_series_options_default(limn_series_options *o)
{
    abi_default(&abi_series_options, o);
}

void limn_morph_options_default(limn_morph_options *o)
{
    abi_default(&abi_morph_options, o);
}

limn_status series_check_options(limn_context *ctx, const limn_series_options *o)
{
    if (o->scheme != LIMN_SCHEME_AUTO && o->scheme != LIMN_SCHEME_LOOP &&
        o->scheme != LIMN_SCHEME_CATMARK)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "unknown scheme %d", (int)o->scheme);
    if (!(o->alpha >= 0.0 && o->alpha <= 1.0))
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "alpha is %g; it must lie in [0, 1]", o->alpha);
    return LIMN_OK;
}

void series_report_init(limn_series_report *r, const limn_mesh *mesh)
{
    memset(r, 0, sizeof *r);
    r->vertices = mesh->vertex_count;
    r->faces = mesh->face_count;
}

void series_report_operator(limn_series_report *r, const stencil_operator *op)
{
    r->scheme = op->scheme;
    r->alpha = op->alpha;
    r->seconds_topology += op->seconds_topology;
    r->seconds_stencil += op->seconds_stencil;
    r->stencil_nonzeros = op->host.row_offsets[op->host.rows];
    r->bbox_diagonal = op->bbox_diagonal;
    snprintf(r->device, sizeof r->device, "%s", op->dev->name);
}

limn_status series_open(limn_context *ctx, const limn_mesh *mesh, limn_scheme scheme,
                        double alpha, int buffers, series_run *s, limn_series_report *r)
{
    memset(s, 0, sizeof *s);
    if (mesh->vertex_count == 0 || mesh->face_count == 0)
        return ctx_fail(ctx, LIMN_ERR_TOPOLOGY, "the mesh has no %s",
                         mesh->vertex_count ? "faces" : "vertices");
    if (buffers > SERIES_MAX_BUFFERS)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "series_open: too many buffers");
    limn_status st = operator_build(ctx, mesh, scheme, alpha, &s->op);
    if (st)
        return st;
    s->open = 1;
    s->dev = s->op.dev;
    s->n = mesh->vertex_count;
    if (r)
        series_report_operator(r, &s->op);
    s->host = calloc(4 * s->n, sizeof *s->host);
    if (!s->host)
        st = ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for %zu vertices", s->n);
    for (int b = 0; !st && b < buffers; b++)
        st = s->dev->ops->buffer_create(s->dev, 4 * s->n * sizeof(double), NULL, &s->buf[b]);
    if (st)
        series_close(s);
    s->t0 = clock_seconds();
    return st;
}

void series_close(series_run *s)
{
    for (int b = 0; b < SERIES_MAX_BUFFERS; b++)
        if (s->buf[b])
            s->dev->ops->buffer_release(s->dev, s->buf[b]);
    free(s->host);
    if (s->open)
        operator_free(&s->op);
    memset(s, 0, sizeof *s);
}

limn_status series_upload(series_run *s, device_buffer *b, const double *xyz)
{
    for (size_t i = 0; i < s->n; i++) {
        memcpy(s->host + 4 * i, xyz + 3 * i, 3 * sizeof(double));
        s->host[4 * i + 3] = 0.0;
    }
    return s->dev->ops->buffer_write(s->dev, b, 4 * s->n * sizeof(double), s->host);
}

limn_status series_download(series_run *s, device_buffer *b, double *xyz)
{
    limn_status st = s->dev->ops->buffer_read(s->dev, b, 4 * s->n * sizeof(double), s->host);
    for (size_t i = 0; !st && i < s->n; i++)
        memcpy(xyz + 3 * i, s->host + 4 * i, 3 * sizeof(double));
    return st;
}

/* Checks that a result is finite (a diverging filter, e.g. sharpening far too
   hard, must not be written as if it were a mesh). */
limn_status series_check_finite(limn_context *ctx, const double *xyz, size_t n, const char *what)
{
    for (size_t i = 0; i < 3 * n; i++)
        if (!isfinite(xyz[i]))
            return ctx_fail(ctx, LIMN_ERR_NO_CONVERGENCE,
                             "%s produced a non-finite coordinate at vertex %zu; nothing was "
                             "written (use fewer steps or terms)",
                             what, i / 3);
    return LIMN_OK;
}

/* Common start of the drivers after abi_enter (fn: the caller's name, for
   messages; out_missing: the driver returns a mesh and out is NULL). */
static limn_status begin(limn_context *ctx, const char *fn, const limn_mesh *mesh,
                         const limn_series_options *o, limn_series_report *r, int out_missing)
{
    limn_status st = check_mesh_magnitude(ctx, fn, NULL, mesh);
    if (st)
        return st;
    series_report_init(r, mesh);
    st = check_scheme(ctx, fn, o->scheme);
    if (!st)
        st = series_check_options(ctx, o);
    if (!st && out_missing)
        st = ctx_fail(ctx, LIMN_ERR_ARGUMENT, "%s: out is NULL", fn);
    return st;
}

/* The end of a driver whose run is open: its compute time, the run closed. */
static limn_status finish(series_run *s, limn_series_report *r, limn_status st)
{
    r->seconds_compute = clock_seconds() - s->t0;
    series_close(s);
    return st;
}

/* limn_bands on options and report of this library's layout. */
static limn_status bands_sized(limn_context *ctx, const limn_mesh *mesh,
                               const limn_series_options *o, int count, double *bands,
                               double *energy, limn_series_report *r)
{
    limn_status st = begin(ctx, "limn_bands", mesh, o, r, 0);
    if (!st)
        st = check_count(ctx, "limn_bands", "count", count, 0, LIMN_MAX_TERMS, "LIMN_MAX_TERMS");
    series_run s;
    /* 0: M, then ping-pong remainders 1, 2; 3: the band */
    if (!st)
        st = series_open(ctx, mesh, o->scheme, o->alpha, 4, &s, r);
    if (st)
        return st;
    size_t n3 = 3 * s.n;
    st = series_upload(&s, s.buf[0], mesh->positions);
    device_buffer *cur = s.buf[0];
    for (int i = 0; !st && i < count; i++) {
        device_buffer *next = cur == s.buf[1] ? s.buf[2] : s.buf[1];
        device_norms nr;
        st = s.dev->ops->series->series_step(s.dev, &s.op.device, cur, next, s.buf[3], NULL,
                                     SERIES_STORE_AX | SERIES_STORE_NEXT, SERIES_ACC_NONE, &nr);
        r->products++;
        if (!st && energy)
            energy[i] = nr.sum_sq;
        if (!st && bands)
            st = series_download(&s, s.buf[3], bands + (size_t)i * n3);
        cur = next;
        if (count > 1)
            ctx_progress(ctx, "bands", (double)(i + 1) / count);
    }
    if (!st && energy) {
        device_norms nr;
        st = s.dev->ops->norms(s.dev, s.n, cur, &nr);
        if (!st)
            energy[count] = nr.sum_sq;
    }
    if (!st && bands)
        st = series_download(&s, cur, bands + (size_t)count * n3);
    return finish(&s, r, st);
}

/* Reads buffer b into a copy of mesh (positions replaced): the result. */
static limn_status result_mesh(limn_context *ctx, series_run *s, device_buffer *b,
                               const limn_mesh *mesh, const char *what, limn_mesh **out)
{
    limn_mesh *m = NULL;
    limn_status st = limn_mesh_copy(ctx, mesh, &m);
    if (!st)
        st = series_download(s, b, m->positions);
    if (!st)
        st = series_check_finite(ctx, m->positions, m->vertex_count, what);
    return mesh_hand_over(st, m, out);
}

/* ------------------------------------------ the single process's engine */

static limn_status local_term(const series_engine *e, device_buffer *x, device_buffer *next,
                              device_buffer *acc, int flags, int mode, limn_status prior)
{
    series_run *s = e->user;
    device_norms nr;
    (void)prior; /* no carry: never called after a failure */
    return s->dev->ops->series->series_step(s->dev, &s->op.device, x, next, NULL, acc, flags,
                                            mode, &nr);
}

static limn_status local_axpby(const series_engine *e, double a, device_buffer *x, double b,
                               device_buffer *y, device_buffer *out)
{
    series_run *s = e->user;
    return s->dev->ops->axpby(s->dev, s->n, a, x, b, y, out);
}

static limn_status local_upload(const series_engine *e, const double *xyz, device_buffer *b)
{
    return series_upload(e->user, b, xyz);
}

static limn_status local_download(const series_engine *e, device_buffer *b, double *xyz)
{
    return series_download(e->user, b, xyz);
}

static limn_status local_result(const series_engine *e, device_buffer *b, const limn_mesh *mesh,
                                const char *what, limn_mesh **out)
{
    return result_mesh(e->ctx, e->user, b, mesh, what, out);
}

static limn_status local_agree(const series_engine *e, limn_status st)
{
    (void)e;
    return st;
}

static const series_engine_ops local_ops = {local_term,     local_axpby,  local_upload,
                                            local_download, local_result, local_agree};

/* The engine of filter.c on an open series_run (products: the report's):
   the root, no failure carried. */
static series_engine local_engine(limn_context *ctx, series_run *s, long long *products)
{
    return (series_engine){ctx, s, s->buf, products, 1, 0, &local_ops};
}

/* A checked driver's run (four work vectors) and its engine. */
static limn_status open_engine(limn_context *ctx, const limn_mesh *mesh,
                               const limn_series_options *o, limn_series_report *r, series_run *s,
                               series_engine *e)
{
    limn_status st = series_open(ctx, mesh, o->scheme, o->alpha, 4, s, r);
    *e = local_engine(ctx, s, &r->products);
    return st;
}

/* limn_smooth on options and report of this library's layout. */
static limn_status smooth_sized(limn_context *ctx, const limn_mesh *mesh,
                                const limn_series_options *o, int terms, limn_mesh **out,
                                limn_series_report *r)
{
    limn_status st = begin(ctx, "limn_smooth", mesh, o, r, !out);
    if (!st)
        st = check_count(ctx, "limn_smooth", "terms", terms, 1, LIMN_MAX_TERMS, "LIMN_MAX_TERMS");
    series_run s;
    series_engine e;
    if (!st)
        st = open_engine(ctx, mesh, o, r, &s, &e);
    return st ? st : finish(&s, r, series_smooth_run(&e, mesh, terms, out));
}

limn_status series_keep_volume(limn_context *ctx, const limn_mesh *mesh, limn_mesh *out)
{
    double v0, v1, a;
    measure_volume_area(mesh, mesh->positions, &v0, &a);
    measure_volume_area(out, out->positions, &v1, &a);
    if (!(v1 != 0.0 && (v0 > 0.0) == (v1 > 0.0)))
        return ctx_fail(ctx, LIMN_ERR_NO_CONVERGENCE,
                         "cannot keep the volume: it went from %.6g to %.6g", v0, v1);
    double scale = cbrt(v0 / v1), c[3] = {0, 0, 0};
    double *p = out->positions;
    size_t n = out->vertex_count;
    for (size_t i = 0; i < n; i++)
        for (int j = 0; j < 3; j++)
            c[j] += p[3 * i + j];
    for (int j = 0; j < 3; j++)
        c[j] /= (double)n;
    for (size_t i = 0; i < n; i++)
        for (int j = 0; j < 3; j++)
            p[3 * i + j] = c[j] + scale * (p[3 * i + j] - c[j]);
    return LIMN_OK;
}

/* keep_volume needs a closed mesh (the run is closed on refusal). */
static limn_status check_keep_volume(limn_context *ctx, series_run *s, int keep_volume)
{
    if (!keep_volume || measure_topology_closed(&s->op.topo))
        return LIMN_OK;
    limn_status st = ctx_fail(ctx, LIMN_ERR_TOPOLOGY,
                   "keeping the volume needs a closed mesh, and this one has %zu boundary, "
                   "%zu non-manifold and %zu inconsistently oriented edges: its volume is "
                   "not defined",
                   s->op.topo.boundary_edges, s->op.topo.nonmanifold_edges,
                   s->op.topo.inconsistent_edges);
    series_close(s);
    return st;
}

/* limn_denoise on options and report of this library's layout. */
static limn_status denoise_sized(limn_context *ctx, const limn_mesh *mesh,
                                 const limn_series_options *o, int m, int steps, int keep_volume,
                                 limn_mesh **out, limn_series_report *r)
{
    limn_status st = begin(ctx, "limn_denoise", mesh, o, r, !out);
    if (!st)
        st = check_count(ctx, "limn_denoise", "m", m, 0, LIMN_MAX_TERMS, "LIMN_MAX_TERMS");
    if (!st)
        st = check_steps(ctx, "limn_denoise", steps, m + 1LL, "(m + 1) * steps");
    series_run s;
    series_engine e;
    if (!st)
        st = open_engine(ctx, mesh, o, r, &s, &e);
    if (!st)
        st = check_keep_volume(ctx, &s, keep_volume);
    if (st)
        return st;
    return finish(&s, r, series_denoise_run(&e, mesh, m, steps, keep_volume, out));
}

/* limn_denoise_sure on options and report of this library's layout. */
static limn_status denoise_sure_sized(limn_context *ctx, const limn_mesh *mesh,
                                      const limn_series_options *o, int products,
                                      int keep_volume, limn_mesh **out, double *sigma,
                                      limn_series_report *r)
{
    limn_status st = begin(ctx, "limn_denoise_sure", mesh, o, r, !out);
    if (!st)
        st = check_count(ctx, "limn_denoise_sure", "products", products, 1,
                         LIMN_MAX_SURE_PRODUCTS, "LIMN_MAX_SURE_PRODUCTS");
    series_run s;
    if (!st)
        st = series_open(ctx, mesh, o->scheme, o->alpha, 4, &s, r);
    if (!st)
        st = check_keep_volume(ctx, &s, keep_volume);
    if (st)
        return st;
    st = sure_denoise_run(ctx, &s, mesh, products, out, sigma, &r->products);
    if (!st && keep_volume)
        st = series_keep_volume(ctx, mesh, *out);
    if (st && *out) {
        limn_mesh_destroy(*out);
        *out = NULL;
    }
    return finish(&s, r, st);
}

limn_status series_check_sharpen(limn_context *ctx, const char *fn, int from, int to, int steps)
{
    if (from < 0 || to < from)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                         "%s: the terms run from %d to %d; they need 0 <= from <= to", fn, from,
                         to);
    limn_status st = check_count(ctx, fn, "to", to, 0, LIMN_MAX_TERMS, "LIMN_MAX_TERMS");
    return st ? st : check_steps(ctx, fn, steps, to, "to * steps");
}

/* limn_sharpen on options and report of this library's layout. */
static limn_status sharpen_sized(limn_context *ctx, const limn_mesh *mesh,
                                 const limn_series_options *o, int from, int to, int steps,
                                 limn_mesh **out, limn_series_report *r)
{
    limn_status st = begin(ctx, "limn_sharpen", mesh, o, r, !out);
    if (st)
        return st;
    st = series_check_sharpen(ctx, "limn_sharpen", from, to, steps);
    if (st)
        return st;
    series_run s;
    series_engine e;
    st = open_engine(ctx, mesh, o, r, &s, &e);
    return st ? st : finish(&s, r, series_sharpen_run(&e, mesh, from, to, steps, out));
}

/* Fills a frame's measures and calls the user's callback. */
limn_status series_emit_frame(const limn_mesh *from, const limn_mesh *to, int closed,
                              double diag, int index, const double *pos, limn_morph_frame_fn fn,
                              void *user)
{
    limn_morph_frame fr;
    fr.index = index;
    fr.positions = pos;
    double vol;
    measure_volume_area(from, pos, &vol, &fr.area);
    fr.volume = closed ? vol : NAN;
    fr.flipped_faces = measure_flipped(from, from->positions, pos);
    double sum = 0.0;
    for (size_t i = 0; i < from->vertex_count; i++) {
        const double *p = pos + 3 * i, *q = to->positions + 3 * i;
        sum += sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
                    (p[2] - q[2]) * (p[2] - q[2]));
    }
    fr.mean_distance_to_target = sum / (double)from->vertex_count / (diag > 0 ? diag : 1.0);
    return fn(user, &fr);
}

limn_status series_check_morph(limn_context *ctx, const char *fn, const limn_mesh *from,
                               const limn_mesh *to, const limn_morph_options *o)
{
    limn_status st = series_check_morph_counts(ctx, fn, o);
    return st ? st : measure_same_topology(ctx, from, to, "FROM", "TO");
}

limn_status series_check_morph_counts(limn_context *ctx, const char *fn,
                                      const limn_morph_options *o)
{
    limn_status st =
        check_count(ctx, fn, "frames", o->frames, 2, LIMN_MAX_FRAMES, "LIMN_MAX_FRAMES");
    if (!st && !o->linear)
        st = check_count(ctx, fn, "m", o->m, 0, LIMN_MAX_TERMS, "LIMN_MAX_TERMS");
    if (!st && !o->linear)
        st = check_count(ctx, fn, "(m + 1) * (frames - 1)", (o->m + 1LL) * (o->frames - 1LL), 0,
                         LIMN_MAX_PRODUCTS, "LIMN_MAX_PRODUCTS");
    if (!st && !o->linear && !(o->p > 0.0 && o->p < 1.0))
        st = ctx_fail(ctx, LIMN_ERR_ARGUMENT, "p is %g; it must lie strictly between 0 and 1",
                       o->p);
    return st;
}

/* The checks of limn_morph, in its order; r initialised on the way. */
static limn_status check_morph(limn_context *ctx, const limn_mesh *from, const limn_mesh *to,
                               const limn_morph_options *o, limn_morph_frame_fn fn,
                               limn_series_report *r)
{
    if (!fn)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "limn_morph: the frame callback is NULL");
    limn_status st = check_mesh_magnitude(ctx, "limn_morph", "FROM", from);
    if (!st)
        st = check_mesh_magnitude(ctx, "limn_morph", "TO", to);
    if (st)
        return st;
    series_report_init(r, from);
    st = check_scheme(ctx, "limn_morph", o->series.scheme);
    if (!st)
        st = series_check_options(ctx, &o->series);
    if (!st)
        st = series_check_morph(ctx, "limn_morph", from, to, o);
    if (!st && (from->vertex_count == 0 || from->face_count == 0))
        st = ctx_fail(ctx, LIMN_ERR_TOPOLOGY, "the meshes have no %s",
                       from->vertex_count ? "faces" : "vertices");
    return st;
}

/* The comparison: no operator, the frames blended on the host (q: scratch). */
static limn_status morph_linear(limn_context *ctx, const limn_mesh *from, const limn_mesh *to,
                                const limn_morph_options *o, double diag, double *q,
                                limn_morph_frame_fn fn, void *user, limn_series_report *r)
{
    topology t;
    limn_status st = topology_get(ctx, from, &t);
    int closed = !st && measure_topology_closed(&t);
    if (!st) {
        double lo[3], hi[3];
        r->scheme = LIMN_SCHEME_AUTO;
        st = operator_resolve_scheme(ctx, from, o->series.scheme, &r->scheme);
        r->alpha = r->scheme == LIMN_SCHEME_CATMARK ? o->series.alpha : 0.0;
        r->bbox_diagonal = mesh_bbox_diagonal(from, lo, hi);
        snprintf(r->device, sizeof r->device, "none (linear blend on the host)");
        topology_free(&t);
    }
    double t0 = clock_seconds();
    size_t n3 = 3 * from->vertex_count;
    for (int k = 0; !st && k < o->frames; k++) {
        double u = (double)k / (double)(o->frames - 1);
        for (size_t i = 0; i < n3; i++)
            q[i] = (1.0 - u) * from->positions[i] + u * to->positions[i];
        st = series_emit_frame(from, to, closed, diag, k, q, fn, user);
    }
    r->seconds_compute = clock_seconds() - t0;
    return st;
}

/* The series morph on the operator of FROM (q: scratch). */
static limn_status morph_series(limn_context *ctx, const limn_mesh *from, const limn_mesh *to,
                                const limn_morph_options *o, double diag, double *q,
                                limn_morph_frame_fn fn, void *user, limn_series_report *r)
{
    series_run s;
    series_engine e;
    /* 0: D = Q_k - TO, 1: the partial sum, 2, 3: remainders */
    limn_status st = open_engine(ctx, from, &o->series, r, &s, &e);
    if (st)
        return st;
    int closed = measure_topology_closed(&s.op.topo);
    for (size_t i = 0; i < 3 * from->vertex_count; i++)
        q[i] = from->positions[i] - to->positions[i];
    return finish(&s, r, series_morph_run(&e, from, to, o, closed, diag, q, fn, user));
}

/* limn_morph on options and report of this library's layout. */
static limn_status morph_sized(limn_context *ctx, const limn_mesh *from, const limn_mesh *to,
                               const limn_morph_options *o, limn_morph_frame_fn fn, void *user,
                               limn_series_report *r)
{
    limn_status st = check_morph(ctx, from, to, o, fn, r);
    if (st)
        return st;
    size_t n = from->vertex_count;
    double lo[3], hi[3], diag = mesh_bbox_diagonal(to, lo, hi);
    double *q = malloc(3 * n * sizeof *q);
    if (!q)
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for %zu vertices", n);
    st = o->linear ? morph_linear(ctx, from, to, o, diag, q, fn, user, r)
                   : morph_series(ctx, from, to, o, diag, q, fn, user, r);
    free(q);
    return st;
}

limn_status limn_bands(limn_context *ctx, const limn_mesh *mesh, const limn_series_options *options,
                       int count, double *bands, double *energy, limn_series_report *report)
{
    abi_call c;
    limn_status st = abi_enter(&c, ctx, "limn_bands", &abi_series_options, options,
                               &abi_series_report, report, NULL);
    return st ? st
              : abi_leave(&c, bands_sized(ctx, mesh, c.options, count, bands, energy, c.report));
}

limn_status limn_smooth(limn_context *ctx, const limn_mesh *mesh,
                        const limn_series_options *options, int terms, limn_mesh **out,
                        limn_series_report *report)
{
    abi_call c;
    limn_status st = abi_enter(&c, ctx, "limn_smooth", &abi_series_options, options,
                               &abi_series_report, report, out);
    return st ? st : abi_leave(&c, smooth_sized(ctx, mesh, c.options, terms, out, c.report));
}

limn_status limn_denoise(limn_context *ctx, const limn_mesh *mesh,
                         const limn_series_options *options, int m, int steps, int keep_volume,
                         limn_mesh **out, limn_series_report *report)
{
    abi_call c;
    limn_status st = abi_enter(&c, ctx, "limn_denoise", &abi_series_options, options,
                               &abi_series_report, report, out);
    return st ? st
              : abi_leave(
                    &c, denoise_sized(ctx, mesh, c.options, m, steps, keep_volume, out, c.report));
}

limn_status limn_denoise_sure(limn_context *ctx, const limn_mesh *mesh,
                              const limn_series_options *options, int products, int keep_volume,
                              limn_mesh **out, double *sigma, limn_series_report *report)
{
    abi_call c;
    limn_status st = abi_enter(&c, ctx, "limn_denoise_sure", &abi_series_options, options,
                               &abi_series_report, report, out);
    return st ? st
              : abi_leave(&c, denoise_sure_sized(ctx, mesh, c.options, products, keep_volume,
                                                 out, sigma, c.report));
}

limn_status limn_sharpen(limn_context *ctx, const limn_mesh *mesh,
                         const limn_series_options *options, int from, int to, int steps,
                         limn_mesh **out, limn_series_report *report)
{
    abi_call c;
    limn_status st = abi_enter(&c, ctx, "limn_sharpen", &abi_series_options, options,
                               &abi_series_report, report, out);
    return st ? st
              : abi_leave(&c, sharpen_sized(ctx, mesh, c.options, from, to, steps, out, c.report));
}

limn_status limn_morph(limn_context *ctx, const limn_mesh *from, const limn_mesh *to,
                       const limn_morph_options *options, limn_morph_frame_fn fn, void *user,
                       limn_series_report *report)
{
    abi_call c;
    limn_status st = abi_enter(&c, ctx, "limn_morph", &abi_morph_options, options,
                               &abi_series_report, report, NULL);
    return st ? st : abi_leave(&c, morph_sized(ctx, from, to, c.options, fn, user, c.report));
}
