/* SPDX-License-Identifier: MIT */
/*
 * The plain C reference backend. It does the same arithmetic in the same
 * order as kernels/stencil.cl (built with -ffp-contract=off, and the kernels
 * with FP_CONTRACT OFF), so it is the oracle for the OpenCL path.
 */
#include "base/context.h"
#include "device/reference/device_ref.h"
#include "device/reference/ref_open.h"
#include "base/large_alloc.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static limn_status ref_buffer_create(struct device *dev, size_t bytes, const void *init,
                                     device_buffer **out)
{
    device_buffer *b = calloc(1, sizeof *b);
    void *data = large_malloc(bytes);
    if (!b || !data) {
        free(b);
        free(data);
        return ctx_fail(dev->ctx, LIMN_ERR_MEMORY, "out of memory for a %zu-byte buffer",
                         bytes);
    }
    if (init)
        memcpy(data, init, bytes);
    else
        memset(data, 0, bytes ? bytes : 1);
    b->bytes = bytes;
    b->data = data;
    *out = b;
    return LIMN_OK;
}

static limn_status ref_buffer_scratch(struct device *dev, size_t bytes, device_buffer **out)
{
    device_buffer *b = calloc(1, sizeof *b);
    void *data = large_malloc(bytes);
    if (!b || !data) {
        free(b);
        free(data);
        return ctx_fail(dev->ctx, LIMN_ERR_MEMORY, "out of memory for a %zu-byte buffer",
                        bytes);
    }
    b->bytes = bytes;
    b->data = data;
    *out = b;
    return LIMN_OK;
}

/* The host memory itself: nothing writes it while the buffer lives. */
static limn_status ref_buffer_share(struct device *dev, size_t bytes, const void *host,
                                    device_buffer **out)
{
    if (!bytes)
        return ref_buffer_create(dev, bytes, host, out);
    device_buffer *b = calloc(1, sizeof *b);
    if (!b)
        return ctx_fail(dev->ctx, LIMN_ERR_MEMORY, "out of memory for a buffer");
    b->bytes = bytes;
    b->data = (void *)host;
    b->shared = 1;
    *out = b;
    return LIMN_OK;
}

static limn_status ref_buffer_write(struct device *dev, device_buffer *buf, size_t bytes,
                                    const void *src)
{
    if (bytes > buf->bytes)
        return ctx_fail(dev->ctx, LIMN_ERR_ARGUMENT, "buffer write past its end");
    memcpy(buf->data, src, bytes);
    return LIMN_OK;
}

static limn_status ref_buffer_read(struct device *dev, device_buffer *buf, size_t bytes,
                                   void *dst)
{
    if (bytes > buf->bytes)
        return ctx_fail(dev->ctx, LIMN_ERR_ARGUMENT, "buffer read past its end");
    if (dst != buf->data) /* a shared buffer read into its own memory: nothing to move */
        memcpy(dst, buf->data, bytes);
    return LIMN_OK;
}

static limn_status ref_buffer_write_at(struct device *dev, device_buffer *buf,
                                       size_t offset, size_t bytes, const void *src)
{
    if (offset > buf->bytes || bytes > buf->bytes - offset)
        return ctx_fail(dev->ctx, LIMN_ERR_ARGUMENT, "buffer write past its end");
    memcpy((char *)buf->data + offset, src, bytes);
    return LIMN_OK;
}

static limn_status ref_buffer_read_at(struct device *dev, device_buffer *buf, size_t offset,
                                      size_t bytes, void *dst)
{
    if (offset > buf->bytes || bytes > buf->bytes - offset)
        return ctx_fail(dev->ctx, LIMN_ERR_ARGUMENT, "buffer read past its end");
    if (dst != (const char *)buf->data + offset)
        memcpy(dst, (const char *)buf->data + offset, bytes);
    return LIMN_OK;
}

static void ref_buffer_release(struct device *dev, device_buffer *buf)
{
    (void)dev;
    if (buf) {
        if (!buf->shared)
            free(buf->data);
        free(buf);
    }
}

static limn_status ref_spmv(struct device *dev, const device_csr *a, device_buffer *x,
                            device_buffer *y)
{
    (void)dev;
    const double *xs = x->data;
    double *ys = y->data;
    for (size_t i = a->row_begin; i < a->row_begin + a->rows; i++)
        ref_row_product(a, i, xs, ys + 4 * i);
    return LIMN_OK;
}

void ref_chunks(size_t row_begin, size_t rows, ref_chunk_fn fn, void *user, device_norms *out)
{
    out->max = 0;
    out->sum = 0;
    out->sum_sq = 0;
    size_t stop = row_begin + rows;
    for (size_t begin = row_begin; begin < stop; begin += DEVICE_ROWS_PER_ITEM) {
        size_t end = begin + DEVICE_ROWS_PER_ITEM < stop ? begin + DEVICE_ROWS_PER_ITEM : stop;
        double n[3] = {0.0, 0.0, 0.0};
        fn(user, begin, end, n);
        if (n[0] > out->max)
            out->max = n[0];
        out->sum += n[1];
        out->sum_sq += n[2];
    }
}

