/* SPDX-License-Identifier: MIT */
/*
 * limn_mpi_mesh_smooth, _denoise and _sharpen: the series filters with no
 * rank holding the whole mesh. The rows are built as
 * limn_mpi_mesh_interpolate builds them (mpi_mesh_build_rows: PT-Scotch,
 * then mpi_local_build), the terms are the distributed series core of
 * mpi_series.c (filter.c's loops over mpi_series_term and _axpby), and the
 * owned results go back to the vertex blocks of a new distributed mesh with
 * the input's faces (mpi_mesh_results_to_blocks, mpi_mesh_control_of). Each
 * row is summed in the single process's order, so the results are the
 * single process's bits. Denoising with keep_volume checks the mesh is
 * closed (mpi_mesh_census) and scales the result as limn_denoise does
 * (mpi_mesh_keep_volume: the volumes and the centroid summed in the single
 * process's order), so those bits are the single process's too.
 * limn_mpi_mesh_bands gives each band as a distributed mesh, its energy
 * summed in the single process's order by passing the running sums from
 * rank to rank.
 */
#include "mpi/mpi_mesh.h"
#include "base/large_alloc.h"
#include "mpi/mpi_features.h"
#include "mpi/mpi_series.h"

#include "base/context.h"
#include "device/reference/device_ref.h"
#include "mesh/check.h"
#include "mesh/mesh.h"
#include "series/series.h"
#include "series/sure.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The input's owned rows (mpi_local_build's) -> b; every filter uploads
   once, so they go then (the per-rank peak). */
static limn_status mesh_upload(const series_engine *e, const double *xyz_root, device_buffer *b)
{
    (void)xyz_root; /* no rank holds the mesh: e->root is 0 everywhere */
    series_mpi *s = e->user;
    mpi_part *p = &s->p;
    limn_status st = s->m4 ? p->dev->ops->buffer_write(p->dev, b, 4 * p->n_owned * sizeof(double),
                                                       s->m4)
                           : ctx_fail(p->ctx, LIMN_ERR_ARGUMENT, "the input was uploaded already");
    free(s->m4);
    s->m4 = NULL;
    return mpi_agree(p, st);
}

/* Whole vectors are never gathered here (morph and bands take the root path). */
static limn_status mesh_download(const series_engine *e, device_buffer *b, double *xyz_root)
{
    (void)b;
    (void)xyz_root;
    series_mpi *s = e->user;
    return mpi_agree(&s->p, ctx_fail(s->p.ctx, LIMN_ERR_ARGUMENT,
                                     "a distributed mesh's series has no whole vector to gather"));
}

/* b's owned rows, refused when not finite (the lowest such vertex of the
   lowest failing rank named), into the blocks of *s->out. */
static limn_status mesh_result(const series_engine *e, device_buffer *b, const limn_mesh *mesh,
                               const char *what, limn_mesh **out)
{
    (void)mesh;
    (void)out;
    series_mpi *s = e->user;
    mpi_part *p = &s->p;
    limn_status st =
        p->dev->ops->buffer_read_at(p->dev, b, 0, 4 * p->n_owned * sizeof(double), s->rows4);
    size_t bad = (size_t)-1;
    for (size_t i = 0; !st && i < p->n_owned; i++)
        for (int c = 0; c < 3; c++)
            if (!isfinite(s->rows4[4 * i + c]) && p->owned_ids[i] < bad)
                bad = p->owned_ids[i];
    if (!st && bad != (size_t)-1)
        st = ctx_fail(p->ctx, LIMN_ERR_NO_CONVERGENCE,
                       "%s produced a non-finite coordinate at vertex %zu; nothing was "
                       "written (use fewer steps or terms)",
                       what, bad);
    st = mpi_agree(p, st);
    double *block = NULL;
    if (!st)
        st = mpi_mesh_results_to_blocks(p, s->mesh, s->rows4, &block);
    return st ? st : mpi_mesh_control_of(p, s->mesh, block, s->out);
}

