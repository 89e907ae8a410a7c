/* SPDX-License-Identifier: MIT */
/*
 * Kernels of conjugate gradients preconditioned by multicolour symmetric
 * Gauss-Seidel (host/solve_sgs.c; the table: host/sgs_table.c, device.h
 * device_sgs). Rows come in colour order and no entry joins two rows of one
 * colour, so each colour's rows are independent: a sweep is one launch per
 * colour, in order, rows [begin, begin + rows). Row i's off-diagonal entries
 * are [ro[i], ro[i + 1]), lower colours before split[i], higher ones after;
 * info[i] = (d_i, sqrt d_i, scale_i, 0). Vectors are 4 doubles a row.
 * Same conventions as solve.cl: ROWS_PER_ITEM rows per work-item, one
 * partial per item finished on the host in item order (colour by colour),
 * arithmetic identical to device_ref_sgs.c.
 */
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#pragma OPENCL FP_CONTRACT OFF

/* One colour of the backward sweep: phat = rhat + beta phat;
   t = (sqrt(d) phat - sum over higher colours S_ij t_j) / d */
kernel void sgs_upper(uint rows, uint first, global const uint *ro, global const uint *col,
                      global const double *w, global const uint *split,
                      global const double4 *info, global const double4 *rhat,
                      global double4 *phat, global double4 *t, double beta)
{
    item_rows span = rows_of_item(first, rows);
    for (uint i = span.begin; i < span.end; i++) {
        double4 in = info[i];
        double4 p = rhat[i] + beta * phat[i];
        p.w = 0.0;
        phat[i] = p;
        double4 acc = range_product(split[i], ro[i + 1], col, w, t);
        double4 ti = (in.y * p - acc) / in.x;
        ti.w = 0.0;
        t[i] = ti;
    }
}

/* One colour of the forward sweep (see device.h sgs_lower). start: r = b -
   S x first (the whole row: lower entries gather x and u, higher ones x).
   Partials at partials[3 (base + item)]: max scale |r| (start), the sum. */
kernel void sgs_lower(uint rows, uint first, global const uint *ro, global const uint *col,
                      global const double *w, global const uint *split,
                      global const double4 *info, global const double4 *b,
                      global const double4 *x, global double4 *r, global const double4 *phat,
                      global double4 *t, global double4 *u, global double4 *st,
                      global double4 *rhat, global double *partials, uint base, int start)
{
    REDUCTION_SCRATCH;
    item_rows span = rows_of_item(first, rows);
    double mx = 0.0, sum = 0.0;
    for (uint i = span.begin; i < span.end; i++) {
        double4 in = info[i];
        uint lo = ro[i], mid = split[i], hi = ro[i + 1];
        if (start) {
            double4 lx = (double4)(0.0), lu = (double4)(0.0);
            for (uint k = lo; k < mid; k++) {
                uint j = col[k];
                lx += w[k] * x[j];
                lu += w[k] * u[j];
            }
            double4 ri = b[i] - ((in.x * x[i] + lx) + range_product(mid, hi, col, w, x));
            ri.w = 0.0;
            r[i] = ri;
            double len = in.z * sqrt(dot3(ri, ri));
            mx = len > mx ? len : mx;
            double4 ui = (ri - lu) / in.x;
            u[i] = ui;
            double4 rh = in.y * ui;
            rhat[i] = rh;
            sum += dot3(rh, rh);
        } else {
            double4 lt = (double4)(0.0), lu = (double4)(0.0);
            for (uint k = lo; k < mid; k++) {
                uint j = col[k];
                lt += w[k] * t[j];
                lu += w[k] * u[j];
            }
            double4 p = phat[i], ti = t[i];
            double4 v = in.y * p;
            double4 ui = ((v - in.x * ti) - lu) / in.x;
            ui.w = 0.0;
            u[i] = ui;
            double4 sti = v + lt;
            sti.w = 0.0;
            st[i] = sti;
            sum += dot3(p, in.y * (ti + ui));
        }
    }
    STORE_PARTIALS(partials, base, span, mx, sum, 0.0);
}

/* x += alpha t; r -= alpha st; rhat -= alpha sqrt(d) (t + u);
   partials: max scale |r|, sum rhat . rhat */
kernel void sgs_update(uint rows, global const double4 *info, global const double4 *t,
                       global const double4 *u, global const double4 *st, global double4 *x,
                       global double4 *r, global double4 *rhat, double alpha,
                       global double *partials)
{
    REDUCTION_SCRATCH;
    item_rows span = rows_of_item(0, rows);
    double mx = 0.0, sum = 0.0;
    for (uint i = span.begin; i < span.end; i++) {
        double4 in = info[i], ti = t[i];
        double4 xi = x[i] + alpha * ti;
        double4 ri = r[i] - alpha * st[i];
        double4 rh = rhat[i] - alpha * (in.y * (ti + u[i]));
        xi.w = ri.w = rh.w = 0.0;
        x[i] = xi;
        r[i] = ri;
        rhat[i] = rh;
        double len = in.z * sqrt(dot3(ri, ri));
        mx = len > mx ? len : mx;
        sum += dot3(rh, rh);
    }
    STORE_PARTIALS(partials, 0, span, mx, sum, 0.0);
}
