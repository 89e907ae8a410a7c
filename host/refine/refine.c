/* SPDX-License-Identifier: MIT */
/*
 * Uniform refinement, level by level: each step is a CSR table applied by the
 * device's spmv. Level by level rather than factorised to the base mesh
 * because the composed stencils grow with every level (a level-k vertex
 * depends on ever more base vertices) while the per-level tables stay at
 * 4-9 entries a row; see README "Subdivision surfaces" for the measurement.
 */
#include "refine/refine.h"
#include "base/clock.h"
#include "base/context.h"
#include "base/parallel.h"
#include "device/device.h"
#include "mesh/mesh.h"
#include "solve/operator.h"
#include "scheme/scheme_refine.h"
#include "topology/topology.h"
#include "device/choice/choice.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

typedef struct step_rows {
    const topology *t;
    limn_scheme scheme;
    double alpha;
    size_t face_base, edge_base; /* first row of face points / edge points */
} step_rows;

static size_t step_bound(const void *user, size_t r)
{
    const step_rows *s = user;
    if (r < s->face_base)
        return scheme_refine_vertex_bound(s->t, s->scheme, (uint32_t)r);
    if (r < s->edge_base)
        return topology_face_size(s->t, (uint32_t)(r - s->face_base));
    return scheme_refine_edge_bound(s->t, s->scheme, (uint32_t)(r - s->edge_base));
}

static size_t step_fill(const void *user, size_t r, uint32_t *cols, double *w)
{
    const step_rows *s = user;
    if (r < s->face_base)
        return scheme_refine_vertex_mask(s->t, s->scheme, s->alpha, (uint32_t)r, cols, w);
    if (r < s->edge_base)
        return scheme_refine_face_mask(s->t, (uint32_t)(r - s->face_base), cols, w);
    return scheme_refine_edge_mask(s->t, s->scheme, (uint32_t)(r - s->edge_base), cols, w);
}

/* Faces of level k+1. Catmull-Clark: face f of d corners -> d quads
   (v_j, e_j, face point, e_{j-1}); Loop: 3 corner triangles + the middle one.
   Orientation is kept. */
typedef struct child_job {
    const topology *t;
    limn_scheme scheme;
    limn_mesh *m;
    uint32_t nv, edge_base;
} child_job;

/* The children of faces [begin, end): where they go follows from the face
   (Loop: 4 triangles a face; Catmull-Clark: a quad a corner), so ranges
   write disjoint parts and the faces are the same for any thread count. */
static int child_range(void *arg, size_t begin, size_t end)
{
    const child_job *j = arg;
    const topology *t = j->t;
    limn_mesh *m = j->m;
    for (size_t f = begin; f < end; f++) {
        uint32_t b = t->face_offsets[f], e = t->face_offsets[f + 1];
        if (j->scheme == LIMN_SCHEME_LOOP) {
            uint32_t v[3], ep[3];
            for (uint32_t i = 0; i < 3; i++) {
                v[i] = t->face_indices[b + i];
                ep[i] = j->edge_base + t->corner_edge[b + i]; /* edge v[i] -> v[i+1] */
            }
            uint32_t tris[4][3] = {{v[0], ep[0], ep[2]},
                                   {v[1], ep[1], ep[0]},
                                   {v[2], ep[2], ep[1]},
                                   {ep[0], ep[1], ep[2]}};
            size_t k = 12 * f;
            for (int q = 0; q < 4; q++) {
                for (int i = 0; i < 3; i++)
                    m->face_indices[k++] = tris[q][i];
                m->face_offsets[4 * f + (size_t)q + 1] = (uint32_t)k;
            }
        } else {
            uint32_t fp = j->nv + (uint32_t)f;
            for (uint32_t c = b; c < e; c++) {
                uint32_t pc = topology_corner_prev(t, c);
                size_t k = 4 * (size_t)c;
                m->face_indices[k] = t->face_indices[c];
                m->face_indices[k + 1] = j->edge_base + t->corner_edge[c];
                m->face_indices[k + 2] = fp;
                m->face_indices[k + 3] = j->edge_base + t->corner_edge[pc];
                m->face_offsets[(size_t)c + 1] = (uint32_t)(k + 4);
            }
        }
    }
    return 0;
}

