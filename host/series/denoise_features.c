/* SPDX-License-Identifier: MIT */
/*
 * limn_denoise_features (limn.h): rounds of "filter the face normals with
 * the rebuilt operator W on the device, then fit the vertices to them",
 * then with a crease angle the rounds again on W cut at the result's
 * creases (features.h for the pieces, docs/series.md for why).
 */
#include "base/abi.h"
#include "base/clock.h"
#include "base/context.h"
#include "device/choice/choice.h"
#include "device/device.h"
#include "mesh/check.h"
#include "mesh/mesh.h"
#include "series/features.h"
#include "series/series.h"
#include "topology/measure.h"
#include "topology/topology.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void limn_feature_options_default(limn_feature_options *o)
{
    abi_default(&abi_feature_options, o);
}

limn_status feature_check_options(limn_context *ctx, const char *fn,
                                  const limn_feature_options *o)
{
    limn_status st =
        check_count(ctx, fn, "outer_steps", o->outer_steps, 1, LIMN_MAX_STEPS, "LIMN_MAX_STEPS");
    if (!st)
        st = check_count(ctx, fn, "normal_steps", o->normal_steps, 1, LIMN_MAX_STEPS,
                         "LIMN_MAX_STEPS");
    if (!st)
        st = check_count(ctx, fn, "vertex_steps", o->vertex_steps, 1, LIMN_MAX_STEPS,
                         "LIMN_MAX_STEPS");
    if (!st && !(o->sigma_r > 0.0 && isfinite(o->sigma_r)))
        st = ctx_fail(ctx, LIMN_ERR_ARGUMENT, "%s: sigma_r is %g; it must be finite and > 0", fn,
                      o->sigma_r);
    if (!st && !(o->sigma_s >= 0.0 && isfinite(o->sigma_s)))
        st = ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                      "%s: sigma_s is %g; it must be finite and >= 0 (0: the mean spacing)", fn,
                      o->sigma_s);
    if (!st && o->keep_volume != 0 && o->keep_volume != 1)
        st = ctx_fail(ctx, LIMN_ERR_ARGUMENT, "%s: keep_volume is %d; it must be 0 or 1", fn,
                      o->keep_volume);
    if (!st && o->adaptive != 0 && o->adaptive != 1)
        st = ctx_fail(ctx, LIMN_ERR_ARGUMENT, "%s: adaptive is %d; it must be 0 or 1", fn,
                      o->adaptive);
    if (!st && !(o->tangential >= 0.0 && o->tangential <= 1.0))
        st = ctx_fail(ctx, LIMN_ERR_ARGUMENT, "%s: tangential is %g; it must lie in [0, 1]", fn,
                      o->tangential);
    if (!st && !(o->crease_angle >= 0.0 && o->crease_angle < 180.0))
        st = ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                      "%s: crease_angle is %g; it must lie in [0, 180) degrees (0: no crease "
                      "pass)", fn, o->crease_angle);
    return st;
}

void feature_run_close(feature_run *r)
{
    if (r->dev) {
        device_csr_release(r->dev, &r->w);
        if (r->in)
            r->dev->ops->buffer_release(r->dev, r->in);
        if (r->out)
            r->dev->ops->buffer_release(r->dev, r->out);
    }
    free(r->host);
    memset(r, 0, sizeof *r);
}

limn_status feature_run_open(limn_context *ctx, const feature_mesh *fm, feature_run *r)
{
    memset(r, 0, sizeof *r);
    r->faces = fm->faces;
    limn_status st = device_get(ctx, &r->dev);
    if (st)
        return st;
    st = device_csr_upload(r->dev, &fm->ring, &r->w);
    size_t bytes = 4 * fm->faces * sizeof(double);
    if (!st)
        st = r->dev->ops->buffer_create(r->dev, bytes, NULL, &r->in);
    if (!st)
        st = r->dev->ops->buffer_create(r->dev, bytes, NULL, &r->out);
    r->host = calloc(4 * fm->faces, sizeof *r->host);
    if (!st && !r->host)
        st = ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for %zu faces", fm->faces);
    if (st)
        feature_run_close(r);
    return st;
}