static const series_engine_ops mesh_ops = {mpi_series_term, mpi_series_axpby, mesh_upload,
                                           mesh_download,   mesh_result,      mpi_series_agree};

/* Common start after mpi_enter: checks (this call's own, st, included), the
   rows, four work vectors, the engine. Returns with s->p.comm NULL only when
   nothing could be agreed. */
limn_status mpi_mesh_series_open(limn_context *ctx, const char *fn, const limn_mpi_mesh *mesh,
                                    const limn_series_options *o, const limn_mpi_options *mpi,
                                    limn_status st, limn_mpi_mesh **out, series_mpi *s,
                                    series_engine *e, limn_series_report *r)
{
    memset(s, 0, sizeof *s);
    memset(r, 0, sizeof *r);
    limn_status begun = mpi_mesh_part(ctx, mesh, mpi, &s->p);
    if (s->p.comm == MPI_COMM_NULL)
        return begun;
    st = begun ? begun : st;
    if (!st)
        st = series_check_options(ctx, o);
    if (!st && !out)
        st = ctx_fail(ctx, LIMN_ERR_ARGUMENT, "%s: out is NULL", fn);
    st = mpi_agree(&s->p, st);
    if (!st && (mesh->vertex_dist[mesh->size] == 0 || mesh->face_dist[mesh->size] == 0))
        st = ctx_fail(ctx, LIMN_ERR_TOPOLOGY, "the mesh has no %s",
                       mesh->vertex_dist[mesh->size] ? "faces" : "vertices");
    if (!st)
        st = mpi_mesh_check(&s->p, fn, mesh);
    limn_scheme scheme = LIMN_SCHEME_AUTO;
    if (!st)
        st = mpi_mesh_scheme(&s->p, mesh, o->scheme, &scheme);
    if (!st)
        st = mpi_mesh_build_rows(&s->p, mesh, scheme, o->alpha, &s->m4);
    if (!st) /* p.diag: the local build's */
        st = mpi_series_buffers(s, 0, r);
    s->mesh = mesh;
    s->out = out;
    *e = (series_engine){ctx, s, s->buf, &r->products, 0, 1, &mesh_ops};
    return st;
}

/* The end of every filter: timing, statistics, *out dropped on failure. */
limn_status mpi_mesh_series_close(series_mpi *s, limn_status st, limn_mpi_result *result,
                                     limn_series_report *r)
{
    r->seconds_compute = MPI_Wtime() - s->t0;
    if (result)
        result->stats = s->p.stats;
    if (st && s->out) {
        limn_mpi_mesh_destroy(*s->out);
        *s->out = NULL;
    }
    mpi_series_close(s);
    return st;
}

/* limn_mpi_mesh_smooth on structs of this library's layout. */
static limn_status smooth_sized(limn_context *ctx, const limn_mpi_mesh *mesh,
                                const limn_series_options *o, int terms, limn_mpi_mesh **out,
                                limn_series_report *r, const limn_mpi_options *mpi,
                                limn_mpi_result *result)
{
    const char *fn = "limn_mpi_mesh_smooth";
    series_mpi s;
    series_engine e;
    limn_status st = check_count(ctx, fn, "terms", terms, 1, LIMN_MAX_TERMS, "LIMN_MAX_TERMS");
    st = mpi_mesh_series_open(ctx, fn, mesh, o, mpi, st, out, &s, &e, r);
    if (s.p.comm == MPI_COMM_NULL)
        return st;
    if (!st)
        st = series_smooth_run(&e, NULL, terms, NULL);
    return mpi_mesh_series_close(&s, st, result, r);
}

