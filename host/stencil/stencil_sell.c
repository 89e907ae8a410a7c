/* SPDX-License-Identifier: MIT */
/* SELL-C slices of a CSR table (stencil_sell.h). */
#include "stencil/stencil_sell.h"
#include "base/large_alloc.h"
#include "base/context.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* The widest row of slice s (rows past the table's end count as empty). */
static size_t slice_width(const stencil_csr *a, size_t slice, size_t s)
{
    size_t width = 0, end = (s + 1) * slice < a->rows ? (s + 1) * slice : a->rows;
    for (size_t i = s * slice; i < end; i++) {
        size_t len = a->row_offsets[i + 1] - a->row_offsets[i];
        width = len > width ? len : width;
    }
    return width;
}

/* Slice s's entries, column-major from `at`: row entries in CSR order, then
   the padding (weight 0, the row's last column, 0 for an empty row). */
static void fill_slice(const stencil_csr *a, size_t slice, size_t s, size_t width, size_t at,
                       stencil_sell *out)
{
    for (size_t l = 0; l < slice; l++) {
        size_t i = s * slice + l;
        size_t lo = i < a->rows ? a->row_offsets[i] : 0;
        size_t len = i < a->rows ? a->row_offsets[i + 1] - lo : 0;
        uint32_t pad = len ? a->columns[lo + len - 1] : 0;
        for (size_t k = 0; k < width; k++) {
            size_t e = at + k * slice + l;
            out->columns[e] = k < len ? a->columns[lo + k] : pad;
            out->weights[e] = k < len ? a->weights[lo + k] : 0.0;
        }
    }
}

limn_status stencil_sell_build(limn_context *ctx, const stencil_csr *a, size_t slice,
                               stencil_sell *out)
{
    memset(out, 0, sizeof *out);
    if (slice == 0)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "SELL layout: a slice of 0 rows");
    size_t slices = (a->rows + slice - 1) / slice, total = 0;
    out->slice_offsets = large_malloc((slices + 1) * sizeof *out->slice_offsets);
    if (!out->slice_offsets)
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for the SELL layout's offsets");
    out->slice_offsets[0] = 0;
    for (size_t s = 0; s < slices; s++) {
        total += slice_width(a, slice, s) * slice;
        if (total > UINT32_MAX) {
            stencil_sell_free(out);
            return ctx_fail(ctx, LIMN_ERR_MEMORY,
                            "SELL layout: more than 2^32 entries with padding (%zu rows)",
                            a->rows);
        }
        out->slice_offsets[s + 1] = (uint32_t)total;
    }
    out->columns = large_malloc((total ? total : 1) * sizeof *out->columns);
    out->weights = large_malloc((total ? total : 1) * sizeof *out->weights);
    if (!out->columns || !out->weights) {
        stencil_sell_free(out);
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for the SELL layout (%zu entries)",
                        total);
    }
    for (size_t s = 0; s < slices; s++)
        fill_slice(a, slice, s, (out->slice_offsets[s + 1] - out->slice_offsets[s]) / slice,
                   out->slice_offsets[s], out);
    out->rows = a->rows;
    out->slice = slice;
    out->slices = slices;
    return LIMN_OK;
}

void stencil_sell_free(stencil_sell *s)
{
    free(s->slice_offsets);
    free(s->columns);
    free(s->weights);
    memset(s, 0, sizeof *s);
}
