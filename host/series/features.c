/* SPDX-License-Identifier: MIT */
/*
 * The face operator of the feature-preserving denoiser and its vertex fit
 * (features.h). The loops over faces, W's rows and vertices split into
 * ranges over the host threads, each element computed on its own in a fixed
 * order, so the weights and positions are the same bytes for any thread
 * count.
 */
#include "series/features.h"

#include "base/context.h"
#include "base/parallel.h"
#include "mesh/mesh.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static size_t ring_bound(const void *user, size_t f)
{
    const feature_mesh *fm = user;
    size_t sum = 0;
    for (uint32_t k = fm->offsets[f]; k < fm->offsets[f + 1]; k++) {
        uint32_t v = fm->indices[k];
        sum += fm->vf_offsets[v + 1] - fm->vf_offsets[v];
    }
    return sum;
}

/* Every face around every corner of f (repeats merged by stencil_build). */
static size_t ring_fill(const void *user, size_t f, uint32_t *cols, double *w)
{
    const feature_mesh *fm = user;
    size_t n = 0;
    for (uint32_t k = fm->offsets[f]; k < fm->offsets[f + 1]; k++) {
        uint32_t v = fm->indices[k];
        for (uint32_t j = fm->vf_offsets[v]; j < fm->vf_offsets[v + 1]; j++) {
            cols[n] = fm->vf[j];
            w[n++] = 1.0;
        }
    }
    return n;
}

/* vertex -> faces as CSR, faces in increasing order. */
static limn_status build_vertex_faces(limn_context *ctx, feature_mesh *fm)
{
    size_t corners = fm->offsets[fm->faces];
    fm->vf_offsets = calloc(fm->vertices + 1, sizeof *fm->vf_offsets);
    fm->vf = malloc((corners ? corners : 1) * sizeof *fm->vf);
    uint32_t *fill = calloc(fm->vertices + 1, sizeof *fill);
    if (!fm->vf_offsets || !fm->vf || !fill) {
        free(fill);
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for the faces of %zu vertices",
                        fm->vertices);
    }
    for (size_t k = 0; k < corners; k++)
        fm->vf_offsets[fm->indices[k] + 1]++;
    for (size_t v = 0; v < fm->vertices; v++)
        fm->vf_offsets[v + 1] += fm->vf_offsets[v];
    for (size_t f = 0; f < fm->faces; f++)
        for (uint32_t k = fm->offsets[f]; k < fm->offsets[f + 1]; k++) {
            uint32_t v = fm->indices[k];
            fm->vf[fm->vf_offsets[v] + fill[v]++] = (uint32_t)f;
        }
    free(fill);
    return LIMN_OK;
}

limn_status feature_mesh_build(limn_context *ctx, const limn_mesh *mesh, feature_mesh *fm)
{
    memset(fm, 0, sizeof *fm);
    fm->vertices = mesh->vertex_count;
    fm->faces = mesh->face_count;
    fm->offsets = mesh->face_offsets;
    fm->indices = mesh->face_indices;
    limn_status st = build_vertex_faces(ctx, fm);
    if (!st)
        st = stencil_build(ctx, fm->faces, fm->faces, ring_bound, ring_fill, fm, &fm->ring);
    size_t nf = fm->faces ? fm->faces : 1;
    /* threads by the ring's pairs: each costs an exp, about the time of
       streaming 64 bytes, so a mesh of a few thousand faces stays on the
       calling thread */
    if (!st)
        fm->threads = parallel_threads(ctx, (uint64_t)fm->ring.row_offsets[fm->faces] * 64);
    if (!st) {
        fm->normal = malloc(3 * nf * sizeof(double));
        fm->centroid = malloc(3 * nf * sizeof(double));
        fm->area = malloc(nf * sizeof(double));
        if (!fm->normal || !fm->centroid || !fm->area)
            st = ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for %zu faces", fm->faces);
    }
    if (st)
        feature_mesh_free(fm);
    return st;
}

