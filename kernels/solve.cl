/*
 * Kernels of the conjugate-gradient solver (host/solve_cg.c), built into the
 * same program as stencil.cl (row_product). Same conventions: ROWS_PER_ITEM
 * consecutive rows per work-item, one partial reduction per item finished on
 * the host in item order, arithmetic identical to device_ref.c.
 * Vectors are 4 doubles per row (x, y, z used); dinv holds one double per row.
 */

/* y = A x; partials[3 item + 1] = sum_i dinv_i (x_i . y_i) */
kernel void spmv_dot(uint rows, global const uint *ro, global const uint *col,
                     global const double *w, global const double4 *x, global double4 *y,
                     global const double *dinv, global double *partials)
{
    uint item = (uint)get_global_id(0);
    uint begin = item * ROWS_PER_ITEM;
    uint end = min(rows, begin + ROWS_PER_ITEM);
    double sum = 0.0;
    for (uint i = begin; i < end; i++) {
        double4 acc = row_product(i, ro, col, w, x);
        y[i] = acc;
        double4 xi = x[i];
        double d = xi.x * acc.x + xi.y * acc.y + xi.z * acc.z;
        sum += dinv[i] * d;
    }
    if (begin < rows) {
        partials[3 * item] = 0.0;
        partials[3 * item + 1] = sum;
        partials[3 * item + 2] = 0.0;
    }
}

/* x += alpha p; z -= alpha q; partials: max |z_i|, sum dinv_i |z_i|^2, sum |z_i|^2 */
kernel void pcg_update(uint rows, double alpha, global const double4 *p,
                       global const double4 *q, global double4 *x, global double4 *z,
                       global const double *dinv, global double *partials)
{
    uint item = (uint)get_global_id(0);
    uint begin = item * ROWS_PER_ITEM;
    uint end = min(rows, begin + ROWS_PER_ITEM);
    double mx = 0.0, rz = 0.0, sq = 0.0;
    for (uint i = begin; i < end; i++) {
        double4 pi = p[i], qi = q[i], xi = x[i], zi = z[i];
        xi = (double4)(xi.x + alpha * pi.x, xi.y + alpha * pi.y, xi.z + alpha * pi.z, 0.0);
        zi = (double4)(zi.x - alpha * qi.x, zi.y - alpha * qi.y, zi.z - alpha * qi.z, 0.0);
        x[i] = xi;
        z[i] = zi;
        double s = zi.x * zi.x + zi.y * zi.y + zi.z * zi.z;
        double len = sqrt(s);
        mx = len > mx ? len : mx;
        rz += dinv[i] * s;
        sq += s;
    }
    if (begin < rows) {
        partials[3 * item] = mx;
        partials[3 * item + 1] = rz;
        partials[3 * item + 2] = sq;
    }
}
