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

limn_status stencil_limit_build(limn_context *ctx, const struct topology *topo,
                                limn_scheme scheme, double alpha, stencil_csr *out);
void stencil_free(stencil_csr *csr);
/* y = A x with 3 doubles per vertex (host side; used by tests and small jobs). */
void stencil_apply3(const stencil_csr *a, const double *x, double *y);

#endif
