/* SPDX-License-Identifier: MIT */
/*
 * Kernels of the mixed-precision refinement (host/solve_mixed.c), built into
 * the same program after stencil.cl (row_product_ahead, GATHER_AHEAD). The residual of P is
 * taken in double; the correction d with A d = r is iterated in float (float
 * weights, float4 vectors: 8 bytes a nonzero and 48 a row instead of 12 and
 * 96), with its norms summed in double so they do not lose the digits float
 * vectors keep. Same conventions as stencil.cl (ROWS_PER_ITEM rows per item,
 * partials finished on the host in order, FP_CONTRACT OFF so that
 * host/device_ref_mixed.c gives the same bits).
 */
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#pragma OPENCL FP_CONTRACT OFF

inline float4 row_product_f(uint i, global const uint *ro, global const uint *col,
                            global const float *w, global const float4 *x, uint last,
                            uint ahead)
{
    float4 acc = (float4)(0.0f);
    for (uint k = ro[i]; k < ro[i + 1]; k++) {
        GATHER_AHEAD(ahead, x, col, k, last);
        acc += w[k] * x[col[k]];
    }
    return acc;
}

/* r = m - A p in double; r_f = r rounded to float; partial norms of r. */
kernel void residual_f(uint rows, global const uint *ro, global const uint *col,
                       global const double *w, global const double4 *m,
                       global const double4 *p, global float4 *r_f, global double *partials,
                       uint ahead)
{
    uint item = (uint)get_global_id(0);
    uint begin = item * ROWS_PER_ITEM;
    uint end = min(rows, begin + ROWS_PER_ITEM);
    double mx = 0.0, sum = 0.0, sq = 0.0;
    uint last = ro[rows] - 1;
    for (uint i = begin; i < end; i++) {
        double4 acc = row_product_ahead(i, ro, col, w, p, last, ahead);
        double4 mi = m[i];
        double r0 = mi.x - acc.x, r1 = mi.y - acc.y, r2 = mi.z - acc.z;
        r_f[i] = (float4)((float)r0, (float)r1, (float)r2, 0.0f);
        accumulate_norms(r0, r1, r2, &mx, &sum, &sq);
    }
    store_partials(partials, item, begin, rows, mx, sum, sq);
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
    uint item = (uint)get_global_id(0);
    uint begin = item * ROWS_PER_ITEM;
    uint end = min(rows, begin + ROWS_PER_ITEM);
    double mx = 0.0, sum = 0.0, sq = 0.0;
    uint last = ro[rows] - 1;
    for (uint i = begin; i < end; i++) {
        float4 acc = row_product_f(i, ro, col, w, d, last, ahead);
        float4 bi = b[i], di = d[i], qi = prev[i];
        float s0 = bi.x - acc.x, s1 = bi.y - acc.y, s2 = bi.z - acc.z;
        next[i] = (float4)(di.x + c1 * (di.x - qi.x) + c2 * s0,
                           di.y + c1 * (di.y - qi.y) + c2 * s1,
                           di.z + c1 * (di.z - qi.z) + c2 * s2, 0.0f);
        accumulate_norms(s0, s1, s2, &mx, &sum, &sq);
    }
    store_partials(partials, item, begin, rows, mx, sum, sq);
}

/* p += d (float widened to double, exactly). */
kernel void add_f(uint rows, global double4 *p, global const float4 *d)
{
    uint begin = (uint)get_global_id(0) * ROWS_PER_ITEM;
    uint end = min(rows, begin + ROWS_PER_ITEM);
    for (uint i = begin; i < end; i++) {
        double4 pi = p[i];
        float4 di = d[i];
        p[i] = (double4)(pi.x + (double)di.x, pi.y + (double)di.y, pi.z + (double)di.z, 0.0);
    }
}

/* w_f = w rounded to float (the float copy of a table's weights, made on the
   device: no host copy, no transfer). */
kernel void to_float(uint count, global const double *w, global float *w_f)
{
    uint begin = (uint)get_global_id(0) * ROWS_PER_ITEM;
    uint end = min(count, begin + ROWS_PER_ITEM);
    for (uint i = begin; i < end; i++)
        w_f[i] = (float)w[i];
}