limn_status mpi_mesh_check_closed(mpi_part *p, const limn_mpi_mesh *mesh)
{
    mpi_mesh_counts k;
    limn_status st = mpi_mesh_census(p, mesh, &k);
    if (!st && (k.boundary_edges || k.nonmanifold_edges || k.inconsistent_edges))
        st = ctx_fail(p->ctx, LIMN_ERR_TOPOLOGY,
                      "keeping the volume needs a closed mesh, and this one has %zu boundary, "
                      "%zu non-manifold and %zu inconsistently oriented edges: its volume is "
                      "not defined",
                      k.boundary_edges, k.nonmanifold_edges, k.inconsistent_edges);
    return st;
}

/* limn_mpi_mesh_denoise on structs of this library's layout. */
static limn_status denoise_sized(limn_context *ctx, const limn_mpi_mesh *mesh,
                                 const limn_series_options *o, int m, int steps, int keep_volume,
                                 limn_mpi_mesh **out, limn_series_report *r,
                                 const limn_mpi_options *mpi, limn_mpi_result *result)
{
    const char *fn = "limn_mpi_mesh_denoise";
    series_mpi s;
    series_engine e;
    limn_status st = check_count(ctx, fn, "m", m, 0, LIMN_MAX_TERMS, "LIMN_MAX_TERMS");
    if (!st)
        st = check_steps(ctx, fn, steps, m + 1LL, "(m + 1) * steps");
    st = mpi_mesh_series_open(ctx, fn, mesh, o, mpi, st, out, &s, &e, r);
    if (s.p.comm == MPI_COMM_NULL)
        return st;
    if (!st && keep_volume)
        st = mpi_mesh_check_closed(&s.p, mesh);
    /* keep_volume after the run: filter.c's step needs the whole mesh on the root */
    if (!st)
        st = series_denoise_run(&e, NULL, m, steps, 0, NULL);
    if (!st && keep_volume)
        st = mpi_agree(&s.p, mpi_mesh_keep_volume(&s.p, mesh, *out));
    return mpi_mesh_series_close(&s, st, result, r);
}

/* sure_sum's dot over the vertex blocks: the ranks in turn carry the
   running sum along (input order, the single process's additions). */
static double chained_dot(void *user, const double *x, const double *y, size_t n)
{
    mpi_part *p = user;
    double s = 0.0;
    if (p->rank > 0)
        MPI_Recv(&s, 1, MPI_DOUBLE, p->rank - 1, 2, p->comm, MPI_STATUS_IGNORE);
    s = sure_dot_from(s, x, y, n);
    if (p->rank + 1 < p->size)
        MPI_Send(&s, 1, MPI_DOUBLE, p->rank + 1, 2, p->comm);
    MPI_Bcast(&s, 1, MPI_DOUBLE, p->size - 1, p->comm);
    return s;
}

/* sure_sum's agreement: mpi_agree. */
static limn_status agree_blocks(void *user, limn_status st)
{
    return mpi_agree(user, st);
}

/* The owned rows of b (or, b NULL, each owned row's 1 - a_vv in its first
   slot) into the vertex blocks, 3 per block vertex, at dst. */
static limn_status rows_to_block(series_mpi *s, device_buffer *b, double *dst)
{
    mpi_part *p = &s->p;
    limn_status st = LIMN_OK;
    if (b)
        st = p->dev->ops->buffer_read_at(p->dev, b, 0, 4 * p->n_owned * sizeof(double), s->rows4);
    for (size_t i = 0; !b && i < p->n_owned; i++)
        s->rows4[4 * i] = sure_row_diagonal(&p->host, i);
    st = mpi_agree(p, st);
    double *block = NULL;
    if (!st)
        st = mpi_mesh_results_to_blocks(p, s->mesh, s->rows4, &block);
    if (!st)
        memcpy(dst, block, 3 * s->mesh->slice.vertex_count * sizeof *dst);
    free(block);
    return st;
}

