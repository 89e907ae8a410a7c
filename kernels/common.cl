/* SPDX-License-Identifier: MIT */
/*
 * The helpers every kernel file uses, first in the one program
 * (host/device/opencl/opencl_program.c joins common.cl, stencil.cl, series.cl,
 * solve.cl, mixed.cl and sgs.cl). ROWS_PER_ITEM comes from the build options
 * (-D ROWS_PER_ITEM=DEVICE_ROWS_PER_ITEM, host/device/device.h). FP_CONTRACT
 * OFF as in every file (tests/check_kernels.sh).
 */
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#pragma OPENCL FP_CONTRACT OFF

#ifndef ROWS_PER_ITEM
#error ROWS_PER_ITEM is a build option (-D ROWS_PER_ITEM=DEVICE_ROWS_PER_ITEM, device.h)
#endif

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

/* One work-item's partials; an item past the rows writes nothing. */
inline void store_partials(global double *partials, uint item, uint begin, uint rows,
                           double mx, double sum, double sq)
{
    if (begin < rows) {
        partials[3 * item] = mx;
        partials[3 * item + 1] = sum;
        partials[3 * item + 2] = sq;
    }
}
