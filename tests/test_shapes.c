/* SPDX-License-Identifier: MIT */
/*
 * The two kernel shapes (host/device/opencl/opencl_shape.h), both on PoCL
 * (LIMN_KERNEL_SHAPE=cpu|gpu forces either):
 *  - The SELL-C layout (host/stencil/stencil_sell.c) against its CSR table:
 *    every row's entries in order at slice_offsets[s] + k C + lane, each
 *    slice as wide as its longest row, padding weight 0 and the row's last
 *    column; on a ragged synthetic table and on spot's.
 *  - Each operation on both shapes: every vector bit for bit the same (a
 *    row's sum is the same sum in the same order; SELL's padding adds exact
 *    zeros), the norms' max the same (order-free) and their sums within
 *    2 (n - 1) eps sum|terms| (each order's sum is within (n - 1) eps of the
 *    exact one; here n = rows).
 *  - limn bench's triad (the axpby kernel) on both shapes: no mismatch.
 *  - The launch arithmetic of each shape, and the group narrowed to what
 *    every kernel allows.
 *  - Every method and precision and every series command, through the API:
 *    the same iteration counts; bit-identical positions where no scalar of
 *    the iteration comes from a reduction (paper, chebyshev, the series,
 *    subdivide, texture), else (weighted's omega, cg's and sgs's alpha and
 *    beta) within k n eps |M| with k the iterations: each step's scalar
 *    carries a relative difference <= 2 n eps, moving the iterate by at most
 *    that times an update no larger than |M|.
 */
#include "support.h"

#include "device/device.h"
#include "device/opencl/opencl_shape.h"
#include "solve/operator.h"
#include "stencil/stencil_sell.h"

#include <float.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

static const char *const shapes[2] = {"cpu", "gpu"};

/* A context on PoCL whose device is built in `shape` (the variable is read
   when the device opens, by the first operation). */
static limn_context *shaped(const char *shape)
{
    setenv("LIMN_KERNEL_SHAPE", shape, 1);
    limn_context *ctx = limn_context_create();
    assert_non_null(ctx);
    assert_int_equal(limn_context_set_device(ctx, "opencl"), LIMN_OK);
    return ctx;
}

static limn_mesh *read_spot(limn_context *ctx)
{
    char path[1024];
    const char *data = getenv("LIMN_TEST_DATA");
    snprintf(path, sizeof path, "%s/spot_control_mesh.obj", data ? data : "data");
    limn_mesh *m = NULL;
    if (limn_mesh_read(ctx, path, LIMN_FORMAT_AUTO, &m) != LIMN_OK)
        fail_msg("%s", limn_context_message(ctx));
    return m;
}

/* spot refined `levels` times (Catmull-Clark): 188 vertices at 0, 746 at
   1, 2978 at 2, so the gpu shape runs several groups of 256 rows with a
   ragged last one. */
static limn_mesh *refined_spot(limn_context *ctx, int levels)
{
    limn_mesh *spot = read_spot(ctx), *out = NULL;
    limn_subdivide_options so;
    limn_subdivide_options_default(&so);
    so.levels = levels;
    if (limn_subdivide(ctx, spot, &so, &out, NULL) != LIMN_OK)
        fail_msg("%s", limn_context_message(ctx));
    limn_mesh_destroy(spot);
    return out;
}

/* Every row of a in s, in order, and the padding as documented. */
static void check_sell(const stencil_csr *a, const stencil_sell *s)
{
    assert_int_equal(s->slices, (a->rows + s->slice - 1) / s->slice);
    for (size_t sl = 0; sl < s->slices; sl++) {
        size_t width = (s->slice_offsets[sl + 1] - s->slice_offsets[sl]) / s->slice, widest = 0;
        assert_int_equal((s->slice_offsets[sl + 1] - s->slice_offsets[sl]) % s->slice, 0);
        for (size_t l = 0; l < s->slice; l++) {
            size_t i = sl * s->slice + l;
            size_t lo = i < a->rows ? a->row_offsets[i] : 0;
            size_t len = i < a->rows ? a->row_offsets[i + 1] - lo : 0;
            widest = len > widest ? len : widest;
            for (size_t k = 0; k < width; k++) {
                size_t e = s->slice_offsets[sl] + k * s->slice + l;
                uint32_t pad = len ? a->columns[lo + len - 1] : 0;
                assert_int_equal(s->columns[e], k < len ? a->columns[lo + k] : pad);
                double w = k < len ? a->weights[lo + k] : 0.0;
                assert_memory_equal(&s->weights[e], &w, sizeof w);
            }
        }
        assert_int_equal(width, widest);
    }
}

