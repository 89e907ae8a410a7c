/* SPDX-License-Identifier: MIT */
/*
 * Procedural texture (seed 000 §5, DESIGN.md §1). Refine the mesh G_0 into
 * G_1 .. G_L; on the vertices of G_i put improved Perlin noise
 * f(2^i p) / 2^i (a scalar per vertex: channel x of the device vectors);
 * interpolate it on G_i (the scalar version of the progressive interpolation,
 * with G_i's own limit operator); carry the control values to G_L through
 * the refinement steps (refine_plan_apply) and sum them there; evaluate the
 * sum at the limit points of G_L (so level L's own field is reproduced
 * exactly), normalise to [0, 1] and map through the uniform cubic B-spline
 * interpolating the user's colours.
 */
#include "base/abi.h"
#include "mesh/check.h"
#include "base/context.h"
#include "device/device.h"
#include "mesh/mesh.h"
#include "solve/operator.h"
#include "solve/monitor.h"
#include "refine/refine.h"
#include "series/series.h"
#include "base/clock.h"
#include "device/choice/choice.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ------------------------------------------------------- Perlin noise 2002 */

static uint64_t splitmix64(uint64_t *state)
{
    uint64_t z = (*state += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
}

void limn_noise_init(limn_noise *noise, uint64_t seed)
{
    if (!noise)
        return; /* no context to report to */
    uint8_t p[256];
    for (int i = 0; i < 256; i++)
        p[i] = (uint8_t)i;
    uint64_t state = seed;
    for (int i = 255; i > 0; i--) { /* Fisher-Yates */
        int j = (int)(splitmix64(&state) % (uint64_t)(i + 1));
        uint8_t t = p[i];
        p[i] = p[j];
        p[j] = t;
    }
    for (int i = 0; i < 512; i++)
        noise->perm[i] = p[i & 255];
}

static double fade(double t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); }
static double lerp(double t, double a, double b) { return a + t * (b - a); }
static double grad(int hash, double x, double y, double z)
{
    int h = hash & 15;
    double u = h < 8 ? x : y, v = h < 4 ? y : (h == 12 || h == 14) ? x : z;
    return ((h & 1) == 0 ? u : -u) + ((h & 2) == 0 ? v : -v);
}

double limn_noise_eval(const limn_noise *noise, double x, double y, double z)
{
    if (!noise)
        return 0.0;
    const uint8_t *p = noise->perm;
    double fx = floor(x), fy = floor(y), fz = floor(z);
    int X = (int)((long long)fx & 255), Y = (int)((long long)fy & 255),
        Z = (int)((long long)fz & 255);
    x -= fx;
    y -= fy;
    z -= fz;
    double u = fade(x), v = fade(y), w = fade(z);
    int A = p[X] + Y, AA = p[A] + Z, AB = p[A + 1] + Z;
    int B = p[X + 1] + Y, BA = p[B] + Z, BB = p[B + 1] + Z;
    return lerp(w,
                lerp(v, lerp(u, grad(p[AA], x, y, z), grad(p[BA], x - 1, y, z)),
                     lerp(u, grad(p[AB], x, y - 1, z), grad(p[BB], x - 1, y - 1, z))),
                lerp(v, lerp(u, grad(p[AA + 1], x, y, z - 1), grad(p[BA + 1], x - 1, y, z - 1)),
                     lerp(u, grad(p[AB + 1], x, y - 1, z - 1),
                          grad(p[BB + 1], x - 1, y - 1, z - 1))));
}

/* ------------------------------------------------------ colour B-spline */

/* Control points d_{-1} .. d_K of the uniform cubic B-spline through the K
   colours at t_j = j / (K - 1), natural ends (d_{-1} = 2 d_0 - d_1): then
   d_0 = c_0, d_{K-1} = c_{K-1}, and d_{j-1} + 4 d_j + d_{j+1} = 6 c_j inside. */
