/* SPDX-License-Identifier: MIT */
/* Internals of the reference backend shared by device_ref.c,
   device_ref_mixed.c (the float operations of the mixed-precision solve) and
   device_ref_sgs.c (the SGS-preconditioned CG's sweeps). */
#ifndef LIMN_DEVICE_REF_H
#define LIMN_DEVICE_REF_H

#include "device/device.h"

#include <math.h>

struct device_buffer {
    size_t bytes;
    void *data;
    int shared; /* data is the caller's (buffer_share): not freed here */
};

/* The fixed chunks of the reductions: fn computes rows [begin, end) of one
   chunk of DEVICE_ROWS_PER_ITEM rows and its partial norms n (max, sum,
   sum of squares, zero on entry); the chunks of rows [row_begin, row_begin +
   rows) run in order and their partials are finished as
   device_norms_finish does, chunk after chunk, so the results are the
   kernels' bit for bit. */
typedef void (*ref_chunk_fn)(void *user, size_t begin, size_t end, double n[3]);
void ref_chunks(size_t row_begin, size_t rows, ref_chunk_fn fn, void *user, device_norms *out);

/* Adds the vector (v0, v1, v2) to partial norms n, in the kernels' order. */
static inline void ref_norms_add(double v0, double v1, double v2, double n[3])
{
    double s = v0 * v0 + v1 * v1 + v2 * v2;
    double len = sqrt(s);
    n[0] = len > n[0] ? len : n[0];
    n[1] += len;
    n[2] += s;
}

/* acc = sum_k w_k x_{col_k}, component by component, in row order (the
   kernels' row_product). */
static inline void ref_row_product(const device_csr *a, size_t i, const double *x, double acc[4])
{
    const uint32_t *ro = a->row_offsets->data;
    const uint32_t *col = a->columns->data;
    const double *w = a->weights->data;
    acc[0] = acc[1] = acc[2] = acc[3] = 0.0;
    for (uint32_t k = ro[i]; k < ro[i + 1]; k++) {
        const double *p = x + 4 * (size_t)col[k];
        double wk = w[k];
        acc[0] += wk * p[0];
        acc[1] += wk * p[1];
        acc[2] += wk * p[2];
        acc[3] += wk * p[3];
    }
}

/* r = m_i - (A p)_i over x, y, z (the kernels' residual_row). */
static inline void ref_residual_row(const device_csr *a, size_t i, const double *ms,
                                    const double *ps, double r[3])
{
    double acc[4];
    ref_row_product(a, i, ps, acc);
    for (int d = 0; d < 3; d++)
        r[d] = ms[4 * i + d] - acc[d];
}

/* The float family (device_ref_mixed.c) and the sweeps (device_ref_sgs.c). */
extern const device_mixed_ops ref_mixed_ops;
extern const device_sgs_ops ref_sgs_ops;

#endif
