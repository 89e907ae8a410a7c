/* SPDX-License-Identifier: MIT */
/*
 * limn_mpi_mesh_texture: limn_texture with no rank holding the whole mesh.
 * Level i is a distributed mesh of mpi_refine_level's steps; its noise is
 * evaluated at the positions each rank's rows hold (position only), the
 * scalar interpolation is the single process's loop (the paper step,
 * omega 1, the same monitor) run as overlapped products on the local rows
 * of mpi_local_build with the maximum reduced exactly; the controls go back
 * to the level's owners and are carried down the steps as a refined field
 * (three fields per extra mpi_refine_level on a copy of the segments: every
 * point from the same parents with the same weights, as refine_plan_apply
 * computes it); on G_L they are summed in level order, the limit of the sum
 * and of the positions is mpi_refine_limit's (subdivide --limit), and the
 * colours follow from the range reduced over the ranks. Every number is
 * the single process's, so the file is its bytes.
 */
#include "mpi/mpi_refine.h"
#include "base/large_alloc.h"

#include "base/context.h"
#include "device/device.h"
#include "device/choice/choice.h"
#include "mesh/check.h"
#include "mpi/mpi_blocks.h"
#include "series/series.h"
#include "solve/monitor.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define TEXTURE_MAX_ITER 2000 /* texture.c's cap */

/* The run's state on this rank. */
typedef struct tex {
    mpi_part *p;
    const limn_texture_options *o;
    const limn_mpi_options *mpi;
    limn_series_report *r;
    limn_scheme scheme;
    limn_noise noise;
    double lo[3], scale;
    mpi_rmesh cur;    /* the level, on its owners */
    int fields;       /* the levels' controls carried to cur so far */
    double *carried;  /* fields * cur.n_owned, field-major */
} tex;

/* G_0's bbox corner and the noise's scale, as mesh_bbox_diagonal gives them. */
static void noise_frame(tex *t, const limn_mpi_mesh *mesh)
{
    const mesh_slice *s = &mesh->slice;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t v = 0; v < s->vertex_count; v++)
        for (int c = 0; c < 3; c++) {
            double x = s->positions[3 * v + c];
            lo[c] = x < lo[c] ? x : lo[c];
            hi[c] = x > hi[c] ? x : hi[c];
        }
    double glo[3], ghi[3];
    MPI_Allreduce(lo, glo, 3, MPI_DOUBLE, MPI_MIN, t->p->comm);
    MPI_Allreduce(hi, ghi, 3, MPI_DOUBLE, MPI_MAX, t->p->comm);
    double diag = sqrt((ghi[0] - glo[0]) * (ghi[0] - glo[0]) +
                       (ghi[1] - glo[1]) * (ghi[1] - glo[1]) +
                       (ghi[2] - glo[2]) * (ghi[2] - glo[2]));
    memcpy(t->lo, glo, sizeof glo);
    t->scale = diag > 0 ? t->o->frequency / diag : 1.0;
}

/* The single process's solve_scalar on the level's rows: buffers and step. */
typedef struct scalar_solve {
    mpi_part *p;
    device_buffer *m, *x[2];
    int cur;
} scalar_solve;

static limn_status rows_step(void *user, const device_csr *rows, device_norms *norms)
{
    scalar_solve *s = user;
    struct device *dev = s->p->dev;
    return dev->ops->stationary->interp_step(dev, rows, s->m, s->x[s->cur], s->x[1 - s->cur],
                                             1.0, norms);
}

/* p_{k+1} = p_k + (N - A p_k) from p_0 = N (m4's channel x) to the monitor's
   verdict on the global maximum; the answer's owned rows into p4. */