/* A ragged table: 77 rows of i % 9 entries (empty rows among them). */
static void sell_layout(void **state)
{
    limn_context *ctx = *state;
    enum { ROWS = 77 };
    uint32_t ro[ROWS + 1], col[ROWS * 9];
    double w[ROWS * 9];
    ro[0] = 0;
    for (size_t i = 0; i < ROWS; i++) {
        ro[i + 1] = ro[i] + (uint32_t)(i % 9);
        for (uint32_t k = ro[i]; k < ro[i + 1]; k++) {
            col[k] = (uint32_t)((i * 7 + k * 13) % 50);
            w[k] = 1.0 / (1.0 + (double)k);
        }
    }
    stencil_csr a = {ROWS, 50, ro, col, w};
    size_t slices[] = {1, 8, 32, 128};
    for (size_t t = 0; t < 4; t++) {
        stencil_sell s;
        assert_int_equal(stencil_sell_build(ctx, &a, slices[t], &s), LIMN_OK);
        check_sell(&a, &s);
        stencil_sell_free(&s);
    }
    stencil_sell s;
    assert_int_equal(stencil_sell_build(ctx, &a, 0, &s), LIMN_ERR_ARGUMENT);
    assert_non_null(strstr(limn_context_message(ctx), "slice of 0 rows"));
    /* spot's limit table */
    limn_mesh *mesh = test_keep_mesh(read_spot(ctx));
    stencil_operator op;
    assert_int_equal(limn_context_set_device(ctx, "reference"), LIMN_OK);
    assert_int_equal(operator_build(ctx, mesh, LIMN_SCHEME_AUTO, 0.0, &op), LIMN_OK);
    assert_int_equal(stencil_sell_build(ctx, &op.host, 32, &s), LIMN_OK);
    check_sell(&op.host, &s);
    stencil_sell_free(&s);
    operator_free(&op);
}

/* The norms of two shapes: the same max, sums within 2 (n - 1) eps of
   `scale` (the sum of the terms' magnitudes). */
static void close_norms(const device_norms *a, const device_norms *b, size_t n,
                        double sum_scale, double sq_scale)
{
    double eps = DBL_EPSILON * 2.0 * (double)n;
    assert_memory_equal(&a->max, &b->max, sizeof a->max);
    assert_true(fabs(a->sum - b->sum) <= eps * sum_scale);
    assert_true(fabs(a->sum_sq - b->sum_sq) <= eps * sq_scale);
}

typedef struct shape_run {
    double *out[6];     /* the vectors the operations wrote, 4 doubles a row */
    device_norms n[5];  /* interp, cheb, series, norms, residual_f */
    double dot;
} shape_run;

static double *read_back(struct device *dev, device_buffer *b, size_t n)
{
    double *x = malloc(4 * n * sizeof *x);
    assert_non_null(x);
    assert_int_equal(dev->ops->buffer_read(dev, b, 4 * n * sizeof *x, x), LIMN_OK);
    return x;
}

