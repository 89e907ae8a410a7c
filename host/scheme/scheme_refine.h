/* SPDX-License-Identifier: MIT */
/*
 * Refinement masks: the weights that make one vertex of level k+1 from the
 * vertices of level k. Pure functions of the topology (see scheme.h for the
 * limit masks). Rules: Catmull-Clark (face centroid; edge (a+b+f1+f2)/4;
 * vertex (n-2)/n V + 1/n^2 sum(alpha V + (1-alpha) E_j) + 1/n^2 sum f_j) and
 * Loop (edge 3/8, 3/8, 1/8, 1/8; vertex (1 - n beta) V + beta sum E_j); sharp
 * edges (boundary, non-manifold) give midpoints, crease vertices
 * (1, 6, 1)/8, corners and pinned vertices stay.
 */
#ifndef LIMN_SCHEME_REFINE_H
#define LIMN_SCHEME_REFINE_H

#include "topology/topology.h"

/* Loop's 3/8 + cos(2 pi/n)/4, which both betas square: from a table of the
   formula's values for n <= 16, else the formula (scheme_loop_cos_term_formula). */
double scheme_loop_cos_term(uint32_t valence);
double scheme_loop_cos_term_formula(uint32_t valence);
/* Loop's vertex weight beta_n = (5/8 - (3/8 + cos(2 pi/n)/4)^2) / n. */
double scheme_loop_refine_beta(uint32_t valence);

/* The masks of the vertices whose rule is not smooth, one shape for the
   limit and refinement masks of both schemes: an isolated or corner vertex keeps itself; a crease vertex takes
   centre times itself and side times each crease neighbour. Returns the
   entries, or 0 for a smooth vertex (its mask is the scheme's). */
size_t scheme_sharp_vertex_mask(const topology *t, uint32_t v, double centre, double side,
                                uint32_t *cols, double *w);

/* Upper bounds on the entries of each mask under scheme (exact where the
   element is smooth, so the stencil build's scratch stays small). */
size_t scheme_refine_vertex_bound(const topology *t, limn_scheme scheme, uint32_t v);
size_t scheme_refine_edge_bound(const topology *t, limn_scheme scheme, uint32_t e);

size_t scheme_refine_vertex_mask(const topology *t, limn_scheme scheme, double alpha, uint32_t v,
                                 uint32_t *cols, double *w);
size_t scheme_refine_edge_mask(const topology *t, limn_scheme scheme, uint32_t e, uint32_t *cols,
                               double *w);
/* Catmull-Clark face point: the centroid. */
size_t scheme_refine_face_mask(const topology *t, uint32_t f, uint32_t *cols, double *w);

#endif
