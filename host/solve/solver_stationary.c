/* SPDX-License-Identifier: MIT */
/* The stationary and semi-iterative methods: solve_iterate (iterate.c) with
   their update is the whole method, and each may take float corrections. */
#include "solve/solver.h"

/* the seeds' iteration, P += M - A P */
const solver_ops solver_paper = {.method = LIMN_METHOD_PAPER, .floats = 1, .kind = SOLVE_PAPER};
/* P += omega (M - A P), omega estimated from the first steps' contraction */
const solver_ops solver_weighted = {
    .method = LIMN_METHOD_WEIGHTED, .floats = 1, .kind = SOLVE_WEIGHTED};
/* the three-term recurrence of solve_chebyshev.c */
const solver_ops solver_chebyshev = {
    .method = LIMN_METHOD_CHEBYSHEV, .floats = 1, .kind = SOLVE_CHEBYSHEV};