/*
 * The fused residual step of kernels/stencil.cl (interp_step) and
 * kernels/solve.cl (cheb_step), in their order: r = m - A p and, per row,
 * prev == NULL: next = p + c2 r (interp_step, c2 = omega);
 * otherwise:    next = p + c1 (p - prev) + c2 r (cheb_step; next may be prev).
 * Norms of r.
 */
typedef struct fused_step {
    const device_csr *a;
    const double *ms, *ps, *prev;
    double *next, c1, c2;
} fused_step;

static void fused_chunk(void *user, size_t begin, size_t end, double n[3])
{
    const fused_step *f = user;
    const double *ms = f->ms, *ps = f->ps, *prev = f->prev;
    double *next = f->next;
    for (size_t i = begin; i < end; i++) {
        double r[3];
        ref_residual_row(f->a, i, ms, ps, r);
        for (int d = 0; d < 3; d++) {
            double pi = ps[4 * i + d];
            next[4 * i + d] = prev ? pi + f->c1 * (pi - prev[4 * i + d]) + f->c2 * r[d]
                                   : pi + f->c2 * r[d];
        }
        next[4 * i + 3] = 0.0;
        ref_norms_add(r[0], r[1], r[2], n);
    }
}

static limn_status ref_interp_step(struct device *dev, const device_csr *a,
                                   device_buffer *m, device_buffer *p, device_buffer *p_next,
                                   double omega, device_norms *norms)
{
    (void)dev;
    fused_step f = {a, m->data, p->data, NULL, p_next->data, 0.0, omega};
    ref_chunks(a->row_begin, a->rows, fused_chunk, &f, norms);
    return LIMN_OK;
}

static limn_status ref_cheb_step(struct device *dev, const device_csr *a, device_buffer *m,
                                 device_buffer *p, device_buffer *prev_next, double c1,
                                 double c2, device_norms *norms)
{
    (void)dev;
    fused_step f = {a, m->data, p->data, prev_next->data, prev_next->data, c1, c2};
    ref_chunks(a->row_begin, a->rows, fused_chunk, &f, norms);
    return LIMN_OK;
}

/* Same order as kernels/series.cl: series_step. */
typedef struct series_term {
    const device_csr *a;
    const double *xs;
    double *xn, *axs, *as;
    int flags, acc_mode;
} series_term;

static void series_chunk(void *user, size_t begin, size_t end, double n[3])
{
    const series_term *t = user;
    double *xn = t->xn, *axs = t->axs, *as = t->as;
    for (size_t i = begin; i < end; i++) {
        double v[4];
        ref_row_product(t->a, i, t->xs, v);
        const double *xi = t->xs + 4 * i;
        if (t->flags & SERIES_STORE_AX)
            for (int c = 0; c < 4; c++)
                axs[4 * i + c] = v[c];
        if (t->flags & SERIES_STORE_NEXT)
            for (int c = 0; c < 4; c++)
                xn[4 * i + c] = xi[c] - v[c];
        if (t->acc_mode == SERIES_ACC_SET_AX)
            for (int c = 0; c < 4; c++)
                as[4 * i + c] = v[c];
        else if (t->acc_mode == SERIES_ACC_ADD_AX)
            for (int c = 0; c < 4; c++)
                as[4 * i + c] = as[4 * i + c] + v[c];
        else if (t->acc_mode == SERIES_ACC_ADD_X)
            for (int c = 0; c < 4; c++)
                as[4 * i + c] = as[4 * i + c] + xi[c];
        ref_norms_add(v[0], v[1], v[2], n);
    }
}

static limn_status ref_series_step(struct device *dev, const device_csr *a,
                                   device_buffer *x, device_buffer *x_next, device_buffer *ax,
                                   device_buffer *acc, int flags, int acc_mode,
                                   device_norms *norms)
{
    (void)dev;
    series_term t = {a,     x->data, x_next ? x_next->data : NULL, ax ? ax->data : NULL,
                     acc ? acc->data : NULL, flags, acc_mode};
    ref_chunks(a->row_begin, a->rows, series_chunk, &t, norms);
    return LIMN_OK;
}

static limn_status ref_axpby(struct device *dev, size_t rows, double a, device_buffer *x,
                             double b, device_buffer *y, device_buffer *out)
{
    (void)dev;
    const double *xs = x->data, *ys = y->data;
    double *os = out->data;
    for (size_t i = 0; i < 4 * rows; i++)
        os[i] = a * xs[i] + b * ys[i];
    return LIMN_OK;
}