static limn_status child_faces(limn_context *ctx, topology *t, limn_scheme scheme,
                               size_t child_vertices, limn_mesh **out)
{
    limn_status st = topology_corner_edges(ctx, t); /* child faces name parent edges */
    if (st)
        return st;
    size_t nf = scheme == LIMN_SCHEME_LOOP ? 4 * t->face_count : t->corner_count;
    size_t ni = scheme == LIMN_SCHEME_LOOP ? 12 * t->face_count : 4 * t->corner_count;
    st = mesh_alloc(ctx, child_vertices, nf, ni, out);
    if (st)
        return st;
    limn_mesh *m = *out; /* positions unset: written by whoever applies the plan */
    uint32_t nv = (uint32_t)t->vertex_count;
    child_job j = {t, scheme, m, nv,
                   scheme == LIMN_SCHEME_LOOP ? nv : nv + (uint32_t)t->face_count};
    parallel_run(t->face_count, parallel_threads(ctx, (uint64_t)ni * 4), child_range, &j);
    return LIMN_OK;
}

void refine_plan_free(refine_plan *plan)
{
    if (!plan)
        return;
    if (plan->meshes)
        for (int k = 0; k <= plan->levels; k++)
            limn_mesh_destroy(plan->meshes[k]);
    if (plan->steps)
        for (int k = 0; k < plan->levels; k++)
            stencil_free(&plan->steps[k]);
    free(plan->meshes);
    free(plan->steps);
    memset(plan, 0, sizeof *plan);
}

limn_status refine_plan_build(limn_context *ctx, const limn_mesh *base, limn_scheme scheme,
                              double alpha, int levels, refine_plan *plan)
{
    memset(plan, 0, sizeof *plan);
    if (levels < 0 || levels > 16)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "levels is %d; it must lie in 0..16", levels);
    limn_status st = operator_resolve_scheme(ctx, base, scheme, &plan->scheme);
    if (st)
        return st;
    plan->alpha = plan->scheme == LIMN_SCHEME_CATMARK ? alpha : 0.0;
    plan->levels = levels;
    plan->meshes = calloc((size_t)levels + 1, sizeof *plan->meshes);
    plan->steps = calloc(levels ? (size_t)levels : 1, sizeof *plan->steps);
    if (!plan->meshes || !plan->steps) {
        refine_plan_free(plan);
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for a refinement plan");
    }
    st = limn_mesh_copy(ctx, base, &plan->meshes[0]);
    for (int k = 0; !st && k < levels; k++) {
        topology t;
        /* level 0 is a copy of base: the same faces, so base's cached topology */
        st = k == 0 ? topology_get(ctx, base, &t) : topology_build(ctx, plan->meshes[k], &t);
        if (st)
            break;
        step_rows rows = {.t = &t, .scheme = plan->scheme, .alpha = k == 0 ? plan->alpha : 0.0};
        rows.face_base = t.vertex_count;
        rows.edge_base = t.vertex_count + (plan->scheme == LIMN_SCHEME_LOOP ? 0 : t.face_count);
        size_t child_vertices = rows.edge_base + t.edge_count;
        if (child_vertices > UINT32_MAX)
            st = ctx_fail(ctx, LIMN_ERR_MEMORY, "level %d would have %zu vertices (over 2^32)",
                           k + 1, child_vertices);
        if (!st)
            st = stencil_build(ctx, child_vertices, t.vertex_count, step_bound, step_fill, &rows,
                               &plan->steps[k]);
        if (!st)
            st = child_faces(ctx, &t, plan->scheme, child_vertices, &plan->meshes[k + 1]);
        topology_free(&t);
        ctx_progress(ctx, "refine", (double)(k + 1) / (double)levels);
    }
    if (st)
        refine_plan_free(plan);
    return st;
}

/* One level of refine_surface: cur's child mesh (faces as refine_plan_build
   makes them) with its positions made from the masks as they are made. */
