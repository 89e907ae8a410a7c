/* SPDX-License-Identifier: MIT */
/*
 * The series filters over MPI: bands, smooth, denoise, sharpen and morph
 * (seed 000 §3, §6, §7; series.c is the single process). Each term
 * (E - A)^i x is one overlapped product on every rank's rows with the
 * running sum fused in (series_step on a row range); rows are summed in the
 * single process's order, so the results are the single process's bits.
 * Measures that need the whole mesh (volumes, frames, band energies) are
 * taken on the root after a gather, in the single process's arithmetic.
 */
#include "mpi/mpi_series.h"
#include "base/large_alloc.h"

#include "mesh/check.h"
#include "base/context.h"
#include "device/reference/device_ref.h"
#include "topology/measure.h"
#include "mesh/mesh.h"
#include "series/filter.h"
#include "series/series.h"
#include "series/sure.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void mpi_series_close(series_mpi *s)
{
    for (int b = 0; b < 4; b++)
        if (s->buf[b])
            s->p.dev->ops->buffer_release(s->p.dev, s->buf[b]);
    free(s->rows4);
    free(s->xyz);
    free(s->m4);
    mpi_part_end(&s->p);
}

limn_status mpi_series_buffers(series_mpi *s, int root_xyz, limn_series_report *r)
{
    mpi_part *p = &s->p;
    limn_status st = LIMN_OK;
    size_t nl = p->n_owned + p->n_ghost;
    int want_xyz = root_xyz && p->rank == p->root;
    s->rows4 = calloc(nl ? 4 * nl : 4, sizeof *s->rows4);
    if (want_xyz)
        s->xyz = large_malloc(3 * p->n_global * sizeof *s->xyz);
    if (!s->rows4 || (want_xyz && !s->xyz))
        st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu vertices", nl);
    for (int b = 0; !st && b < 4; b++)
        st = p->dev->ops->buffer_create(p->dev, 4 * nl * sizeof(double), NULL, &s->buf[b]);
    MPI_REPORT_OPERATOR(r, p);
    s->t0 = MPI_Wtime();
    return mpi_agree(p, st);
}

/* Common start after mpi_enter: checks, the distributed operator, four work
   vectors (result, where given, zeroed first). */
static limn_status open_series(limn_context *ctx, const char *fn, MPI_Comm comm,
                               const limn_mesh *mesh, const limn_series_options *o,
                               const limn_mpi_options *mpi, limn_mpi_result *result,
                               series_mpi *s, limn_series_report *r)
{
    if (result)
        memset(result, 0, sizeof *result);
    memset(s, 0, sizeof *s);
    memset(r, 0, sizeof *r);
    limn_status st = mpi_part_begin(ctx, comm, mpi, &s->p);
    if (st)
        return st;
    mpi_part *p = &s->p;
    st = series_check_options(ctx, o);
    if (!st && p->rank == p->root) {
        if (!mesh)
            st = ctx_fail(ctx, LIMN_ERR_ARGUMENT, "the root rank needs the mesh");
        else if (mesh->vertex_count == 0 || mesh->face_count == 0)
            st = ctx_fail(ctx, LIMN_ERR_TOPOLOGY, "the mesh has no %s",
                           mesh->vertex_count ? "faces" : "vertices");
        else
            st = check_mesh_magnitude(ctx, fn, NULL, mesh);
    }
    st = mpi_agree(p, st);
    if (!st)
        st = mpi_distribute(p, mesh, o->scheme, o->alpha, 0); /* series.c: input order */
    return st ? st : mpi_series_buffers(s, 1, r);
}

/* ----------------------------------------------- the engine of filter.c */

/* Root's positions (3 per input vertex) -> b on every rank. */
static limn_status mpi_upload(const series_engine *e, const double *xyz_root, device_buffer *b)
{
    series_mpi *s = e->user;
    mpi_part *p = &s->p;
    limn_status st = mpi_scatter_rows(p, xyz_root, s->rows4);
    if (!st)
        st = p->dev->ops->buffer_write(p->dev, b, 4 * p->n_owned * sizeof(double), s->rows4);
    return mpi_agree(p, st);
}

