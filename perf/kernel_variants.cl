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
#define NORMS(a,b,c) { double s_ = (double)(a)*(double)(a) + (double)(b)*(double)(b) + (double)(c)*(double)(c); double l_ = sqrt(s_); mx = l_ > mx ? l_ : mx; sum += l_; sq += s_; }
#define HEAD uint item = (uint)get_global_id(0); uint begin = item * ROWS_PER_ITEM; uint end = min(rows, begin + ROWS_PER_ITEM); double mx = 0.0, sum = 0.0, sq = 0.0;
#define TAIL if (begin < rows) { partials[3 * item] = mx; partials[3 * item + 1] = sum; partials[3 * item + 2] = sq; }

kernel void d_base(uint rows, global const uint *ro, global const uint *col, global const double *w,
   global const double4 *m, global const double4 *p, global double4 *p_next, global double *partials, double omega)
{
    HEAD
    for (uint i = begin; i < end; i++) {
        double4 acc = (double4)(0.0);
        for (uint k = ro[i]; k < ro[i + 1]; k++) acc += w[k] * p[col[k]];
        double4 mi = m[i], pi = p[i];
        double r0 = mi.x - acc.x, r1 = mi.y - acc.y, r2 = mi.z - acc.z;
        p_next[i] = (double4)(pi.x + omega * r0, pi.y + omega * r1, pi.z + omega * r2, 0.0);
        NORMS(r0, r1, r2)
    }
    TAIL
}

/* row offsets carried: read ro once per row */
kernel void d_ro(uint rows, global const uint *ro, global const uint *col, global const double *w,
   global const double4 *m, global const double4 *p, global double4 *p_next, global double *partials, double omega)
{
    HEAD
    uint k = begin < end ? ro[begin] : 0;
    for (uint i = begin; i < end; i++) {
        double4 acc = (double4)(0.0);
        uint kend = ro[i + 1];
        for (; k < kend; k++) acc += w[k] * p[col[k]];
        double4 mi = m[i], pi = p[i];
        double r0 = mi.x - acc.x, r1 = mi.y - acc.y, r2 = mi.z - acc.z;
        p_next[i] = (double4)(pi.x + omega * r0, pi.y + omega * r1, pi.z + omega * r2, 0.0);
        NORMS(r0, r1, r2)
    }
    TAIL
}

/* two rows interleaved: each row's sum in its own order */
kernel void d_two(uint rows, global const uint *ro, global const uint *col, global const double *w,
   global const double4 *m, global const double4 *p, global double4 *p_next, global double *partials, double omega)
{
    HEAD
    uint i = begin;
    for (; i + 1 < end; i += 2) {
        double4 a0 = (double4)(0.0), a1 = (double4)(0.0);
        uint k0 = ro[i], e0 = ro[i + 1], k1 = e0, e1 = ro[i + 2];
        while (k0 < e0 && k1 < e1) { a0 += w[k0] * p[col[k0]]; a1 += w[k1] * p[col[k1]]; k0++; k1++; }
        for (; k0 < e0; k0++) a0 += w[k0] * p[col[k0]];
        for (; k1 < e1; k1++) a1 += w[k1] * p[col[k1]];
        double4 mi = m[i], pi = p[i];
        double r0 = mi.x - a0.x, r1 = mi.y - a0.y, r2 = mi.z - a0.z;
        p_next[i] = (double4)(pi.x + omega * r0, pi.y + omega * r1, pi.z + omega * r2, 0.0);
        NORMS(r0, r1, r2)
        mi = m[i + 1]; pi = p[i + 1];
        r0 = mi.x - a1.x; r1 = mi.y - a1.y; r2 = mi.z - a1.z;
        p_next[i + 1] = (double4)(pi.x + omega * r0, pi.y + omega * r1, pi.z + omega * r2, 0.0);
        NORMS(r0, r1, r2)
    }
    for (; i < end; i++) {
        double4 acc = (double4)(0.0);
        for (uint k = ro[i]; k < ro[i + 1]; k++) acc += w[k] * p[col[k]];
        double4 mi = m[i], pi = p[i];
        double r0 = mi.x - acc.x, r1 = mi.y - acc.y, r2 = mi.z - acc.z;
        p_next[i] = (double4)(pi.x + omega * r0, pi.y + omega * r1, pi.z + omega * r2, 0.0);
        NORMS(r0, r1, r2)
    }
    TAIL
}

kernel void f_base(uint rows, global const uint *ro, global const uint *col, global const float *w,
   global const float4 *b, global const float4 *d, global float4 *d_next, global double *partials, float omega)
{
    HEAD
    for (uint i = begin; i < end; i++) {
        float4 acc = (float4)(0.0f);
        for (uint k = ro[i]; k < ro[i + 1]; k++) acc += w[k] * d[col[k]];
        float4 bi = b[i], di = d[i];
        float s0 = bi.x - acc.x, s1 = bi.y - acc.y, s2 = bi.z - acc.z;
        d_next[i] = (float4)(di.x + omega * s0, di.y + omega * s1, di.z + omega * s2, 0.0f);
        NORMS(s0, s1, s2)
    }
    TAIL
}

