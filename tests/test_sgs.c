/* SPDX-License-Identifier: MIT */
/*
 * The pieces of the SGS-preconditioned conjugate gradients (--method sgs),
 * checked from outside:
 * - the multicolour table (host/stencil/sgs_table.c): its order is a permutation,
 *   no entry joins two rows of one colour, entries before split[i] have
 *   lower colours and the rest higher ones, and S = dinv A is symmetric;
 * - the sweeps (kernels/sgs.cl, host/device/reference/device_ref_sgs.c) against the
 *   definitions, computed densely without Eisenstat's trick: the start sweep's
 *   r = b - S x, u = (D + L)^-1 r; a step's t = (D + U)^-1 D^1/2 phat and
 *   D^1/2 (t + u) = C^-1 S C^-T phat with C = (D + L) D^-1/2 (a backward
 *   solve, a full product by S, a forward solve), st = S t, the dot, and
 *   the update; to 1e-12 of the values' scale;
 * - the reference and OpenCL backends agree bit for bit on every output.
 * Meshes: spot refined twice (Catmull-Clark) and an icosahedron three times
 * (Loop), both perturbed: 642 and ~3,000 rows, several chunks in some colours.
 */
#include "support.h"

#include "base/context.h"
#include "device/device.h"
#include "solve/operator.h"
#include "scheme/scheme.h"
#include "stencil/sgs_table.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

/* What one backend computed, kept for the bit-for-bit comparison. */
typedef struct outputs {
    size_t n;
    double *r, *u, *rhat, *phat, *t, *u2, *st, *x, *r2, *rhat2;
    double start_max, start_sum, dot, update_max, update_sum;
} outputs;

static double *vec4(size_t n)
{
    double *v = calloc(4 * n, sizeof *v);
    assert_non_null(v);
    return v;
}

static void fill(double *v, size_t n, unsigned seed)
{
    for (size_t i = 0; i < n; i++) {
        for (int c = 0; c < 3; c++) {
            seed = seed * 1103515245u + 12345u;
            v[4 * i + c] = (double)((seed >> 8) % 20001) / 10000.0 - 1.0;
        }
        v[4 * i + 3] = 0.0;
    }
}

static double max_abs(const double *v, size_t count)
{
    double m = 0.0;
    for (size_t i = 0; i < count; i++)
        m = fmax(m, fabs(v[i]));
    return m;
}

static void expect_close(const char *what, const double *got, const double *want, size_t n)
{
    double scale = fmax(max_abs(want, 4 * n), 1e-300), worst = 0.0;
    for (size_t i = 0; i < n; i++)
        for (int c = 0; c < 3; c++)
            worst = fmax(worst, fabs(got[4 * i + c] - want[4 * i + c]));
    if (worst > 1e-12 * scale)
        fail_msg("%s: off by %.3g of its scale %.3g", what, worst / scale, scale);
}

/* The structure of the table, and S dense in table order (diagonal included). */
static double *check_table(const sgs_table *t)
{
    size_t n = t->rows;
    char *seen = calloc(n, 1);
    size_t *colour = calloc(n, sizeof *colour);
    assert_true(seen && colour);
    for (size_t c = 0; c < t->colours; c++)
        for (size_t i = t->colour_begin[c]; i < t->colour_begin[c + 1]; i++) {
            colour[i] = c;
            assert_true(t->order[i] < n);
            assert_false(seen[t->order[i]]);
            seen[t->order[i]] = 1;
        }
    assert_int_equal(t->colour_begin[t->colours], n);
    double *s = calloc(n * n, sizeof *s);
    assert_non_null(s);
    for (size_t i = 0; i < n; i++) {
        s[i * n + i] = t->info[4 * i];
        assert_true(t->info[4 * i] > 0.0);
        for (uint32_t k = t->row_offsets[i]; k < t->row_offsets[i + 1]; k++) {
            size_t j = t->columns[k];
            assert_true(colour[j] != colour[i]);
            assert_true(k < t->split[i] ? colour[j] < colour[i] : colour[j] > colour[i]);
            s[i * n + j] += t->weights[k];
        }
    }
    for (size_t i = 0; i < n; i++)
        for (size_t j = 0; j < i; j++)
            assert_true(fabs(s[i * n + j] - s[j * n + i]) <= 1e-14);
    free(seen);
    free(colour);
    return s;
}