/* b's owned rows on every rank -> xyz_root on root. */
static limn_status mpi_download(const series_engine *e, device_buffer *b, double *xyz_root)
{
    series_mpi *s = e->user;
    mpi_part *p = &s->p;
    limn_status st =
        p->dev->ops->buffer_read_at(p->dev, b, 0, 4 * p->n_owned * sizeof(double), s->rows4);
    st = mpi_agree(p, st);
    return st ? st : mpi_gather_rows(p, s->rows4, xyz_root);
}

typedef struct term {
    struct device *dev;
    device_buffer *x, *next, *acc;
    int flags, mode;
} term;

static limn_status rows_term(void *user, const device_csr *rows, device_norms *norms)
{
    term *t = user;
    return t->dev->ops->series->series_step(t->dev, rows, t->x, t->next, NULL, t->acc, t->flags,
                                            t->mode, norms);
}

/* One term as an overlapped product on every rank's rows; a failure is
   carried through the exchanges (series_terms agrees after the last). */
limn_status mpi_series_term(const series_engine *e, device_buffer *x, device_buffer *next,
                            device_buffer *acc, int flags, int mode, limn_status prior)
{
    series_mpi *s = e->user;
    double t0 = MPI_Wtime();
    term t = {s->p.dev, x, next, acc, flags, mode};
    device_norms unused;
    limn_status st = mpi_overlapped(&s->p, &s->p.all, x, rows_term, &t, prior, &unused);
    s->p.stats.seconds_solve += MPI_Wtime() - t0;
    return st;
}

limn_status mpi_series_axpby(const series_engine *e, double a, device_buffer *x, double b,
                             device_buffer *y, device_buffer *out)
{
    mpi_part *p = &((series_mpi *)e->user)->p;
    return mpi_agree(p, p->dev->ops->axpby(p->dev, p->n_owned, a, x, b, y, out));
}

/* The root's result: a copy of mesh with the gathered b, refused when not finite. */
static limn_status mpi_result(const series_engine *e, device_buffer *b, const limn_mesh *mesh,
                              const char *what, limn_mesh **out)
{
    series_mpi *s = e->user;
    mpi_part *p = &s->p;
    limn_status st = mpi_download(e, b, s->xyz);
    if (st)
        return st;
    if (p->rank == p->root) {
        st = series_check_finite(p->ctx, s->xyz, p->n_global, what);
        if (!st)
            st = limn_mesh_copy(p->ctx, mesh, out);
        if (!st)
            memcpy((*out)->positions, s->xyz, 3 * p->n_global * sizeof *s->xyz);
    }
    return mpi_agree(p, st);
}

limn_status mpi_series_agree(const series_engine *e, limn_status st)
{
    return mpi_agree(&((series_mpi *)e->user)->p, st);
}

static const series_engine_ops mpi_ops = {mpi_series_term, mpi_series_axpby, mpi_upload,
                                          mpi_download,    mpi_result,       mpi_series_agree};

/* After the checks: their status agreed (where the communicator is up) and
   the engine of filter.c on the open distributed run (products: the
   report's), carrying a failure through the exchanges. */
static limn_status start_engine(series_mpi *s, limn_status st, series_engine *e,
                                long long *products)
{
    if (s->p.comm != MPI_COMM_NULL)
        st = mpi_agree(&s->p, st);
    *e = (series_engine){s->p.ctx, s, s->buf, products, s->p.rank == s->p.root, 1, &mpi_ops};
    return st;
}

/* The root's out, required (fn names the call). */
static limn_status root_out(series_mpi *s, limn_status st, const char *fn, limn_mesh **out)
{
    if (!st && s->p.rank == s->p.root && !out)
        st = ctx_fail(s->p.ctx, LIMN_ERR_ARGUMENT, "%s: out is NULL on the root", fn);
    return st;
}

