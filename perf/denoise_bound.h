/* SPDX-License-Identifier: MIT */
/*
 * The oracle bound of issue 16: the best polynomial p of degree N in A with
 * p(1) = 1 for one noisy mesh, fitted *knowing the clean mesh* — what no
 * degree-N polynomial filter in A (limn's or any other) can beat.
 */
#ifndef LIMN_PERF_DENOISE_BOUND_H
#define LIMN_PERF_DENOISE_BOUND_H

#include "limn.h"

/* *l2 gets p(A) y for the p minimising sum_v |p(A) y - x|^2 (least squares),
   *dist the p minimising the mean distance sum_v |p(A) y - x|_v / n (convex in
   the coefficients; iteratively reweighted least squares, 40 rounds), and
   (normals not NULL) *normals the best p in mean face-normal error found by
   normal_fit.h from those two fits and from the identity (a local search:
   evidence, not a bound). y = noisy, x = clean, same topology. Exits on
   failure (a benchmark). */
void denoise_bound(limn_context *ctx, const limn_mesh *noisy, const limn_mesh *clean,
                   const limn_series_options *o, int degree, limn_mesh **l2, limn_mesh **dist,
                   limn_mesh **normals);
/* The same for the default's form (sure_split): y + sum_i a_i (n . r_i) n +
   sum_i b_i (r_i - (n . r_i) n), n the unit normals of the default's frame
   (sure_frame_positions, sure_vertex_normals), 2 degree coefficients fitted
   knowing the clean mesh: what no filter of the split's form can beat. */
void denoise_bound_split(limn_context *ctx, const limn_mesh *noisy, const limn_mesh *clean,
                         const limn_series_options *o, int degree, limn_mesh **l2,
                         limn_mesh **dist, limn_mesh **normals);

#endif