static void spline_controls(const uint8_t *colors, size_t k, double *d /* (k + 2) * 3 */)
{
    double *in = d + 3; /* d_0 at in[0] */
    for (int c = 0; c < 3; c++) {
        in[c] = colors[c];
        in[3 * (k - 1) + c] = colors[3 * (k - 1) + c];
    }
    if (k > 2) {
        /* Thomas algorithm on rows 1 .. k-2 (diagonal 4, off-diagonals 1) */
        size_t m = k - 2;
        double *cp = malloc(m * sizeof *cp), *rhs = malloc(3 * m * sizeof *rhs);
        if (cp && rhs) {
            for (size_t j = 0; j < m; j++)
                for (int c = 0; c < 3; c++) {
                    rhs[3 * j + c] = 6.0 * colors[3 * (j + 1) + c];
                    if (j == 0)
                        rhs[c] -= in[c];
                    if (j == m - 1)
                        rhs[3 * j + c] -= in[3 * (k - 1) + c];
                }
            double denom = 4.0;
            cp[0] = 1.0 / denom;
            for (int c = 0; c < 3; c++)
                rhs[c] /= denom;
            for (size_t j = 1; j < m; j++) {
                denom = 4.0 - cp[j - 1];
                cp[j] = 1.0 / denom;
                for (int c = 0; c < 3; c++)
                    rhs[3 * j + c] = (rhs[3 * j + c] - rhs[3 * (j - 1) + c]) / denom;
            }
            for (size_t j = m; j-- > 0;)
                for (int c = 0; c < 3; c++) {
                    double v = rhs[3 * j + c];
                    if (j + 1 < m)
                        v -= cp[j] * in[3 * (j + 2) + c];
                    in[3 * (j + 1) + c] = v;
                }
        }
        free(cp);
        free(rhs);
    }
    for (int c = 0; c < 3; c++) {
        if (k == 1) {
            d[c] = in[c];
            in[3 + c] = in[c];
            continue;
        }
        d[c] = 2.0 * in[c] - in[3 + c];
        in[3 * k + c] = 2.0 * in[3 * (k - 1) + c] - in[3 * (k - 2) + c];
    }
}

static void spline_color(const double *d, size_t k, const uint8_t lo[3], const uint8_t hi[3],
                         double t, uint8_t out[3])
{
    double s = k > 1 ? t * (double)(k - 1) : 0.0;
    size_t j = s <= 0.0 ? 0 : (size_t)s;
    if (k > 1 && j > k - 2)
        j = k - 2;
    double u = k > 1 ? s - (double)j : 0.0;
    double b0 = (1 - u) * (1 - u) * (1 - u) / 6.0;
    double b1 = (3 * u * u * u - 6 * u * u + 4) / 6.0;
    double b2 = (-3 * u * u * u + 3 * u * u + 3 * u + 1) / 6.0;
    double b3 = u * u * u / 6.0;
    for (int c = 0; c < 3; c++) {
        /* segment j uses d_{j-1} .. d_{j+2}, stored from d[3 * j] */
        double v = k == 1 ? d[3 + c]
                          : b0 * d[3 * j + c] + b1 * d[3 * (j + 1) + c] +
                                b2 * d[3 * (j + 2) + c] + b3 * d[3 * (j + 3) + c];
        v = v < lo[c] ? lo[c] : v > hi[c] ? hi[c] : v;
        out[c] = (uint8_t)lround(v);
    }
}

/* ----------------------------------------------------------- the texture */

void limn_texture_options_default(limn_texture_options *o)
{
    abi_default(&abi_texture_options, o);
}

#define TEXTURE_MAX_ITER 2000

/* Solves A P = N for a scalar field (channel x) by the paper's iteration on
   the operator of s; buf[0] holds N, the answer ends in *answer. */
static limn_status solve_scalar(limn_context *ctx, series_run *s, double tol, int level,
                                device_buffer **answer, long long *products)
{
    device_buffer *p[2] = {s->buf[1], s->buf[2]};
    limn_status st = s->dev->ops->axpby(s->dev, s->n, 1.0, s->buf[0], 0.0, s->buf[0], p[0]);
    monitor mon;
    monitor_init(&mon, tol, TEXTURE_MAX_ITER, MONITOR_STALL_WINDOW, MONITOR_STALL_RATIO);
    monitor_words words = {MONITOR_LOOP_TEXTURE, "the residual of the noise interpolation", 0.0,
                           0.0, s->op.scheme, s->op.alpha, 0, 0, level};
    for (int k = 0; !st; k++) {
        device_norms nr;
        st = s->dev->ops->stationary->interp_step(s->dev, &s->op.device, s->buf[0], p[k & 1],
                                      p[(k + 1) & 1], 1.0, &nr);
        ++*products;
        if (st)
            break;
        nr.max = check_norm_max(nr.max, nr.sum);
        monitor_verdict v = monitor_step(&mon, nr.max, k);
        if (v == MONITOR_CONVERGED) {
            *answer = p[k & 1];
            return LIMN_OK;
        }
        if (v != MONITOR_CONTINUE) /* a stall: LIMN_ERR_SINGULAR; the cap: NO_CONVERGENCE */
            return monitor_fail(ctx, &mon, v, &words);
    }
    return st;
}

