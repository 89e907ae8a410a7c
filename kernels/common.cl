/* SPDX-License-Identifier: MIT */
/*
 * The helpers every kernel file uses, first in the one program
 * (host/device/opencl/opencl_program.c joins common.cl, stencil.cl, series.cl,
 * solve.cl, mixed.cl and sgs.cl). The kernel shape comes from the build
 * options (host/device/opencl/opencl_shape.c): the cpu shape
 * -D ROWS_PER_ITEM=DEVICE_ROWS_PER_ITEM (host/device/device.h), the CSR table
 * and one partial reduction per work-item; the gpu shape -D ROWS_PER_ITEM=1
 * -D KERNEL_SHAPE_GPU=1 -D GROUP_SIZE=G -D SELL_C=C: one row per work-item,
 * the table in SELL-C slices (host/stencil/stencil_sell.h; the SGS table
 * stays CSR) and one partial per group, reduced in local memory.
 * FP_CONTRACT OFF as in every file (tests/check_kernels.sh).
 */
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#pragma OPENCL FP_CONTRACT OFF

#ifndef ROWS_PER_ITEM
#error ROWS_PER_ITEM is a build option (-D ROWS_PER_ITEM=DEVICE_ROWS_PER_ITEM, device.h)
#endif
#if defined(KERNEL_SHAPE_GPU) && (ROWS_PER_ITEM != 1 || !defined(GROUP_SIZE) || !defined(SELL_C))
#error the gpu shape is -D ROWS_PER_ITEM=1 -D KERNEL_SHAPE_GPU=1 -D GROUP_SIZE=G -D SELL_C=C
#endif

/* A work-item's rows: [begin, end), ROWS_PER_ITEM of them from
   first + item ROWS_PER_ITEM, cut at first + rows (sgs.cl's colours start at
   first; every other kernel at 0). begin < end: the item has rows. */
typedef struct item_rows {
    uint item, begin, end;
} item_rows;