/* The end of smooth and denoise: pieces, statistics, the result on root. */
static limn_status finish(series_mpi *s, limn_status st, const limn_mesh *mesh,
                          const limn_mpi_options *mpi, limn_mpi_result *result, limn_mesh **out,
                          limn_series_report *r)
{
    r->seconds_compute = MPI_Wtime() - s->t0;
    if (!st && mpi && mpi->keep_piece)
        st = mpi_pieces(&s->p, mesh, s->xyz, result);
    if (result)
        result->stats = s->p.stats;
    if (st && out) {
        limn_mesh_destroy(*out);
        *out = NULL;
        limn_mpi_result_free(result);
    }
    mpi_series_close(s);
    return st;
}

/* limn_smooth_mpi on structs of this library's layout. */
static limn_status smooth_mpi_sized(limn_context *ctx, MPI_Comm comm, const limn_mesh *mesh,
                                    const limn_series_options *o, int terms, limn_mesh **out,
                                    limn_series_report *r, const limn_mpi_options *mpi,
                                    limn_mpi_result *result)
{
    series_mpi s;
    series_engine e;
    limn_status st = open_series(ctx, "limn_smooth_mpi", comm, mesh, o, mpi, result, &s, r);
    if (!st)
        st = check_count(ctx, "limn_smooth_mpi", "terms", terms, 1, LIMN_MAX_TERMS,
                         "LIMN_MAX_TERMS");
    st = start_engine(&s, root_out(&s, st, "limn_smooth_mpi", out), &e, &r->products);
    if (!st)
        st = series_smooth_run(&e, mesh, terms, out);
    return finish(&s, st, mesh, mpi, result, out, r);
}

/* limn_denoise's refusal of keep_volume on a mesh whose volume is not
   defined, on the root (the others pass st through). */
static limn_status check_root_closed(series_mpi *s, limn_status st, int keep_volume)
{
    const topology *t = &s->p.global.topo;
    if (!st && keep_volume && s->p.rank == s->p.root && !measure_topology_closed(t))
        st = ctx_fail(s->p.ctx, LIMN_ERR_TOPOLOGY,
                      "keeping the volume needs a closed mesh, and this one has %zu boundary, "
                      "%zu non-manifold and %zu inconsistently oriented edges: its volume is "
                      "not defined",
                      t->boundary_edges, t->nonmanifold_edges, t->inconsistent_edges);
    return st;
}

/* limn_denoise_mpi on structs of this library's layout. */
static limn_status denoise_mpi_sized(limn_context *ctx, MPI_Comm comm, const limn_mesh *mesh,
                                     const limn_series_options *o, int m, int steps,
                                     int keep_volume, limn_mesh **out, limn_series_report *r,
                                     const limn_mpi_options *mpi, limn_mpi_result *result)
{
    series_mpi s;
    series_engine e;
    limn_status st = open_series(ctx, "limn_denoise_mpi", comm, mesh, o, mpi, result, &s, r);
    if (!st)
        st = check_count(ctx, "limn_denoise_mpi", "m", m, 0, LIMN_MAX_TERMS, "LIMN_MAX_TERMS");
    if (!st)
        st = check_steps(ctx, "limn_denoise_mpi", steps, m + 1LL, "(m + 1) * steps");
    st = check_root_closed(&s, root_out(&s, st, "limn_denoise_mpi", out), keep_volume);
    st = start_engine(&s, st, &e, &r->products);
    if (!st)
        st = series_denoise_run(&e, mesh, m, steps, keep_volume, out);
    return finish(&s, st, mesh, mpi, result, out, r);
}

/* The root's half of limn_denoise_sure: the fit on the gathered vectors r
   (degree of them, input order; sure_split overwrites them) in the single
   process's arithmetic (sure_denoise_run's), the result a copy of mesh, its
   volume kept. */