/* The device operations over spot's table on one shape. */
static void run_ops(const char *shape, limn_mesh *mesh, shape_run *out, size_t *rows)
{
    limn_context *ctx = shaped(shape);
    stencil_operator op;
    if (operator_build(ctx, mesh, LIMN_SCHEME_AUTO, 0.0, &op) != LIMN_OK)
        fail_msg("%s", limn_context_message(ctx));
    struct device *dev = op.dev;
    const device_ops *ops = dev->ops;
    assert_int_equal(dev->sell_slice, shape[0] == 'g' ? 32 : 0);
    size_t n = op.vertex_count;
    *rows = n;
    double *m4 = malloc(4 * n * sizeof *m4), *p4 = malloc(4 * n * sizeof *p4);
    operator_pack(&op, limn_mesh_positions(mesh), m4);
    for (size_t i = 0; i < 4 * n; i++)
        p4[i] = (i & 3) == 3 ? 0.0 : m4[i] * (1.0 + 1e-2 * sin((double)i));
    device_buffer *m, *p, *q, *prev, *ax, *acc, *dinv, *y, *rf;
    assert_int_equal(ops->buffer_create(dev, 4 * n * sizeof(double), m4, &m), LIMN_OK);
    assert_int_equal(ops->buffer_create(dev, 4 * n * sizeof(double), p4, &p), LIMN_OK);
    assert_int_equal(ops->buffer_create(dev, 4 * n * sizeof(double), NULL, &q), LIMN_OK);
    assert_int_equal(ops->buffer_create(dev, 4 * n * sizeof(double), m4, &prev), LIMN_OK);
    assert_int_equal(ops->buffer_create(dev, 4 * n * sizeof(double), NULL, &ax), LIMN_OK);
    assert_int_equal(ops->buffer_create(dev, 4 * n * sizeof(double), p4, &acc), LIMN_OK);
    assert_int_equal(ops->buffer_create(dev, 4 * n * sizeof(double), NULL, &y), LIMN_OK);
    assert_int_equal(ops->buffer_create(dev, 4 * n * sizeof(float), NULL, &rf), LIMN_OK);
    for (size_t i = 0; i < n; i++)
        p4[i] = 1.0 + 0.25 * cos((double)i); /* dinv */
    assert_int_equal(ops->buffer_create(dev, n * sizeof(double), p4, &dinv), LIMN_OK);
    assert_int_equal(ops->stationary->interp_step(dev, &op.device, m, p, q, 0.7, &out->n[0]),
                     LIMN_OK);
    assert_int_equal(ops->stationary->cheb_step(dev, &op.device, m, p, prev, 0.3, 1.2,
                                                &out->n[1]),
                     LIMN_OK);
    assert_int_equal(ops->series->series_step(dev, &op.device, p, y, ax, acc,
                                              SERIES_STORE_AX | SERIES_STORE_NEXT,
                                              SERIES_ACC_ADD_AX, &out->n[2]),
                     LIMN_OK);
    assert_int_equal(ops->norms(dev, n, p, &out->n[3]), LIMN_OK);
    assert_int_equal(ops->mixed->residual_f(dev, &op.device, m, p, rf, &out->n[4]), LIMN_OK);
    device_buffer *vecs[] = {q, prev, ax, acc, y};
    for (int k = 0; k < 5; k++)
        out->out[k] = read_back(dev, vecs[k], n);
    assert_int_equal(ops->cg->spmv_dot(dev, &op.device, p, q, dinv, &out->dot), LIMN_OK);
    out->out[5] = read_back(dev, q, n);
    device_buffer *all[] = {m, p, q, prev, ax, acc, dinv, y, rf};
    for (int k = 0; k < 9; k++)
        ops->buffer_release(dev, all[k]);
    free(m4);
    free(p4);
    operator_free(&op);
    limn_context_destroy(ctx);
    unsetenv("LIMN_KERNEL_SHAPE");
}

/* A norm's scales from a vector of 4-double rows: sum |v_i|, sum |v_i|^2. */
static void scales_of(const double *v, size_t n, double *sum, double *sq)
{
    *sum = *sq = 0.0;
    for (size_t i = 0; i < n; i++) {
        double s = v[4 * i] * v[4 * i] + v[4 * i + 1] * v[4 * i + 1] + v[4 * i + 2] * v[4 * i + 2];
        *sum += sqrt(s);
        *sq += s;
    }
}

static void operations(void **state)
{
    limn_context *ctx = *state;
    limn_mesh *mesh = test_keep_mesh(refined_spot(ctx, 2));
    shape_run run[2];
    size_t n = 0;
    for (int s = 0; s < 2; s++)
        run_ops(shapes[s], mesh, &run[s], &n);
    for (int k = 0; k < 6; k++)
        assert_memory_equal(run[0].out[k], run[1].out[k], 4 * n * sizeof(double));
    /* the residual r = q - p (interp_step, omega 0.7) is not kept: scale its
       norms by the magnitude of the products the other norms saw */
    double sum, sq;
    scales_of(run[0].out[2], n, &sum, &sq); /* ax = A p */
    close_norms(&run[0].n[2], &run[1].n[2], n, sum, sq);
    for (int k = 0; k < 5; k++)
        close_norms(&run[0].n[k], &run[1].n[k], n, run[0].n[k].sum + sum,
                    run[0].n[k].sum_sq + sq);
    assert_true(fabs(run[0].dot - run[1].dot) <= 2.0 * (double)n * DBL_EPSILON * 4.0 * sq);
    for (int s = 0; s < 2; s++)
        for (int k = 0; k < 6; k++)
            free(run[s].out[k]);
}