limn_status texture_check_options(limn_context *ctx, const limn_texture_options *o)
{
    limn_status st = check_scheme(ctx, "limn_texture", o->series.scheme);
    if (!st)
        st = series_check_options(ctx, &o->series);
    if (!st)
        st = check_count(ctx, "limn_texture", "levels", o->levels, 0, LIMN_MAX_TEXTURE_LEVELS,
                         "LIMN_MAX_TEXTURE_LEVELS");
    if (st)
        return st;
    if (!o->colors || o->color_count < 1)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "limn_texture: at least one colour is needed "
                                                 "(colors %s, color_count %zu)",
                         o->colors ? "given" : "NULL", o->color_count);
    if (o->color_count > LIMN_MAX_COLORS)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                         "limn_texture: color_count is %zu, over the cap of %d "
                         "(LIMN_MAX_COLORS)",
                         o->color_count, LIMN_MAX_COLORS);
    if (!(o->frequency > 0.0 && isfinite(o->frequency)))
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "frequency is %g; it must be positive",
                         o->frequency);
    if (!(o->tolerance > 0.0 && isfinite(o->tolerance)))
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "tolerance is %g; it must be positive",
                         o->tolerance);
    return LIMN_OK;
}

/* Positions of every level: level k+1 = step k applied to level k, on the device. */
static limn_status level_positions(limn_context *ctx, refine_plan *plan)
{
    struct device *dev;
    limn_status st = device_get(ctx, &dev);
    if (st)
        return st;
    size_t nmax = plan->meshes[plan->levels]->vertex_count;
    double *buf = calloc(4 * nmax + 4, sizeof *buf);
    if (!buf)
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for %zu vertices", nmax);
    device_buffer *x = NULL, *y = NULL;
    const limn_mesh *g0 = plan->meshes[0];
    for (size_t i = 0; i < g0->vertex_count; i++)
        memcpy(buf + 4 * i, g0->positions + 3 * i, 3 * sizeof(double));
    st = dev->ops->buffer_create(dev, 4 * g0->vertex_count * sizeof(double), buf, &x);
    for (int k = 0; !st && k < plan->levels; k++) {
        device_csr a;
        const stencil_csr *h = &plan->steps[k];
        st = device_csr_share(dev, h, &a); /* the plan's table outlives it */
        if (st)
            break;
        st = dev->ops->buffer_scratch(dev, 4 * h->rows * sizeof(double), &y);
        if (!st)
            st = dev->ops->spmv(dev, &a, x, y);
        device_csr_release(dev, &a);
        if (!st)
            st = dev->ops->buffer_read(dev, y, 4 * h->rows * sizeof(double), buf);
        limn_mesh *g = plan->meshes[k + 1];
        for (size_t i = 0; !st && i < g->vertex_count; i++)
            memcpy(g->positions + 3 * i, buf + 4 * i, 3 * sizeof(double));
        dev->ops->buffer_release(dev, x);
        x = y;
        y = NULL;
    }
    if (x)
        dev->ops->buffer_release(dev, x);
    free(buf);
    return st;
}

/* The checks of limn_texture, in its order, the memory estimate last: it
   refuses before any work when the levels would not fit (the estimate of
   `limn subdivide --limit`: the plan plus the finest operator). */
static limn_status check_texture(limn_context *ctx, const limn_mesh *mesh,
                                 const limn_texture_options *o, limn_mesh **out,
                                 limn_series_report *r)
{
    limn_status st = abi_begin(ctx, "limn_texture", "options", o);
    if (!st)
        st = abi_begin(ctx, "limn_texture", "out", out);
    if (st)
        return st;
    *out = NULL;
    st = check_mesh_magnitude(ctx, "limn_texture", NULL, mesh);
    if (st)
        return st;
    series_report_init(r, mesh);
    st = texture_check_options(ctx, o);
    if (st)
        return st;
    if (mesh->vertex_count == 0 || mesh->face_count == 0)
        return ctx_fail(ctx, LIMN_ERR_TOPOLOGY, "the mesh has no %s",
                         mesh->vertex_count ? "faces" : "vertices");
    limn_subdivide_options so;
    limn_subdivide_options_default(&so);
    so.scheme = o->series.scheme;
    so.alpha = o->series.alpha;
    so.levels = o->levels;
    so.limit = 1;
    so.max_memory = o->max_memory;
    size_t est_v, est_f, est_peak;
    return limn_subdivide_estimate(ctx, mesh, &so, &est_v, &est_f, &est_peak);
}