static limn_status surface_level(limn_context *ctx, const limn_mesh *cur, int first,
                                 limn_scheme scheme, double alpha, limn_mesh **next,
                                 size_t *entries, double *seconds_apply)
{
    topology t;
    /* the base's cached topology (the repair's) on the first level */
    limn_status st = first ? topology_get(ctx, cur, &t) : topology_build(ctx, cur, &t);
    if (st)
        return st;
    step_rows rows = {.t = &t, .scheme = scheme, .alpha = first ? alpha : 0.0};
    rows.face_base = t.vertex_count;
    rows.edge_base = t.vertex_count + (scheme == LIMN_SCHEME_LOOP ? 0 : t.face_count);
    size_t child_vertices = rows.edge_base + t.edge_count, n = 0;
    if (child_vertices > UINT32_MAX)
        st = ctx_fail(ctx, LIMN_ERR_MEMORY, "the next level would have %zu vertices (over 2^32)",
                      child_vertices);
    if (!st)
        st = child_faces(ctx, &t, scheme, child_vertices, next);
    double t0 = clock_seconds();
    if (!st)
        st = stencil_build_apply3(ctx, child_vertices, step_bound, step_fill, &rows,
                                  cur->positions, (*next)->positions, &n);
    *seconds_apply += clock_seconds() - t0;
    *entries += n;
    if (st) {
        limn_mesh_destroy(*next);
        *next = NULL;
    }
    topology_free(&t);
    return st;
}

limn_status refine_surface(limn_context *ctx, const limn_mesh *base, limn_scheme scheme,
                           double alpha, int levels, limn_mesh **out, size_t *entries,
                           double *seconds_apply)
{
    *out = NULL;
    *entries = 0;
    *seconds_apply = 0;
    if (levels < 0 || levels > 16)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "levels is %d; it must lie in 0..16", levels);
    if (levels == 0)
        return limn_mesh_copy(ctx, base, out);
    limn_mesh *cur = NULL;
    limn_status st = LIMN_OK;
    for (int k = 0; !st && k < levels; k++) {
        limn_mesh *next = NULL;
        st = surface_level(ctx, k == 0 ? base : cur, k == 0, scheme, alpha, &next, entries,
                           seconds_apply);
        limn_mesh_destroy(cur); /* the level below is no longer read */
        cur = next;
        ctx_progress(ctx, "refine", (double)(k + 1) / (double)levels);
    }
    *out = cur;
    return st;
}

/* Level `from`'s data (`channels` doubles a vertex) carried to the finest
   level: *rows is its device rows (4 doubles a vertex, device_host_alloc),
   which the caller frees. Each level's rows are host memory the device uses
   in place where it shares it (no device copy, the last read-back a map). */
static limn_status apply_rows(limn_context *ctx, const refine_plan *plan, int from, int channels,
                              const double *in, double **rows)
{
    *rows = NULL;
    struct device *dev;
    limn_status st = device_get(ctx, &dev);
    if (st)
        return st;
    size_t n = plan->meshes[from]->vertex_count;
    double *x_host = n < SIZE_MAX / 32 ? device_host_alloc(4 * n * sizeof *x_host) : NULL;
    if (!x_host)
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for %zu vertices", n);
    for (size_t i = 0; i < n; i++) {
        memset(x_host + 4 * i, 0, 4 * sizeof *x_host);
        memcpy(x_host + 4 * i, in + (size_t)channels * i, (size_t)channels * sizeof(double));
    }
    device_buffer *x = NULL;
    st = dev->ops->buffer_share(dev, 4 * n * sizeof(double), x_host, &x);
    for (int k = from; !st && k < plan->levels; k++) {
        const stencil_csr *h = &plan->steps[k];
        double *y_host = device_host_alloc(4 * h->rows * sizeof *y_host);
        device_buffer *y = NULL;
        device_csr a = {0};
        st = y_host ? device_csr_share(dev, h, &a) /* the plan's table outlives it */
                    : ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for %zu vertices", h->rows);
        if (!st) /* the spmv writes every row */
            st = dev->ops->buffer_share(dev, 4 * h->rows * sizeof(double), y_host, &y);
        if (!st)
            st = dev->ops->spmv(dev, &a, x, y);
        if (a.row_offsets)
            device_csr_release(dev, &a);
        dev->ops->buffer_release(dev, x); /* before its memory goes */
        free(x_host);
        x = y;
        x_host = y_host;
    }
    size_t n_out = plan->meshes[plan->levels]->vertex_count;
    if (!st) /* into its own memory: in place where shared */
        st = dev->ops->buffer_read(dev, x, 4 * n_out * sizeof(double), x_host);
    if (x)
        dev->ops->buffer_release(dev, x);
    if (st)
        free(x_host);
    else
        *rows = x_host;
    return st;
}

