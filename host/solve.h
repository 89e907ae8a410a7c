/* Solvers for A P = M beyond the seeds' iteration (host/solve_*.c). */
#ifndef LIMN_SOLVE_H
#define LIMN_SOLVE_H

#include "operator.h"

typedef struct solve_stats {
    double products;     /* stencil products, in units of one full A x */
    int iterations;      /* solver steps */
    int catmark_alpha0;  /* for messages about the singular alpha = 0 case */
} solve_stats;

/*
 * Tiered, D-preconditioned conjugate gradients (solve_cg.c). m4: M in the
 * operator's row order, 4 doubles per row; p4 receives P. Returns
 * LIMN_ERR_TOPOLOGY, without a message, when A is not block triangular by
 * vertex rule (the caller then falls back to the seeds' iteration).
 */
limn_status solve_cg(limn_context *ctx, const limn_operator *op, const double *m4,
                     double tol_abs, int max_iter, double *p4, solve_stats *stats);

/* One update P_next = P_cur + omega (M - A P_cur) with the norms of the
   residual M - A P_cur over all vertices (cur: 0 or 1, the buffer holding P). */
typedef limn_status (*solve_step_fn)(void *user, int cur, double omega, device_norms *norms);

/*
 * The seeds' iteration and its weighted form (interpolate.c), on any way of
 * running a step (one device, or MPI ranks): stop when max |r| <= tol * diag,
 * singular / cap / divergence detection with messages; *which gets the buffer
 * holding the answer. vertices: for the mean error; scheme and alpha: for the
 * messages.
 */
limn_status solve_iterate(limn_context *ctx, solve_step_fn step, void *user, size_t vertices,
                          limn_scheme scheme, double alpha, const limn_interpolate_options *o,
                          double diag, int weighted, int *which, limn_report *r);

/* Refuses bad interpolation options with a message (interpolate.c). */
limn_status solve_check_options(limn_context *ctx, const limn_interpolate_options *o);

#endif