/* One texture's work: the levels, G_L's sum and the open level's run. */
typedef struct texture_work {
    const limn_texture_options *o;
    limn_series_report *r;
    refine_plan plan;
    size_t nf;                     /* vertices of G_L */
    double *sum, *carried, *field; /* on G_L; field: a level's values */
    uint8_t *rgb;
    double lo[3], scale;           /* the noise's frame */
    limn_noise noise;
    series_run s;                  /* level i's operator; G_L's after the last */
} texture_work;

/* Sets every vertex's channel x (the others zero) and writes buf[0]. */
static limn_status write_scalar(series_run *s, const double *v, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        s->host[4 * i] = v[i];
        s->host[4 * i + 1] = s->host[4 * i + 2] = s->host[4 * i + 3] = 0.0;
    }
    return s->dev->ops->buffer_write(s->dev, s->buf[0], 4 * n * sizeof(double), s->host);
}

/* Level i: its noise, interpolated on G_i, carried to G_L and summed. */
static limn_status texture_level(limn_context *ctx, texture_work *w, int i)
{
    const limn_mesh *g = w->plan.meshes[i];
    series_run *s = &w->s;
    limn_series_report *r = w->r;
    int levels = w->o->levels;
    double f = ldexp(1.0, i), amp = 1.0 / f, range = 0.0, fs = f * w->scale;
    for (size_t v = 0; v < g->vertex_count; v++) {
        const double *p = g->positions + 3 * v;
        w->field[v] = amp * limn_noise_eval(&w->noise, fs * (p[0] - w->lo[0]),
                                            fs * (p[1] - w->lo[1]), fs * (p[2] - w->lo[2]));
        range = fmax(range, fabs(w->field[v]));
    }
    /* the alpha rule belongs to the first refinement step only */
    limn_status st = series_open(ctx, g, w->plan.scheme, i == 0 ? w->plan.alpha : 0.0, 3, s, NULL);
    if (st)
        return st;
    if (i == levels) {
        series_report_operator(r, &s->op);
    } else {
        r->seconds_topology += s->op.seconds_topology;
        r->seconds_stencil += s->op.seconds_stencil;
    }
    double tc = clock_seconds();
    st = write_scalar(s, w->field, g->vertex_count);
    device_buffer *ctrl = NULL;
    if (!st)
        st = solve_scalar(ctx, s, w->o->tolerance * (range > 0 ? range : 1.0), i, &ctrl,
                          &r->products);
    if (!st)
        st = s->dev->ops->buffer_read(s->dev, ctrl, 4 * s->n * sizeof(double), s->host);
    for (size_t v = 0; !st && v < g->vertex_count; v++)
        w->field[v] = s->host[4 * v];
    /* carry the control values to G_L and sum there */
    if (!st)
        st = refine_plan_apply(ctx, &w->plan, i, 1, w->field, w->carried);
    for (size_t v = 0; !st && v < w->nf; v++)
        w->sum[v] += w->carried[v];
    r->seconds_compute += clock_seconds() - tc;
    if (i < levels)
        series_close(s);
    ctx_progress(ctx, "texture", (double)(i + 1) / (levels + 1));
    return st;
}

limn_status texture_map_colors(limn_context *ctx, const limn_texture_options *o,
                               const double *values, size_t stride, size_t n, double mn,
                               double mx, uint8_t *rgb)
{
    size_t k = o->color_count;
    double *d = malloc((k + 2) * 3 * sizeof *d);
    if (!d)
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for the colour spline");
    uint8_t clo[3] = {255, 255, 255}, chi[3] = {0, 0, 0};
    for (size_t j = 0; j < k; j++)
        for (int c = 0; c < 3; c++) {
            uint8_t x = o->colors[3 * j + c];
            clo[c] = x < clo[c] ? x : clo[c];
            chi[c] = x > chi[c] ? x : chi[c];
        }
    spline_controls(o->colors, k, d);
    for (size_t v = 0; v < n; v++) {
        double t = mx > mn ? (values[stride * v] - mn) / (mx - mn) : 0.5;
        spline_color(d, k, clo, chi, t, rgb + 3 * v);
    }
    free(d);
    return LIMN_OK;
}

/* The field (channel x of s's host, nf vertices) normalised to [0, 1] and
   mapped through the colour spline onto result. */
