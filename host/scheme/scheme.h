/* SPDX-License-Identifier: MIT */
/*
 * Subdivision rules as weights over a vertex's neighbourhood: pure functions
 * of the topology, no I/O, no device. The masks are the closed forms of
 * DESIGN.md §1 (Loop; general Catmull-Clark with alpha; B-spline crease and
 * boundary curves; pinned corners).
 */
#ifndef LIMN_SCHEME_H
#define LIMN_SCHEME_H

#include "topology/topology.h"

/* Upper bound on the entries scheme_limit_mask writes for vertex v under
   scheme (exact for a smooth vertex, before repeats are merged). */
size_t scheme_limit_mask_bound(const topology *t, limn_scheme scheme, uint32_t v);

/*
 * Writes the limit mask of vertex v as (column, weight) pairs into cols and
 * weights (room for scheme_limit_mask_bound entries); a column may appear
 * more than once. Returns the number of entries. scheme is LOOP or CATMARK.
 */
size_t scheme_limit_mask(const topology *t, limn_scheme scheme, double alpha, uint32_t v,
                         uint32_t *cols, double *weights);

/*
 * The row scale d_v with which the limit operator becomes symmetric on its
 * smooth block: A = D S, S symmetric (seeds 002 §6, 003 §3). Loop smooth:
 * (1 - beta_n)/n (every neighbour weight); Catmull-Clark smooth: 1/(n(n+5))
 * (edge weights b_ij and face weights 4/d are symmetric in i, j); crease:
 * 1/6; pinned and isolated: 1. Rows that reference a sharper class (smooth ->
 * crease, crease -> pinned) are what breaks symmetry; solvers move those
 * columns to the right-hand side (see README "Solvers").
 */
double scheme_limit_row_scale(const topology *t, limn_scheme scheme, uint32_t v);

/* Loop's beta_n of the limit mask: 3 / (11 - 8 (3/8 + (3/8 + cos(2 pi/n)/4)^2)). */
double scheme_loop_limit_beta(uint32_t valence);

#endif
