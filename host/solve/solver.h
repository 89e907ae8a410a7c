/* SPDX-License-Identifier: MIT */
/*
 * The one solver contract for A P = M (PETSc's KSP is the model): a solver
 * is created for a method from the registry (solver.c), set from the
 * interpolation options, run, destroyed. Each method fills a solver_ops in
 * its own file; adding one is that file and its line in the registry.
 */
#ifndef LIMN_SOLVER_H
#define LIMN_SOLVER_H

#include "solve/solve.h"

/* What a method is. Every method finishes with a stationary loop
   (solve_iterate) that measures the residual of the P it returns, so the
   reported error is exact; a method with a start runs it first. */
typedef struct solver_ops {
    limn_method method;
    int floats;      /* may take float corrections (--precision float, solve_mixed.c) */
    solve_kind kind; /* the finishing loop's update */
    /* Optional: the start, a Krylov solve tier by tier (solve_tiers,
       solve_cg.c) with this solver of one tier's block, in host arrays.
       LIMN_ERR_TOPOLOGY without a message when the operator does not suit
       it: the solver then falls back to the paper method with a warning
       that names it `long_name` and the report reason `fallback_reason`. */
    solve_block_fn block;
    const char *long_name;
    const char *fallback_reason;
} solver_ops;

/* The methods (solver_stationary.c, solve_cg.c, solve_sgs.c). */
extern const solver_ops solver_paper, solver_weighted, solver_chebyshev, solver_cg, solver_sgs;

/* The registered method, NULL for AUTO or an unknown value. */
const solver_ops *solver_find(limn_method method);

typedef struct solver {
    const solver_ops *ops;
    limn_context *ctx;
    const limn_interpolate_options *o;
    limn_precision precision;
    struct device *dev;
    device_buffer *m, *p[2]; /* M and the two iterates, on the device */
    double *p_host[2];       /* the iterates' host memory (device_host_alloc) */
    int which;               /* after solver_solve: the buffer p[which] holds P */
    double finish_begin;     /* clock_seconds() when the last loop ended */
} solver;

/* method: resolved, not AUTO. */
void solver_create(limn_context *ctx, limn_method method, solver *s);
/* Takes the options and chooses the precision (r->precision and its reason). */
limn_status solver_set_from_options(solver *s, const limn_interpolate_options *o,
                                    size_t vertices, limn_report *r);
/* Solves on op's device: buf holds M packed in the operator's order (4
   doubles a row; a start may overwrite it); on success *p_out is P in that
   layout, host memory the caller frees (NULL on failure). Fills the report's
   method, iteration, product and error fields. diag: scale of the tolerance. */
limn_status solver_solve(solver *s, stencil_operator *op, double diag, double *buf,
                         double **p_out, limn_report *r);
void solver_destroy(solver *s);

#endif
