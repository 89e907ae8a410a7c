/* SPDX-License-Identifier: MIT */
/*
 * The mesh series toolkit (issue 4) against independent routes:
 *  - bands and the filters against dense matrices built from the CSR table
 *    and powered explicitly ((E - A)^i as a matrix, not the iteration);
 *  - bands sum back to M to 1e-12 of the bbox diagonal; band energy falls on
 *    smooth meshes;
 *  - denoising a shared mesh with seeded Gaussian noise (sigma = 0.3 x mean
 *    edge) brings it closer to the clean mesh in distance and normal angle;
 *  - sharpening raises the energy of the high bands; morph frame 0 is FROM and
 *    the error to TO falls monotonically; texture colours stay in the list's
 *    range and neighbours differ little;
 *  - the OpenCL and reference backends agree (bit-identical expected);
 *  - volume / area / flips on closed forms; the renderer on a cube.
 */
#include "noise.h"
#include "support.h"

#include "stencil/stencil.h"
#include "topology/topology.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

static const double PI = 3.14159265358979323846;

/* ------------------------------------------------------------ helpers */

static limn_context *ctx_for(const char *device)
{
    limn_context *ctx = limn_context_create();
    assert_non_null(ctx);
    assert_int_equal(limn_context_set_device(ctx, device), LIMN_OK);
    return ctx;
}