static limn_status texture_colors(limn_context *ctx, const limn_texture_options *o,
                                  const double *host, size_t nf, uint8_t *rgb, limn_mesh *result)
{
    double mn = INFINITY, mx = -INFINITY;
    for (size_t v = 0; v < nf; v++) {
        mn = fmin(mn, host[4 * v]);
        mx = fmax(mx, host[4 * v]);
    }
    limn_status st = texture_map_colors(ctx, o, host, 4, nf, mn, mx, rgb);
    return st ? st : limn_mesh_set_colors(ctx, result, rgb);
}

/* G_L's operator (still open): its limit points, the summed field there, the colours. */
static limn_status texture_finish(limn_context *ctx, texture_work *w, limn_mesh **result)
{
    series_run *s = &w->s;
    const limn_mesh *fine = w->plan.meshes[w->o->levels];
    size_t nf = w->nf;
    double tc = clock_seconds();
    limn_status st = limn_mesh_copy(ctx, fine, result);
    device_norms nr;
    if (!st)
        st = series_upload(s, s->buf[0], fine->positions);
    if (!st)
        st = s->dev->ops->series->series_step(s->dev, &s->op.device, s->buf[0], NULL, s->buf[1],
                                              NULL, SERIES_STORE_AX, SERIES_ACC_NONE, &nr);
    if (!st)
        st = series_download(s, s->buf[1], (*result)->positions);
    if (!st)
        st = write_scalar(s, w->sum, nf);
    if (!st)
        st = s->dev->ops->spmv(s->dev, &s->op.device, s->buf[0], s->buf[1]);
    if (!st)
        st = s->dev->ops->buffer_read(s->dev, s->buf[1], 4 * nf * sizeof(double), s->host);
    w->r->products += 2;
    if (!st)
        st = texture_colors(ctx, w->o, s->host, nf, w->rgb, *result);
    w->r->seconds_compute += clock_seconds() - tc;
    return st;
}

/* limn_texture on options and report of this library's layout (options
   NULL: refused, there are no default colours). */
static limn_status texture_sized(limn_context *ctx, const limn_mesh *mesh,
                                 const limn_texture_options *o, limn_mesh **out,
                                 limn_series_report *r)
{
    limn_status st = check_texture(ctx, mesh, o, out, r);
    if (st)
        return st;
    texture_work w = {.o = o, .r = r};
    int levels = o->levels;
    double t0 = clock_seconds();
    st = refine_plan_build(ctx, mesh, o->series.scheme, o->series.alpha, levels, &w.plan);
    if (st)
        return st;
    r->seconds_topology += clock_seconds() - t0;
    st = level_positions(ctx, &w.plan);
    w.nf = w.plan.meshes[levels]->vertex_count;
    w.sum = calloc(w.nf, sizeof *w.sum);
    w.carried = calloc(w.nf, sizeof *w.carried);
    w.field = calloc(w.nf > mesh->vertex_count ? w.nf : mesh->vertex_count, sizeof *w.field);
    w.rgb = malloc(3 * w.nf);
    if (!st && (!w.sum || !w.carried || !w.field || !w.rgb))
        st = ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for %zu vertices", w.nf);
    double hi[3], diag = mesh_bbox_diagonal(mesh, w.lo, hi);
    w.scale = diag > 0 ? o->frequency / diag : 1.0;
    limn_noise_init(&w.noise, o->seed);
    limn_mesh *result = NULL;
    for (int i = 0; !st && i <= levels; i++)
        st = texture_level(ctx, &w, i);
    if (!st)
        st = texture_finish(ctx, &w, &result);
    r->vertices = mesh->vertex_count;
    r->faces = mesh->face_count;
    r->alpha = w.plan.alpha; /* the user's alpha (used on the first refinement step) */
    series_close(&w.s);
    refine_plan_free(&w.plan);
    free(w.sum);
    free(w.carried);
    free(w.field);
    free(w.rgb);
    return mesh_hand_over(st, result, out);
}

limn_status limn_texture(limn_context *ctx, const limn_mesh *mesh,
                         const limn_texture_options *options, limn_mesh **out,
                         limn_series_report *report)
{
    abi_call c;
    limn_status st = abi_enter(&c, ctx, "limn_texture", &abi_texture_options, options,
                               &abi_series_report, report, out);
    /* no defaults to stand in for NULL options: texture_sized refuses them */
    return st ? st
              : abi_leave(&c, texture_sized(ctx, mesh, options ? c.options : NULL, out, c.report));
}
