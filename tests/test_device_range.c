/* SPDX-License-Identifier: MIT */
/*
 * Row ranges of a device CSR table (device_csr.row_begin) and partial buffer
 * reads/writes, on both backends: computing the rows [0, b) and [b, n)
 * separately must give exactly the bits of one whole launch (each row's
 * arithmetic is the same), and the norms the same maximum and the same sums
 * up to the association of the per-chunk partials (1e-14 relative). The MPI
 * layer relies on this to compute interior rows while the halo is in flight.
 */
#include "support.h"

#include "device/device.h"
#include "solve/operator.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

typedef struct fixture {
    limn_context *ctx;
    limn_mesh *mesh;
    stencil_operator op;
    size_t n;
    double *host;
} fixture;

static void open_fixture(fixture *f, const char *device, int triangles)
{
    memset(f, 0, sizeof *f);
    f->ctx = limn_context_create();
    assert_int_equal(limn_context_set_device(f->ctx, device), LIMN_OK);
    /* 1558 rows: 7 chunks of 256, the last ragged */
    f->mesh = test_mesh_grid(f->ctx, 40, 37, triangles);
    if (operator_build(f->ctx, f->mesh, LIMN_SCHEME_AUTO, 0.0, &f->op) != LIMN_OK)
        fail_msg("%s", limn_context_message(f->ctx));
    f->n = f->op.vertex_count;
    f->host = malloc(4 * f->n * sizeof *f->host);
    operator_pack(&f->op, limn_mesh_positions(f->mesh), f->host);
}

static void close_fixture(fixture *f)
{
    free(f->host);
    operator_free(&f->op);
    limn_mesh_destroy(f->mesh);
    limn_context_destroy(f->ctx);
}

static device_buffer *make(fixture *f, const double *init)
{
    device_buffer *b = NULL;
    assert_int_equal(f->op.dev->ops->buffer_create(f->op.dev, 4 * f->n * sizeof(double), init, &b),
                     LIMN_OK);
    return b;
}

static double *read_all(fixture *f, device_buffer *b)
{
    double *out = malloc(4 * f->n * sizeof *out);
    assert_int_equal(f->op.dev->ops->buffer_read(f->op.dev, b, 4 * f->n * sizeof(double), out),
                     LIMN_OK);
    return out;
}

static void split(const fixture *f, size_t b, device_csr *lo, device_csr *hi)
{
    *lo = f->op.device;
    *hi = f->op.device;
    lo->rows = b;
    hi->row_begin = b;
    hi->rows = f->n - b;
}

static void combine(const device_norms *a, const device_norms *b, device_norms *out)
{
    out->max = fmax(a->max, b->max);
    out->sum = a->sum + b->sum;
    out->sum_sq = a->sum_sq + b->sum_sq;
}

static void same_norms(const device_norms *whole, const device_norms *parts)
{
    assert_true(whole->max == parts->max);
    assert_true(fabs(whole->sum - parts->sum) <= 1e-14 * whole->sum);
    assert_true(fabs(whole->sum_sq - parts->sum_sq) <= 1e-14 * whole->sum_sq);
}