/* y = S x (dense), 4 doubles a row */
static void dense_product(const double *s, size_t n, const double *x, double *y)
{
    test_dense_product(s, n, x, 4, y);
}

/* x = (D + L)^-1 y (lower) or (D + U)^-1 y (upper), dense substitution */
static void dense_solve(const double *s, size_t n, int lower, const double *y, double *x)
{
    for (size_t step = 0; step < n; step++) {
        size_t i = lower ? step : n - 1 - step;
        for (int c = 0; c < 3; c++) {
            double acc = y[4 * i + c];
            for (size_t j = 0; j < n; j++)
                if (lower ? j < i : j > i)
                    acc -= s[i * n + j] * x[4 * j + c];
            x[4 * i + c] = acc / s[i * n + i];
        }
    }
}

static double dot3(const double *a, const double *b, size_t n)
{
    double sum = 0.0;
    for (size_t i = 0; i < n; i++)
        sum += a[4 * i] * b[4 * i] + a[4 * i + 1] * b[4 * i + 1] + a[4 * i + 2] * b[4 * i + 2];
    return sum;
}

/* max_i scale_i |r_i|: A's residual from S's (info[4 i + 2] is the row scale) */
static double scaled_max(const sgs_table *t, const double *r, size_t n)
{
    double worst = 0.0;
    for (size_t i = 0; i < n; i++)
        worst = fmax(worst, t->info[4 * i + 2] * sqrt(dot3(r + 4 * i, r + 4 * i, 1)));
    return worst;
}

static void read_back(struct device *dev, device_buffer *b, size_t n, double **out)
{
    *out = vec4(n);
    assert_int_equal(dev->ops->buffer_read(dev, b, 4 * n * sizeof(double), *out), LIMN_OK);
}

/* read_back of count buffers into count outputs, pairwise. */
static void read_back_all(struct device *dev, size_t n, size_t count, device_buffer *const *from,
                          double **const *to)
{
    for (size_t k = 0; k < count; k++)
        read_back(dev, from[k], n, to[k]);
}

/* Runs a start sweep, one step's sweeps and an update on one backend and
   checks each against the dense definitions. */
