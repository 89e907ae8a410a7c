/* SPDX-License-Identifier: MIT */
/*
 * Locality reordering of a mesh's vertices for the stencil products: reverse
 * Cuthill-McKee on the edge graph, so that the rows a work-item handles touch
 * nearby columns (DESIGN.md §6: random vertex order is 7-9x slower at 4M
 * vertices). Results are always returned in the input order.
 */
#ifndef LIMN_REORDER_H
#define LIMN_REORDER_H

#include "stencil/stencil.h"
#include "topology/topology.h"

/* order[k] = the input vertex placed at position k; rank[v] = position of
   input vertex v. Both hold t->vertex_count entries (caller frees). */
limn_status reorder_rcm(limn_context *ctx, const topology *t, uint32_t **order, uint32_t **rank);

/* out = P A P^T with P given by order/rank (rows and columns renumbered;
   each row's entries stay in their input order, so every row sums as the
   unpermuted row does, bit for bit). */
limn_status stencil_permute(limn_context *ctx, const stencil_csr *a, const uint32_t *order,
                            const uint32_t *rank, stencil_csr *out);

/* Mean jump of the first column from one row to the next: small when the
   columns a run of rows reads stream through memory (scan order, refined
   meshes), large when they hop at random (shuffled vertices). */
double stencil_mean_row_jump(const stencil_csr *a);

#endif
