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

/* Per-chunk partial norms, finished in chunk order like the kernels'. */
typedef struct chunk_norms {
    double *partials;
    size_t chunks;
} chunk_norms;

static limn_status chunks_begin(struct device *dev, size_t rows, chunk_norms *c)
{
    c->chunks = (rows + DEVICE_ROWS_PER_ITEM - 1) / DEVICE_ROWS_PER_ITEM;
    c->partials = malloc((c->chunks ? c->chunks : 1) * 3 * sizeof *c->partials);
    return c->partials ? LIMN_OK
                       : ctx_fail(dev->ctx, LIMN_ERR_MEMORY, "out of memory for reductions");
}

static void chunks_end(chunk_norms *c, device_norms *out)
{
    device_norms_finish(c->partials, c->chunks, out);
    free(c->partials);
}

static inline void accumulate_norms(double v0, double v1, double v2, double n[3])
{
    double s = v0 * v0 + v1 * v1 + v2 * v2;
    double len = sqrt(s);
    n[0] = len > n[0] ? len : n[0];
    n[1] += len;
    n[2] += s;
}

static limn_status ref_residual_f(struct device *dev, const device_csr *a, device_buffer *m,
                                  device_buffer *p, device_buffer *r_f, device_norms *norms)
{
    const uint32_t *ro = a->row_offsets->data, *col = a->columns->data;
    const double *w = a->weights->data, *ms = m->data, *ps = p->data;
    float *rs = r_f->data;
    chunk_norms c;
    limn_status st = chunks_begin(dev, a->rows, &c);
    if (st)
        return st;
    for (size_t g = 0; g < c.chunks; g++) {
        size_t begin = a->row_begin + g * DEVICE_ROWS_PER_ITEM;
        size_t end = begin + DEVICE_ROWS_PER_ITEM, stop = a->row_begin + a->rows;
        end = end < stop ? end : stop;
        double *n = c.partials + 3 * g;
        n[0] = n[1] = n[2] = 0.0;
        for (size_t i = begin; i < end; i++) {
            double acc[4] = {0.0, 0.0, 0.0, 0.0};
            for (uint32_t k = ro[i]; k < ro[i + 1]; k++)
                for (int j = 0; j < 4; j++)
                    acc[j] += w[k] * ps[4 * (size_t)col[k] + j];
            double r0 = ms[4 * i] - acc[0], r1 = ms[4 * i + 1] - acc[1],
                   r2 = ms[4 * i + 2] - acc[2];
            rs[4 * i] = (float)r0;
            rs[4 * i + 1] = (float)r1;
            rs[4 * i + 2] = (float)r2;
            rs[4 * i + 3] = 0.0f;
            accumulate_norms(r0, r1, r2, n);
        }
    }
    chunks_end(&c, norms);
    return LIMN_OK;
}

static limn_status ref_step_f(struct device *dev, const device_csr *a, device_buffer *b,
                              device_buffer *d, device_buffer *prev, device_buffer *next, float c1,
                              float c2, device_norms *norms)
{
    if (!a->weights_f)
        return ctx_fail(dev->ctx, LIMN_ERR_ARGUMENT, "step_f: no float weights");
    const uint32_t *ro = a->row_offsets->data, *col = a->columns->data;
    const float *w = a->weights_f->data, *bs = b->data, *ds = d->data;
    const float *qs = prev->data;
    float *dn = next->data;
    chunk_norms c;
    limn_status st = chunks_begin(dev, a->rows, &c);
    if (st)
        return st;
    for (size_t g = 0; g < c.chunks; g++) {
        size_t begin = a->row_begin + g * DEVICE_ROWS_PER_ITEM;
        size_t end = begin + DEVICE_ROWS_PER_ITEM, stop = a->row_begin + a->rows;
        end = end < stop ? end : stop;
        double *n = c.partials + 3 * g;
        n[0] = n[1] = n[2] = 0.0;
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
            accumulate_norms(s[0], s[1], s[2], n);
        }
    }
    chunks_end(&c, norms);
    return LIMN_OK;
}

static limn_status ref_add_f(struct device *dev, size_t rows, device_buffer *p, device_buffer *d)
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
