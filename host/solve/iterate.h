/* SPDX-License-Identifier: MIT */
/* The stationary and semi-iterative interpolation loop shared by the single
   process (interpolate.c) and the MPI layer, and the checks of its options. */
#ifndef LIMN_ITERATE_H
#define LIMN_ITERATE_H

#include "limn.h"
#include "device/device.h"

/* The updates of solve_iterate. */
typedef enum solve_kind { SOLVE_PAPER, SOLVE_WEIGHTED, SOLVE_CHEBYSHEV } solve_kind;
solve_kind solve_kind_of(limn_method method); /* AUTO is resolved before */

/* One step from P in buffer cur: chebyshev: P_next = P + c1 (P - P_prev) +
   c2 (M - A P), P_prev in buffer 1 - cur in, P_next out; otherwise P_next =
   P + omega (M - A P) into buffer 1 - cur. norms: of the residual M - A P
   over all vertices. */
typedef struct solve_step {
    solve_kind kind;
    double omega, c1, c2;
} solve_step;
typedef limn_status (*solve_step_fn)(void *user, int cur, const solve_step *step,
                                     device_norms *norms);

/*
 * The seeds' iteration, its weighted form and Chebyshev (iterate.c), on
 * any way of running a step (one device, or MPI ranks): stop when max |r| <=
 * tol * diag, singular / cap / divergence detection with messages; *which
 * gets the buffer holding the answer. vertices: for the mean error; scheme
 * and alpha: for the Chebyshev interval and the messages. Every decision reads
 * the norms step() returns, so ranks given the same norms decide alike.
 */
limn_status solve_iterate(limn_context *ctx, solve_step_fn step, void *user, size_t vertices,
                          limn_scheme scheme, double alpha, const limn_interpolate_options *o,
                          double diag, solve_kind kind, int *which, limn_report *r);

/*
 * Whether the solve renumbers its rows for locality (OPERATOR_REORDER) with
 * `method` (resolved from auto): when the options allow it and the method
 * takes many products (paper, weighted: 23-82 at 1e-6). The renumbering
 * (RCM: three sequential graph sweeps and the table's permutation) costs
 * about 30 iterations of a shuffled mesh's loop, more than Chebyshev, CG or
 * SGS run in all (docs/performance.md "The whole job, end to end"). The
 * single process and MPI ask the same, so their bytes agree.
 */
int solve_reorder_wanted(const limn_interpolate_options *o, limn_method method);

/* Refuses bad interpolation options with a message (iterate.c). */
limn_status solve_check_options(limn_context *ctx, const limn_interpolate_options *o);

#endif