/* series_check_finite on the blocks: the lowest non-finite vertex of all. */
static limn_status check_finite_blocks(mpi_part *p, const limn_mpi_mesh *mesh, const double *q)
{
    unsigned long long bad = ULLONG_MAX, all;
    for (size_t k = 0; k < 3 * mesh->slice.vertex_count && bad == ULLONG_MAX; k++)
        if (!isfinite(q[k]))
            bad = mesh->vertex_dist[p->rank] + k / 3;
    MPI_Allreduce(&bad, &all, 1, MPI_UNSIGNED_LONG_LONG, MPI_MIN, p->comm);
    if (all == ULLONG_MAX)
        return LIMN_OK;
    return ctx_fail(p->ctx, LIMN_ERR_NO_CONVERGENCE,
                    "denoising produced a non-finite coordinate at vertex %llu; nothing was "
                    "written (use fewer steps or terms)",
                    all);
}

/* sure_spectrum_bound of the whole operator: a max over rows, so the max
   of the ranks' owned rows (exact, in any order). Before p->host goes. */
static double spectrum_bound(const mpi_part *p)
{
    double mine = sure_spectrum_bound(&p->host), all = 0.0;
    MPI_Allreduce(&mine, &all, 1, MPI_DOUBLE, MPI_MAX, p->comm);
    return all;
}

/* The unit normals of the block's vertices at the block's positions x (3
   a vertex) into nrm, as sure_vertex_normals gives them on the whole mesh:
   on this rank's patch (every face around a block vertex, in increasing
   id: each vertex's faces added in the single process's order), its ghost
   vertices' positions from their block owners. */
static limn_status block_normals(mpi_part *p, const limn_mpi_mesh *mesh, const double *x,
                                 double *nrm)
{
    size_t nb = mesh->slice.vertex_count;
    mpi_feature_patch fp;
    limn_status st = mpi_feature_patch_build(p, mesh, &fp);
    if (st)
        return st;
    double *pos = fp.mesh->positions;
    memcpy(pos + 3 * fp.vertex_base, x, 3 * nb * sizeof *pos);
    st = mpi_feature_sync_vertices(p, mesh, &fp, pos);
    double *pn = st ? NULL : large_malloc((3 * fp.mesh->vertex_count + 1) * sizeof *pn);
    if (!st && !pn)
        st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu normals",
                      fp.mesh->vertex_count);
    st = mpi_agree(p, st);
    if (!st) {
        sure_vertex_normals(fp.mesh, pos, pn);
        memcpy(nrm, pn + 3 * fp.vertex_base, 3 * nb * sizeof *nrm);
    }
    free(pn);
    mpi_feature_patch_free(&fp);
    return st;
}

/* The SURE filter on the blocks: tr(E - A), the spectrum bound and the
   degree vectors B^i y (distributed products) in block order, then the noise
   estimate (sure_sigma with chained_dot), the block's normals of
   sure_frame_positions and sure_split, every rank on its block. */
static limn_status sure_blocks(series_mpi *s, const series_engine *e, int degree, double *r,
                               double *q, double *sigma)
{
    mpi_part *p = &s->p;
    const limn_mpi_mesh *mesh = s->mesh;
    size_t n3 = 3 * mesh->slice.vertex_count;
    double t[2 * LIMN_MAX_SURE_PRODUCTS], tr[3], mu_max = 0.0;
    limn_status st = rows_to_block(s, NULL, q); /* the diagonal first: p->host goes later */
    if (!st) {
        mu_max = spectrum_bound(p);
        mpi_mesh_chained_sums(p, q, mesh->slice.vertex_count, 3, tr);
        sure_traces_from(tr[0], mesh->vertex_dist[p->size], p->scheme, 2 * degree, t);
        st = e->ops->upload(e, NULL, e->buf[0]);
    }
    device_buffer **b = e->buf, *cur = b[0];
    for (int i = 0; !st && i < degree; i++) {
        device_buffer *next = cur == b[1] ? b[2] : b[1];
        st = e->ops->term(e, cur, next, b[3], SERIES_STORE_NEXT, SERIES_ACC_NONE, LIMN_OK);
        ++*e->products;
        st = e->ops->agree(e, st);
        if (!st)
            st = rows_to_block(s, next, r + (size_t)i * n3);
        cur = next;
    }
    sure_sum sum = {chained_dot, agree_blocks, p};
    if (!st)
        *sigma = sure_sigma(r, n3, degree, t, &sum);
    double *nrm = st ? NULL : large_malloc((n3 + 1) * sizeof *nrm), split_sigma[2];
    if (!st && !nrm)
        st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu normals", n3 / 3);
    st = mpi_agree(p, st);
    if (!st) {
        sure_frame_positions(mesh->slice.positions, r, n3, degree, q);
        st = block_normals(p, mesh, q, nrm);
    }
    if (!st)
        st = mpi_agree(p, sure_split(p->ctx, mesh->slice.positions, r, n3, degree, t, &sum,
                                     mu_max, nrm, split_sigma, q));
    free(nrm);
    return st ? st : check_finite_blocks(p, mesh, q);
}