static void ranges_on(const char *device, int triangles)
{
    fixture f;
    open_fixture(&f, device, triangles);
    const device_ops *ops = f.op.dev->ops;
    struct device *dev = f.op.dev;
    device_csr lo, hi;
    split(&f, 2 * DEVICE_ROWS_PER_ITEM, &lo, &hi);

    /* interp_step, omega != 1 so the update is exercised */
    device_buffer *m = make(&f, f.host), *p = make(&f, f.host), *q1 = make(&f, NULL),
                  *q2 = make(&f, NULL);
    for (size_t i = 0; i < 4 * f.n; i += 4)
        f.host[i] += 0.01 * sin((double)i); /* p != m */
    assert_int_equal(ops->buffer_write(dev, p, 4 * f.n * sizeof(double), f.host), LIMN_OK);
    device_norms whole, a, b, parts;
    assert_int_equal(ops->stationary->interp_step(dev, &f.op.device, m, p, q1, 0.7, &whole), LIMN_OK);
    assert_int_equal(ops->stationary->interp_step(dev, &hi, m, p, q2, 0.7, &b), LIMN_OK);
    assert_int_equal(ops->stationary->interp_step(dev, &lo, m, p, q2, 0.7, &a), LIMN_OK);
    combine(&a, &b, &parts);
    same_norms(&whole, &parts);
    double *x1 = read_all(&f, q1), *x2 = read_all(&f, q2);
    assert_memory_equal(x1, x2, 4 * f.n * sizeof(double));
    free(x1);
    free(x2);

    /* cheb_step: its previous iterate is read and overwritten row by row */
    device_buffer *prev1 = make(&f, f.host), *prev2 = make(&f, f.host);
    assert_int_equal(ops->stationary->cheb_step(dev, &f.op.device, m, p, prev1, 0.3, 1.2, &whole), LIMN_OK);
    assert_int_equal(ops->stationary->cheb_step(dev, &hi, m, p, prev2, 0.3, 1.2, &b), LIMN_OK);
    assert_int_equal(ops->stationary->cheb_step(dev, &lo, m, p, prev2, 0.3, 1.2, &a), LIMN_OK);
    combine(&a, &b, &parts);
    same_norms(&whole, &parts);
    x1 = read_all(&f, prev1);
    x2 = read_all(&f, prev2);
    assert_memory_equal(x1, x2, 4 * f.n * sizeof(double));
    free(x1);
    free(x2);
    ops->buffer_release(dev, prev1);
    ops->buffer_release(dev, prev2);

    /* series_step with every output */
    device_buffer *ax1 = make(&f, NULL), *ax2 = make(&f, NULL), *acc1 = make(&f, f.host),
                  *acc2 = make(&f, f.host);
    assert_int_equal(ops->series->series_step(dev, &f.op.device, p, q1, ax1, acc1,
                                      SERIES_STORE_AX | SERIES_STORE_NEXT, SERIES_ACC_ADD_AX,
                                      &whole),
                     LIMN_OK);
    assert_int_equal(ops->series->series_step(dev, &lo, p, q2, ax2, acc2,
                                      SERIES_STORE_AX | SERIES_STORE_NEXT, SERIES_ACC_ADD_AX, &a),
                     LIMN_OK);
    assert_int_equal(ops->series->series_step(dev, &hi, p, q2, ax2, acc2,
                                      SERIES_STORE_AX | SERIES_STORE_NEXT, SERIES_ACC_ADD_AX, &b),
                     LIMN_OK);
    combine(&a, &b, &parts);
    same_norms(&whole, &parts);
    device_buffer *pairs[3][2] = {{q1, q2}, {ax1, ax2}, {acc1, acc2}};
    for (int k = 0; k < 3; k++) {
        x1 = read_all(&f, pairs[k][0]);
        x2 = read_all(&f, pairs[k][1]);
        assert_memory_equal(x1, x2, 4 * f.n * sizeof(double));
        free(x1);
        free(x2);
    }

    /* spmv and spmv_dot */
    assert_int_equal(ops->spmv(dev, &f.op.device, p, q1), LIMN_OK);
    assert_int_equal(ops->spmv(dev, &lo, p, q2), LIMN_OK);
    assert_int_equal(ops->spmv(dev, &hi, p, q2), LIMN_OK);
    x1 = read_all(&f, q1);
    x2 = read_all(&f, q2);
    assert_memory_equal(x1, x2, 4 * f.n * sizeof(double));
    free(x1);
    free(x2);
    double *ones = malloc(f.n * sizeof *ones);
    for (size_t i = 0; i < f.n; i++)
        ones[i] = 1.0 + (double)(i % 7);
    device_buffer *dinv = NULL;
    assert_int_equal(ops->buffer_create(dev, f.n * sizeof(double), ones, &dinv), LIMN_OK);
    double dw, dl, dh;
    assert_int_equal(ops->cg->spmv_dot(dev, &f.op.device, p, q1, dinv, &dw), LIMN_OK);
    assert_int_equal(ops->cg->spmv_dot(dev, &lo, p, q2, dinv, &dl), LIMN_OK);
    assert_int_equal(ops->cg->spmv_dot(dev, &hi, p, q2, dinv, &dh), LIMN_OK);
    assert_true(fabs(dw - (dl + dh)) <= 1e-14 * fabs(dw));

    /* partial reads and writes land where asked, and refuse past the end */
    double rec[8] = {1, 2, 3, 4, 5, 6, 7, 8}, back[8];
    size_t at = 4 * (f.n - 2) * sizeof(double);
    assert_int_equal(ops->buffer_write_at(dev, q1, at, sizeof rec, rec), LIMN_OK);
    assert_int_equal(ops->buffer_read_at(dev, q1, at, sizeof back, back), LIMN_OK);
    assert_memory_equal(rec, back, sizeof rec);
    x1 = read_all(&f, q1);
    assert_memory_equal(x1 + 4 * (f.n - 2), rec, sizeof rec);
    free(x1);
    assert_int_equal(ops->buffer_write_at(dev, q1, at + 8, sizeof rec, rec), LIMN_ERR_ARGUMENT);
    assert_int_equal(ops->buffer_read_at(dev, q1, at + 8, sizeof back, back), LIMN_ERR_ARGUMENT);

    device_buffer *all[] = {m, p, q1, q2, ax1, ax2, acc1, acc2, dinv};
    for (size_t k = 0; k < sizeof all / sizeof *all; k++)
        ops->buffer_release(dev, all[k]);
    free(ones);
    close_fixture(&f);
}

static void reference_ranges(void **s)
{
    (void)s;
    ranges_on("reference", 0);
    ranges_on("reference", 1);
}

static void opencl_ranges(void **s)
{
    (void)s;
    ranges_on("opencl", 0);
    ranges_on("opencl", 1);
}

TEST_MAIN(NULL, NULL, cmocka_unit_test(reference_ranges), cmocka_unit_test(opencl_ranges))
