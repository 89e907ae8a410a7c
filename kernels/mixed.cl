/* SPDX-License-Identifier: MIT */
/*
 * Kernels of the mixed-precision refinement (host/solve_mixed.c), built into
 * the same program after common.cl (residual_row, residual_row_f). The residual of P is
 * taken in double; the correction d with A d = r is iterated in float (float
 * weights, float4 vectors: 8 bytes a nonzero and 48 a row instead of 12 and
 * 96), with its norms summed in double so they do not lose the digits float
 * vectors keep. Same conventions as stencil.cl (ROWS_PER_ITEM rows per item,
 * partials finished on the host in order, FP_CONTRACT OFF so that
 * host/device_ref_mixed.c gives the same bits).
 */
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#pragma OPENCL FP_CONTRACT OFF

/* r = m - A p in double; r_f = r rounded to float; partial norms of r. */
kernel void residual_f(uint rows, global const uint *ro, global const uint *col,
                       global const double *w, global const double4 *m,
                       global const double4 *p, global float4 *r_f, global double *partials,
                       uint ahead)
{
    REDUCTION_SCRATCH;
    item_rows span = rows_of_item(0, rows);
    double mx = 0.0, sum = 0.0, sq = 0.0;
    uint last = TABLE_LAST(ro, rows);
    for (uint i = span.begin; i < span.end; i++) {
        double4 ri = residual_row(i, ro, col, w, m, p, last, ahead);
        r_f[i] = (float4)((float)ri.x, (float)ri.y, (float)ri.z, 0.0f);
        accumulate_norms(ri.x, ri.y, ri.z, &mx, &sum, &sq);
    }
    STORE_PARTIALS(partials, 0, span, mx, sum, sq);
}

/* s = b - A_f d; next = d + c1 (d - prev) + c2 s, in float (the Chebyshev
   recurrence; c1 = 0, c2 = omega: the seeds' or the weighted step); partial
   norms of s in double. prev and next may be one buffer (each row reads its
   prev before writing its next); prev may be d. */
kernel void step_f(uint rows, global const uint *ro, global const uint *col,
                   global const float *w, global const float4 *b, global const float4 *d,
                   global const float4 *prev, global float4 *next, global double *partials,
                   float c1, float c2, uint ahead)
{
    REDUCTION_SCRATCH;
    item_rows span = rows_of_item(0, rows);
    double mx = 0.0, sum = 0.0, sq = 0.0;
    uint last = TABLE_LAST(ro, rows);
    for (uint i = span.begin; i < span.end; i++) {
        float4 si = residual_row_f(i, ro, col, w, b, d, last, ahead);
        next[i] = recurrence_row_f(d[i], prev[i], si, c1, c2);
        accumulate_norms(si.x, si.y, si.z, &mx, &sum, &sq);
    }
    STORE_PARTIALS(partials, 0, span, mx, sum, sq);
}

/* p += d (float widened to double, exactly). */
kernel void add_f(uint rows, global double4 *p, global const float4 *d)
{
    item_rows span = rows_of_item(0, rows);
    for (uint i = span.begin; i < span.end; i++) {
        double4 pi = p[i];
        float4 di = d[i];
        p[i] = (double4)(pi.x + (double)di.x, pi.y + (double)di.y, pi.z + (double)di.z, 0.0);
    }
}

/* w_f = w rounded to float (the float copy of a table's weights, made on the
   device: no host copy, no transfer). */
kernel void to_float(uint count, global const double *w, global float *w_f)
{
    item_rows span = rows_of_item(0, count);
    for (uint i = span.begin; i < span.end; i++)
        w_f[i] = (float)w[i];
}
