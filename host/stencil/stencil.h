/* SPDX-License-Identifier: MIT */
/* CSR stencil tables: row i holds the weights of the vertices that make
   output vertex i (a limit point, or a refined vertex). */
#ifndef LIMN_STENCIL_H
#define LIMN_STENCIL_H

#include "limn.h"

typedef struct stencil_csr {
    size_t rows;
    size_t cols;
    uint32_t *row_offsets;   /* rows + 1 */
    uint32_t *columns;
    double *weights;
} stencil_csr;

struct topology;

/* Row callbacks for stencil_build: an upper bound on a row's entries, and the
   entries themselves (columns may repeat; they are merged and sorted). */
typedef size_t (*stencil_row_bound)(const void *user, size_t row);
typedef size_t (*stencil_row_fill)(const void *user, size_t row, uint32_t *cols, double *weights);

limn_status stencil_build(limn_context *ctx, size_t rows, size_t cols, stencil_row_bound bound,
                          stencil_row_fill fill, const void *user, stencil_csr *out);

/* y = A x, 3 doubles a vertex, with the rows stencil_build would make used
   as they are made (no table is stored): the same bytes as stencil_build and
   stencil_apply3 or the device's spmv, for any thread count. *entries: the
   entries the table would hold. */
limn_status stencil_build_apply3(limn_context *ctx, size_t rows, stencil_row_bound bound,
                                 stencil_row_fill fill, const void *user, const double *x,
                                 double *y, size_t *entries);
limn_status stencil_limit_build(limn_context *ctx, const struct topology *topo,
                                limn_scheme scheme, double alpha, stencil_csr *out);
void stencil_free(stencil_csr *csr);
/* y = A x with 3 doubles per vertex (host side; used by tests and small jobs). */
void stencil_apply3(const stencil_csr *a, const double *x, double *y);

#endif