static limn_status sure_root(series_mpi *s, const limn_mesh *mesh, int degree, double *r,
                             int keep_volume, limn_mesh **out, double *sigma)
{
    limn_context *ctx = s->p.ctx;
    double t[2 * LIMN_MAX_SURE_PRODUCTS];
    sure_traces(&s->p.global.host, s->p.scheme, 2 * degree, t);
    double mu_max = sure_spectrum_bound(&s->p.global.host);
    limn_status st = limn_mesh_copy(ctx, mesh, out);
    if (!st) /* sure_denoise_run's filter */
        st = sure_filter(ctx, mesh, r, degree, t, mu_max, sigma, (*out)->positions);
    if (!st)
        st = series_check_finite(ctx, (*out)->positions, s->p.n_global, "denoising");
    if (!st && keep_volume)
        st = series_keep_volume(ctx, mesh, *out);
    return st;
}

/* limn_denoise_sure over MPI: the degree products B^i y distributed (halo
   exchanges, the single process's rows and bits), each gathered to the
   root, which fits and combines them as one process does (it holds the
   mesh on this path, and degree vectors as one process does). */
static limn_status sure_run(const series_engine *e, const limn_mesh *mesh, int degree,
                            int keep_volume, limn_mesh **out, double *sigma)
{
    series_mpi *s = e->user;
    size_t n3 = e->root ? 3 * s->p.n_global : 0;
    double *r = e->root ? large_malloc((size_t)degree * n3 * sizeof *r) : NULL;
    limn_status st = mpi_agree(&s->p, e->root && !r ? ctx_fail(s->p.ctx, LIMN_ERR_MEMORY,
                                                               "out of memory for %d vectors",
                                                               degree)
                                                    : LIMN_OK);
    device_buffer **b = e->buf, *cur = b[0];
    if (!st)
        st = e->ops->upload(e, e->root ? mesh->positions : NULL, cur);
    for (int i = 0; !st && i < degree; i++) {
        device_buffer *next = cur == b[1] ? b[2] : b[1];
        st = e->ops->term(e, cur, next, b[3], SERIES_STORE_NEXT, SERIES_ACC_NONE, LIMN_OK);
        ++*e->products;
        st = e->ops->agree(e, st);
        if (!st)
            st = e->ops->download(e, next, r ? r + (size_t)i * n3 : NULL);
        cur = next;
    }
    double sg = 0.0;
    if (!st && e->root)
        st = sure_root(s, mesh, degree, r, keep_volume, out, &sg);
    st = mpi_agree(&s->p, st);
    MPI_Bcast(&sg, 1, MPI_DOUBLE, s->p.root, s->p.comm);
    if (sigma)
        *sigma = sg;
    free(r);
    return st;
}

/* limn_denoise_sure_mpi on structs of this library's layout. */
static limn_status denoise_sure_mpi_sized(limn_context *ctx, MPI_Comm comm, const limn_mesh *mesh,
                                          const limn_series_options *o, int products,
                                          int keep_volume, limn_mesh **out, double *sigma,
                                          limn_series_report *r, const limn_mpi_options *mpi,
                                          limn_mpi_result *result)
{
    const char *fn = "limn_denoise_sure_mpi";
    series_mpi s;
    series_engine e;
    limn_status st = open_series(ctx, fn, comm, mesh, o, mpi, result, &s, r);
    if (!st)
        st = check_count(ctx, fn, "products", products, 1, LIMN_MAX_SURE_PRODUCTS,
                         "LIMN_MAX_SURE_PRODUCTS");
    st = check_root_closed(&s, root_out(&s, st, fn, out), keep_volume);
    st = start_engine(&s, st, &e, &r->products);
    if (!st)
        st = sure_run(&e, mesh, products, keep_volume, out, sigma);
    return finish(&s, st, mesh, mpi, result, out, r);
}

