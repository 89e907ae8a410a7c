/* SPDX-License-Identifier: MIT */
/* Precision of the interpolation solve: the choice, and the mixed-precision
   refinement that runs the float kernels (solve_mixed.c). */
#ifndef LIMN_SOLVE_MIXED_H
#define LIMN_SOLVE_MIXED_H

#include "solve/operator.h"

/* Below this many vertices `auto` runs in double (README "Precision": float
   measured 3-5% slower at 48k, 0-7% faster at 134k, 9-14% at 194k-2.1M). */
#define SOLVE_FLOAT_MIN_VERTICES 200000

/*
 * Resolves o->precision for `method` (already resolved, never AUTO) and a
 * mesh of `vertices`; sets r->precision and r->precision_reason. Refuses an
 * unknown precision, and float with cg (CG runs in double).
 */
limn_status solve_precision_choose(limn_context *ctx, const limn_interpolate_options *o,
                                   limn_method method, size_t vertices, limn_precision *out,
                                   limn_report *r);

/*
 * Mixed-precision iterative refinement of P (p: 4 doubles a row, in the
 * operator's order; m: M likewise): r = M - A P in double with the stop test
 * of the double iteration (exact, on the P returned); the correction d with
 * A d = r iterated in float (`method`: the seeds', the weighted or the
 * Chebyshev step, d starting at r) until its residual is INNER_REDUCTION of r's or the tolerance; P += d
 * in double; again. Counts products (float ones in r->products_float) and
 * updates in r. On LIMN_OK, *converged says whether P meets the tolerance;
 * 0 means the float corrections stopped gaining (A singular or nearly so, a
 * tolerance near double's rounding), and the caller goes on in double from
 * p, whose own stall test then speaks.
 */
limn_status solve_mixed(limn_context *ctx, stencil_operator *op, device_buffer *m, device_buffer *p,
                        const limn_interpolate_options *o, double diag, limn_method method,
                        int *converged, limn_report *r);

#endif