static void norms_chunk(void *user, size_t begin, size_t end, double n[3])
{
    const double *xs = user;
    for (size_t i = begin; i < end; i++)
        ref_norms_add(xs[4 * i], xs[4 * i + 1], xs[4 * i + 2], n);
}

static limn_status ref_norms(struct device *dev, size_t rows, device_buffer *x,
                             device_norms *out)
{
    (void)dev;
    ref_chunks(0, rows, norms_chunk, x->data, out);
    return LIMN_OK;
}

/* y = A x; n[1] = sum_i dinv_i (x_i . y_i) over the chunk. */
typedef struct spmv_dot {
    const device_csr *a;
    const double *xs, *dv;
    double *ys;
} spmv_dot;

static void spmv_dot_chunk(void *user, size_t begin, size_t end, double n[3])
{
    const spmv_dot *s = user;
    for (size_t i = begin; i < end; i++) {
        double *acc = s->ys + 4 * i;
        ref_row_product(s->a, i, s->xs, acc);
        const double *xi = s->xs + 4 * i;
        double d = xi[0] * acc[0] + xi[1] * acc[1] + xi[2] * acc[2];
        n[1] += s->dv[i] * d;
    }
}

static limn_status ref_spmv_dot(struct device *dev, const device_csr *a, device_buffer *x,
                                device_buffer *y, device_buffer *dinv, double *dot)
{
    (void)dev;
    spmv_dot s = {a, x->data, dinv->data, y->data};
    device_norms n;
    ref_chunks(a->row_begin, a->rows, spmv_dot_chunk, &s, &n);
    *dot = n.sum;
    return LIMN_OK;
}

typedef struct pcg_update {
    double alpha;
    const double *ps, *qs, *dv;
    double *xs, *zs;
} pcg_update;

/* n: max |z_i|, sum dinv_i |z_i|^2, sum |z_i|^2 */
static void pcg_update_chunk(void *user, size_t begin, size_t end, double n[3])
{
    const pcg_update *u = user;
    double *xs = u->xs, *zs = u->zs;
    for (size_t i = begin; i < end; i++) {
        for (int c = 0; c < 3; c++) {
            xs[4 * i + c] = xs[4 * i + c] + u->alpha * u->ps[4 * i + c];
            zs[4 * i + c] = zs[4 * i + c] - u->alpha * u->qs[4 * i + c];
        }
        xs[4 * i + 3] = zs[4 * i + 3] = 0.0;
        const double *zi = zs + 4 * i;
        double s = zi[0] * zi[0] + zi[1] * zi[1] + zi[2] * zi[2];
        double len = sqrt(s);
        n[0] = len > n[0] ? len : n[0];
        n[1] += u->dv[i] * s;
        n[2] += s;
    }
}

static limn_status ref_pcg_update(struct device *dev, size_t rows, double alpha,
                                  device_buffer *p, device_buffer *q, device_buffer *x,
                                  device_buffer *z, device_buffer *dinv, device_norms *norms)
{
    (void)dev;
    pcg_update u = {alpha, p->data, q->data, dinv->data, x->data, z->data};
    ref_chunks(0, rows, pcg_update_chunk, &u, norms);
    return LIMN_OK;
}

static void ref_close(struct device *dev)
{
    free(dev);
}

static const device_stationary_ops reference_stationary = {ref_interp_step, ref_cheb_step};
static const device_cg_ops reference_cg = {ref_spmv_dot, ref_pcg_update};
static const device_series_ops reference_series = {ref_series_step};

static const device_ops reference_ops = {
    .kind = "reference",
    .buffer_create = ref_buffer_create,
    .buffer_share = ref_buffer_share,
    .buffer_scratch = ref_buffer_scratch,
    .buffer_write = ref_buffer_write,
    .buffer_read = ref_buffer_read,
    .buffer_release = ref_buffer_release,
    .buffer_write_at = ref_buffer_write_at,
    .buffer_read_at = ref_buffer_read_at,
    .spmv = ref_spmv,
    .axpby = ref_axpby,
    .norms = ref_norms,
    .close = ref_close,
    .stationary = &reference_stationary,
    .cg = &reference_cg,
    .mixed = &ref_mixed_ops,
    .sgs = &ref_sgs_ops,
    .series = &reference_series,
};

limn_status device_open_reference(limn_context *ctx, struct device **out)
{
    struct device *dev = calloc(1, sizeof *dev);
    if (!dev)
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory opening the reference backend");
    dev->ops = &reference_ops;
    dev->ctx = ctx;
    dev->host_shared = 1;
    strcpy(dev->name, "reference (plain C, 1 thread)");
    *out = dev;
    return LIMN_OK;
}