void feature_mesh_free(feature_mesh *fm)
{
    free(fm->vf_offsets);
    free(fm->vf);
    stencil_free(&fm->ring);
    free(fm->normal);
    free(fm->area);
    free(fm->centroid);
    free(fm->keep);
    memset(fm, 0, sizeof *fm);
}

static double dist2(const double *a, const double *b)
{
    double d0 = a[0] - b[0], d1 = a[1] - b[1], d2 = a[2] - b[2];
    return d0 * d0 + d1 * d1 + d2 * d2;
}

/* Scales v to unit length (a zero vector stays zero); returns the length. */
static double normalise(double *v)
{
    double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (l > 0.0)
        for (int c = 0; c < 3; c++)
            v[c] /= l;
    return l;
}

/* A range of a parallel loop over fm's faces, rows or vertices. */
typedef struct feature_range_job {
    feature_mesh *fm;
    const double *n, *x;
    double *y, a, b; /* a, b: the loop's two constants */
} feature_range_job;

static int faces_range(void *arg, size_t begin, size_t end)
{
    const feature_range_job *job = arg;
    feature_mesh *fm = job->fm;
    const double *x = job->x;
    for (size_t f = begin; f < end; f++) {
        uint32_t b = fm->offsets[f], e = fm->offsets[f + 1];
        double n[3] = {0, 0, 0}, c[3] = {0, 0, 0};
        for (uint32_t k = b; k < e; k++) {
            const double *p = x + 3 * (size_t)fm->indices[k];
            const double *q = x + 3 * (size_t)fm->indices[k + 1 < e ? k + 1 : b];
            n[0] += (p[1] - q[1]) * (p[2] + q[2]);
            n[1] += (p[2] - q[2]) * (p[0] + q[0]);
            n[2] += (p[0] - q[0]) * (p[1] + q[1]);
            for (int j = 0; j < 3; j++)
                c[j] += p[j];
        }
        fm->area[f] = 0.5 * normalise(n);
        for (int j = 0; j < 3; j++) {
            fm->normal[3 * f + j] = n[j];
            fm->centroid[3 * f + j] = c[j] / (double)(e - b);
        }
    }
    return 0;
}

void feature_faces_update(feature_mesh *fm, const double *x)
{
    feature_range_job job = {.fm = fm, .x = x};
    parallel_run(fm->faces, fm->threads, faces_range, &job);
}

double feature_spacing_add(const feature_mesh *fm, size_t begin, size_t end, double sum,
                           size_t *count)
{
    const stencil_csr *w = &fm->ring;
    for (size_t i = begin; i < end; i++)
        for (uint32_t k = w->row_offsets[i]; k < w->row_offsets[i + 1]; k++)
            if (w->columns[k] != i) {
                sum += sqrt(dist2(fm->centroid + 3 * i, fm->centroid + 3 * (size_t)w->columns[k]));
                (*count)++;
            }
    return sum;
}

double feature_mean_spacing(const feature_mesh *fm)
{
    size_t count = 0;
    double sum = feature_spacing_add(fm, 0, fm->ring.rows, 0.0, &count);
    return count ? sum / (double)count : 0.0;
}

static int weights_range(void *arg, size_t begin, size_t end)
{
    const feature_range_job *job = arg;
    feature_mesh *fm = job->fm;
    stencil_csr *w = &fm->ring;
    const double *n = job->n;
    double ks = job->a, kr = job->b;
    for (size_t i = begin; i < end; i++) {
        uint32_t b = w->row_offsets[i], e = w->row_offsets[i + 1];
        double sum = 0.0;
        for (uint32_t k = b; k < e; k++) {
            size_t j = w->columns[k];
            double s = dist2(fm->centroid + 3 * i, fm->centroid + 3 * j);
            double r = dist2(n + 3 * i, n + 3 * j);
            w->weights[k] = fm->keep && !fm->keep[k] ? 0.0 : fm->area[j] * exp(-ks * s - kr * r);
            sum += w->weights[k];
        }
        /* a row of zero weights (degenerate faces all round) keeps its face */
        for (uint32_t k = b; k < e; k++)
            w->weights[k] = sum > 0.0 ? w->weights[k] / sum : (w->columns[k] == i ? 1.0 : 0.0);
    }
    return 0;
}

