/* SPDX-License-Identifier: MIT */
/*
 * Variants of the solve loop's step, for perf/kernel_variants.c: the design
 * measurements behind README "Performance" (which layouts and work shapes
 * were tried, and which were kept). Each variant computes what
 * kernels/stencil.cl's interp_step (d_*, double) or kernels/mixed.cl's
 * step_f with c1 = 0 (f_*, float) compute, in the same order per row, so
 * their checks agree; d_local / f_local are wrong on purpose (every gather
 * made local: the bound that locality would give).
 *   *_base   the kernels as built into limn (no prefetch)
 *   *_pref   gathers prefetched PD entries ahead (kept, for scattered tables)
 *   d_ro     the row offset carried from row to row
 *   *_two    two rows interleaved per work-item (more independent gathers)
 *   f_cw     (column, weight) pairs interleaved in one stream
 *   *_d16    16-bit column deltas from the row (RCM order only)
 *   *_v3     xyz packed, 3 doubles / 3 floats a vertex (vload3)
 */
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#pragma OPENCL FP_CONTRACT OFF
/* Every variant is written from these pieces, so that they differ only where
   the variant says (T: double for d_*, float for f_*). */
#define NORMS(a,b,c) { double s_ = (double)(a)*(double)(a) + (double)(b)*(double)(b) + (double)(c)*(double)(c); double l_ = sqrt(s_); mx = l_ > mx ? l_ : mx; sum += l_; sq += s_; }
#define HEAD uint item = (uint)get_global_id(0); uint begin = item * ROWS_PER_ITEM; uint end = min(rows, begin + ROWS_PER_ITEM); double mx = 0.0, sum = 0.0, sq = 0.0;
#define TAIL if (begin < rows) { partials[3 * item] = mx; partials[3 * item + 1] = sum; partials[3 * item + 2] = sq; }
/* the arguments of the xyzw layouts; COL: the column stream's type */
#define ARGS(T, COL) uint rows, global const uint *ro, global const COL *col, global const T *w, \
   global const T##4 *m, global const T##4 *p, global T##4 *p_next, global double *partials, T omega
/* row I's residual from its gathered sum ACC, its next iterate and its norms */
#define STEP(T, I, ACC) { \
        T##4 mi = m[I], pi = p[I]; \
        T r0 = mi.x - ACC.x, r1 = mi.y - ACC.y, r2 = mi.z - ACC.z; \
        p_next[I] = (T##4)(pi.x + omega * r0, pi.y + omega * r1, pi.z + omega * r2, (T)0); \
        NORMS(r0, r1, r2) }
/* the rows up to end, one at a time, from INIT (a declaration of i, or
   none: go on from the i there is); GATHER: the neighbour that weight k
   scales, AHEAD: what runs before it (the prefetch) */
#define ROWS_LOOP(T, INIT, AHEAD, GATHER) \
    for (INIT; i < end; i++) { \
        T##4 acc = (T##4)((T)0); \
        for (uint k = ro[i]; k < ro[i + 1]; k++) { AHEAD acc += w[k] * GATHER; } \
        STEP(T, i, acc) \
    }
#define ROWS_KERNEL(NAME, T, COL, SETUP, AHEAD, GATHER) \
kernel void NAME(ARGS(T, COL)) { HEAD SETUP ROWS_LOOP(T, uint i = begin, AHEAD, GATHER) TAIL }
/* the gather PD entries ahead */
#define LAST uint last = ro[end];
#define PREFETCH uint kp = min(k + PD, last - 1); __builtin_prefetch(&p[col[kp]]);

ROWS_KERNEL(d_base, double, uint, , , p[col[k]])
ROWS_KERNEL(f_base, float, uint, , , p[col[k]])
ROWS_KERNEL(d_pref, double, uint, LAST, PREFETCH, p[col[k]])
ROWS_KERNEL(f_pref, float, uint, LAST, PREFETCH, p[col[k]])
/* bound: gathers replaced by the row's own vector (wrong math, locality probe) */
ROWS_KERNEL(d_local, double, uint, , , p[(col[k] & 7) + (i & ~7u)])
ROWS_KERNEL(f_local, float, uint, , , p[(col[k] & 7) + (i & ~7u)])
/* 16-bit column deltas from the row */
ROWS_KERNEL(d_d16, double, short, , , p[(int)i + col[k]])
ROWS_KERNEL(f_d16, float, short, , , p[(int)i + col[k]])

/* row offsets carried: read ro once per row */
kernel void d_ro(ARGS(double, uint))
{
    HEAD
    uint k = begin < end ? ro[begin] : 0;
    for (uint i = begin; i < end; i++) {
        double4 acc = (double4)(0.0);
        uint kend = ro[i + 1];
        for (; k < kend; k++) acc += w[k] * p[col[k]];
        STEP(double, i, acc)
    }
    TAIL
}

/* two rows interleaved: each row's sum in its own order */
#define TWO_KERNEL(NAME, T) \
kernel void NAME(ARGS(T, uint)) \
{ \
    HEAD \
    uint i = begin; \
    for (; i + 1 < end; i += 2) { \
        T##4 a0 = (T##4)((T)0), a1 = (T##4)((T)0); \
        uint k0 = ro[i], e0 = ro[i + 1], k1 = e0, e1 = ro[i + 2]; \
        while (k0 < e0 && k1 < e1) { a0 += w[k0] * p[col[k0]]; a1 += w[k1] * p[col[k1]]; k0++; k1++; } \
        for (; k0 < e0; k0++) a0 += w[k0] * p[col[k0]]; \
        for (; k1 < e1; k1++) a1 += w[k1] * p[col[k1]]; \
        STEP(T, i, a0) \
        STEP(T, i + 1, a1) \
    } \
    ROWS_LOOP(T, , , p[col[k]]) \
    TAIL \
}
TWO_KERNEL(d_two, double)
TWO_KERNEL(f_two, float)

/* interleaved (col, weight) pairs */
kernel void f_cw(uint rows, global const uint *ro, global const uint2 *cw,
   global const float4 *m, global const float4 *p, global float4 *p_next, global double *partials, float omega)
{
    HEAD
    for (uint i = begin; i < end; i++) {
        float4 acc = (float4)(0.0f);
        for (uint k = ro[i]; k < ro[i + 1]; k++) { uint2 e = cw[k]; acc += as_float(e.y) * p[e.x]; }
        STEP(float, i, acc)
    }
    TAIL
}

/* xyz packed, 3 values a vertex */
#define V3_KERNEL(NAME, T) \
kernel void NAME(uint rows, global const uint *ro, global const uint *col, global const T *w, \
   global const T *m, global const T *p, global T *p_next, global double *partials, T omega) \
{ \
    HEAD \
    for (uint i = begin; i < end; i++) { \
        T##3 acc = (T##3)((T)0); \
        for (uint k = ro[i]; k < ro[i + 1]; k++) acc += w[k] * vload3(col[k], p); \
        T##3 mi = vload3(i, m), pi = vload3(i, p); \
        T r0 = mi.x - acc.x, r1 = mi.y - acc.y, r2 = mi.z - acc.z; \
        vstore3((T##3)(pi.x + omega * r0, pi.y + omega * r1, pi.z + omega * r2), i, p_next); \
        NORMS(r0, r1, r2) \
    } \
    TAIL \
}
V3_KERNEL(d_v3, double)
V3_KERNEL(f_v3, float)
