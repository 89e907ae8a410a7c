/* SPDX-License-Identifier: MIT */
/*
 * The reference twins of kernels/mixed.cl: the same float and double
 * operations in the same order (built with -ffp-contract=off; float
 * expressions are evaluated in float on x86-64 and AArch64, FLT_EVAL_METHOD
 * 0), so the OpenCL float path is checked bit for bit, like the double one.
 */
#include "base/context.h"
#include "device/reference/device_ref.h"

#include <math.h>
#include <stdlib.h>

/* r = m - A p in double, stored rounded to float. */
typedef struct residual_f {
    const device_csr *a;
    const double *ms, *ps;
    float *rs;
} residual_f;

static void residual_f_chunk(void *user, size_t begin, size_t end, double n[3])
{
    const residual_f *f = user;
    float *rs = f->rs;
    for (size_t i = begin; i < end; i++) {
        double r[3];
        ref_residual_row(f->a, i, f->ms, f->ps, r);
        for (int j = 0; j < 3; j++)
            rs[4 * i + j] = (float)r[j];
        rs[4 * i + 3] = 0.0f;
        ref_norms_add(r[0], r[1], r[2], n);
    }
}

static limn_status ref_residual_f(struct device *dev, const device_csr *a, device_buffer *m,
                                  device_buffer *p, device_buffer *r_f, device_norms *norms)
{
    (void)dev;
    residual_f f = {a, m->data, p->data, r_f->data};
    ref_chunks(a->row_begin, a->rows, residual_f_chunk, &f, norms);
    return LIMN_OK;
}

/* The float step: s = b - A_f d, next = d + c1 (d - prev) + c2 s. */
typedef struct step_f {
    const device_csr *a;
    const float *bs, *ds, *qs;
    float *dn, c1, c2;
} step_f;

static void step_f_chunk(void *user, size_t begin, size_t end, double n[3])
{
    const step_f *f = user;
    const uint32_t *ro = f->a->row_offsets->data, *col = f->a->columns->data;
    const float *w = f->a->weights_f->data, *bs = f->bs, *ds = f->ds, *qs = f->qs;
    float *dn = f->dn, c1 = f->c1, c2 = f->c2;
    for (size_t i = begin; i < end; i++) {
        float acc[4] = {0.0f, 0.0f, 0.0f, 0.0f};
        for (uint32_t k = ro[i]; k < ro[i + 1]; k++)
            for (int j = 0; j < 4; j++)
                acc[j] += w[k] * ds[4 * (size_t)col[k] + j];
        float s[3] = {bs[4 * i] - acc[0], bs[4 * i + 1] - acc[1], bs[4 * i + 2] - acc[2]};
        for (int j = 0; j < 3; j++) {
            float dj = ds[4 * i + j], qj = qs[4 * i + j]; /* prev before next */
            dn[4 * i + j] = dj + c1 * (dj - qj) + c2 * s[j];
        }
        dn[4 * i + 3] = 0.0f;
        ref_norms_add(s[0], s[1], s[2], n);
    }
}

static limn_status ref_step_f(struct device *dev, const device_csr *a, device_buffer *b,
                              device_buffer *d, device_buffer *prev, device_buffer *next,
                              float c1, float c2, device_norms *norms)
{
    if (!a->weights_f)
        return ctx_fail(dev->ctx, LIMN_ERR_ARGUMENT, "step_f: no float weights");
    step_f f = {a, b->data, d->data, prev->data, next->data, c1, c2};
    ref_chunks(a->row_begin, a->rows, step_f_chunk, &f, norms);
    return LIMN_OK;
}

limn_status ref_add_f(struct device *dev, size_t rows, device_buffer *p, device_buffer *d)
{
    (void)dev;
    double *ps = p->data;
    const float *ds = d->data;
    for (size_t i = 0; i < rows; i++) {
        for (int j = 0; j < 3; j++)
            ps[4 * i + j] = ps[4 * i + j] + (double)ds[4 * i + j];
        ps[4 * i + 3] = 0.0;
    }
    return LIMN_OK;
}

static limn_status ref_to_float(struct device *dev, size_t count, device_buffer *w,
                                device_buffer *w_f)
{
    (void)dev;
    const double *ws = w->data;
    float *fs = w_f->data;
    for (size_t i = 0; i < count; i++)
        fs[i] = (float)ws[i];
    return LIMN_OK;
}

const device_mixed_ops ref_mixed_ops = {ref_residual_f, ref_step_f, ref_add_f, ref_to_float};