static void run_backend(const char *device, const limn_mesh *mesh, limn_scheme scheme,
                        outputs *o)
{
    limn_context *ctx = limn_context_create();
    if (device)
        assert_int_equal(limn_context_set_device(ctx, device), LIMN_OK);
    stencil_operator op;
    assert_int_equal(operator_build_ex(ctx, mesh, scheme, 0.0, OPERATOR_REORDER, &op), LIMN_OK);
    size_t n = op.host.rows;
    double *dinv = malloc(n * sizeof *dinv);
    for (size_t r = 0; r < n; r++)
        dinv[r] = 1.0 / scheme_limit_row_scale(&op.topo, op.scheme,
                                               op.order ? op.order[r] : (uint32_t)r);
    sgs_table t;
    assert_int_equal(sgs_table_build(ctx, &op.host, dinv, &t), LIMN_OK);
    assert_true(t.colours >= 3 && t.colours <= 12);
    double *s = check_table(&t);
    struct device *dev = op.dev;
    const device_ops *ops = dev->ops;
    device_sgs da;
    assert_int_equal(device_sgs_upload(dev, &t, &da), LIMN_OK);
    double *init[8] = {vec4(n), vec4(n), NULL, NULL, NULL, NULL, NULL, NULL};
    fill(init[0], n, 1); /* b */
    fill(init[1], n, 2); /* x */
    device_buffer *buf[8];
    for (int i = 0; i < 8; i++)
        assert_int_equal(ops->buffer_create(dev, 4 * n * sizeof(double), init[i], &buf[i]),
                         LIMN_OK);
    sgs_vectors v = {buf[0], buf[1], buf[2], buf[3], buf[4], buf[5], buf[6], buf[7]};
    o->n = n;

    /* the start sweep: r = b - S x, u = (D + L)^-1 r, rhat = D^1/2 u */
    device_norms nm;
    assert_int_equal(ops->sgs->sgs_lower(dev, &da, 1, &v, &nm), LIMN_OK);
    o->start_max = nm.max;
    o->start_sum = nm.sum;
    read_back_all(dev, n, 3, (device_buffer *[]){v.r, v.u, v.rhat},
                  (double **[]){&o->r, &o->u, &o->rhat});
    double *want = vec4(n), *want2 = vec4(n), *tmp = vec4(n);
    dense_product(s, n, init[1], tmp);
    for (size_t i = 0; i < 4 * n; i++)
        want[i] = (i % 4 == 3) ? 0.0 : init[0][i] - tmp[i];
    expect_close("start: r = b - S x", o->r, want, n);
    double worst = scaled_max(&t, want, n);
    assert_true(fabs(o->start_max - worst) <= 1e-12 * worst);
    dense_solve(s, n, 1, want, want2);
    expect_close("start: u = (D + L)^-1 r", o->u, want2, n);
    for (size_t i = 0; i < n; i++)
        for (int c = 0; c < 3; c++)
            want2[4 * i + c] *= t.info[4 * i + 1];
    expect_close("start: rhat = D^1/2 u", o->rhat, want2, n);
    assert_true(fabs(o->start_sum - dot3(want2, want2, n)) <= 1e-12 * o->start_sum);

    /* one step from a given rhat and phat, beta = 0.5 */
    double *rhat0 = vec4(n), *phat0 = vec4(n);
    fill(rhat0, n, 3);
    fill(phat0, n, 4);
    assert_int_equal(ops->buffer_write(dev, v.rhat, 4 * n * sizeof(double), rhat0), LIMN_OK);
    assert_int_equal(ops->buffer_write(dev, v.phat, 4 * n * sizeof(double), phat0), LIMN_OK);
    assert_int_equal(ops->sgs->sgs_upper(dev, &da, 0.5, &v), LIMN_OK);
    device_norms dot;
    assert_int_equal(ops->sgs->sgs_lower(dev, &da, 0, &v, &dot), LIMN_OK);
    o->dot = dot.sum;
    read_back_all(dev, n, 4, (device_buffer *[]){v.phat, v.t, v.u, v.st},
                  (double **[]){&o->phat, &o->t, &o->u2, &o->st});
    for (size_t i = 0; i < 4 * n; i++)
        want[i] = (i % 4 == 3) ? 0.0 : rhat0[i] + 0.5 * phat0[i];
    expect_close("phat = rhat + beta phat", o->phat, want, n);
    /* C^-T phat = (D + U)^-1 D^1/2 phat */
    for (size_t i = 0; i < n; i++)
        for (int c = 0; c < 3; c++)
            tmp[4 * i + c] = t.info[4 * i + 1] * want[4 * i + c];
    double *y = vec4(n);
    dense_solve(s, n, 0, tmp, y);
    expect_close("t = (D + U)^-1 D^1/2 phat", o->t, y, n);
    /* C^-1 S y = D^1/2 (D + L)^-1 S y, against D^1/2 (t + u) */
    dense_product(s, n, y, tmp);
    expect_close("st = S t", o->st, tmp, n);
    dense_solve(s, n, 1, tmp, want2);
    double *q = vec4(n), *qd = vec4(n);
    for (size_t i = 0; i < n; i++)
        for (int c = 0; c < 3; c++) {
            qd[4 * i + c] = t.info[4 * i + 1] * want2[4 * i + c];
            q[4 * i + c] = t.info[4 * i + 1] * (o->t[4 * i + c] + o->u2[4 * i + c]);
        }
    expect_close("D^1/2 (t + u) = C^-1 S C^-T phat", q, qd, n);
    double pq = dot3(want, qd, n);
    assert_true(pq > 0.0);
    assert_true(fabs(o->dot - pq) <= 1e-12 * pq);

    /* the update, alpha = 0.3 */
    double *x0, *r0;
    read_back(dev, v.x, n, &x0);
    read_back(dev, v.r, n, &r0);
    assert_int_equal(ops->sgs->sgs_update(dev, &da, 0.3, &v, &nm), LIMN_OK);
    o->update_max = nm.max;
    o->update_sum = nm.sum;
    read_back_all(dev, n, 3, (device_buffer *[]){v.x, v.r, v.rhat},
                  (double **[]){&o->x, &o->r2, &o->rhat2});
    for (size_t i = 0; i < n; i++)
        for (int c = 0; c < 3; c++) {
            want[4 * i + c] = x0[4 * i + c] + 0.3 * o->t[4 * i + c];
            want2[4 * i + c] = r0[4 * i + c] - 0.3 * o->st[4 * i + c];
            tmp[4 * i + c] = rhat0[4 * i + c] - 0.3 * q[4 * i + c];
        }
    double rmax = scaled_max(&t, want2, n);
    expect_close("x += alpha t", o->x, want, n);
    expect_close("r -= alpha st", o->r2, want2, n);
    expect_close("rhat -= alpha q", o->rhat2, tmp, n);
    assert_true(fabs(o->update_max - rmax) <= 1e-12 * rmax);
    assert_true(fabs(o->update_sum - dot3(tmp, tmp, n)) <= 1e-12 * o->update_sum);
    printf("  %-10s %-8s %zu rows, %zu colours: sweeps match the dense definitions\n",
           device ? device : "opencl", limn_scheme_name(op.scheme), n, t.colours);

    double *frees[] = {want, want2, tmp, y, q, qd, rhat0, phat0, x0, r0, init[0], init[1], s,
                       dinv};
    for (size_t i = 0; i < sizeof frees / sizeof *frees; i++)
        free(frees[i]);
    for (int i = 0; i < 8; i++)
        ops->buffer_release(dev, buf[i]);
    device_sgs_release(dev, &da);
    sgs_table_free(&t);
    operator_free(&op);
    limn_context_destroy(ctx);
}

