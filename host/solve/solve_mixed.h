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

/*
 * The refinement over any way of running its products (one device, or MPI
 * ranks: mpi_interpolate.c). user: the side's state; every norm returned is
 * over all rows (all ranks), and every decision reads only those norms.
 */
typedef struct mixed_ops {
    void *user;
    /* r_f = M - A P in double, stored rounded to float (residual_f). */
    limn_status (*residual)(void *user, device_buffer *r_f, device_norms *norms);
    /* The float step_f on b, d, prev, next (device_mixed_ops). */
    limn_status (*step)(void *user, device_buffer *b, device_buffer *d, device_buffer *prev,
                        device_buffer *next, float c1, float c2, device_norms *norms);
    /* P += d (add_f). */
    limn_status (*add)(void *user, device_buffer *d);
    /* Every process's status after the work vectors' allocation (NULL: one
       process): one that failed alone would leave the others waiting in
       the residual's exchanges. */
    limn_status (*agree)(void *user, limn_status st);
} mixed_ops;

/* solve_mixed's loop on ops: dev holds the float work vectors, `rows` rows
   each (MPI: owned and ghost rows); vertices: all of them (the mean error);
   scheme, alpha: for the Chebyshev interval and the messages. The weights'
   float copy (device_csr_add_float) is the caller's. */
limn_status solve_mixed_run(limn_context *ctx, struct device *dev, const mixed_ops *ops,
                            size_t rows, size_t vertices, limn_scheme scheme, double alpha,
                            const limn_interpolate_options *o, double diag, limn_method method,
                            int *converged, limn_report *r);

#endif