/* limn_mpi_mesh_denoise_sure on structs of this library's layout. */
static limn_status denoise_sure_sized(limn_context *ctx, const limn_mpi_mesh *mesh,
                                      const limn_series_options *o, int products,
                                      int keep_volume, limn_mpi_mesh **out, double *sigma,
                                      limn_series_report *r, const limn_mpi_options *mpi,
                                      limn_mpi_result *result)
{
    const char *fn = "limn_mpi_mesh_denoise_sure";
    series_mpi s;
    series_engine e;
    limn_status st = check_count(ctx, fn, "products", products, 1, LIMN_MAX_SURE_PRODUCTS,
                                 "LIMN_MAX_SURE_PRODUCTS");
    st = mpi_mesh_series_open(ctx, fn, mesh, o, mpi, st, out, &s, &e, r);
    if (s.p.comm == MPI_COMM_NULL)
        return st;
    if (!st && keep_volume)
        st = mpi_mesh_check_closed(&s.p, mesh);
    size_t n3 = 3 * mesh->slice.vertex_count + 1; /* + 1: an empty block */
    double *rv = large_malloc((size_t)products * n3 * sizeof *rv);
    double *q = large_malloc(n3 * sizeof *q);
    if (!st && (!rv || !q))
        st = ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for %d vectors of %zu vertices",
                      products, mesh->slice.vertex_count);
    st = mpi_agree(&s.p, st);
    double sg = 0.0;
    if (!st)
        st = sure_blocks(&s, &e, products, rv, q, &sg);
    free(rv);
    if (!st) {
        st = mpi_mesh_control_of(&s.p, mesh, q, out); /* takes q */
        q = NULL;
    }
    free(q);
    if (!st && keep_volume)
        st = mpi_agree(&s.p, mpi_mesh_keep_volume(&s.p, mesh, *out));
    if (sigma)
        *sigma = st ? 0.0 : sg;
    return mpi_mesh_series_close(&s, st, result, r);
}

/* limn_mpi_mesh_sharpen on structs of this library's layout. */
static limn_status sharpen_sized(limn_context *ctx, const limn_mpi_mesh *mesh,
                                 const limn_series_options *o, int from, int to, int steps,
                                 limn_mpi_mesh **out, limn_series_report *r,
                                 const limn_mpi_options *mpi, limn_mpi_result *result)
{
    const char *fn = "limn_mpi_mesh_sharpen";
    series_mpi s;
    series_engine e;
    limn_status st = series_check_sharpen(ctx, fn, from, to, steps);
    st = mpi_mesh_series_open(ctx, fn, mesh, o, mpi, st, out, &s, &e, r);
    if (s.p.comm == MPI_COMM_NULL)
        return st;
    if (!st)
        st = series_sharpen_run(&e, NULL, from, to, steps, NULL);
    return mpi_mesh_series_close(&s, st, result, r);
}