/* limn_sharpen_mpi on structs of this library's layout. */
static limn_status sharpen_mpi_sized(limn_context *ctx, MPI_Comm comm, const limn_mesh *mesh,
                                     const limn_series_options *o, int from, int to, int steps,
                                     limn_mesh **out, limn_series_report *r,
                                     const limn_mpi_options *mpi, limn_mpi_result *result)
{
    series_mpi s;
    series_engine e;
    limn_status st = open_series(ctx, "limn_sharpen_mpi", comm, mesh, o, mpi, result, &s, r);
    if (!st)
        st = series_check_sharpen(ctx, "limn_sharpen_mpi", from, to, steps);
    st = start_engine(&s, root_out(&s, st, "limn_sharpen_mpi", out), &e, &r->products);
    if (!st)
        st = series_sharpen_run(&e, mesh, from, to, steps, out);
    return finish(&s, st, mesh, mpi, result, out, r);
}

/* The sum of squares of xyz (n vertices) as the single process's device
   reduces it: chunks of DEVICE_ROWS_PER_ITEM rows in row order (the series
   run in input order), each summed row by row, the chunks in order. */
static double chunked_energy(const double *xyz, size_t n)
{
    double total = 0.0;
    for (size_t begin = 0; begin < n; begin += DEVICE_ROWS_PER_ITEM) {
        size_t end = begin + DEVICE_ROWS_PER_ITEM < n ? begin + DEVICE_ROWS_PER_ITEM : n;
        double part[3] = {0.0, 0.0, 0.0};
        for (size_t i = begin; i < end; i++)
            ref_norms_add(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2], part);
        total += part[2];
    }
    return total;
}

/* What bands_root hands band_out: the root's bands and energies (may be NULL). */
typedef struct root_bands {
    double *bands, *energy;
    size_t n3;
} root_bands;

/* Band i (count: the remainder) in b gathered to the root, into its slot of
   the root's bands (or the scratch) and its energy there. */
static limn_status band_out(const series_engine *e, device_buffer *b, int i, void *user)
{
    series_mpi *s = e->user;
    root_bands *rb = user;
    double *xyz = rb->bands ? rb->bands + (size_t)i * rb->n3 : s->xyz;
    limn_status st = mpi_download(e, b, xyz);
    if (!st && e->root && rb->energy)
        rb->energy[i] = chunked_energy(xyz, s->p.n_global);
    return st;
}

limn_status mpi_series_bands(const series_engine *e, const double *xyz_root, int count,
                             mpi_band_fn out, void *user)
{
    device_buffer **b = e->buf, *cur = b[0];
    limn_status st = e->ops->upload(e, xyz_root, cur);
    for (int i = 0; !st && i < count; i++) {
        device_buffer *next = cur == b[1] ? b[2] : b[1];
        /* acc = A r_i: the single process's ax, the same values */
        st = e->ops->term(e, cur, next, b[3], SERIES_STORE_NEXT, SERIES_ACC_SET_AX, LIMN_OK);
        ++*e->products;
        st = e->ops->agree(e, st);
        if (!st)
            st = out(e, b[3], i, user);
        cur = next;
        if (count > 1)
            ctx_progress(e->ctx, "bands", (double)(i + 1) / count);
    }
    return st ? st : out(e, cur, count, user);
}

