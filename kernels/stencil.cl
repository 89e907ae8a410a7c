/* SPDX-License-Identifier: MIT */
/*
 * Stencil products for limn. Each work-item handles ROWS_PER_ITEM
 * consecutive rows (set with -D at build time) and writes one partial
 * reduction, finished on the host in item order: no barriers (slow on
 * PoCL's CPU device) and results independent of the thread count.
 * FP_CONTRACT OFF keeps the arithmetic identical to the C reference backend;
 * each kernel file states it itself, so that none depends on being joined
 * after this one (tests/check_kernels.sh checks every file for it).
 */
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#pragma OPENCL FP_CONTRACT OFF

/* test-only (LIMN_TEST_EXTRA_BUILD_OPTIONS, tests/test_opencl.c): a build
   error after a build log longer than any fixed buffer */
#ifdef LIMN_FORCE_BUILD_ERROR
#warning limn forced build log line 01: longer than a fixed buffer (LIMN_FORCE_BUILD_ERROR)
#warning limn forced build log line 02: longer than a fixed buffer (LIMN_FORCE_BUILD_ERROR)
#warning limn forced build log line 03: longer than a fixed buffer (LIMN_FORCE_BUILD_ERROR)
#warning limn forced build log line 04: longer than a fixed buffer (LIMN_FORCE_BUILD_ERROR)
#warning limn forced build log line 05: longer than a fixed buffer (LIMN_FORCE_BUILD_ERROR)
#warning limn forced build log line 06: longer than a fixed buffer (LIMN_FORCE_BUILD_ERROR)
#warning limn forced build log line 07: longer than a fixed buffer (LIMN_FORCE_BUILD_ERROR)
#warning limn forced build log line 08: longer than a fixed buffer (LIMN_FORCE_BUILD_ERROR)
#warning limn forced build log line 09: longer than a fixed buffer (LIMN_FORCE_BUILD_ERROR)
#warning limn forced build log line 10: longer than a fixed buffer (LIMN_FORCE_BUILD_ERROR)
#warning limn forced build log line 11: longer than a fixed buffer (LIMN_FORCE_BUILD_ERROR)
#warning limn forced build log line 12: longer than a fixed buffer (LIMN_FORCE_BUILD_ERROR)
#error limn forced build error 01: longer than a fixed buffer (LIMN_FORCE_BUILD_ERROR)
#error limn forced build error 02: longer than a fixed buffer (LIMN_FORCE_BUILD_ERROR)
#error limn forced build error 03: longer than a fixed buffer (LIMN_FORCE_BUILD_ERROR)
#error limn forced build error 04: longer than a fixed buffer (LIMN_FORCE_BUILD_ERROR)
#error limn forced build error 05: longer than a fixed buffer (LIMN_FORCE_BUILD_ERROR)
#error limn forced build error 06: longer than a fixed buffer (LIMN_FORCE_BUILD_ERROR)
#error limn forced build error 07: longer than a fixed buffer (LIMN_FORCE_BUILD_ERROR)
#error limn forced build error 08: longer than a fixed buffer (LIMN_FORCE_BUILD_ERROR)
#error limn forced build error 09: longer than a fixed buffer (LIMN_FORCE_BUILD_ERROR)
#error limn forced build error 10: longer than a fixed buffer (LIMN_FORCE_BUILD_ERROR)
#error limn forced build error 11: longer than a fixed buffer (LIMN_FORCE_BUILD_ERROR)
#error limn forced build error 12: longer than a fixed buffer (LIMN_FORCE_BUILD_ERROR)
#error limn forced build error: the end of the log (LIMN_FORCE_BUILD_ERROR)
#endif

/* y = A x */
kernel void spmv(uint rows, global const uint *ro, global const uint *col,
                 global const double *w, global const double4 *x, global double4 *y)
{
    item_rows span = rows_of_item(0, rows);
    for (uint i = span.begin; i < span.end; i++)
        y[i] = row_product(i, ro, col, w, x);
}

/* r = m - A p; p_next = p + omega r; partial max |r|, sum |r|, sum |r|^2 per item
   (omega = 1: the seeds' iteration; other values: the weighted iteration).
   ahead: prefetch the gathers (common.cl, GATHER_AHEAD). */
kernel void interp_step(uint rows, global const uint *ro, global const uint *col,
                        global const double *w, global const double4 *m,
                        global const double4 *p, global double4 *p_next,
                        global double *partials, double omega, uint ahead)
{
    REDUCTION_SCRATCH;
    item_rows span = rows_of_item(0, rows);
    double mx = 0.0, sum = 0.0, sq = 0.0;
    uint last = TABLE_LAST(ro, rows);
    for (uint i = span.begin; i < span.end; i++) {
        double4 ri = residual_row(i, ro, col, w, m, p, last, ahead), pi = p[i];
        p_next[i] = (double4)(pi.x + omega * ri.x, pi.y + omega * ri.y, pi.z + omega * ri.z, 0.0);
        accumulate_norms(ri.x, ri.y, ri.z, &mx, &sum, &sq);
    }
    STORE_PARTIALS(partials, 0, span, mx, sum, sq);
}