/* One solve on one shape: its positions (caller frees) and report. */
static double *solve_on(const char *shape, const limn_mesh *mesh, limn_method method,
                        limn_precision precision, limn_report *r)
{
    limn_context *ctx = shaped(shape);
    limn_interpolate_options o;
    limn_interpolate_options_default(&o);
    o.method = method;
    o.precision = precision;
    limn_mesh *p = NULL;
    r->size = sizeof *r;
    if (limn_interpolate(ctx, mesh, &o, &p, r) != LIMN_OK)
        fail_msg("%s %s: %s", shape, limn_method_name(method), limn_context_message(ctx));
    size_t n = limn_mesh_vertex_count(p);
    double *x = malloc(3 * n * sizeof *x);
    memcpy(x, limn_mesh_positions(p), 3 * n * sizeof *x);
    limn_mesh_destroy(p);
    limn_context_destroy(ctx);
    unsetenv("LIMN_KERNEL_SHAPE");
    return x;
}

static double max_abs(const double *x, size_t count)
{
    double m = 0.0;
    for (size_t i = 0; i < count; i++)
        m = fabs(x[i]) > m ? fabs(x[i]) : m;
    return m;
}

static void methods_on(const limn_mesh *mesh)
{
    static const struct {
        limn_method method;
        limn_precision precision;
        int exact; /* no scalar from a reduction */
    } cases[] = {
        {LIMN_METHOD_PAPER, LIMN_PRECISION_DOUBLE, 1},
        {LIMN_METHOD_WEIGHTED, LIMN_PRECISION_DOUBLE, 0},
        {LIMN_METHOD_CHEBYSHEV, LIMN_PRECISION_DOUBLE, 1},
        {LIMN_METHOD_CG, LIMN_PRECISION_DOUBLE, 0},
        {LIMN_METHOD_SGS, LIMN_PRECISION_DOUBLE, 0},
        {LIMN_METHOD_PAPER, LIMN_PRECISION_FLOAT, 1},
        {LIMN_METHOD_WEIGHTED, LIMN_PRECISION_FLOAT, 0},
        {LIMN_METHOD_CHEBYSHEV, LIMN_PRECISION_FLOAT, 1},
    };
    size_t n = limn_mesh_vertex_count(mesh);
    double scale = max_abs(limn_mesh_positions(mesh), 3 * n);
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        limn_report r[2];
        double *x[2];
        for (int s = 0; s < 2; s++)
            x[s] = solve_on(shapes[s], mesh, cases[c].method, cases[c].precision, &r[s]);
        assert_int_equal(r[0].iterations, r[1].iterations);
        assert_string_equal(r[0].precision, r[1].precision);
        if (cases[c].exact) {
            assert_memory_equal(x[0], x[1], 3 * n * sizeof(double));
        } else {
            double bound = (double)r[0].iterations * (double)n * DBL_EPSILON * scale, worst = 0;
            for (size_t i = 0; i < 3 * n; i++)
                worst = fabs(x[0][i] - x[1][i]) > worst ? fabs(x[0][i] - x[1][i]) : worst;
            if (worst > bound)
                fail_msg("%s %s: shapes differ by %g > %g", limn_method_name(cases[c].method),
                         r[0].precision, worst, bound);
        }
        free(x[0]);
        free(x[1]);
    }
}

static void methods(void **state)
{
    limn_context *ctx = *state;
    methods_on(test_keep_mesh(refined_spot(ctx, 1)));
    /* Loop: an icosahedron refined twice (162 vertices) */
    limn_subdivide_options so;
    limn_subdivide_options_default(&so);
    so.levels = 2;
    limn_mesh *tri = NULL;
    assert_int_equal(limn_subdivide(ctx, test_keep_mesh(test_mesh_icosahedron(ctx)), &so, &tri,
                                    NULL),
                     LIMN_OK);
    methods_on(test_keep_mesh(tri));
}

