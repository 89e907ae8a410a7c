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

inline double4 row_product(uint i, global const uint *ro, global const uint *col,
                           global const double *w, global const double4 *x)
{
    double4 acc = (double4)(0.0);
    for (uint k = ro[i]; k < ro[i + 1]; k++)
        acc += w[k] * x[col[k]];
    return acc;
}

/*
 * Gathers prefetched ahead. On CPU devices (built with -D LIMN_PREFETCH=N by
 * a clang-based compiler, as PoCL's), for tables whose gathers scatter over
 * memory (device_csr.gather_ahead: a mesh refined in place, in its input
 * order), the solve loop prefetches x[col[k + N]]: a step of a 2.1M-vertex
 * refined mesh ran 13% (double) to 20% (float) faster. In a local order the
 * extra work cost 4-17%, hence the flag. `last` is the table's last entry
 * (ro[rows] - 1), so the look-ahead stays inside it. No result changes.
 * Not on SPIR targets (Oclgrind): there the compiler takes the builtin but
 * the device cannot run it (clCreateKernel fails); OpenCL's own prefetch()
 * runs on PoCL at half the speed (a call per gather), so it is not used.
 */
#if defined(LIMN_PREFETCH) && defined(__has_builtin) && !defined(__SPIR__) && !defined(__SPIRV__)
#if __has_builtin(__builtin_prefetch)
#define GATHER_AHEAD(ahead, x, col, k, last)                                                   \
    do {                                                                                       \
        if (ahead)                                                                             \
            __builtin_prefetch(&x[col[min((k) + LIMN_PREFETCH, last)]]);                       \
    } while (0)
#endif
#endif
#ifndef GATHER_AHEAD
#define GATHER_AHEAD(ahead, x, col, k, last) ((void)0)
#endif

inline double4 row_product_ahead(uint i, global const uint *ro, global const uint *col,
                                 global const double *w, global const double4 *x, uint last,
                                 uint ahead)
{
    double4 acc = (double4)(0.0);
    for (uint k = ro[i]; k < ro[i + 1]; k++) {
        GATHER_AHEAD(ahead, x, col, k, last);
        acc += w[k] * x[col[k]];
    }
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
   (omega = 1: the seeds' iteration; other values: the weighted iteration).
   ahead: prefetch the gathers (see GATHER_AHEAD). */
kernel void interp_step(uint rows, global const uint *ro, global const uint *col,
                        global const double *w, global const double4 *m,
                        global const double4 *p, global double4 *p_next,
                        global double *partials, double omega, uint ahead)
{
    uint item = (uint)get_global_id(0);
    uint begin = item * ROWS_PER_ITEM;
    uint end = min(rows, begin + ROWS_PER_ITEM);
    double mx = 0.0, sum = 0.0, sq = 0.0;
    uint last = ro[rows] - 1;
    for (uint i = begin; i < end; i++) {
        double4 acc = row_product_ahead(i, ro, col, w, p, last, ahead);
        double4 mi = m[i], pi = p[i];
        double r0 = mi.x - acc.x, r1 = mi.y - acc.y, r2 = mi.z - acc.z;
        p_next[i] = (double4)(pi.x + omega * r0, pi.y + omega * r1, pi.z + omega * r2, 0.0);
        accumulate_norms(r0, r1, r2, &mx, &sum, &sq);
    }
    store_partials(partials, item, begin, rows, mx, sum, sq);
}