/* limn_bands_mpi on structs of this library's layout. */
static limn_status bands_mpi_sized(limn_context *ctx, MPI_Comm comm, const limn_mesh *mesh,
                                   const limn_series_options *o, int count, double *bands,
                                   double *energy, limn_series_report *r,
                                   const limn_mpi_options *mpi, limn_mpi_result *result)
{
    series_mpi s;
    series_engine e;
    limn_status st = open_series(ctx, "limn_bands_mpi", comm, mesh, o, mpi, result, &s, r);
    if (!st)
        st = check_count(ctx, "limn_bands_mpi", "count", count, 0, LIMN_MAX_TERMS,
                         "LIMN_MAX_TERMS");
    st = start_engine(&s, st, &e, &r->products);
    int root = s.p.rank == s.p.root && mesh; /* a NULL mesh on the root: refused above */
    root_bands rb = {root ? bands : NULL, root ? energy : NULL, root ? 3 * mesh->vertex_count : 0};
    if (!st)
        st = mpi_series_bands(&e, root ? mesh->positions : NULL, count, band_out, &rb);
    r->seconds_compute = MPI_Wtime() - s.t0;
    if (result)
        result->stats = s.p.stats;
    mpi_series_close(&s);
    return st;
}

/* The checks of limn_morph's operator path, run on the root. */
static limn_status check_morph(limn_context *ctx, const limn_mesh *from, const limn_mesh *to,
                               const limn_morph_options *o)
{
    const char *fn = "limn_morph_mpi";
    limn_status st = check_mesh_magnitude(ctx, fn, "FROM", from);
    if (!st)
        st = check_mesh_magnitude(ctx, fn, "TO", to);
    return st ? st : series_check_morph(ctx, fn, from, to, o);
}

/* limn_morph_mpi on structs of this library's layout. */
static limn_status morph_mpi_sized(limn_context *ctx, MPI_Comm comm, const limn_mesh *from,
                                   const limn_mesh *to, const limn_morph_options *o,
                                   limn_morph_frame_fn fn, void *user, limn_series_report *r,
                                   const limn_mpi_options *mpi, limn_mpi_result *result)
{
    if (result)
        memset(result, 0, sizeof *result);
    memset(r, 0, sizeof *r);
    r->size = sizeof *r; /* passed on to limn_morph */
    /* the checks of limn_morph, on the root; agreed before any work */
    mpi_part probe;
    limn_status st = mpi_part_begin(ctx, comm, mpi, &probe);
    if (!st && probe.rank == probe.root) {
        if (!from || !to || !fn)
            st = ctx_fail(ctx, LIMN_ERR_ARGUMENT, "limn_morph_mpi: NULL argument on the root");
        else if (o->linear)
            st = limn_morph(ctx, from, to, o, fn, user, r); /* no operator: the root alone */
        else
            st = check_morph(ctx, from, to, o);
    }
    if (probe.comm != MPI_COMM_NULL)
        st = mpi_agree(&probe, st);
    int linear = o->linear;
    mpi_part_end(&probe);
    if (st || linear)
        return st;

    series_mpi s;
    series_engine e;
    st = open_series(ctx, "limn_morph_mpi", comm, from, &o->series, mpi, result, &s, r);
    double diag = 0.0, lo[3], hi[3], *q = NULL;
    int closed = 0;
    if (!st && s.p.rank == s.p.root) {
        diag = mesh_bbox_diagonal(to, lo, hi);
        closed = measure_topology_closed(&s.p.global.topo);
        q = large_malloc(3 * s.p.n_global * sizeof *q);
        if (!q)
            st = ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for %zu vertices", s.p.n_global);
        for (size_t i = 0; q && i < 3 * s.p.n_global; i++)
            q[i] = from->positions[i] - to->positions[i];
    }
    st = start_engine(&s, st, &e, &r->products);
    if (!st)
        st = series_morph_run(&e, from, to, o, closed, diag, q, fn, user);
    r->seconds_compute = MPI_Wtime() - s.t0;
    if (result)
        result->stats = s.p.stats;
    free(q);
    mpi_series_close(&s);
    return st;
}

limn_status limn_smooth_mpi(limn_context *ctx, MPI_Comm comm, const limn_mesh *mesh,
                            const limn_series_options *options, int terms, limn_mesh **out,
                            limn_series_report *report, const limn_mpi_options *mpi,
                            limn_mpi_result *result)
{
    mpi_call c;
    limn_status st = mpi_enter(&c, ctx, comm, "limn_smooth_mpi", &abi_series_options, options,
                               &abi_series_report, report, mpi, result, out);
    return st ? st
              : mpi_leave(&c, smooth_mpi_sized(ctx, comm, mesh, c.abi.options, terms, out,
                                               c.abi.report, c.mpi, c.result));
}