/* The series commands, subdivide (with its limit) and texture on one shape:
   every output's doubles (colours too) in one array (caller frees), *count
   of them. */
static void append(double **all, size_t *count, const double *x, size_t k)
{
    *all = realloc(*all, (*count + k) * sizeof **all);
    assert_non_null(*all);
    memcpy(*all + *count, x, k * sizeof *x);
    *count += k;
}

static void append_mesh(double **all, size_t *count, limn_mesh *m)
{
    append(all, count, limn_mesh_positions(m), 3 * limn_mesh_vertex_count(m));
    limn_mesh_destroy(m);
}

typedef struct morph_sink {
    double *all;
    size_t count, n;
} morph_sink;

static limn_status sink_frame(void *user, const limn_morph_frame *f)
{
    morph_sink *s = user;
    append(&s->all, &s->count, f->positions, 3 * s->n);
    return LIMN_OK;
}

static double *series_on(const char *shape, const limn_mesh *spot, const limn_mesh *tri,
                         size_t *count, double energy[3])
{
    limn_context *ctx = shaped(shape);
    limn_series_options so;
    limn_series_options_default(&so);
    size_t n = limn_mesh_vertex_count(spot);
    double *all = NULL;
    *count = 0;
    limn_mesh *out = NULL;
    assert_int_equal(limn_smooth(ctx, spot, &so, 3, &out, NULL), LIMN_OK);
    append_mesh(&all, count, out);
    assert_int_equal(limn_sharpen(ctx, spot, &so, 1, 2, 1, &out, NULL), LIMN_OK);
    append_mesh(&all, count, out);
    assert_int_equal(limn_denoise(ctx, spot, &so, 2, 2, 1, &out, NULL), LIMN_OK);
    append_mesh(&all, count, out);
    double *bands = malloc(3 * 3 * n * sizeof *bands);
    assert_int_equal(limn_bands(ctx, spot, &so, 2, bands, energy, NULL), LIMN_OK);
    append(&all, count, bands, 9 * n);
    free(bands);
    limn_morph_options mo;
    limn_morph_options_default(&mo);
    mo.frames = 3;
    morph_sink sink = {all, *count, n};
    limn_mesh *target = NULL;
    assert_int_equal(limn_smooth(ctx, spot, &so, 2, &target, NULL), LIMN_OK);
    assert_int_equal(limn_morph(ctx, spot, target, &mo, sink_frame, &sink, NULL), LIMN_OK);
    limn_mesh_destroy(target);
    all = sink.all;
    *count = sink.count;
    limn_subdivide_options sd;
    limn_subdivide_options_default(&sd);
    sd.levels = 1;
    sd.limit = 1;
    assert_int_equal(limn_subdivide(ctx, tri, &sd, &out, NULL), LIMN_OK);
    append_mesh(&all, count, out);
    limn_texture_options to;
    limn_texture_options_default(&to);
    static const uint8_t rgb[] = {255, 0, 0, 0, 255, 0, 0, 0, 255};
    to.colors = rgb;
    to.color_count = 3;
    to.levels = 1;
    assert_int_equal(limn_texture(ctx, tri, &to, &out, NULL), LIMN_OK);
    size_t v = limn_mesh_vertex_count(out);
    double *c = malloc(3 * v * sizeof *c);
    for (size_t i = 0; i < 3 * v; i++)
        c[i] = limn_mesh_colors(out)[i];
    append(&all, count, c, 3 * v);
    free(c);
    append_mesh(&all, count, out);
    limn_context_destroy(ctx);
    unsetenv("LIMN_KERNEL_SHAPE");
    return all;
}

static void series(void **state)
{
    limn_context *ctx = *state;
    limn_mesh *spot = test_keep_mesh(refined_spot(ctx, 1));
    limn_mesh *tri = test_keep_mesh(test_mesh_icosahedron(ctx));
    size_t count[2], n = limn_mesh_vertex_count(spot);
    double *x[2], energy[2][3];
    for (int s = 0; s < 2; s++)
        x[s] = series_on(shapes[s], spot, tri, &count[s], energy[s]);
    assert_int_equal(count[0], count[1]);
    assert_memory_equal(x[0], x[1], count[0] * sizeof(double));
    /* the bands' energies are device sums of non-negative terms */
    for (int k = 0; k < 3; k++)
        assert_true(fabs(energy[0][k] - energy[1][k]) <=
                    2.0 * (double)n * DBL_EPSILON * energy[0][k]);
    free(x[0]);
    free(x[1]);
}