static void outputs_free(outputs *o)
{
    double *v[] = {o->r, o->u, o->rhat, o->phat, o->t, o->u2, o->st, o->x, o->r2, o->rhat2};
    for (int i = 0; i < 10; i++)
        free(v[i]);
}

static void both_backends(const limn_mesh *mesh, limn_scheme scheme)
{
    outputs a, b;
    run_backend(NULL, mesh, scheme, &a);
    run_backend("reference", mesh, scheme, &b);
    double *va[] = {a.r, a.u, a.rhat, a.phat, a.t, a.u2, a.st, a.x, a.r2, a.rhat2};
    double *vb[] = {b.r, b.u, b.rhat, b.phat, b.t, b.u2, b.st, b.x, b.r2, b.rhat2};
    for (int k = 0; k < 10; k++)
        assert_memory_equal(va[k], vb[k], 4 * a.n * sizeof(double));
    assert_memory_equal(&a.start_max, &b.start_max, sizeof(double));
    assert_memory_equal(&a.start_sum, &b.start_sum, sizeof(double));
    assert_memory_equal(&a.dot, &b.dot, sizeof(double));
    assert_memory_equal(&a.update_max, &b.update_max, sizeof(double));
    assert_memory_equal(&a.update_sum, &b.update_sum, sizeof(double));
    outputs_free(&a);
    outputs_free(&b);
}

static limn_mesh *refined(limn_context *ctx, limn_mesh *m, int levels)
{
    limn_subdivide_options so;
    limn_subdivide_options_default(&so);
    so.levels = levels;
    limn_mesh *out = NULL;
    assert_int_equal(limn_subdivide(ctx, m, &so, &out, NULL), LIMN_OK);
    limn_mesh_destroy(m);
    test_perturb(out, 0.02, 7);
    return out;
}

static void catmull_clark(void **state)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/spot_control_mesh.obj", getenv("LIMN_TEST_DATA"));
    limn_context *ctx = *state;
    limn_mesh *spot = NULL;
    assert_int_equal(limn_mesh_read(ctx, path, LIMN_FORMAT_AUTO, &spot), LIMN_OK);
    spot = refined(ctx, spot, 2);
    both_backends(spot, LIMN_SCHEME_CATMARK);
    limn_mesh_destroy(spot);
}

static void loop(void **state)
{
    limn_context *ctx = *state;
    limn_mesh *ico = refined(ctx, test_mesh_icosahedron(ctx), 3);
    both_backends(ico, LIMN_SCHEME_LOOP);
    limn_mesh_destroy(ico);
}

TEST_MAIN(NULL, NULL, CONTEXT_TEST(catmull_clark), CONTEXT_TEST(loop))
