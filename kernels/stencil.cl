/*
 * Stencil products for limn. Each work-item handles ROWS_PER_ITEM
 * consecutive rows (set with -D at build time) and writes one partial
 * reduction, finished on the host in item order: no barriers (slow on
 * PoCL's CPU device) and results independent of the thread count.
 * FP_CONTRACT OFF keeps the arithmetic identical to the C reference backend.
 */
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#pragma OPENCL FP_CONTRACT OFF

#ifndef ROWS_PER_ITEM
#define ROWS_PER_ITEM 256
#endif

inline double4 row_product(uint i, global const uint *ro, global const uint *col,
                           global const double *w, global const double4 *x)
{
    double4 acc = (double4)(0.0);
    for (uint k = ro[i]; k < ro[i + 1]; k++)
        acc += w[k] * x[col[k]];
    return acc;
}

/* y = A x */
kernel void spmv(uint rows, global const uint *ro, global const uint *col,
                 global const double *w, global const double4 *x, global double4 *y)
{
    uint begin = (uint)get_global_id(0) * ROWS_PER_ITEM;
    uint end = min(rows, begin + ROWS_PER_ITEM);
    for (uint i = begin; i < end; i++)
        y[i] = row_product(i, ro, col, w, x);
}

/* r = m - A p; p_next = p + omega r; partial max |r|, sum |r|, sum |r|^2 per item
   (omega = 1: the seeds' iteration; other values: the weighted iteration). */
kernel void interp_step(uint rows, global const uint *ro, global const uint *col,
                        global const double *w, global const double4 *m,
                        global const double4 *p, global double4 *p_next,
                        global double *partials, double omega)
{
    uint item = (uint)get_global_id(0);
    uint begin = item * ROWS_PER_ITEM;
    uint end = min(rows, begin + ROWS_PER_ITEM);
    double mx = 0.0, sum = 0.0, sq = 0.0;
    for (uint i = begin; i < end; i++) {
        double4 acc = row_product(i, ro, col, w, p);
        double4 mi = m[i], pi = p[i];
        double r0 = mi.x - acc.x, r1 = mi.y - acc.y, r2 = mi.z - acc.z;
        p_next[i] = (double4)(pi.x + omega * r0, pi.y + omega * r1, pi.z + omega * r2, 0.0);
        double r2sum = r0 * r0 + r1 * r1 + r2 * r2;
        double len = sqrt(r2sum);
        mx = len > mx ? len : mx;
        sum += len;
        sq += r2sum;
    }
    if (begin < rows) {
        partials[3 * item] = mx;
        partials[3 * item + 1] = sum;
        partials[3 * item + 2] = sq;
    }
}
