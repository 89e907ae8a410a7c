/* SPDX-License-Identifier: MIT */
/* Solvers for A P = M beyond the seeds' iteration (host/solve_*.c). */
#ifndef LIMN_SOLVE_H
#define LIMN_SOLVE_H

#include "solve/operator.h"
#include "solve/iterate.h"
#include "solve/monitor.h"

typedef struct solve_stats {
    double products;     /* stencil products, in units of one full A x */
    int iterations;      /* solver steps */
    int catmark_alpha0;  /* for messages about the singular alpha = 0 case */
    double seconds_loop; /* in the CG-type loops: their products, sweeps and reductions,
                            without buffer and table set-up or first-launch compiles */
} solve_stats;

/* One tier's block A x = b (rows of table a, 4 doubles a row in b and x0,
   dinv = 1 / row scale, so that dinv A is symmetric); the answer returns in
   x0. on_device: a's copy on the device when it has one, else NULL. */
typedef limn_status (*solve_block_fn)(limn_context *ctx, struct device *dev,
                                      const stencil_csr *a, const device_csr *on_device,
                                      const double *b, double *x0, const double *dinv,
                                      double tol_abs, int max_iter, double n_total,
                                      solve_stats *stats);
/* The tiers' block solvers: D-preconditioned CG (solve_cg.c, solver_cg) and
   CG preconditioned by multicolour symmetric Gauss-Seidel (solve_sgs.c,
   solver_sgs) are filled into their solver_ops. */
/* Pinned rows P = M, then the crease and the smooth block (solve_cg.c).
   m4: M in the operator's row order, 4 doubles per row; p4 receives P.
   LIMN_ERR_TOPOLOGY, without a message, when A is not block triangular by
   vertex rule (the caller then falls back to the seeds' iteration). */
limn_status solve_tiers(limn_context *ctx, const stencil_operator *op, const double *m4,
                        double tol_abs, int max_iter, double *p4, solve_block_fn solve_block,
                        solve_stats *stats);

/* The guards of a CG-type loop (solve_cg.c): cg_watch_step sees the max
   residual before each step and sets *done when it meets tol_abs, or fails
   with a message on divergence, stalling (singular operator) or the step cap. */
typedef struct cg_watch {
    monitor mon; /* set up by the first cg_watch_step (zero-initialise the watch) */
} cg_watch;
limn_status cg_watch_step(limn_context *ctx, cg_watch *w, double residual, solve_stats *stats,
                          double tol_abs, int max_iter, int *done);
/* LIMN_OK when p . S p is positive, else the breakdown message. */
limn_status cg_curvature(limn_context *ctx, double pq, solve_stats *stats);

/*
 * The Chebyshev iteration's schedule (solve_chebyshev.c): interval [a, 1],
 * coefficients of each fused step, and the restart rule when the residual
 * shows an eigenvalue below a.
 */
typedef struct chebyshev {
    double a, theta, delta, sigma, tau, rho;
    double first, history[4];
    int step;        /* steps since the last (re)start */
    int lead, in_lead; /* seeds' steps still to take before the recurrence */
    int restarts;
} chebyshev;

double chebyshev_prior(limn_scheme scheme);
/* Steps of the seeds' iteration that precede the recurrence for a scheme. */
int chebyshev_lead_steps(limn_scheme scheme);
void chebyshev_init(chebyshev *c, double a, int lead_steps);
/* Coefficients of the next step: x_next = x + c1 (x - x_prev) + c2 (M - A x). */
void chebyshev_coefficients(chebyshev *c, double *c1, double *c2);
/* Records max |r| measured by the step just taken (optional: without it the
   schedule is the plain recurrence); returns 1 when a was lowered and the
   recurrence restarts with the next step. */
int chebyshev_observe(chebyshev *c, double residual);

#endif
