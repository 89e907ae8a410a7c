/* SPDX-License-Identifier: MIT */
/*
 * The oracle bound (denoise_bound.h). The Krylov vectors r_i = (E - A)^i y
 * come from limn_bands (r_N is its remainder, r_i = band_i + r_{i+1}); every
 * polynomial of degree N in A with p(1) = 1 is y + sum_{i=1..N} d_i r_i.
 */
#include "denoise_bound.h"
#include "normal_fit.h"
#include "series/sure.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void fail(limn_context *ctx, const char *what)
{
    fprintf(stderr, "denoise_bound: %s: %s\n", what, limn_context_message(ctx));
    exit(1);
}

/* r + (i-1)*n3 = r_i, i = 1..N. */
static double *krylov(limn_context *ctx, const limn_mesh *y, const limn_series_options *o,
                      int degree, size_t n3)
{
    double *bands = malloc((size_t)(degree + 1) * n3 * sizeof *bands);
    if (!bands || limn_bands(ctx, y, o, degree, bands, NULL, NULL))
        fail(ctx, "bands");
    /* bands + degree*n3 is r_N; r_i = band_i + r_{i+1}, downwards, in place */
    for (int i = degree - 1; i >= 1; i--)
        for (size_t k = 0; k < n3; k++)
            bands[(size_t)i * n3 + k] += bands[(size_t)(i + 1) * n3 + k];
    memmove(bands, bands + n3, (size_t)degree * n3 * sizeof *bands);
    return bands;
}

/* out = y + sum_i d_i r_i as a copy of y. */
static limn_mesh *combine(limn_context *ctx, const limn_mesh *y, const double *r, size_t n3,
                          int degree, const double *d)
{
    limn_mesh *m = NULL;
    if (limn_mesh_copy(ctx, y, &m))
        fail(ctx, "copy");
    double *p = limn_mesh_positions_mutable(m);
    for (size_t k = 0; k < n3; k++)
        for (int i = 0; i < degree; i++)
            p[k] += d[i] * r[(size_t)i * n3 + k];
    return m;
}

/* d minimising sum_v w_v |y + sum_i d_i r_i - x|_v^2 (w NULL: all 1). */
static void weighted_fit(limn_context *ctx, const double *r, const double *e0, const double *w,
                         size_t n3, int degree, double *scratch, double *d)
{
    double rhs[LIMN_MAX_SURE_PRODUCTS];
    for (int i = 0; i < degree; i++) {
        const double *ri = r + (size_t)i * n3;
        double s = 0.0;
        for (size_t k = 0; k < n3; k++) {
            double sw = w ? sqrt(w[k / 3]) : 1.0;
            scratch[(size_t)i * n3 + k] = sw * ri[k];
            s -= w ? w[k / 3] * ri[k] * e0[k] : ri[k] * e0[k];
        }
        rhs[i] = s;
    }
    if (sure_least_squares(ctx, scratch, n3, degree, rhs, NULL, 0.0, d))
        fail(ctx, "least squares");
}

/* The columns of the split form into r (2 degree of them): r_i's parts
   along the default's frame normals (those of sure_frame_positions), then
   its parts across them. */
static double *split_columns(const limn_mesh *noisy, double *r, size_t n3, int degree)
{
    size_t n = n3 / 3;
    double *c = malloc(2 * (size_t)degree * n3 * sizeof *c), *q = malloc(n3 * sizeof *q);
    double *nrm = malloc(n3 * sizeof *nrm);
    if (!c || !q || !nrm) {
        fprintf(stderr, "denoise_bound: out of memory\n");
        exit(1);
    }
    sure_frame_positions(limn_mesh_positions(noisy), r, n3, degree, q);
    sure_vertex_normals(noisy, q, nrm); /* the noisy mesh's faces at q */
    for (int i = 0; i < degree; i++)
        for (size_t v = 0; v < n; v++) {
            const double *x = r + (size_t)i * n3 + 3 * v, *nv = nrm + 3 * v;
            double a = x[0] * nv[0] + x[1] * nv[1] + x[2] * nv[2];
            for (int k = 0; k < 3; k++) {
                c[(size_t)i * n3 + 3 * v + k] = a * nv[k];
                c[(size_t)(degree + i) * n3 + 3 * v + k] = x[k] - a * nv[k];
            }
        }
    free(q), free(nrm), free(r);
    return c;
}