/* limn bench's yardstick (limn_device_triad, the axpby kernel) in each
   shape: every element as the host computes it. */
static void triad(void **state)
{
    (void)state;
    for (int s = 0; s < 2; s++) {
        limn_context *ctx = shaped(shapes[s]);
        limn_triad_report r = {.size = sizeof r};
        /* 3 arrays of 1 MiB: 131072 doubles, 32768 rows of 4 */
        assert_int_equal(limn_device_triad(ctx, 1 << 20, 2, &r), LIMN_OK);
        assert_int_equal(r.mismatches, 0);
        assert_int_equal(r.elements, 131072);
        limn_context_destroy(ctx);
        unsetenv("LIMN_KERNEL_SHAPE");
    }
}

/* The shapes' launch arithmetic, and the group narrowed to what every kernel
   allows (a power of two in the gpu shape, whose GROUP_SIZE is a -D: then
   a rebuild). */
static void shape_rules(void **state)
{
    (void)state;
    opencl_shape gpu = {1, 1, 256, 256, 32}, cpu = {0, DEVICE_ROWS_PER_ITEM, 8,
                                                    DEVICE_ROWS_PER_ITEM, 0};
    assert_int_equal(opencl_shape_fit(&gpu, 0), 0);   /* none reported */
    assert_int_equal(opencl_shape_fit(&gpu, 1024), 0);
    assert_int_equal(gpu.group, 256);
    assert_int_equal(opencl_shape_fit(&gpu, 100), 1); /* 64: rebuild */
    assert_int_equal(gpu.group, 64);
    assert_int_equal(gpu.rows_per_slot, 64);
    assert_int_equal(opencl_shape_items(&gpu, 1000), 1024);
    assert_int_equal(opencl_shape_slots(&gpu, 1000), 16);
    assert_int_equal(opencl_shape_chunks(&gpu, 1000), 16);
    assert_int_equal(opencl_shape_items(&gpu, 0), 0);
    assert_int_equal(opencl_shape_fit(&cpu, 4), 0);   /* no rebuild */
    assert_int_equal(cpu.group, 4);
    assert_int_equal(cpu.rows_per_slot, DEVICE_ROWS_PER_ITEM);
    assert_int_equal(opencl_shape_items(&cpu, 1000), 4);  /* 4 items of 256 rows */
    assert_int_equal(opencl_shape_slots(&cpu, 1000), 4);
    assert_int_equal(opencl_shape_items(&cpu, 1100), 8);  /* 5, rounded to groups of 4 */
    assert_int_equal(opencl_shape_chunks(&cpu, 1100), 5);
    char opts[160];
    opencl_shape_options(&gpu, opts, sizeof opts);
    assert_string_equal(opts,
                        "-D ROWS_PER_ITEM=1 -D KERNEL_SHAPE_GPU=1 -D GROUP_SIZE=64 -D SELL_C=32");
    opencl_shape_options(&cpu, opts, sizeof opts);
    assert_string_equal(opts, "-D ROWS_PER_ITEM=256");
}

/* A value other than cpu or gpu is refused, naming it. */
static void bad_shape(void **state)
{
    (void)state;
    limn_context *ctx = shaped("vector");
    limn_mesh *mesh = read_spot(ctx);
    limn_mesh *p = NULL;
    assert_int_equal(limn_interpolate(ctx, mesh, NULL, &p, NULL), LIMN_ERR_ARGUMENT);
    assert_non_null(strstr(limn_context_message(ctx), "LIMN_KERNEL_SHAPE is 'vector'"));
    assert_null(p);
    limn_mesh_destroy(mesh);
    limn_context_destroy(ctx);
    unsetenv("LIMN_KERNEL_SHAPE");
}

TEST_MAIN(NULL, NULL, CONTEXT_TEST(sell_layout), CONTEXT_TEST(operations), CONTEXT_TEST(methods),
          CONTEXT_TEST(series), cmocka_unit_test(triad), cmocka_unit_test(shape_rules),
          cmocka_unit_test(bad_shape))