void feature_weights(feature_mesh *fm, const double *n, double sigma_r)
{
    feature_range_job job = {.fm = fm, .n = n};
    job.a = fm->sigma_s > 0.0 ? 0.5 / (fm->sigma_s * fm->sigma_s) : 0.0;
    job.b = 0.5 / (sigma_r * sigma_r);
    parallel_run(fm->ring.rows, fm->threads, weights_range, &job);
}

/* The move of vertex v (at p) in one sweep: towards the planes of its faces
   along their filtered normals (Sun et al. 2007), plus `tangential` times
   the pull to the mean of its faces' centroids within the plane of its
   normal (the normals' area-weighted mean), which untangles faces that the
   noise folded over without rounding an edge (the pull across a crease is
   along the normal there, and projected away). */
static void fit_move(const feature_mesh *fm, const double *n, size_t v, const double *p,
                     double tangential, double d[3])
{
    uint32_t b = fm->vf_offsets[v], e = fm->vf_offsets[v + 1];
    double m[3] = {0, 0, 0}, t[3] = {0, 0, 0};
    d[0] = d[1] = d[2] = 0.0;
    for (uint32_t k = b; k < e; k++) {
        size_t f = fm->vf[k];
        const double *nf = n + 3 * f, *c = fm->centroid + 3 * f;
        double h = nf[0] * (c[0] - p[0]) + nf[1] * (c[1] - p[1]) + nf[2] * (c[2] - p[2]);
        for (int j = 0; j < 3; j++) {
            d[j] += h * nf[j];
            m[j] += fm->area[f] * nf[j];
            t[j] += c[j] - p[j];
        }
    }
    if (e == b)
        return;
    normalise(m);
    double tm = t[0] * m[0] + t[1] * m[1] + t[2] * m[2];
    for (int j = 0; j < 3; j++)
        d[j] = (d[j] + tangential * (t[j] - tm * m[j])) / (double)(e - b);
}

static int sweep_range(void *arg, size_t begin, size_t end)
{
    const feature_range_job *job = arg;
    const double *x = job->x;
    for (size_t v = begin; v < end; v++) {
        double d[3];
        fit_move(job->fm, job->n, v, x + 3 * v, job->a, d);
        for (int j = 0; j < 3; j++)
            job->y[3 * v + j] = x[3 * v + j] + d[j];
    }
    return 0;
}

/* One Jacobi sweep of the vertex fit: y from x (both 3 per vertex). */
static void fit_sweep(feature_mesh *fm, const double *n, const double *x, double *y,
                      double tangential)
{
    feature_faces_update(fm, x);
    feature_range_job job = {.fm = fm, .n = n, .x = x, .y = y, .a = tangential};
    parallel_run(fm->vertices, fm->threads, sweep_range, &job);
}

limn_status feature_fit_vertices(limn_context *ctx, feature_mesh *fm, const double *n, double *x,
                                 int steps, double tangential, const feature_sync *sync)
{
    double *y = malloc(3 * (fm->vertices ? fm->vertices : 1) * sizeof *y);
    limn_status st = y ? LIMN_OK
                       : ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for %zu vertices",
                                  fm->vertices);
    if (sync) /* every rank learns of a failed allocation before the sweeps */
        st = sync->positions(sync->user, st, x);
    for (int s = 0; !st && s < steps; s++) {
        fit_sweep(fm, n, x, y, tangential);
        memcpy(x, y, 3 * fm->vertices * sizeof *x);
        if (sync)
            st = sync->positions(sync->user, st, x);
    }
    free(y);
    return st;
}