limn_status refine_plan_apply(limn_context *ctx, const refine_plan *plan, int from, int channels,
                              const double *in, double *out)
{
    if (from < 0 || from > plan->levels || channels < 1 || channels > 4)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "refine_plan_apply: bad level %d or channels %d",
                         from, channels);
    double *rows;
    limn_status st = apply_rows(ctx, plan, from, channels, in, &rows);
    size_t n_out = plan->meshes[plan->levels]->vertex_count;
    for (size_t i = 0; !st && i < n_out; i++)
        memcpy(out + (size_t)channels * i, rows + 4 * i, (size_t)channels * sizeof(double));
    free(rows);
    return st;
}

limn_status refine_plan_apply_positions(limn_context *ctx, refine_plan *plan,
                                        const double *positions)
{
    double *rows;
    limn_status st = apply_rows(ctx, plan, 0, 3, positions, &rows);
    if (st)
        return st;
    limn_mesh *fine = plan->meshes[plan->levels];
    free(fine->positions);
    fine->positions = mesh_rows4_to_xyz(rows, fine->vertex_count);
    return LIMN_OK;
}

void refine_estimate(const limn_mesh *base, limn_scheme scheme, int levels, int limit,
                     size_t *vertices, size_t *faces, size_t *indices, size_t *peak_bytes)
{
    /* Counts follow exactly from V, F, E and the corners of the base. */
    double c = (double)base->face_offsets[base->face_count];
    double e = c; /* an upper bound if the topology cannot be built */
    topology t;
    if (topology_get(NULL, base, &t) == LIMN_OK) {
        e = (double)t.edge_count;
        topology_free(&t);
    }
    refine_estimate_counts((double)base->vertex_count, (double)base->face_count, c, e, scheme,
                           levels, limit, vertices, faces, indices, peak_bytes);
}

void refine_estimate_counts(double v, double f, double c, double e, limn_scheme scheme,
                            int levels, int limit, size_t *vertices, size_t *faces,
                            size_t *indices, size_t *peak_bytes)
{
    double v0 = v, idx = c;
    for (int k = 0; k < levels; k++) {
        double nv, nf, ne, ni;
        if (scheme == LIMN_SCHEME_LOOP) {
            nv = v + e;
            nf = 4 * f;
            ne = 2 * e + 3 * f;
            ni = 3 * nf;
        } else {
            nv = v + f + e;
            nf = c;
            ne = 2 * e + c;
            ni = 4 * nf;
        }
        v = nv, f = nf, e = ne, idx = ni, c = ni;
    }
    *vertices = (size_t)v;
    *faces = (size_t)f;
    *indices = (size_t)idx;
    /* Measured peaks less ~150 MiB of runtime (docs/subdivision.md, 2026-12-04,
       after the levels were applied as they are made): 38-114 bytes per output
       vertex without --limit, 248-316 with it (the finest level's topology and
       limit table), and the input mesh with its topology held throughout, ~250
       bytes per input vertex at most (limn info's peak); about 20% margin on
       each, tests/test_robust.c checks the estimate against measured peaks. */
    double per_output = limit ? 400.0 : 140.0, per_input = 250.0;
    *peak_bytes = (size_t)(per_output * v + per_input * v0) + REFINE_RUNTIME_BYTES;
}