/* n <- normalise(W n) with W's current weights (n: 3 per face). */
static limn_status filter_product(feature_run *r, const feature_mesh *fm, double *n)
{
    struct device *dev = r->dev;
    for (size_t f = 0; f < r->faces; f++) {
        memcpy(r->host + 4 * f, n + 3 * f, 3 * sizeof(double));
        r->host[4 * f + 3] = 0.0;
    }
    size_t bytes = 4 * r->faces * sizeof(double);
    limn_status st = dev->ops->buffer_write(dev, r->w.weights,
                                            r->w.nonzeros * sizeof(double), fm->ring.weights);
    if (!st)
        st = dev->ops->buffer_write(dev, r->in, bytes, r->host);
    if (!st)
        st = dev->ops->spmv(dev, &r->w, r->in, r->out);
    if (!st)
        st = dev->ops->buffer_read(dev, r->out, bytes, r->host);
    for (size_t f = 0; !st && f < r->faces; f++) {
        double *v = r->host + 4 * f, l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        for (int c = 0; c < 3; c++)
            n[3 * f + c] = l > 0.0 ? v[c] / l : 0.0;
    }
    return st;
}

/* One pass of rounds: its first round's products and range width, and
   the share of the progress bar it fills. */
typedef struct feature_pass {
    int products;
    double sigma_r, progress_begin, progress_end;
} feature_pass;

/* The range width and products of round k: the pass's in the first, the
   options' in every later one without adaptive; with adaptive, from the
   noise left in the current normals fm->normal, summed over the ranks by
   sync. */
static limn_status round_kernel(limn_context *ctx, const feature_mesh *fm,
                                const limn_feature_options *o, const feature_pass *pass, int k,
                                const feature_sync *sync, double *sigma_r, int *products)
{
    *sigma_r = k == 0 ? pass->sigma_r : o->sigma_r;
    *products = k == 0 ? pass->products : o->normal_steps;
    if (k == 0 || !o->adaptive)
        return LIMN_OK;
    uint64_t *bins = calloc(FEATURE_NOISE_BINS, sizeof *bins);
    limn_status st = bins ? LIMN_OK
                          : ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for the noise census");
    if (!st)
        feature_noise_count(fm, fm->normal, sync ? sync->rows_begin : 0,
                            sync ? sync->rows_end : fm->faces, bins);
    if (sync)
        st = sync->counts(sync->user, st, bins, FEATURE_NOISE_BINS);
    if (!st)
        *sigma_r = feature_adaptive_sigma(feature_noise_median(bins));
    *products = (o->normal_steps + 1) / 2;
    free(bins);
    return st;
}

static limn_status feature_rounds(limn_context *ctx, feature_mesh *fm, feature_run *run,
                                  const limn_feature_options *o, const feature_pass *pass,
                                  double *x, double *n, limn_series_report *r,
                                  const feature_sync *sync)
{
    limn_status st = LIMN_OK;
    for (int k = 0; !st && k < o->outer_steps; k++) {
        feature_faces_update(fm, x);
        memcpy(n, fm->normal, 3 * fm->faces * sizeof *n);
        double sigma_r;
        int products;
        st = round_kernel(ctx, fm, o, pass, k, sync, &sigma_r, &products);
        for (int t = 0; !st && t < products; t++) {
            feature_weights(fm, n, sigma_r);
            st = filter_product(run, fm, n);
            if (sync)
                st = sync->normals(sync->user, st, n);
            r->products++;
        }
        if (!st)
            st = feature_fit_vertices(ctx, fm, n, x, o->vertex_steps, o->tangential, sync);
        ctx_progress(ctx, "denoise",
                     pass->progress_begin + (pass->progress_end - pass->progress_begin) *
                                                (double)(k + 1) / o->outer_steps);
    }
    return st;
}

limn_status feature_passes(limn_context *ctx, feature_mesh *fm, feature_run *run,
                           const limn_feature_options *o, double *x, double *n,
                           limn_series_report *r, const feature_sync *sync)
{
    int creases = o->crease_angle > 0.0;
    feature_pass first = {o->normal_steps, o->sigma_r, 0.0, creases ? 0.5 : 1.0};
    size_t bytes = 3 * fm->vertices * sizeof *x;
    double *start = creases ? malloc(bytes ? bytes : 1) : NULL;
    limn_status st = creases && !start ? ctx_fail(ctx, LIMN_ERR_MEMORY,
                                                  "out of memory for %zu vertices", fm->vertices)
                                       : LIMN_OK;
    if (sync && creases) /* every rank learns of a failed allocation */
        st = sync->positions(sync->user, st, x);
    if (!st && creases)
        memcpy(start, x, bytes);
    if (!st)
        st = feature_rounds(ctx, fm, run, o, &first, x, n, r, sync);
    if (!st && creases) {
        const double radians = 3.14159265358979323846 / 180.0;
        feature_faces_update(fm, x);
        st = feature_cut_creases(ctx, fm, fm->normal, cos(o->crease_angle * radians));
        if (sync)
            st = sync->positions(sync->user, st, x);
    }
    if (!st && creases) {
        int products = o->normal_steps < FEATURE_CREASE_PRODUCTS ? o->normal_steps
                                                                  : FEATURE_CREASE_PRODUCTS;
        feature_pass again = {products, FEATURE_CREASE_SIGMA_R, 0.5, 1.0};
        memcpy(x, start, bytes);
        st = feature_rounds(ctx, fm, run, o, &again, x, n, r, sync);
    }
    free(start);
    return st;
}