static limn_status solve_scalar(tex *t, mpi_part *lp, const double *m4, double tol, int level,
                                double *p4)
{
    const device_ops *ops = lp->dev->ops;
    size_t row = 4 * sizeof(double), nl = lp->n_owned + lp->n_ghost;
    scalar_solve s = {.p = lp};
    limn_status st = ops->buffer_create(lp->dev, (lp->n_owned ? lp->n_owned : 1) * row, m4, &s.m);
    memcpy(p4, m4, lp->n_owned * row);
    if (!st)
        st = ops->buffer_create(lp->dev, (nl ? nl : 1) * row, p4, &s.x[0]);
    if (!st)
        st = ops->buffer_create(lp->dev, (nl ? nl : 1) * row, NULL, &s.x[1]);
    st = mpi_agree(lp, st);
    monitor mon;
    monitor_init(&mon, tol, TEXTURE_MAX_ITER, MONITOR_STALL_WINDOW, MONITOR_STALL_RATIO);
    monitor_words words = {MONITOR_LOOP_TEXTURE, "the residual of the noise interpolation", 0.0,
                           0.0, t->scheme, lp->alpha, 0, 0, level};
    int answer = -1;
    for (int k = 0; !st && answer < 0; k++) {
        device_norms local, nr;
        s.cur = k & 1;
        st = mpi_overlapped(lp, &lp->all, s.x[k & 1], rows_step, &s, LIMN_OK, &local);
        st = mpi_reduce_norms(lp, st, &local, &nr);
        t->r->products++;
        if (st)
            break;
        nr.max = check_norm_max(nr.max, nr.sum);
        monitor_verdict v = monitor_step(&mon, nr.max, k);
        if (v == MONITOR_CONVERGED)
            answer = k & 1;
        else if (v != MONITOR_CONTINUE)
            st = monitor_fail(lp->ctx, &mon, v, &words);
    }
    if (!st)
        st = ops->buffer_read_at(lp->dev, s.x[answer], 0, lp->n_owned * row, p4);
    device_buffer *all[] = {s.m, s.x[0], s.x[1]};
    for (int k = 0; k < 3; k++)
        if (all[k])
            ops->buffer_release(lp->dev, all[k]);
    return mpi_agree(lp, st);
}

/* Level i's noise on the positions of the owned rows (channel x, the others
   zero) and its largest magnitude over the ranks. */
static double level_noise(tex *t, mpi_part *lp, double *m4, int level)
{
    double f = ldexp(1.0, level), amp = 1.0 / f, fs = f * t->scale, range = 0.0, all = 0.0;
    for (size_t v = 0; v < lp->n_owned; v++) {
        double *q = m4 + 4 * v;
        q[0] = amp * limn_noise_eval(&t->noise, fs * (q[0] - t->lo[0]), fs * (q[1] - t->lo[1]),
                                     fs * (q[2] - t->lo[2]));
        q[1] = q[2] = q[3] = 0.0;
        range = fmax(range, fabs(q[0]));
    }
    MPI_Allreduce(&range, &all, 1, MPI_DOUBLE, MPI_MAX, lp->comm);
    return all;
}

/* The controls of level i's noise on lm (the level in even blocks): *block,
   3 doubles per block vertex, the control in the first. */
static limn_status level_controls(tex *t, const limn_mpi_mesh *lm, int level, double **block)
{
    mpi_part lp;
    limn_status st = mpi_mesh_part(t->p->ctx, lm, t->mpi, &lp);
    if (lp.comm == MPI_COMM_NULL)
        return st;
    double alpha = level == 0 ? t->r->alpha : 0.0, *m4 = NULL, *p4 = NULL;
    if (!st)
        st = mpi_mesh_build_rows(&lp, lm, t->scheme, alpha, &m4);
    if (!st) {
        size_t nl = lp.n_owned + lp.n_ghost;
        p4 = calloc(nl ? 4 * nl : 4, sizeof *p4);
        st = mpi_agree(&lp, p4 ? LIMN_OK : ctx_fail(lp.ctx, LIMN_ERR_MEMORY,
                                                    "out of memory for %zu vertices", nl));
    }
    if (!st) {
        double range = level_noise(t, &lp, m4, level);
        st = solve_scalar(t, &lp, m4, t->o->tolerance * (range > 0 ? range : 1.0), level, p4);
    }
    if (!st && level == t->o->levels) {
        t->r->stencil_nonzeros = lp.nnz_global;
        t->r->bbox_diagonal = lp.diag;
    }
    free(m4);
    mpi_part_drop_rows(&lp);
    if (!st)
        st = mpi_mesh_results_to_blocks(&lp, lm, p4, block);
    free(p4);
    mpi_part_end(&lp);
    return st;
}

