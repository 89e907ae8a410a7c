/* SPDX-License-Identifier: MIT */
/*
 * Kernels for the mesh series (seed 000 §3, §5-7): one term of
 * M = sum_i (E - A)^i A M per launch, fused with the partial sums that the
 * filters need, plus a vector update and norms. Built in one program after
 * common.cl (row_product comes from there). Same conventions: ROWS_PER_ITEM
 * consecutive rows per work-item, one partial reduction per item finished on
 * the host, FP_CONTRACT OFF so host/device_ref.c gives the same bits.
 */
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#pragma OPENCL FP_CONTRACT OFF

/* Must match host/device.h. */
#define SERIES_STORE_AX 1
#define SERIES_STORE_NEXT 2
#define SERIES_ACC_SET_AX 1
#define SERIES_ACC_ADD_AX 2
#define SERIES_ACC_ADD_X 3

/* ax = A x; x_next = x - ax; acc by mode; partial max, sum, sum of squares of |ax|.
   Buffers a launch does not use are bound to x and never touched. */
kernel void series_step(uint rows, global const uint *ro, global const uint *col,
                        global const double *w, global const double4 *x,
                        global double4 *x_next, global double4 *ax, global double4 *acc,
                        int flags, int acc_mode, global double *partials)
{
    REDUCTION_SCRATCH;
    item_rows span = rows_of_item(0, rows);
    double mx = 0.0, sum = 0.0, sq = 0.0;
    for (uint i = span.begin; i < span.end; i++) {
        double4 v = row_product(i, ro, col, w, x);
        double4 xi = x[i];
        if (flags & SERIES_STORE_AX)
            ax[i] = v;
        if (flags & SERIES_STORE_NEXT)
            x_next[i] = xi - v;
        if (acc_mode == SERIES_ACC_SET_AX)
            acc[i] = v;
        else if (acc_mode == SERIES_ACC_ADD_AX)
            acc[i] = acc[i] + v;
        else if (acc_mode == SERIES_ACC_ADD_X)
            acc[i] = acc[i] + xi;
        accumulate_norms(v.x, v.y, v.z, &mx, &sum, &sq);
    }
    STORE_PARTIALS(partials, 0, span, mx, sum, sq);
}

/* out = a x + b y */
kernel void axpby(uint rows, double a, global const double4 *x, double b,
                  global const double4 *y, global double4 *out)
{
    item_rows span = rows_of_item(0, rows);
    for (uint i = span.begin; i < span.end; i++)
        out[i] = a * x[i] + b * y[i];
}

/* Partial max, sum and sum of squares of |x_i| (x, y, z). */
kernel void norms(uint rows, global const double4 *x, global double *partials)
{
    REDUCTION_SCRATCH;
    item_rows span = rows_of_item(0, rows);
    double mx = 0.0, sum = 0.0, sq = 0.0;
    for (uint i = span.begin; i < span.end; i++) {
        double4 v = x[i];
        accumulate_norms(v.x, v.y, v.z, &mx, &sum, &sq);
    }
    STORE_PARTIALS(partials, 0, span, mx, sum, sq);
}