/* The filter on a checked mesh: out a copy of mesh with the new positions. */
static limn_status features_compute(limn_context *ctx, const limn_mesh *mesh,
                                    const limn_feature_options *o, limn_mesh **out,
                                    limn_series_report *r)
{
    feature_mesh fm;
    feature_run run;
    double t0 = clock_seconds();
    limn_status st = feature_mesh_build(ctx, mesh, &fm);
    if (st)
        return st;
    r->seconds_stencil = clock_seconds() - t0;
    r->stencil_nonzeros = fm.ring.row_offsets[fm.faces];
    st = feature_run_open(ctx, &fm, &run);
    limn_mesh *m = NULL;
    double *n = malloc(3 * (fm.faces ? fm.faces : 1) * sizeof *n);
    if (!st && !n)
        st = ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for %zu faces", fm.faces);
    if (!st) {
        snprintf(r->device, sizeof r->device, "%s", run.dev->name);
        st = limn_mesh_copy(ctx, mesh, &m);
    }
    if (!st) {
        feature_faces_update(&fm, m->positions);
        fm.sigma_s = o->sigma_s > 0.0 ? o->sigma_s : feature_mean_spacing(&fm);
        double t1 = clock_seconds();
        st = feature_passes(ctx, &fm, &run, o, m->positions, n, r, NULL);
        r->seconds_compute = clock_seconds() - t1;
    }
    if (!st)
        st = series_check_finite(ctx, m->positions, m->vertex_count, "feature denoising");
    if (!st && o->keep_volume)
        st = series_keep_volume(ctx, mesh, m);
    free(n);
    if (run.dev)
        feature_run_close(&run);
    feature_mesh_free(&fm);
    return mesh_hand_over(st, m, out);
}

/* keep_volume needs a volume: a closed mesh. */
static limn_status check_closed(limn_context *ctx, const limn_mesh *mesh)
{
    topology t;
    limn_status st = topology_get(ctx, mesh, &t);
    if (st)
        return st;
    if (!measure_topology_closed(&t))
        st = ctx_fail(ctx, LIMN_ERR_TOPOLOGY,
                      "keeping the volume needs a closed mesh, and this one has %zu boundary, "
                      "%zu non-manifold and %zu inconsistently oriented edges: its volume is "
                      "not defined",
                      t.boundary_edges, t.nonmanifold_edges, t.inconsistent_edges);
    topology_free(&t);
    return st;
}

static limn_status features_sized(limn_context *ctx, const limn_mesh *mesh,
                                  const limn_feature_options *o, limn_mesh **out,
                                  limn_series_report *r)
{
    const char *fn = "limn_denoise_features";
    limn_status st = check_mesh_magnitude(ctx, fn, NULL, mesh);
    if (st)
        return st;
    series_report_init(r, mesh);
    if (!out)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "%s: out is NULL", fn);
    st = feature_check_options(ctx, fn, o);
    if (!st && (mesh->vertex_count == 0 || mesh->face_count == 0))
        st = ctx_fail(ctx, LIMN_ERR_TOPOLOGY, "the mesh has no %s",
                      mesh->vertex_count ? "faces" : "vertices");
    if (!st && o->keep_volume)
        st = check_closed(ctx, mesh);
    if (st)
        return st;
    double lo[3], hi[3];
    r->bbox_diagonal = mesh_bbox_diagonal(mesh, lo, hi);
    return features_compute(ctx, mesh, o, out, r);
}

limn_status limn_denoise_features(limn_context *ctx, const limn_mesh *mesh,
                                  const limn_feature_options *options, limn_mesh **out,
                                  limn_series_report *report)
{
    abi_call c;
    limn_status st = abi_enter(&c, ctx, "limn_denoise_features", &abi_feature_options, options,
                               &abi_series_report, report, out);
    return st ? st : abi_leave(&c, features_sized(ctx, mesh, c.options, out, c.report));
}