inline item_rows rows_of_item(uint first, uint rows)
{
    item_rows span;
    span.item = (uint)get_global_id(0);
    span.begin = first + span.item * ROWS_PER_ITEM;
    span.end = min(first + rows, span.begin + ROWS_PER_ITEM);
    return span;
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

/* sum of w_k x_col(k) over the entries [from, to), in entry order (as
   ref_row_product); without look-ahead. */
inline double4 range_product(uint from, uint to, global const uint *col, global const double *w,
                             global const double4 *x)
{
    double4 acc = (double4)(0.0);
    for (uint k = from; k < to; k++)
        acc += w[k] * x[col[k]];
    return acc;
}

#ifdef KERNEL_SHAPE_GPU
/* The table in SELL-C slices: row i's k-th entry at ro[s] + k SELL_C + lane
   (s = i / SELL_C, lane = i % SELL_C), the slice's entries ending at
   ro[s + 1]; the padding past a row's own entries has weight 0. The same
   sum in the same order as CSR, plus those 0 x_j terms (exact). No
   prefetching (`last`, `ahead` unused). */
#define SELL_PRODUCT(name, real, vec)                                                          \
    inline vec name(uint i, global const uint *ro, global const uint *col,                     \
                    global const real *w, global const vec *x, uint last, uint ahead)          \
    {                                                                                          \
        vec acc = (vec)((real)0);                                                              \
        uint s = i / SELL_C, end = ro[s + 1];                                                  \
        for (uint k = ro[s] + i % SELL_C; k < end; k += SELL_C)                                \
            acc += w[k] * x[col[k]];                                                           \
        return acc;                                                                            \
    }
SELL_PRODUCT(row_product_ahead, double, double4)
SELL_PRODUCT(row_product_f, float, float4)

inline double4 row_product(uint i, global const uint *ro, global const uint *col,
                           global const double *w, global const double4 *x)
{
    return row_product_ahead(i, ro, col, w, x, 0, 0);
}

/* The prefetch bound: unused (and ro has one entry a slice, not a row). */
#define TABLE_LAST(ro, rows) 0u
#else
inline double4 row_product(uint i, global const uint *ro, global const uint *col,
                           global const double *w, global const double4 *x)
{
    return range_product(ro[i], ro[i + 1], col, w, x);
}

/* The table's last entry, the look-ahead's bound (GATHER_AHEAD). */
#define TABLE_LAST(ro, rows) (ro[rows] - 1)

/* Row i of A x with the gathers prefetched (GATHER_AHEAD), in double
   (row_product_ahead) and in float (row_product_f, mixed.cl): the same sum
   in the same order, so written once. */
#define ROW_PRODUCT_AHEAD(name, real, vec)                                                     \
    inline vec name(uint i, global const uint *ro, global const uint *col,                     \
                    global const real *w, global const vec *x, uint last, uint ahead)          \
    {                                                                                          \
        vec acc = (vec)((real)0);                                                              \
        for (uint k = ro[i]; k < ro[i + 1]; k++) {                                             \
            GATHER_AHEAD(ahead, x, col, k, last);                                              \
            acc += w[k] * x[col[k]];                                                           \
        }                                                                                      \
        return acc;                                                                            \
    }
ROW_PRODUCT_AHEAD(row_product_ahead, double, double4)
ROW_PRODUCT_AHEAD(row_product_f, float, float4)
#endif

/* Row i's residual b_i - (A x)_i (x, y, z; w = 0), component by component as
   the reference backend: in double (residual_row) and float (residual_row_f). */
#define RESIDUAL_ROW(name, product, real, vec)                                                 \
    inline vec name(uint i, global const uint *ro, global const uint *col,                     \
                    global const real *w, global const vec *b, global const vec *x,            \
                    uint last, uint ahead)                                                     \
    {                                                                                          \
        vec acc = product(i, ro, col, w, x, last, ahead);                                      \
        vec bi = b[i];                                                                         \
        return (vec)(bi.x - acc.x, bi.y - acc.y, bi.z - acc.z, (real)0);                       \
    }
RESIDUAL_ROW(residual_row, row_product_ahead, double, double4)
RESIDUAL_ROW(residual_row_f, row_product_f, float, float4)

/* x + c1 (x - q) + c2 r over x, y, z (w = 0): a row of the two-term
   recurrence (Chebyshev; c1 = 0: x + c2 r), in double (solve.cl's cheb_step)
   and in float (mixed.cl's step_f). */
#define RECURRENCE_ROW(name, real, vec)                                                        \
    inline vec name(vec x, vec q, vec r, real c1, real c2)                                     \
    {                                                                                          \
        return (vec)(x.x + c1 * (x.x - q.x) + c2 * r.x, x.y + c1 * (x.y - q.y) + c2 * r.y,     \
                     x.z + c1 * (x.z - q.z) + c2 * r.z, (real)0);                              \
    }
RECURRENCE_ROW(recurrence_row, double, double4)
RECURRENCE_ROW(recurrence_row_f, float, float4)

/* a . b over x, y, z, in that order. */
inline double dot3(double4 a, double4 b)
{
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

/* Partial max |v|, sum |v|, sum |v|^2 of one work-item, in double, in the
   reference backend's order (ref_norms_add). */
inline void accumulate_norms(double v0, double v1, double v2, double *mx, double *sum,
                             double *sq)
{
    double s = v0 * v0 + v1 * v1 + v2 * v2;
    double len = sqrt(s);
    *mx = len > *mx ? len : *mx;
    *sum += len;
    *sq += s;
}

/* One work-item's partials, at partials[3 slot]; an item without rows
   writes nothing. */
inline void store_partials(global double *partials, uint slot, item_rows span, double mx,
                           double sum, double sq)
{
    if (span.begin < span.end) {
        partials[3 * slot] = mx;
        partials[3 * slot + 1] = sum;
        partials[3 * slot + 2] = sq;
    }
}

/*
 * A reducing kernel declares REDUCTION_SCRATCH first and ends with
 * STORE_PARTIALS(partials, base, span, mx, sum, sq), reached by every
 * work-item. cpu shape: the item's partials at slot base + item. gpu shape:
 * the group's, at slot base + global id / GROUP_SIZE (a global offset is a
 * whole number of groups), combined in local memory by a fixed pairwise
 * tree (item l takes l + stride for stride = G/2, G/4, ..., 1; an item without
 * rows brings 0, 0, 0), so the order is the same on every run.
 */
#ifdef KERNEL_SHAPE_GPU
#define REDUCTION_SCRATCH local double reduction_scratch_[3 * GROUP_SIZE]
#define STORE_PARTIALS(partials, base, span, mx, sum, sq)                                      \
    group_partials(partials, (base) + (uint)(get_global_id(0) / GROUP_SIZE), span, mx, sum,   \
                   sq, reduction_scratch_)

inline void group_partials(global double *partials, uint slot, item_rows span, double mx,
                           double sum, double sq, local double *red)
{
    /* three arrays of GROUP_SIZE (max, sum, sum of squares): neighbouring
       items use neighbouring words, free of bank conflicts */
    local double *rmax = red, *rsum = red + GROUP_SIZE, *rsq = red + 2 * GROUP_SIZE;
    uint l = (uint)get_local_id(0);
    rmax[l] = mx;
    rsum[l] = sum;
    rsq[l] = sq;
    for (uint stride = GROUP_SIZE / 2; stride > 0; stride /= 2) {
        barrier(CLK_LOCAL_MEM_FENCE);
        if (l < stride) {
            double other = rmax[l + stride];
            rmax[l] = other > rmax[l] ? other : rmax[l];
            rsum[l] += rsum[l + stride];
            rsq[l] += rsq[l + stride];
        }
    }
    /* item 0's own span starts at the group's first row */
    if (l == 0 && span.begin < span.end) {
        partials[3 * slot] = rmax[0];
        partials[3 * slot + 1] = rsum[0];
        partials[3 * slot + 2] = rsq[0];
    }
}
#else
#define REDUCTION_SCRATCH (void)0
#define STORE_PARTIALS(partials, base, span, mx, sum, sq)                                      \
    store_partials(partials, (base) + span.item, span, mx, sum, sq)
#endif