/* The energy of a vector in the vertex blocks (3 per block vertex) as the
   single process's device sums the whole (mpi_series.c's chunked_energy:
   chunks of DEVICE_ROWS_PER_ITEM rows in input order, each row by row, the
   chunks in order): the ranks in turn carry the running sums along, so the
   arithmetic is the same; every rank gets the total. */
static double chained_energy(mpi_part *p, const limn_mpi_mesh *mesh, const double *xyz)
{
    double carry[2] = {0.0, 0.0}; /* the total of the closed chunks, the open chunk's sum */
    if (p->rank > 0)
        MPI_Recv(carry, 2, MPI_DOUBLE, p->rank - 1, 0, p->comm, MPI_STATUS_IGNORE);
    size_t begin = mesh->vertex_dist[p->rank];
    double part[3] = {0.0, 0.0, carry[1]};
    for (size_t i = 0; i < mesh->slice.vertex_count; i++) {
        size_t g = begin + i;
        if (g > 0 && g % DEVICE_ROWS_PER_ITEM == 0) {
            carry[0] += part[2];
            part[0] = part[1] = part[2] = 0.0;
        }
        ref_norms_add(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2], part);
    }
    carry[1] = part[2];
    if (p->rank + 1 < p->size)
        MPI_Send(carry, 2, MPI_DOUBLE, p->rank + 1, 0, p->comm);
    else
        carry[0] += carry[1];
    MPI_Bcast(carry, 1, MPI_DOUBLE, p->size - 1, p->comm);
    return carry[0];
}

/* Where band i goes: bands[i], its energy energy[i] (may be NULL). */
typedef struct mesh_bands {
    limn_mpi_mesh **bands;
    double *energy;
} mesh_bands;

static limn_status mesh_band_out(const series_engine *e, device_buffer *b, int i, void *user)
{
    series_mpi *s = e->user;
    mpi_part *p = &s->p;
    mesh_bands *mb = user;
    limn_status st = mpi_agree(p, p->dev->ops->buffer_read_at(
                                      p->dev, b, 0, 4 * p->n_owned * sizeof(double), s->rows4));
    double *block = NULL;
    if (!st)
        st = mpi_mesh_results_to_blocks(p, s->mesh, s->rows4, &block);
    if (!st) { /* collective: every rank sums, whether it keeps the energy or not */
        double en = chained_energy(p, s->mesh, block);
        if (mb->energy)
            mb->energy[i] = en;
    }
    return st ? st : mpi_mesh_control_of(p, s->mesh, block, &mb->bands[i]);
}

/* limn_mpi_mesh_bands on structs of this library's layout. */
static limn_status bands_sized(limn_context *ctx, const limn_mpi_mesh *mesh,
                               const limn_series_options *o, int count, limn_mpi_mesh **bands,
                               double *energy, limn_series_report *r,
                               const limn_mpi_options *mpi, limn_mpi_result *result)
{
    const char *fn = "limn_mpi_mesh_bands";
    series_mpi s;
    series_engine e;
    limn_status st = check_count(ctx, fn, "count", count, 0, LIMN_MAX_TERMS, "LIMN_MAX_TERMS");
    if (!st && !bands)
        st = ctx_fail(ctx, LIMN_ERR_ARGUMENT, "%s: bands is NULL", fn);
    for (int i = 0; !st && i <= count; i++)
        bands[i] = NULL;
    limn_mpi_mesh *unused = NULL;
    st = mpi_mesh_series_open(ctx, fn, mesh, o, mpi, st, &unused, &s, &e, r);
    if (s.p.comm == MPI_COMM_NULL)
        return st;
    mesh_bands mb = {bands, energy};
    if (!st)
        st = mpi_series_bands(&e, NULL, count, mesh_band_out, &mb);
    for (int i = 0; st && bands && i <= count; i++) {
        limn_mpi_mesh_destroy(bands[i]);
        bands[i] = NULL;
    }
    s.out = NULL;
    return mpi_mesh_series_close(&s, st, result, r);
}