/* The fits (least squares, then mean distance by reweighting) of y + sum
   d_i r_i (cols columns r) to x. */
static void fits(limn_context *ctx, const limn_mesh *noisy, const double *x, const double *r,
                 size_t n3, int cols, limn_mesh **l2, limn_mesh **dist, double *coefficients)
{
    size_t n = n3 / 3;
    const double *y = limn_mesh_positions(noisy);
    double *e0 = malloc(n3 * sizeof *e0), *w = malloc(n * sizeof *w);
    double *scratch = malloc((size_t)cols * n3 * sizeof *scratch), d[LIMN_MAX_SURE_PRODUCTS];
    if (!e0 || !w || !scratch || cols > LIMN_MAX_SURE_PRODUCTS)
        fail(ctx, "the fit's arrays");
    for (size_t k = 0; k < n3; k++)
        e0[k] = y[k] - x[k]; /* the error of the identity filter */
    weighted_fit(ctx, r, e0, NULL, n3, cols, scratch, d);
    *l2 = combine(ctx, noisy, r, n3, cols, d);
    if (coefficients)
        memcpy(coefficients, d, (size_t)cols * sizeof *d);
    for (int round = 0; round < 40; round++) {
        /* w_v = 1 / |error_v|: the weighted squares' minimum is the mean distance's */
        for (size_t v = 0; v < n; v++) {
            double s = 0.0;
            for (int c = 0; c < 3; c++) {
                double e = e0[3 * v + c];
                for (int i = 0; i < cols; i++)
                    e += d[i] * r[(size_t)i * n3 + 3 * v + c];
                s += e * e;
            }
            w[v] = 1.0 / fmax(sqrt(s), 1e-12);
        }
        weighted_fit(ctx, r, e0, w, n3, cols, scratch, d);
    }
    *dist = combine(ctx, noisy, r, n3, cols, d);
    if (coefficients)
        memcpy(coefficients + cols, d, (size_t)cols * sizeof *d);
    free(e0), free(w), free(scratch);
}

/* The fits of columns c (cols of them), and with normals the normal-error
   oracle from both fits' coefficients and from the identity (d = 0). */
static void fits_and_normals(limn_context *ctx, const limn_mesh *noisy, const limn_mesh *clean,
                             const double *c, size_t n3, int cols, limn_mesh **l2,
                             limn_mesh **dist, limn_mesh **normals)
{
    double starts[3 * LIMN_MAX_SURE_PRODUCTS * 2] = {0}, d[2 * LIMN_MAX_SURE_PRODUCTS];
    if (cols > 2 * LIMN_MAX_SURE_PRODUCTS)
        fail(ctx, "too many columns");
    fits(ctx, noisy, limn_mesh_positions(clean), c, n3, cols, l2, dist, starts);
    if (!normals)
        return;
    const char *env = getenv("LIMN_BENCH_NORMAL_RESTARTS");
    normal_fit(clean, limn_mesh_positions(noisy), c, n3, cols, starts, 3, env ? atoi(env) : 0, d);
    *normals = combine(ctx, noisy, c, n3, cols, d);
}

void denoise_bound_split(limn_context *ctx, const limn_mesh *noisy, const limn_mesh *clean,
                         const limn_series_options *o, int degree, limn_mesh **l2,
                         limn_mesh **dist, limn_mesh **normals)
{
    size_t n3 = 3 * limn_mesh_vertex_count(noisy);
    double *c = split_columns(noisy, krylov(ctx, noisy, o, degree, n3), n3, degree);
    fits_and_normals(ctx, noisy, clean, c, n3, 2 * degree, l2, dist, normals);
    free(c);
}

void denoise_bound(limn_context *ctx, const limn_mesh *noisy, const limn_mesh *clean,
                   const limn_series_options *o, int degree, limn_mesh **l2, limn_mesh **dist,
                   limn_mesh **normals)
{
    size_t n3 = 3 * limn_mesh_vertex_count(noisy);
    double *r = krylov(ctx, noisy, o, degree, n3);
    fits_and_normals(ctx, noisy, clean, r, n3, degree, l2, dist, normals);
    free(r);
}
