/* SPDX-License-Identifier: MIT */
/* A CSR stencil table laid out in SELL-C slices (sigma = 1: rows keep their
   order) for the GPU kernel shape (host/device/opencl/opencl_shape.c,
   kernels/common.cl): slice s holds rows [s C, s C + C) and the entries
   [slice_offsets[s], slice_offsets[s + 1]), column-major: row i = s C + l's
   k-th entry is at slice_offsets[s] + k C + l. A slice is as wide as its
   longest row; a shorter row (and a lane past the last row) is padded with
   weight 0 and, so that the padding reads memory the row already read, the
   row's last column (0 for an empty row). One row per work-item then reads
   consecutive addresses across a slice's lanes (coalesced). Each row's
   entries keep their CSR order, so a row's sum is the same sum in the same
   order, plus 0 x_j terms at its end. */
#ifndef LIMN_STENCIL_SELL_H
#define LIMN_STENCIL_SELL_H

#include "stencil/stencil.h"

typedef struct stencil_sell {
    size_t rows, slice, slices;
    uint32_t *slice_offsets; /* slices + 1 */
    uint32_t *columns;       /* slice_offsets[slices] */
    double *weights;         /* slice_offsets[slices] */
} stencil_sell;

/* The SELL-`slice` layout of a (slice >= 1). Fails (out of memory, or more
   entries than 32-bit offsets hold) with a message and leaves out empty. */
limn_status stencil_sell_build(limn_context *ctx, const stencil_csr *a, size_t slice,
                               stencil_sell *out);
void stencil_sell_free(stencil_sell *s);

#endif