/* The values of block (3 doubles per vertex of dist's blocks, the first
   kept) at cur's owned vertices, appended to t->carried as a new field. */
static limn_status append_field(tex *t, const size_t *dist, const double *block)
{
    mpi_part *p = t->p;
    size_t n = t->cur.n_owned;
    uint32_t *ids = large_malloc((n ? n : 1) * sizeof *ids);
    double *got = large_malloc((n ? 3 * n : 3) * sizeof *got);
    double *more = realloc(t->carried, ((size_t)t->fields + 1) * (n ? n : 1) * sizeof *more);
    if (more)
        t->carried = more;
    limn_status st = ids && got && more ? LIMN_OK
                                        : ctx_fail(p->ctx, LIMN_ERR_MEMORY,
                                                   "out of memory for %zu controls", n);
    st = mpi_agree(p, st);
    for (size_t i = 0; !st && i < n; i++)
        ids[i] = (uint32_t)mpi_rmesh_id(&t->cur, p->rank, i);
    if (!st)
        st = mpi_blocks_fetch(p, dist, block, 3 * sizeof(double), n, ids, got);
    for (size_t i = 0; !st && i < n; i++)
        t->carried[(size_t)t->fields * n + i] = got[3 * i];
    if (!st)
        t->fields++;
    free(ids);
    free(got);
    return st;
}

/* Fields [f0, f0 + 3) of t->carried (zero past the last) as positions. */
static double *pack_fields(const tex *t, int f0)
{
    size_t n = t->cur.n_owned;
    double *pos = calloc(n ? 3 * n : 3, sizeof *pos);
    for (int c = 0; pos && c < 3 && f0 + c < t->fields; c++)
        for (size_t i = 0; i < n; i++)
            pos[3 * i + (size_t)c] = t->carried[(size_t)(f0 + c) * n + i];
    return pos;
}

/* Step k: the carried fields, three at a time, refined on a copy of cur's
   segments, then cur's positions (its segments moving to the next level). */