#define CHECK_OK(ctx, call)                                                                    \
    do {                                                                                       \
        limn_status st_ = (call);                                                              \
        if (st_ != LIMN_OK)                                                                    \
            fail_msg("%s failed: %s", #call, limn_context_message(ctx));                       \
    } while (0)

/* Icosahedron refined `levels` times by edge midpoints, projected to the unit sphere. */
static limn_mesh *icosphere(limn_context *ctx, int levels)
{
    limn_mesh *m = test_mesh_icosahedron(ctx);
    for (int l = 0; l < levels; l++) {
        size_t nv = limn_mesh_vertex_count(m), nf = limn_mesh_face_count(m);
        const double *p = limn_mesh_positions(m);
        const uint32_t *idx = limn_mesh_face_indices(m);
        size_t cap = nv + 3 * nf;
        double *pos = malloc(3 * cap * sizeof *pos);
        uint32_t *key = malloc(2 * cap * sizeof *key), *nidx = malloc(12 * nf * sizeof *nidx);
        uint32_t *off = malloc((4 * nf + 1) * sizeof *off);
        memcpy(pos, p, 3 * nv * sizeof *pos);
        size_t n = nv;
        for (size_t f = 0; f < nf; f++) {
            uint32_t v[3] = {idx[3 * f], idx[3 * f + 1], idx[3 * f + 2]}, mid[3];
            for (int e = 0; e < 3; e++) {
                uint32_t a = v[e], b = v[(e + 1) % 3], lo = a < b ? a : b, hi = a < b ? b : a;
                size_t k = nv;
                while (k < n && !(key[2 * k] == lo && key[2 * k + 1] == hi))
                    k++;
                if (k == n) {
                    key[2 * n] = lo, key[2 * n + 1] = hi;
                    for (int c = 0; c < 3; c++)
                        pos[3 * n + c] = 0.5 * (p[3 * a + c] + p[3 * b + c]);
                    n++;
                }
                mid[e] = (uint32_t)k;
            }
            uint32_t t[12] = {v[0], mid[0], mid[2], v[1], mid[1], mid[0],
                              v[2], mid[2], mid[1], mid[0], mid[1], mid[2]};
            memcpy(nidx + 12 * f, t, sizeof t);
        }
        for (size_t i = 0; i <= 4 * nf; i++)
            off[i] = (uint32_t)(3 * i);
        for (size_t i = 0; i < n; i++) {
            double *q = pos + 3 * i, r = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
            for (int c = 0; c < 3; c++)
                q[c] /= r;
        }
        limn_mesh *next = NULL;
        CHECK_OK(ctx, limn_mesh_create(ctx, n, pos, 4 * nf, off, nidx, &next));
        limn_mesh_destroy(m);
        m = next;
        free(pos);
        free(key);
        free(nidx);
        free(off);
    }
    return m;
}

/* ------------------------------------------------------- dense oracle */

typedef struct dense {
    size_t n;
    double *a; /* n x n, row-major */
} dense;

static dense dense_operator(limn_context *ctx, const limn_mesh *m, limn_scheme scheme,
                            double alpha)
{
    topology t;
    stencil_csr csr;
    CHECK_OK(ctx, topology_build(ctx, m, &t));
    CHECK_OK(ctx, stencil_limit_build(ctx, &t, scheme, alpha, &csr));
    dense d = {limn_mesh_vertex_count(m), NULL};
    d.a = calloc(d.n * d.n, sizeof *d.a);
    for (size_t i = 0; i < csr.rows; i++)
        for (uint32_t k = csr.row_offsets[i]; k < csr.row_offsets[i + 1]; k++)
            d.a[i * d.n + csr.columns[k]] += csr.weights[k];
    stencil_free(&csr);
    topology_free(&t);
    return d;
}

static double *mat_mul(const double *x, const double *y, size_t n)
{
    double *z = calloc(n * n, sizeof *z);
    for (size_t i = 0; i < n; i++)
        for (size_t k = 0; k < n; k++) {
            double v = x[i * n + k];
            if (v != 0)
                for (size_t j = 0; j < n; j++)
                    z[i * n + j] += v * y[k * n + j];
        }
    return z;
}

/* (E - A)^i as an explicit matrix. */
static double *power_e_minus_a(const dense *d, int i)
{
    size_t n = d->n;
    double *b = calloc(n * n, sizeof *b), *p = calloc(n * n, sizeof *p);
    for (size_t r = 0; r < n; r++) {
        p[r * n + r] = 1.0;
        for (size_t c = 0; c < n; c++)
            b[r * n + c] = (r == c) - d->a[r * n + c];
    }
    for (int k = 0; k < i; k++) {
        double *q = mat_mul(p, b, n);
        free(p);
        p = q;
    }
    free(b);
    return p;
}

/* y = X x for 3 channels. */
static void apply(const double *x, size_t n, const double *v, double *y)
{
    test_dense_product(x, n, v, 3, y);
}

/* sum_{i=0..top} (E - A)^i, each term times a unless a is NULL. */
static double *power_sum(const dense *d, int top, const double *a)
{
    size_t n = d->n;
    double *sum = calloc(n * n, sizeof *sum);
    for (int i = 0; i <= top; i++) {
        double *p = power_e_minus_a(d, i), *term = a ? mat_mul(p, a, n) : p;
        for (size_t k = 0; k < n * n; k++)
            sum[k] += term[k];
        if (term != p)
            free(term);
        free(p);
    }
    return sum;
}

/* t = X^steps pos for 3 channels; t2 is scratch. */
static void apply_steps(const double *x, size_t n, const double *pos, int steps, double *t,
                        double *t2)
{
    memcpy(t, pos, 3 * n * sizeof *t);
    for (int k = 0; k < steps; k++) {
        apply(x, n, t, t2);
        memcpy(t, t2, 3 * n * sizeof *t);
    }
}

static void expect_close(const char *what, const double *a, const double *b, size_t count,
                         double scale, double tol)
{
    for (size_t i = 0; i < count; i++)
        if (!(fabs(a[i] - b[i]) <= tol * scale))
            fail_msg("%s: entry %zu: %.17g vs %.17g (tolerance %.3g)", what, i, a[i], b[i],
                     tol * scale);
}

static double max_abs(const double *x, size_t n)
{
    double m = 0;
    for (size_t i = 0; i < n; i++)
        m = fmax(m, fabs(x[i]));
    return m;
}

/* Bands, smooth, denoise, sharpen and morph against dense matrices. */
static void dense_check(const char *name, limn_mesh *m, limn_scheme scheme, double alpha)
{
    limn_context *ctx = ctx_for("reference");
    size_t n = limn_mesh_vertex_count(m), n3 = 3 * n;
    const double *pos = limn_mesh_positions(m);
    double scale = fmax(1.0, max_abs(pos, n3));
    dense d = dense_operator(ctx, m, scheme, alpha);
    limn_series_options o;
    limn_series_options_default(&o);
    o.scheme = scheme;
    o.alpha = alpha;

    /* bands */
    const int count = 6;
    double *bands = malloc((count + 1) * n3 * sizeof *bands), *energy = malloc((count + 1) * sizeof *energy);
    double *am = malloc(n3 * sizeof *am), *want = malloc(n3 * sizeof *want);
    CHECK_OK(ctx, limn_bands(ctx, m, &o, count, bands, energy, NULL));
    apply(d.a, n, pos, am);
    for (int i = 0; i <= count; i++) {
        double *p = power_e_minus_a(&d, i);
        apply(p, n, i < count ? am : pos, want);
        char what[128];
        snprintf(what, sizeof what, "%s band %d", name, i);
        expect_close(what, bands + i * n3, want, n3, scale, 1e-12);
        double e = 0;
        for (size_t k = 0; k < n3; k++)
            e += want[k] * want[k];
        assert_true(fabs(e - energy[i]) <= 1e-10 * fmax(e, 1e-300) + 1e-24);
        free(p);
    }

    /* smooth: the sum of the first 3 bands = (E - (E - A)^3) M */
    limn_mesh *out = NULL;
    CHECK_OK(ctx, limn_smooth(ctx, m, &o, 3, &out, NULL));
    double *p3 = power_e_minus_a(&d, 3);
    apply(p3, n, pos, want);
    for (size_t k = 0; k < n3; k++)
        want[k] = pos[k] - want[k];
    expect_close("smooth", limn_mesh_positions(out), want, n3, scale, 1e-12);
    limn_mesh_destroy(out);

    /* denoise m = 2, 2 steps: T <- sum_{i=0..2} (E - A)^i A T, summed here term by
       term as dense matrices (it telescopes to E - (E - A)^3; DESIGN.md §1's
       "(E - (E - A)^{m+1}) A" has one factor A too many, as has seed 000's
       "T_k = D^k A T_0") */
    double *filt = power_sum(&d, 2, d.a);
    double *t = malloc(n3 * sizeof *t), *t2 = malloc(n3 * sizeof *t2);
    apply_steps(filt, n, pos, 2, t, t2);
    CHECK_OK(ctx, limn_denoise(ctx, m, &o, 2, 2, 0, &out, NULL));
    expect_close("denoise", limn_mesh_positions(out), t, n3, scale, 1e-12);
    limn_mesh_destroy(out);

    /* sharpen from 1 to 3, 2 steps: T <- (E + sum_{i=1..3} (E - A)^i) T */
    double *sh = power_sum(&d, 3, NULL);
    apply_steps(sh, n, pos, 2, t, t2);
    CHECK_OK(ctx, limn_sharpen(ctx, m, &o, 1, 3, 2, &out, NULL));
    expect_close("sharpen", limn_mesh_positions(out), t, n3, scale, 1e-11);
    limn_mesh_destroy(out);

    free(p3);
    free(filt);
    free(sh);
    free(t);
    free(t2);
    free(bands);
    free(energy);
    free(am);
    free(want);
    free(d.a);
    limn_context_destroy(ctx);
}

static void series_against_dense(void **s)
{
    limn_context *ctx = *s;
    limn_mesh *ico = test_mesh_icosahedron(ctx), *cube = test_mesh_cube(ctx);
    limn_mesh *grid = test_mesh_grid(ctx, 5, 4, 0), *tgrid = test_mesh_grid(ctx, 4, 4, 1);
    limn_mesh *pyr = test_mesh_pyramid(ctx), *fan = test_mesh_fan(ctx, 5, 0);
    test_perturb(ico, 0.1, 1);
    test_perturb(cube, 0.1, 2);
    dense_check("icosahedron (Loop)", ico, LIMN_SCHEME_LOOP, 0.0);
    dense_check("icosahedron (Catmull-Clark)", ico, LIMN_SCHEME_CATMARK, 0.0);
    dense_check("cube (alpha 0.5)", cube, LIMN_SCHEME_CATMARK, 0.5);
    dense_check("quad grid (boundary)", grid, LIMN_SCHEME_CATMARK, 0.0);
    dense_check("triangle grid (boundary)", tgrid, LIMN_SCHEME_LOOP, 0.0);
    dense_check("pyramid (mixed faces)", pyr, LIMN_SCHEME_CATMARK, 0.0);
    dense_check("quad fan (valence 5)", fan, LIMN_SCHEME_CATMARK, 0.0);
    if (test_shared_meshes()) {
        limn_mesh *m = test_read_shared(ctx, "small/spot_control_mesh.obj");
        dense_check("spot_control_mesh", m, LIMN_SCHEME_CATMARK, 0.0);
        limn_mesh_destroy(m);
    }
    limn_mesh_destroy(ico);
    limn_mesh_destroy(cube);
    limn_mesh_destroy(grid);
    limn_mesh_destroy(tgrid);
    limn_mesh_destroy(pyr);
    limn_mesh_destroy(fan);
}

/* --------------------------------------------- bands sum back, energy falls */

static void bands_of(const char *name, limn_mesh *m, int count, int expect_decreasing)
{
    limn_context *ctx = ctx_for("opencl");
    size_t n3 = 3 * limn_mesh_vertex_count(m);
    double *bands = malloc((size_t)(count + 1) * n3 * sizeof *bands);
    double *energy = malloc((size_t)(count + 1) * sizeof *energy);
    limn_series_report r = {.size = sizeof r};
    CHECK_OK(ctx, limn_bands(ctx, m, NULL, count, bands, energy, &r));
    assert_int_equal(r.products, count);
    const double *pos = limn_mesh_positions(m);
    double diag = test_bbox_diagonal(m), worst = 0;
    for (size_t k = 0; k < n3; k++) {
        double sum = 0;
        for (int i = 0; i <= count; i++)
            sum += bands[(size_t)i * n3 + k];
        worst = fmax(worst, fabs(sum - pos[k]));
    }
    printf("  %-30s %zu vertices: bands + remainder = M to %.2g of the diagonal; energy",
           name, n3 / 3, worst / diag);
    for (int i = 0; i <= count && i < 6; i++)
        printf(" %.3g", energy[i]);
    printf("\n");
    if (!(worst <= 1e-12 * diag))
        fail_msg("%s: bands sum to M only to %.3g of the diagonal", name, worst / diag);
    if (expect_decreasing)
        for (int i = 0; i + 1 < count; i++)
            if (!(energy[i + 1] < energy[i]))
                fail_msg("%s: band energy rises from band %d (%.6g) to %d (%.6g)", name, i,
                         energy[i], i + 1, energy[i + 1]);
    free(bands);
    free(energy);
    limn_context_destroy(ctx);
}

static void bands_sum_and_energy(void **s)
{
    limn_context *ctx = *s;
    limn_mesh *sphere = icosphere(ctx, 3), *grid = test_mesh_grid(ctx, 40, 37, 0);
    bands_of("icosphere (3 levels)", sphere, 10, 1);
    bands_of("quad grid 40x37", grid, 10, 0);
    limn_mesh_destroy(sphere);
    limn_mesh_destroy(grid);
    static const char *smooth[] = {"medium/bunny_closed.off", "medium/bob_quad.obj",
                                   "small/spot_triangulated.obj"};
    for (size_t i = 0; test_shared_meshes() && i < sizeof smooth / sizeof *smooth; i++) {
        limn_mesh *m = test_read_shared(ctx, smooth[i]);
        bands_of(smooth[i], m, 8, 1);
        limn_mesh_destroy(m);
    }
}

/* ------------------------------------------------------------- denoise */

static void denoise_one(limn_context *ctx, const char *name, limn_mesh *clean, double factor)
{
    limn_mesh *noisy = NULL, *out = NULL;
    CHECK_OK(ctx, limn_mesh_copy(ctx, clean, &noisy));
    test_gaussian_noise(noisy, factor * test_mean_edge(clean), 2024);
    limn_mesh_comparison before = {.size = sizeof before}, after = {.size = sizeof after};
    CHECK_OK(ctx, limn_mesh_compare(ctx, clean, noisy, &before));
    limn_series_report r = {.size = sizeof r};
    CHECK_OK(ctx, limn_denoise(ctx, noisy, NULL, 2, 3, 0, &out, &r));
    assert_int_equal(r.products, 9);
    CHECK_OK(ctx, limn_mesh_compare(ctx, clean, out, &after));
    double diag = test_bbox_diagonal(clean);
    printf("  %-30s sigma %.1f edge: distance %.3g -> %.3g of the diagonal, normal error %.2f -> "
           "%.2f degrees\n",
           name, factor, before.mean_distance / diag, after.mean_distance / diag,
           before.mean_normal_angle, after.mean_normal_angle);
    if (!(after.mean_distance < before.mean_distance))
        fail_msg("%s: denoising did not reduce the distance to the clean mesh", name);
    if (!(after.mean_normal_angle < before.mean_normal_angle))
        fail_msg("%s: denoising did not reduce the normal error", name);
    /* keep-volume restores the volume of the (noisy) input */
    limn_mesh *kept = NULL;
    limn_mesh_measures mi = {.size = sizeof mi}, mo = {.size = sizeof mo};
    CHECK_OK(ctx, limn_mesh_measure(ctx, noisy, &mi));
    if (mi.closed) {
        CHECK_OK(ctx, limn_denoise(ctx, noisy, NULL, 2, 3, 1, &kept, NULL));
        CHECK_OK(ctx, limn_mesh_measure(ctx, kept, &mo));
        assert_true(fabs(mo.volume - mi.volume) <= 1e-9 * fabs(mi.volume));
        limn_mesh_destroy(kept);
    } else {
        assert_int_equal(limn_denoise(ctx, noisy, NULL, 2, 3, 1, &kept, NULL), LIMN_ERR_TOPOLOGY);
        assert_null(kept);
        assert_non_null(strstr(limn_context_message(ctx), "closed"));
    }
    limn_mesh_destroy(noisy);
    limn_mesh_destroy(out);
}

static void denoise_brings_closer(void **s)
{
    limn_context *ctx = *s;
    limn_mesh *sphere = icosphere(ctx, 4);
    denoise_one(ctx, "icosphere (4 levels)", sphere, 0.3);
    limn_mesh_destroy(sphere);
    static const char *files[] = {"medium/bunny_closed.off", "medium/bob_quad.obj",
                                  "medium/bun_zipper.ply"};
    for (size_t i = 0; test_shared_meshes() && i < sizeof files / sizeof *files; i++) {
        limn_mesh *m = test_read_shared(ctx, files[i]);
        denoise_one(ctx, files[i], m, 0.3);
        limn_mesh_destroy(m);
    }
}

/* ------------------------------------------------------------- sharpen */

static void sharpen_raises_high_bands(void **s)
{
    limn_context *ctx = *s;
    limn_mesh *m = icosphere(ctx, 3), *sharp = NULL;
    test_perturb(m, 0.01, 7);
    if (test_shared_meshes()) {
        limn_mesh_destroy(m);
        m = test_read_shared(ctx, "small/spot_triangulated.obj");
    }
    CHECK_OK(ctx, limn_sharpen(ctx, m, NULL, 1, 3, 2, &sharp, NULL));
    const int count = 8;
    double e0[9], e1[9];
    CHECK_OK(ctx, limn_bands(ctx, m, NULL, count, NULL, e0, NULL));
    CHECK_OK(ctx, limn_bands(ctx, sharp, NULL, count, NULL, e1, NULL));
    printf("  band energy ratio sharpened / input:");
    for (int i = 0; i <= count; i++)
        printf(" %.3g", e1[i] / e0[i]);
    printf("\n");
    for (int i = 1; i <= count; i++)
        if (!(e1[i] > 1.5 * e0[i]))
            fail_msg("band %d: energy %.6g after sharpening, %.6g before", i, e1[i], e0[i]);
    limn_mesh_destroy(m);
    limn_mesh_destroy(sharp);
}

/* --------------------------------------------------------------- morph */

typedef struct frames {
    int count;
    double *pos;     /* all frames */
    double dist[64];
    double volume[64];
    size_t flipped[64];
    size_t n3;
} frames;

static limn_status keep_frame(void *user, const limn_morph_frame *f)
{
    frames *fr = user;
    assert_int_equal(f->index, fr->count);
    memcpy(fr->pos + (size_t)f->index * fr->n3, f->positions, fr->n3 * sizeof(double));
    fr->dist[f->index] = f->mean_distance_to_target;
    fr->volume[f->index] = f->volume;
    fr->flipped[f->index] = f->flipped_faces;
    fr->count++;
    return LIMN_OK;
}

static limn_status stop_at_two(void *user, const limn_morph_frame *f)
{
    (void)user;
    return f->index == 2 ? LIMN_ERR_IO : LIMN_OK;
}

static void morph_to(limn_context *ctx, const char *name, limn_mesh *from, limn_mesh *to,
                     int linear)
{
    limn_morph_options o;
    limn_morph_options_default(&o);
    o.frames = 20;
    o.m = 2;
    o.p = 0.7;
    o.linear = linear;
    frames fr = {.n3 = 3 * limn_mesh_vertex_count(from)};
    fr.pos = malloc(20 * fr.n3 * sizeof *fr.pos);
    limn_series_report r = {.size = sizeof r};
    CHECK_OK(ctx, limn_morph(ctx, from, to, &o, keep_frame, &fr, &r));
    assert_int_equal(fr.count, 20);
    assert_memory_equal(fr.pos, limn_mesh_positions(from), fr.n3 * sizeof(double));
    assert_int_equal(r.products, linear ? 0 : 19 * 3);
    for (int k = 1; k < 20; k++)
        if (!(fr.dist[k] < fr.dist[k - 1]))
            fail_msg("%s: the distance to TO rises at frame %d: %.6g after %.6g", name, k,
                     fr.dist[k], fr.dist[k - 1]);
    printf("  %-32s %s: distance to TO %.3g -> %.3g, volume %.4g -> %.4g\n", name,
           linear ? "linear" : "series", fr.dist[0], fr.dist[19], fr.volume[0], fr.volume[19]);
    if (linear)
        assert_memory_equal(fr.pos + 19 * fr.n3, limn_mesh_positions(to), fr.n3 * sizeof(double));
    else
        assert_true(fr.dist[19] < 0.05 * fr.dist[0]);
    free(fr.pos);
}

/* A mesh and its projection onto a sphere about its centroid (seed 000 Fig. 5). */
static limn_mesh *spherized(limn_context *ctx, const limn_mesh *m)
{
    limn_mesh *s = NULL;
    CHECK_OK(ctx, limn_mesh_copy(ctx, m, &s));
    limn_mesh_measures me = {.size = sizeof me};
    CHECK_OK(ctx, limn_mesh_measure(ctx, m, &me));
    test_spherize(s, me.centroid);
    return s;
}

static void morph_frames(void **s)
{
    (void)s;
    limn_context *ctx = ctx_for("opencl");
    limn_mesh *a = icosphere(ctx, 2), *b = NULL;
    CHECK_OK(ctx, limn_mesh_copy(ctx, a, &b));
    test_perturb(a, 0.2, 3);
    double *p = limn_mesh_positions_mutable(b);
    for (size_t i = 0; i < limn_mesh_vertex_count(b); i++)
        p[3 * i] *= 2.0; /* an ellipsoid */
    morph_to(ctx, "perturbed icosphere to ellipsoid", a, b, 0);
    morph_to(ctx, "perturbed icosphere to ellipsoid", a, b, 1);
    if (test_shared_meshes()) {
        limn_mesh *m = test_read_shared(ctx, "small/spot_triangulated.obj");
        limn_mesh *sp = spherized(ctx, m);
        morph_to(ctx, "spot to its sphere", m, sp, 0);
        morph_to(ctx, "spot to its sphere", m, sp, 1);
        limn_mesh_destroy(m);
        limn_mesh_destroy(sp);
    }
    /* a callback's failure stops the morph and is returned */
    assert_int_equal(limn_morph(ctx, a, b, NULL, stop_at_two, NULL, NULL), LIMN_ERR_IO);

    /* topologies that differ: named face */
    limn_mesh *c = NULL;
    CHECK_OK(ctx, limn_mesh_create(ctx, limn_mesh_vertex_count(a), limn_mesh_positions(a),
                                   limn_mesh_face_count(a), limn_mesh_face_offsets(a),
                                   limn_mesh_face_indices(a), &c));
    uint32_t *idx = (uint32_t *)limn_mesh_face_indices(c); /* test only: swap two corners */
    uint32_t t = idx[3 * 7 + 1];
    idx[3 * 7 + 1] = idx[3 * 7 + 2];
    idx[3 * 7 + 2] = t;
    assert_int_equal(limn_morph(ctx, a, c, NULL, keep_frame, NULL, NULL), LIMN_ERR_TOPOLOGY);
    assert_non_null(strstr(limn_context_message(ctx), "face 7"));
    limn_mesh *cube = test_mesh_cube(ctx);
    assert_int_equal(limn_morph(ctx, a, cube, NULL, keep_frame, NULL, NULL), LIMN_ERR_TOPOLOGY);
    assert_non_null(strstr(limn_context_message(ctx), "vertices"));
    limn_morph_options o;
    limn_morph_options_default(&o);
    o.p = 1.0;
    assert_int_equal(limn_morph(ctx, a, b, &o, keep_frame, NULL, NULL), LIMN_ERR_ARGUMENT);
    limn_mesh_destroy(a);
    limn_mesh_destroy(b);
    limn_mesh_destroy(c);
    limn_mesh_destroy(cube);
    limn_context_destroy(ctx);
}

/* ------------------------------------------------------------- texture */

static void texture_colors(void **s)
{
    (void)s;
    limn_context *ctx = ctx_for("opencl");
    limn_mesh *m = icosphere(ctx, 2);
    if (test_shared_meshes()) {
        limn_mesh_destroy(m);
        m = test_read_shared(ctx, "small/spot_control_mesh.obj");
    }
    static const uint8_t colors[] = {20, 40, 120, 240, 220, 160, 140, 30, 10, 60, 200, 60};
    limn_texture_options o;
    limn_texture_options_default(&o);
    o.colors = colors;
    o.color_count = 4;
    o.levels = 2;
    limn_mesh *out = NULL, *again = NULL, *other = NULL;
    limn_series_report r = {.size = sizeof r};
    CHECK_OK(ctx, limn_texture(ctx, m, &o, &out, &r));
    CHECK_OK(ctx, limn_texture(ctx, m, &o, &again, NULL));
    o.seed = 99;
    CHECK_OK(ctx, limn_texture(ctx, m, &o, &other, NULL));
    size_t n = limn_mesh_vertex_count(out);
    const uint8_t *c = limn_mesh_colors(out);
    assert_non_null(c);
    /* deterministic, and the seed matters */
    assert_memory_equal(c, limn_mesh_colors(again), 3 * n);
    assert_true(memcmp(c, limn_mesh_colors(other), 3 * n) != 0);
    /* in the list's per-channel range */
    int lo[3] = {255, 255, 255}, hi[3] = {0, 0, 0};
    for (int k = 0; k < 4; k++)
        for (int j = 0; j < 3; j++) {
            lo[j] = colors[3 * k + j] < lo[j] ? colors[3 * k + j] : lo[j];
            hi[j] = colors[3 * k + j] > hi[j] ? colors[3 * k + j] : hi[j];
        }
    int used_lo[3] = {255, 255, 255}, used_hi[3] = {0, 0, 0};
    for (size_t i = 0; i < n; i++)
        for (int j = 0; j < 3; j++) {
            int v = c[3 * i + j];
            if (v < lo[j] || v > hi[j])
                fail_msg("vertex %zu channel %d is %d, outside the list's %d..%d", i, j, v, lo[j],
                         hi[j]);
            used_lo[j] = v < used_lo[j] ? v : used_lo[j];
            used_hi[j] = v > used_hi[j] ? v : used_hi[j];
        }
    /* the whole range is used (normalised to [0, 1]) */
    for (int j = 0; j < 3; j++)
        assert_true(used_hi[j] - used_lo[j] > (hi[j] - lo[j]) / 2);
    /* neighbours differ little: mean colour step across edges vs the range */
    const uint32_t *off = limn_mesh_face_offsets(out), *idx = limn_mesh_face_indices(out);
    double sum = 0;
    size_t edges = 0;
    for (size_t f = 0; f < limn_mesh_face_count(out); f++)
        for (uint32_t k = off[f]; k < off[f + 1]; k++) {
            uint32_t a = idx[k], b = idx[k + 1 < off[f + 1] ? k + 1 : off[f]];
            double d = 0;
            for (int j = 0; j < 3; j++)
                d += fabs((double)c[3 * a + j] - c[3 * b + j]) / (hi[j] - lo[j]);
            sum += d / 3;
            edges++;
        }
    /* against the same measure between vertices paired at random */
    double rnd = 0;
    for (size_t i = 0; i < n; i++) {
        size_t a = i, b = (i * 7919 + 104729) % n;
        double d = 0;
        for (int j = 0; j < 3; j++)
            d += fabs((double)c[3 * a + j] - c[3 * b + j]) / (hi[j] - lo[j]);
        rnd += d / 3;
    }
    double step = sum / (double)edges;
    rnd /= (double)n;
    printf("  texture: %zu vertices, mean colour step across an edge %.4f of the range, between "
           "random vertices %.4f\n",
           n, step, rnd);
    assert_true(step < 0.1 && step < 0.3 * rnd);
    /* bad options */
    o.color_count = 0;
    limn_mesh *none = NULL;
    assert_int_equal(limn_texture(ctx, m, &o, &none, NULL), LIMN_ERR_ARGUMENT);
    assert_null(none);
    limn_mesh_destroy(m);
    limn_mesh_destroy(out);
    limn_mesh_destroy(again);
    limn_mesh_destroy(other);
    limn_context_destroy(ctx);
}

/* The noise itself: zero on the lattice, bounded, continuous, seed-dependent. */
static void perlin_noise(void **s)
{
    (void)s;
    limn_noise a, b;
    limn_noise_init(&a, 1);
    limn_noise_init(&b, 2);
    int differ = 0;
    for (int i = 0; i < 2000; i++) {
        double x = 0.37 * i, y = 0.11 * i - 40, z = 3.3 + 0.05 * i;
        double v = limn_noise_eval(&a, x, y, z);
        assert_true(v >= -1.01 && v <= 1.01);
        assert_true(fabs(limn_noise_eval(&a, x + 1e-7, y, z) - v) < 1e-5);
        differ += v != limn_noise_eval(&b, x, y, z);
        assert_true(fabs(limn_noise_eval(&a, (double)(i % 17), (double)(i % 5), -3.0)) < 1e-15);
    }
    assert_true(differ > 1000);
}

/* ------------------------------------------------------------ backends */

static void compare_bits(const char *what, const double *a, const double *b, size_t n)
{
    double scale = fmax(1.0, max_abs(a, n));
    size_t same = 0;
    for (size_t i = 0; i < n; i++) {
        if (!(fabs(a[i] - b[i]) <= 1e-12 * scale))
            fail_msg("%s: entry %zu: opencl %.17g reference %.17g", what, i, a[i], b[i]);
        same += a[i] == b[i];
    }
    printf("  %-40s %zu of %zu values bit-identical\n", what, same, n);
}

/* The two backends' output positions agree ("<name> <step>" in the report). */
static void compare_positions(const char *name, const char *step, const limn_mesh *x,
                              const limn_mesh *y, size_t n3)
{
    char what[160];
    snprintf(what, sizeof what, "%s %s", name, step);
    compare_bits(what, limn_mesh_positions(x), limn_mesh_positions(y), n3);
}

static void backends_on(const char *name, limn_mesh *m)
{
    limn_context *cl = ctx_for("opencl"), *ref = ctx_for("reference");
    size_t n3 = 3 * limn_mesh_vertex_count(m);
    char what[160];
    double *b1 = malloc(5 * n3 * sizeof *b1), *b2 = malloc(5 * n3 * sizeof *b2), e1[5], e2[5];
    CHECK_OK(cl, limn_bands(cl, m, NULL, 4, b1, e1, NULL));
    CHECK_OK(ref, limn_bands(ref, m, NULL, 4, b2, e2, NULL));
    snprintf(what, sizeof what, "%s bands", name);
    compare_bits(what, b1, b2, 5 * n3);
    snprintf(what, sizeof what, "%s band energy", name);
    compare_bits(what, e1, e2, 5);
    limn_mesh *x = NULL, *y = NULL;
    CHECK_OK(cl, limn_denoise(cl, m, NULL, 2, 3, 0, &x, NULL));
    CHECK_OK(ref, limn_denoise(ref, m, NULL, 2, 3, 0, &y, NULL));
    compare_positions(name, "denoise", x, y, n3);
    limn_mesh_destroy(x);
    limn_mesh_destroy(y);
    CHECK_OK(cl, limn_sharpen(cl, m, NULL, 1, 4, 2, &x, NULL));
    CHECK_OK(ref, limn_sharpen(ref, m, NULL, 1, 4, 2, &y, NULL));
    compare_positions(name, "sharpen", x, y, n3);
    limn_mesh_destroy(x);
    limn_mesh_destroy(y);
    CHECK_OK(cl, limn_smooth(cl, m, NULL, 4, &x, NULL));
    CHECK_OK(ref, limn_smooth(ref, m, NULL, 4, &y, NULL));
    compare_positions(name, "smooth", x, y, n3);
    /* morph from the mesh to its smoothed self */
    limn_morph_options o;
    limn_morph_options_default(&o);
    o.frames = 6;
    frames f1 = {.n3 = n3}, f2 = {.n3 = n3};
    f1.pos = malloc(6 * n3 * sizeof(double));
    f2.pos = malloc(6 * n3 * sizeof(double));
    CHECK_OK(cl, limn_morph(cl, m, x, &o, keep_frame, &f1, NULL));
    CHECK_OK(ref, limn_morph(ref, m, x, &o, keep_frame, &f2, NULL));
    snprintf(what, sizeof what, "%s morph", name);
    compare_bits(what, f1.pos, f2.pos, 6 * n3);
    free(f1.pos);
    free(f2.pos);
    limn_mesh_destroy(x);
    limn_mesh_destroy(y);
    /* texture: identical colours */
    static const uint8_t colors[] = {0, 0, 0, 255, 128, 0, 255, 255, 255};
    limn_texture_options t;
    limn_texture_options_default(&t);
    t.colors = colors;
    t.color_count = 3;
    t.levels = 1;
    CHECK_OK(cl, limn_texture(cl, m, &t, &x, NULL));
    CHECK_OK(ref, limn_texture(ref, m, &t, &y, NULL));
    size_t nt = limn_mesh_vertex_count(x);
    compare_positions(name, "texture positions", x, y, 3 * nt);
    assert_memory_equal(limn_mesh_colors(x), limn_mesh_colors(y), 3 * nt);
    limn_mesh_destroy(x);
    limn_mesh_destroy(y);
    free(b1);
    free(b2);
    limn_context_destroy(cl);
    limn_context_destroy(ref);
}

static void backends_agree(void **s)
{
    limn_context *ctx = *s;
    /* more rows than one work-item's chunk, and a ragged last chunk */
    limn_mesh *g = test_keep_mesh(test_mesh_grid(ctx, 40, 37, 0));
    limn_mesh *tg = test_keep_mesh(test_mesh_grid(ctx, 40, 37, 1));
    backends_on("quad grid 40x37", g);
    backends_on("triangle grid 40x37", tg);
    if (test_shared_meshes()) {
        limn_mesh *m = test_read_shared(ctx, "medium/bunny_closed.off");
        backends_on("bunny_closed", test_keep_mesh(m));
    }
}

/* ------------------------------------------------------------ measures */

static void measures(void **s)
{
    limn_context *ctx = *s;
    limn_mesh *cube = test_keep_mesh(test_mesh_cube(ctx));
    limn_mesh *grid = test_keep_mesh(test_mesh_grid(ctx, 3, 3, 0));
    limn_mesh *sphere = test_keep_mesh(icosphere(ctx, 5));
    limn_mesh_measures me = {.size = sizeof me};
    CHECK_OK(ctx, limn_mesh_measure(ctx, cube, &me));
    assert_true(me.closed);
    assert_true(fabs(me.volume - 8.0) < 1e-12);
    assert_true(fabs(me.area - 24.0) < 1e-12);
    CHECK_OK(ctx, limn_mesh_measure(ctx, sphere, &me));
    assert_true(fabs(me.volume - 4.0 / 3.0 * PI) < 0.01);
    assert_true(fabs(me.area - 4.0 * PI) < 0.02);
    CHECK_OK(ctx, limn_mesh_measure(ctx, grid, &me));
    assert_false(me.closed);
    assert_true(isnan(me.volume));
    assert_true(fabs(me.area - 9.0) < 0.1);
    /* a mirrored cube: every face flips, the volume changes sign */
    limn_mesh *mirror = NULL;
    CHECK_OK(ctx, limn_mesh_copy(ctx, cube, &mirror));
    double *p = limn_mesh_positions_mutable(test_keep_mesh(mirror));
    for (size_t i = 0; i < 8; i++)
        p[3 * i] = -p[3 * i];
    limn_mesh_comparison cmp = {.size = sizeof cmp};
    CHECK_OK(ctx, limn_mesh_compare(ctx, cube, mirror, &cmp));
    /* n' = -M n for the mirror M: the y and z faces flip, the x faces do not */
    assert_int_equal(cmp.flipped_faces, 4);
    CHECK_OK(ctx, limn_mesh_measure(ctx, mirror, &me));
    assert_true(fabs(me.volume + 8.0) < 1e-12);
    CHECK_OK(ctx, limn_mesh_compare(ctx, cube, cube, &cmp));
    assert_true(cmp.mean_distance == 0 && cmp.mean_normal_angle == 0 && cmp.flipped_faces == 0);
    assert_int_equal(limn_mesh_same_topology(ctx, cube, grid), LIMN_ERR_TOPOLOGY);
}

/* -------------------------------------------------------------- render */

static void render_cube(void **s)
{
    limn_context *ctx = *s;
    limn_mesh *cube = test_keep_mesh(test_mesh_cube(ctx));
    limn_render_options o;
    limn_render_options_default(&o);
    o.width = 80;
    o.height = 60;
    uint8_t *rgb = test_keep(malloc(3 * 80 * 60)), *again = test_keep(malloc(3 * 80 * 60));
    CHECK_OK(ctx, limn_render(ctx, cube, &o, rgb));
    CHECK_OK(ctx, limn_render(ctx, cube, &o, again));
    assert_memory_equal(rgb, again, 3 * 80 * 60);
    /* corners are background, the middle is the shaded cube */
    assert_int_equal(rgb[0], 255);
    assert_int_equal(rgb[3 * (80 * 60 - 1)], 255);
    const uint8_t *mid = rgb + 3 * (30 * 80 + 40);
    assert_true(mid[0] < 250 && mid[0] > 20);
    /* vertex colours are used */
    uint8_t red[24];
    for (int i = 0; i < 8; i++)
        red[3 * i] = 255, red[3 * i + 1] = 0, red[3 * i + 2] = 0;
    CHECK_OK(ctx, limn_mesh_set_colors(ctx, cube, red));
    CHECK_OK(ctx, limn_render(ctx, cube, &o, rgb));
    assert_true(mid[0] > 2 * mid[1] + 20 && mid[1] == mid[2]);
    o.width = 0;
    assert_int_equal(limn_render(ctx, cube, &o, rgb), LIMN_ERR_ARGUMENT);
}

TEST_MAIN(NULL, NULL, CONTEXT_TEST(series_against_dense), CONTEXT_TEST(bands_sum_and_energy),
          OPENCL_TEST(denoise_brings_closer), OPENCL_TEST(sharpen_raises_high_bands),
          cmocka_unit_test(morph_frames), cmocka_unit_test(texture_colors),
          cmocka_unit_test(perlin_noise), CONTEXT_TEST(backends_agree), CONTEXT_TEST(measures),
          CONTEXT_TEST(render_cube))