/* mpi_enter on the mesh's communicator (*out cleared first). */
static limn_status enter(mpi_call *c, limn_context *ctx, const limn_mpi_mesh *mesh,
                         const char *fn, const limn_series_options *options,
                         limn_series_report *report, const limn_mpi_options *mpi,
                         limn_mpi_result *result, limn_mpi_mesh **out)
{
    if (out)
        *out = NULL;
    if (!mesh)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "%s: the mesh is NULL", fn);
    return mpi_enter(c, ctx, mesh->comm, fn, &abi_series_options, options, &abi_series_report,
                     report, mpi, result, NULL);
}

limn_status limn_mpi_mesh_smooth(limn_context *ctx, const limn_mpi_mesh *mesh,
                                 const limn_series_options *options, int terms,
                                 limn_mpi_mesh **out, limn_series_report *report,
                                 const limn_mpi_options *mpi, limn_mpi_result *result)
{
    mpi_call c;
    limn_status st =
        enter(&c, ctx, mesh, "limn_mpi_mesh_smooth", options, report, mpi, result, out);
    return st ? st
              : mpi_leave(&c, smooth_sized(ctx, mesh, c.abi.options, terms, out, c.abi.report,
                                           c.mpi, c.result));
}

limn_status limn_mpi_mesh_denoise(limn_context *ctx, const limn_mpi_mesh *mesh,
                                  const limn_series_options *options, int m, int steps,
                                  int keep_volume, limn_mpi_mesh **out,
                                  limn_series_report *report, const limn_mpi_options *mpi,
                                  limn_mpi_result *result)
{
    mpi_call c;
    limn_status st =
        enter(&c, ctx, mesh, "limn_mpi_mesh_denoise", options, report, mpi, result, out);
    return st ? st
              : mpi_leave(&c, denoise_sized(ctx, mesh, c.abi.options, m, steps, keep_volume,
                                            out, c.abi.report, c.mpi, c.result));
}

limn_status limn_mpi_mesh_denoise_sure(limn_context *ctx, const limn_mpi_mesh *mesh,
                                       const limn_series_options *options, int products,
                                       int keep_volume, limn_mpi_mesh **out, double *sigma,
                                       limn_series_report *report, const limn_mpi_options *mpi,
                                       limn_mpi_result *result)
{
    mpi_call c;
    limn_status st =
        enter(&c, ctx, mesh, "limn_mpi_mesh_denoise_sure", options, report, mpi, result, out);
    return st ? st
              : mpi_leave(&c, denoise_sure_sized(ctx, mesh, c.abi.options, products, keep_volume,
                                                 out, sigma, c.abi.report, c.mpi, c.result));
}

limn_status limn_mpi_mesh_sharpen(limn_context *ctx, const limn_mpi_mesh *mesh,
                                  const limn_series_options *options, int from, int to,
                                  int steps, limn_mpi_mesh **out, limn_series_report *report,
                                  const limn_mpi_options *mpi, limn_mpi_result *result)
{
    mpi_call c;
    limn_status st =
        enter(&c, ctx, mesh, "limn_mpi_mesh_sharpen", options, report, mpi, result, out);
    return st ? st
              : mpi_leave(&c, sharpen_sized(ctx, mesh, c.abi.options, from, to, steps, out,
                                            c.abi.report, c.mpi, c.result));
}

limn_status limn_mpi_mesh_bands(limn_context *ctx, const limn_mpi_mesh *mesh,
                                const limn_series_options *options, int count,
                                limn_mpi_mesh **bands, double *energy,
                                limn_series_report *report, const limn_mpi_options *mpi,
                                limn_mpi_result *result)
{
    mpi_call c;
    limn_status st =
        enter(&c, ctx, mesh, "limn_mpi_mesh_bands", options, report, mpi, result, NULL);
    return st ? st
              : mpi_leave(&c, bands_sized(ctx, mesh, c.abi.options, count, bands, energy,
                                          c.abi.report, c.mpi, c.result));
}