kernel void f_two(uint rows, global const uint *ro, global const uint *col, global const float *w,
   global const float4 *b, global const float4 *d, global float4 *d_next, global double *partials, float omega)
{
    HEAD
    uint i = begin;
    for (; i + 1 < end; i += 2) {
        float4 a0 = (float4)(0.0f), a1 = (float4)(0.0f);
        uint k0 = ro[i], e0 = ro[i + 1], k1 = e0, e1 = ro[i + 2];
        while (k0 < e0 && k1 < e1) { a0 += w[k0] * d[col[k0]]; a1 += w[k1] * d[col[k1]]; k0++; k1++; }
        for (; k0 < e0; k0++) a0 += w[k0] * d[col[k0]];
        for (; k1 < e1; k1++) a1 += w[k1] * d[col[k1]];
        float4 bi = b[i], di = d[i];
        float s0 = bi.x - a0.x, s1 = bi.y - a0.y, s2 = bi.z - a0.z;
        d_next[i] = (float4)(di.x + omega * s0, di.y + omega * s1, di.z + omega * s2, 0.0f);
        NORMS(s0, s1, s2)
        bi = b[i + 1]; di = d[i + 1];
        s0 = bi.x - a1.x; s1 = bi.y - a1.y; s2 = bi.z - a1.z;
        d_next[i + 1] = (float4)(di.x + omega * s0, di.y + omega * s1, di.z + omega * s2, 0.0f);
        NORMS(s0, s1, s2)
    }
    for (; i < end; i++) {
        float4 acc = (float4)(0.0f);
        for (uint k = ro[i]; k < ro[i + 1]; k++) acc += w[k] * d[col[k]];
        float4 bi = b[i], di = d[i];
        float s0 = bi.x - acc.x, s1 = bi.y - acc.y, s2 = bi.z - acc.z;
        d_next[i] = (float4)(di.x + omega * s0, di.y + omega * s1, di.z + omega * s2, 0.0f);
        NORMS(s0, s1, s2)
    }
    TAIL
}

