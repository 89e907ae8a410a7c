/* SPDX-License-Identifier: MIT */
/* The multicolour layout of one solver block for the symmetric Gauss-Seidel
   sweeps (uploaded as device.h device_sgs; kernels/sgs.cl). */
#ifndef LIMN_SGS_TABLE_H
#define LIMN_SGS_TABLE_H

#include "stencil/stencil.h"

typedef struct sgs_table {
    size_t rows, colours;
    size_t *colour_begin;        /* colours + 1 */
    uint32_t *order;             /* table row -> block row */
    uint32_t *row_offsets;       /* rows + 1, off-diagonal entries */
    uint32_t *split;             /* rows: first entry of a higher colour */
    uint32_t *columns;
    double *weights;             /* S = dinv A, off the diagonal */
    double *info;                /* 4 a row: d, sqrt d, 1 / dinv, 0 */
    size_t lower, upper;         /* off-diagonal entries below / above */
} sgs_table;

/*
 * Colours the block's graph greedily in its row order (which keeps the
 * operator's locality within each colour), lays the rows out colour by
 * colour and scales them to S = dinv A. Returns LIMN_ERR_TOPOLOGY without a
 * message when the block does not suit the sweeps (an entry joins two rows
 * of one colour: an unsymmetric pattern; or a diagonal that is not
 * positive), so the caller can fall back.
 */
limn_status sgs_table_build(limn_context *ctx, const stencil_csr *a, const double *dinv,
                            sgs_table *out);
void sgs_table_free(sgs_table *t);

/* The greedy colouring of sgs_table_build: row i takes the smallest colour
   that no neighbour j < i of its group (group[j] == group[i]; group NULL:
   all rows one group) has. Returns the number of colours (0: out of
   memory). */
size_t sgs_colour_rows(const stencil_csr *a, const int8_t *group, uint32_t *colour);

/*
 * sgs_table_build with the colours given (colour: one per column of a,
 * below `colours`). Columns at or past a->rows (MPI: ghost values, a->cols
 * of them in all) keep their number in the table, so the vectors hold the
 * rows in colour order, then those values.
 */
limn_status sgs_table_build_coloured(limn_context *ctx, const stencil_csr *a, const double *dinv,
                                     const uint32_t *colour, size_t colours, sgs_table *out);

#endif
