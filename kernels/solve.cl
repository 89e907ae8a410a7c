/* SPDX-License-Identifier: MIT */
/*
 * Kernels of the conjugate-gradient solver (host/solve_cg.c), built into the
 * same program after common.cl (row_product, residual_row, dot3). Same conventions: ROWS_PER_ITEM
 * consecutive rows per work-item, one partial reduction per item finished on
 * the host in item order, arithmetic identical to device_ref.c.
 * Vectors are 4 doubles per row (x, y, z used); dinv holds one double per row.
 */
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#pragma OPENCL FP_CONTRACT OFF

/* y = A x; partials[3 item + 1] = sum_i dinv_i (x_i . y_i) */
kernel void spmv_dot(uint rows, global const uint *ro, global const uint *col,
                     global const double *w, global const double4 *x, global double4 *y,
                     global const double *dinv, global double *partials)
{
    REDUCTION_SCRATCH;
    item_rows span = rows_of_item(0, rows);
    double sum = 0.0;
    for (uint i = span.begin; i < span.end; i++) {
        double4 acc = row_product(i, ro, col, w, x);
        y[i] = acc;
        sum += dinv[i] * dot3(x[i], acc);
    }
    STORE_PARTIALS(partials, 0, span, 0.0, sum, 0.0);
}

/* x += alpha p; z -= alpha q; partials: max |z_i|, sum dinv_i |z_i|^2, sum |z_i|^2 */
kernel void pcg_update(uint rows, double alpha, global const double4 *p,
                       global const double4 *q, global double4 *x, global double4 *z,
                       global const double *dinv, global double *partials)
{
    REDUCTION_SCRATCH;
    item_rows span = rows_of_item(0, rows);
    double mx = 0.0, rz = 0.0, sq = 0.0;
    for (uint i = span.begin; i < span.end; i++) {
        double4 pi = p[i], qi = q[i], xi = x[i], zi = z[i];
        xi = (double4)(xi.x + alpha * pi.x, xi.y + alpha * pi.y, xi.z + alpha * pi.z, 0.0);
        zi = (double4)(zi.x - alpha * qi.x, zi.y - alpha * qi.y, zi.z - alpha * qi.z, 0.0);
        x[i] = xi;
        z[i] = zi;
        double s = dot3(zi, zi);
        double len = sqrt(s);
        mx = len > mx ? len : mx;
        rz += dinv[i] * s;
        sq += s;
    }
    STORE_PARTIALS(partials, 0, span, mx, rz, sq);
}

/* One step of a two-term recurrence (Chebyshev iteration, host/interpolate.c):
   r = m - A p; prev_next = p + c1 (p - prev_next) + c2 r, row by row (each row
   reads its own prev value before writing it, so one buffer holds x_{k-1} in
   and x_{k+1} out); partials as interp_step. c1 = 0 gives p + c2 r.
   ahead: prefetch the gathers (common.cl, GATHER_AHEAD). */
kernel void cheb_step(uint rows, global const uint *ro, global const uint *col,
                      global const double *w, global const double4 *m,
                      global const double4 *p, global double4 *prev_next,
                      global double *partials, double c1, double c2, uint ahead)
{
    REDUCTION_SCRATCH;
    item_rows span = rows_of_item(0, rows);
    double mx = 0.0, sum = 0.0, sq = 0.0;
    uint last = TABLE_LAST(ro, rows);
    for (uint i = span.begin; i < span.end; i++) {
        double4 ri = residual_row(i, ro, col, w, m, p, last, ahead);
        prev_next[i] = recurrence_row(p[i], prev_next[i], ri, c1, c2);
        accumulate_norms(ri.x, ri.y, ri.z, &mx, &sum, &sq);
    }
    STORE_PARTIALS(partials, 0, span, mx, sum, sq);
}