/* interleaved (col, weight) pairs */
kernel void f_cw(uint rows, global const uint *ro, global const uint2 *cw,
   global const float4 *b, global const float4 *d, global float4 *d_next, global double *partials, float omega)
{
    HEAD
    for (uint i = begin; i < end; i++) {
        float4 acc = (float4)(0.0f);
        for (uint k = ro[i]; k < ro[i + 1]; k++) { uint2 e = cw[k]; acc += as_float(e.y) * d[e.x]; }
        float4 bi = b[i], di = d[i];
        float s0 = bi.x - acc.x, s1 = bi.y - acc.y, s2 = bi.z - acc.z;
        d_next[i] = (float4)(di.x + omega * s0, di.y + omega * s1, di.z + omega * s2, 0.0f);
        NORMS(s0, s1, s2)
    }
    TAIL
}
/* bound: gathers replaced by the row's own vector (wrong math, locality probe) */
kernel void d_local(uint rows, global const uint *ro, global const uint *col, global const double *w,
   global const double4 *m, global const double4 *p, global double4 *p_next, global double *partials, double omega)
{
    HEAD
    for (uint i = begin; i < end; i++) {
        double4 acc = (double4)(0.0);
        for (uint k = ro[i]; k < ro[i + 1]; k++) acc += w[k] * p[(col[k] & 7) + (i & ~7u)];
        double4 mi = m[i], pi = p[i];
        double r0 = mi.x - acc.x, r1 = mi.y - acc.y, r2 = mi.z - acc.z;
        p_next[i] = (double4)(pi.x + omega * r0, pi.y + omega * r1, pi.z + omega * r2, 0.0);
        NORMS(r0, r1, r2)
    }
    TAIL
}
kernel void f_local(uint rows, global const uint *ro, global const uint *col, global const float *w,
   global const float4 *b, global const float4 *d, global float4 *d_next, global double *partials, float omega)
{
    HEAD
    for (uint i = begin; i < end; i++) {
        float4 acc = (float4)(0.0f);
        for (uint k = ro[i]; k < ro[i + 1]; k++) acc += w[k] * d[(col[k] & 7) + (i & ~7u)];
        float4 bi = b[i], di = d[i];
        float s0 = bi.x - acc.x, s1 = bi.y - acc.y, s2 = bi.z - acc.z;
        d_next[i] = (float4)(di.x + omega * s0, di.y + omega * s1, di.z + omega * s2, 0.0f);
        NORMS(s0, s1, s2)
    }
    TAIL
}
kernel void d_pref(uint rows, global const uint *ro, global const uint *col, global const double *w,
   global const double4 *m, global const double4 *p, global double4 *p_next, global double *partials, double omega)
{
    HEAD
    uint last = ro[end] ;
    for (uint i = begin; i < end; i++) {
        double4 acc = (double4)(0.0);
        for (uint k = ro[i]; k < ro[i + 1]; k++) {
            uint kp = min(k + PD, last - 1);
            __builtin_prefetch(&p[col[kp]]);
            acc += w[k] * p[col[k]];
        }
        double4 mi = m[i], pi = p[i];
        double r0 = mi.x - acc.x, r1 = mi.y - acc.y, r2 = mi.z - acc.z;
        p_next[i] = (double4)(pi.x + omega * r0, pi.y + omega * r1, pi.z + omega * r2, 0.0);
        NORMS(r0, r1, r2)
    }
    TAIL
}
kernel void f_pref(uint rows, global const uint *ro, global const uint *col, global const float *w,
   global const float4 *b, global const float4 *d, global float4 *d_next, global double *partials, float omega)
{
    HEAD
    uint last = ro[end];
    for (uint i = begin; i < end; i++) {
        float4 acc = (float4)(0.0f);
        for (uint k = ro[i]; k < ro[i + 1]; k++) {
            uint kp = min(k + PD, last - 1);
            __builtin_prefetch(&d[col[kp]]);
            acc += w[k] * d[col[k]];
        }
        float4 bi = b[i], di = d[i];
        float s0 = bi.x - acc.x, s1 = bi.y - acc.y, s2 = bi.z - acc.z;
        d_next[i] = (float4)(di.x + omega * s0, di.y + omega * s1, di.z + omega * s2, 0.0f);
        NORMS(s0, s1, s2)
    }
    TAIL
}
kernel void d_d16(uint rows, global const uint *ro, global const short *dc, global const double *w,
   global const double4 *m, global const double4 *p, global double4 *p_next, global double *partials, double omega)
{
    HEAD
    for (uint i = begin; i < end; i++) {
        double4 acc = (double4)(0.0);
        for (uint k = ro[i]; k < ro[i + 1]; k++) acc += w[k] * p[(int)i + dc[k]];
        double4 mi = m[i], pi = p[i];
        double r0 = mi.x - acc.x, r1 = mi.y - acc.y, r2 = mi.z - acc.z;
        p_next[i] = (double4)(pi.x + omega * r0, pi.y + omega * r1, pi.z + omega * r2, 0.0);
        NORMS(r0, r1, r2)
    }
    TAIL
}
kernel void f_d16(uint rows, global const uint *ro, global const short *dc, global const float *w,
   global const float4 *b, global const float4 *d, global float4 *d_next, global double *partials, float omega)
{
    HEAD
    for (uint i = begin; i < end; i++) {
        float4 acc = (float4)(0.0f);
        for (uint k = ro[i]; k < ro[i + 1]; k++) acc += w[k] * d[(int)i + dc[k]];
        float4 bi = b[i], di = d[i];
        float s0 = bi.x - acc.x, s1 = bi.y - acc.y, s2 = bi.z - acc.z;
        d_next[i] = (float4)(di.x + omega * s0, di.y + omega * s1, di.z + omega * s2, 0.0f);
        NORMS(s0, s1, s2)
    }
    TAIL
}
kernel void d_v3(uint rows, global const uint *ro, global const uint *col, global const double *w,
   global const double *m, global const double *p, global double *p_next, global double *partials, double omega)
{
    HEAD
    for (uint i = begin; i < end; i++) {
        double3 acc = (double3)(0.0);
        for (uint k = ro[i]; k < ro[i + 1]; k++) acc += w[k] * vload3(col[k], p);
        double3 mi = vload3(i, m), pi = vload3(i, p);
        double r0 = mi.x - acc.x, r1 = mi.y - acc.y, r2 = mi.z - acc.z;
        vstore3((double3)(pi.x + omega * r0, pi.y + omega * r1, pi.z + omega * r2), i, p_next);
        NORMS(r0, r1, r2)
    }
    TAIL
}
kernel void f_v3(uint rows, global const uint *ro, global const uint *col, global const float *w,
   global const float *b, global const float *d, global float *d_next, global double *partials, float omega)
{
    HEAD
    for (uint i = begin; i < end; i++) {
        float3 acc = (float3)(0.0f);
        for (uint k = ro[i]; k < ro[i + 1]; k++) acc += w[k] * vload3(col[k], d);
        float3 bi = vload3(i, b), di = vload3(i, d);
        float s0 = bi.x - acc.x, s1 = bi.y - acc.y, s2 = bi.z - acc.z;
        vstore3((float3)(di.x + omega * s0, di.y + omega * s1, di.z + omega * s2), i, d_next);
        NORMS(s0, s1, s2)
    }
    TAIL
}