limn_status limn_denoise_mpi(limn_context *ctx, MPI_Comm comm, const limn_mesh *mesh,
                             const limn_series_options *options, int m, int steps, int keep_volume,
                             limn_mesh **out, limn_series_report *report,
                             const limn_mpi_options *mpi, limn_mpi_result *result)
{
    mpi_call c;
    limn_status st = mpi_enter(&c, ctx, comm, "limn_denoise_mpi", &abi_series_options, options,
                               &abi_series_report, report, mpi, result, out);
    return st ? st
              : mpi_leave(&c, denoise_mpi_sized(ctx, comm, mesh, c.abi.options, m, steps,
                                                keep_volume, out, c.abi.report, c.mpi, c.result));
}

limn_status limn_denoise_sure_mpi(limn_context *ctx, MPI_Comm comm, const limn_mesh *mesh,
                                  const limn_series_options *options, int products,
                                  int keep_volume, limn_mesh **out, double *sigma,
                                  limn_series_report *report, const limn_mpi_options *mpi,
                                  limn_mpi_result *result)
{
    mpi_call c;
    limn_status st = mpi_enter(&c, ctx, comm, "limn_denoise_sure_mpi", &abi_series_options,
                               options, &abi_series_report, report, mpi, result, out);
    return st ? st
              : mpi_leave(&c, denoise_sure_mpi_sized(ctx, comm, mesh, c.abi.options, products,
                                                     keep_volume, out, sigma, c.abi.report, c.mpi,
                                                     c.result));
}

limn_status limn_morph_mpi(limn_context *ctx, MPI_Comm comm, const limn_mesh *from,
                           const limn_mesh *to, const limn_morph_options *options,
                           limn_morph_frame_fn fn, void *user, limn_series_report *report,
                           const limn_mpi_options *mpi, limn_mpi_result *result)
{
    mpi_call c;
    limn_status st = mpi_enter(&c, ctx, comm, "limn_morph_mpi", &abi_morph_options, options,
                               &abi_series_report, report, mpi, result, NULL);
    return st ? st
              : mpi_leave(&c, morph_mpi_sized(ctx, comm, from, to, c.abi.options, fn, user,
                                              c.abi.report, c.mpi, c.result));
}

limn_status limn_sharpen_mpi(limn_context *ctx, MPI_Comm comm, const limn_mesh *mesh,
                             const limn_series_options *options, int from, int to, int steps,
                             limn_mesh **out, limn_series_report *report,
                             const limn_mpi_options *mpi, limn_mpi_result *result)
{
    mpi_call c;
    limn_status st = mpi_enter(&c, ctx, comm, "limn_sharpen_mpi", &abi_series_options, options,
                               &abi_series_report, report, mpi, result, out);
    return st ? st
              : mpi_leave(&c, sharpen_mpi_sized(ctx, comm, mesh, c.abi.options, from, to, steps,
                                                out, c.abi.report, c.mpi, c.result));
}

limn_status limn_bands_mpi(limn_context *ctx, MPI_Comm comm, const limn_mesh *mesh,
                           const limn_series_options *options, int count, double *bands,
                           double *energy, limn_series_report *report,
                           const limn_mpi_options *mpi, limn_mpi_result *result)
{
    mpi_call c;
    limn_status st = mpi_enter(&c, ctx, comm, "limn_bands_mpi", &abi_series_options, options,
                               &abi_series_report, report, mpi, result, NULL);
    return st ? st
              : mpi_leave(&c, bands_mpi_sized(ctx, comm, mesh, c.abi.options, count, bands,
                                              energy, c.abi.report, c.mpi, c.result));
}