static limn_status refine_step(tex *t, int k, mpi_refine_stats *rs)
{
    mpi_part *p = t->p;
    double alpha = k == 0 ? t->r->alpha : 0.0;
    size_t n_next = 0;
    double *next = NULL;
    limn_status st = LIMN_OK;
    for (int f0 = 0; !st && f0 < t->fields; f0 += 3) {
        double *pos = pack_fields(t, f0);
        mpi_rmesh copy = {0}, out;
        st = mpi_agree(p, pos ? LIMN_OK : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory"));
        if (st) {
            free(pos);
            break;
        }
        st = mpi_rmesh_borrow(p, &t->cur, pos, &copy);
        if (!st)
            st = mpi_refine_level(p, &copy, t->scheme, alpha, &out, rs);
        if (!st) {
            n_next = out.n_owned;
            double *grown = realloc(next, (size_t)t->fields * (n_next ? n_next : 1) * sizeof *grown);
            st = mpi_agree(p, grown ? LIMN_OK
                                    : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory"));
            next = grown ? grown : next;
            for (int c = 0; !st && c < 3 && f0 + c < t->fields; c++)
                for (size_t i = 0; i < n_next; i++)
                    next[(size_t)(f0 + c) * n_next + i] = out.pos[3 * i + (size_t)c];
            mpi_rmesh_free(&out);
        }
        if (copy.seg || copy.pos)
            mpi_rmesh_free(&copy);
    }
    mpi_rmesh nl;
    if (!st)
        st = mpi_refine_level(p, &t->cur, t->scheme, alpha, &nl, rs);
    if (st) {
        free(next);
        return st;
    }
    mpi_rmesh_free(&t->cur);
    t->cur = nl;
    free(t->carried);
    t->carried = next;
    return LIMN_OK;
}

/* One level: G_i moved to even blocks, its noise's controls solved there,
   back on cur's owners as field i; then step i unless it is the last. */
static limn_status texture_level(tex *t, int i, mpi_refine_stats *rs)
{
    limn_mpi_mesh *lm = NULL;
    double *block = NULL;
    limn_status st = mpi_rmesh_to_mesh(t->p, &t->cur, &lm);
    if (!st)
        st = level_controls(t, lm, i, &block);
    if (!st)
        st = append_field(t, lm->vertex_dist, block);
    free(block);
    limn_mpi_mesh_destroy(lm);
    if (!st && i < t->o->levels)
        st = refine_step(t, i, rs);
    ctx_progress(t->p->ctx, "texture", (double)(i + 1) / (t->o->levels + 1));
    return st;
}

/* G_L: the fields summed in level order, the limit of the positions and of
   the sum (the sum refined as a position), the colours over the range. */
static limn_status texture_finish(tex *t, mpi_refine_stats *rs, limn_mpi_mesh **out)
{
    mpi_part *p = t->p;
    size_t n = t->cur.n_owned;
    double alpha = t->o->levels == 0 ? t->r->alpha : 0.0;
    double *sum = calloc(n ? 3 * n : 3, sizeof *sum);
    uint8_t *rgb = large_malloc(n ? 3 * n : 3);
    limn_status st = mpi_agree(p, sum && rgb ? LIMN_OK
                                             : ctx_fail(p->ctx, LIMN_ERR_MEMORY,
                                                        "out of memory for %zu vertices", n));
    for (size_t v = 0; !st && v < n; v++) {
        double x = 0.0; /* texture.c's sum starts at zero (so -0 becomes +0 there too) */
        for (int f = 0; f < t->fields; f++)
            x += t->carried[(size_t)f * n + v];
        sum[3 * v] = x;
    }
    if (!st)
        st = mpi_refine_limit(p, &t->cur, t->scheme, alpha, rs);
    t->r->products += 2; /* texture.c's two limit products */
    double *positions = t->cur.pos;
    t->cur.pos = sum;
    sum = NULL;
    if (!st)
        st = mpi_refine_limit(p, &t->cur, t->scheme, alpha, rs);
    double mn = INFINITY, mx = -INFINITY, gmn = 0, gmx = 0;
    for (size_t v = 0; !st && v < n; v++) {
        mn = fmin(mn, t->cur.pos[3 * v]);
        mx = fmax(mx, t->cur.pos[3 * v]);
    }
    MPI_Allreduce(&mn, &gmn, 1, MPI_DOUBLE, MPI_MIN, p->comm);
    MPI_Allreduce(&mx, &gmx, 1, MPI_DOUBLE, MPI_MAX, p->comm);
    if (!st)
        st = mpi_agree(p, texture_map_colors(p->ctx, t->o, t->cur.pos, 3, n, gmn, gmx, rgb));
    free(t->cur.pos);
    t->cur.pos = positions;
    if (!st)
        st = mpi_rmesh_to_mesh(p, &t->cur, out);
    uint32_t *ids = st ? NULL : large_malloc((n ? n : 1) * sizeof *ids);
    size_t nb = st ? 0 : (*out)->slice.vertex_count;
    uint8_t *block = st ? NULL : large_malloc(nb ? 3 * nb : 3);
    if (!st)
        st = mpi_agree(p, ids && block ? LIMN_OK
                                       : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory"));
    for (size_t i = 0; !st && i < n; i++)
        ids[i] = (uint32_t)mpi_rmesh_id(&t->cur, p->rank, i);
    if (!st)
        st = mpi_blocks_store(p, (*out)->vertex_dist, n, ids, rgb, 3, block);
    if (!st) {
        (*out)->colors = block;
        block = NULL;
    } else if (*out) {
        limn_mpi_mesh_destroy(*out);
        *out = NULL;
    }
    free(ids);
    free(block);
    free(rgb);
    return st;
}

/* The checks before any work, agreed: options, the mesh, the scheme. */
static limn_status check_texture(tex *t, const limn_mpi_mesh *mesh, limn_mpi_mesh **surface,
                                 limn_status st)
{
    mpi_part *p = t->p;
    const char *fn = "limn_mpi_mesh_texture";
    if (!st && !surface)
        st = ctx_fail(p->ctx, LIMN_ERR_ARGUMENT, "%s: surface is NULL", fn);
    if (!st && !t->o)
        st = ctx_fail(p->ctx, LIMN_ERR_ARGUMENT, "%s: options is NULL (there are no default "
                                                 "colours)", fn);
    if (!st)
        st = texture_check_options(p->ctx, t->o);
    struct device *dev = NULL;
    if (!st)
        st = device_get(p->ctx, &dev);
    if (dev)
        snprintf(t->r->device, sizeof t->r->device, "%s", dev->name);
    st = mpi_agree(p, st);
    if (!st)
        st = mpi_mesh_check(p, fn, mesh);
    if (!st && (mesh->vertex_dist[p->size] == 0 || mesh->face_dist[p->size] == 0))
        st = ctx_fail(p->ctx, LIMN_ERR_TOPOLOGY, "the mesh has no %s",
                      mesh->vertex_dist[p->size] ? "faces" : "vertices");
    if (!st)
        st = mpi_mesh_scheme(p, mesh, t->o->series.scheme, &t->scheme);
    size_t estimate = 0; /* as limn_texture: subdivide's estimate with the limit */
    if (!st)
        st = mpi_refine_budget(p, mesh, t->scheme, t->o->levels, 1, t->o->max_memory, &estimate);
    return st;
}

/* limn_mpi_mesh_texture on structs of this library's layout. */
static limn_status texture_sized(limn_context *ctx, const limn_mpi_mesh *mesh,
                                 const limn_texture_options *o, limn_mpi_mesh **surface,
                                 limn_series_report *r, const limn_mpi_options *mpi,
                                 limn_mpi_result *result)
{
    memset(r, 0, sizeof *r);
    mpi_part p;
    limn_status st = mpi_mesh_part(ctx, mesh, mpi, &p);
    if (p.comm == MPI_COMM_NULL)
        return st;
    mpi_mesh_drop_sub(mesh); /* no rows from the repair's sub-mesh here */
    tex t = {.p = &p, .o = o, .mpi = mpi, .r = r};
    st = check_texture(&t, mesh, surface, st);
    r->vertices = mesh->vertex_dist[p.size];
    r->faces = mesh->face_dist[p.size];
    r->scheme = t.scheme;
    r->alpha = t.scheme == LIMN_SCHEME_CATMARK && o ? o->series.alpha : 0.0;
    mpi_refine_stats rs = {0};
    double t0 = MPI_Wtime();
    if (!st) {
        noise_frame(&t, mesh);
        limn_noise_init(&t.noise, o->seed);
        st = mpi_rmesh_of(&p, mesh, &t.cur);
    }
    for (int i = 0; !st && i <= o->levels; i++)
        st = texture_level(&t, i, &rs);
    limn_mpi_mesh *out = NULL;
    if (!st)
        st = texture_finish(&t, &rs, &out);
    if (!st)
        *surface = out;
    r->seconds_compute = MPI_Wtime() - t0;
    if (result) {
        result->stats.owned = t.cur.n_owned;
        result->stats.seconds_solve = r->seconds_compute;
        snprintf(result->stats.device, sizeof result->stats.device, "%s", r->device);
    }
    mpi_rmesh_free(&t.cur);
    free(t.carried);
    mpi_part_end(&p);
    return st;
}

limn_status limn_mpi_mesh_texture(limn_context *ctx, const limn_mpi_mesh *mesh,
                                  const limn_texture_options *options, limn_mpi_mesh **surface,
                                  limn_series_report *report, const limn_mpi_options *mpi,
                                  limn_mpi_result *result)
{
    if (!mesh)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "limn_mpi_mesh_texture: the mesh is NULL");
    mpi_call c;
    limn_status st = mpi_enter(&c, ctx, mesh->comm, "limn_mpi_mesh_texture",
                               &abi_texture_options, options, &abi_series_report, report, mpi,
                               result, NULL);
    /* no defaults stand in for NULL options: check_texture refuses them */
    return st ? st
              : mpi_leave(&c, texture_sized(ctx, mesh, options ? c.abi.options : NULL, surface,
                                            c.abi.report, c.mpi, c.result));
}
