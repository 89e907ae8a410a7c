/* SPDX-License-Identifier: MIT */
/*
 * The multicolour layout for the symmetric Gauss-Seidel sweeps. Gauss-Seidel
 * is sequential row by row; on a device it runs colour by colour, the rows
 * of one colour having no entry between them. Colouring greedily in the
 * block's own order (RCM when the operator was reordered) and keeping that
 * order inside each colour leaves each colour's gathers local. Measured
 * (perf/sgs_pcg_probe.py): the colour order costs no CG step against the
 * natural order on the shared medium meshes (7 colours for Loop, 6-8 for
 * Catmull-Clark).
 */
#include "stencil/sgs_table.h"
#include "base/context.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void sgs_table_free(sgs_table *t)
{
    free(t->colour_begin);
    free(t->order);
    free(t->row_offsets);
    free(t->split);
    free(t->columns);
    free(t->weights);
    free(t->info);
    memset(t, 0, sizeof *t);
}

/* Greedy: each row takes the smallest colour none of its earlier
   neighbours of its group has (group NULL: one group). Returns the number
   of colours, or 0 when out of memory. */
size_t sgs_colour_rows(const stencil_csr *a, const int8_t *group, uint32_t *colour)
{
    size_t longest = 0;
    for (size_t i = 0; i < a->rows; i++) {
        size_t len = a->row_offsets[i + 1] - a->row_offsets[i];
        longest = len > longest ? len : longest;
    }
    /* stamp[c] == i + 1: colour c is taken by a neighbour of row i */
    size_t *stamp = calloc(longest + 2, sizeof *stamp);
    if (!stamp)
        return 0;
    size_t colours = 1;
    for (size_t i = 0; i < a->rows; i++) {
        for (uint32_t k = a->row_offsets[i]; k < a->row_offsets[i + 1]; k++) {
            uint32_t j = a->columns[k];
            if (j < i && colour[j] <= longest && (!group || group[j] == group[i]))
                stamp[colour[j]] = i + 1;
        }
        uint32_t c = 0;
        while (stamp[c] == i + 1)
            c++;
        colour[i] = c;
        colours = (size_t)c + 1 > colours ? (size_t)c + 1 : colours;
    }
    free(stamp);
    return colours;
}

/* The rows in colour order (out->colour_begin, out->order) and where each
   block row went; next: room for the colours, zeroed. */
static void order_rows(sgs_table *out, const uint32_t *colour, size_t *next, uint32_t *where)
{
    size_t n = out->rows;
    for (size_t i = 0; i < n; i++)
        out->colour_begin[colour[i] + 1]++;
    for (size_t c = 0; c < out->colours; c++)
        out->colour_begin[c + 1] += out->colour_begin[c];
    for (size_t i = 0; i < n; i++) {
        size_t at = out->colour_begin[colour[i]] + next[colour[i]]++;
        out->order[at] = (uint32_t)i;
        where[i] = (uint32_t)at;
    }
}

/* Table row t from its block row: the entries of lower colours, then
   (from out->split[t]) higher ones, from *e on; the row's info. A row
   sharing its colour with a neighbour, or without a positive diagonal, is
   LIMN_ERR_TOPOLOGY. */
static limn_status table_row(sgs_table *out, const stencil_csr *a, const double *dinv,
                             const uint32_t *colour, const uint32_t *where, size_t t, size_t *e)
{
    limn_status st = LIMN_OK;
    uint32_t o = out->order[t];
    double d = 0.0;
    /* lower colours first, then higher: two passes over the row */
    for (int pass = 0; pass < 2; pass++) {
        if (pass == 1)
            out->split[t] = (uint32_t)*e;
        for (uint32_t k = a->row_offsets[o]; k < a->row_offsets[o + 1]; k++) {
            uint32_t j = a->columns[k];
            if (j == o) {
                if (pass == 0)
                    d += dinv[o] * a->weights[k];
                continue;
            }
            if (colour[j] == colour[o]) {
                st = LIMN_ERR_TOPOLOGY;
                break;
            }
            if ((colour[j] > colour[o]) == pass) {
                out->columns[*e] = where[j];
                out->weights[(*e)++] = dinv[o] * a->weights[k];
                if (pass)
                    out->upper++;
                else
                    out->lower++;
            }
        }
    }
    out->row_offsets[t + 1] = (uint32_t)*e;
    if (!(d > 0.0) || !isfinite(d))
        st = LIMN_ERR_TOPOLOGY;
    double *in = out->info + 4 * t;
    in[0] = d;
    in[1] = sqrt(d);
    in[2] = 1.0 / dinv[o];
    in[3] = 0.0;
    return st;
}

limn_status sgs_table_build(limn_context *ctx, const stencil_csr *a, const double *dinv,
                            sgs_table *out)
{
    memset(out, 0, sizeof *out);
    uint32_t *colour = malloc((a->rows ? a->rows : 1) * sizeof *colour);
    size_t colours = colour ? sgs_colour_rows(a, NULL, colour) : 0;
    limn_status st = colours ? sgs_table_build_coloured(ctx, a, dinv, colour, colours, out)
                             : ctx_fail(ctx, LIMN_ERR_MEMORY,
                                        "out of memory for the Gauss-Seidel table");
    free(colour);
    return st;
}

limn_status sgs_table_build_coloured(limn_context *ctx, const stencil_csr *a, const double *dinv,
                                     const uint32_t *colour, size_t colours, sgs_table *out)
{
    memset(out, 0, sizeof *out);
    size_t n = a->rows, nnz = a->row_offsets[n], nc = a->cols > n ? a->cols : n;
    uint32_t *where = malloc((nc ? nc : 1) * sizeof *where); /* column -> table column */
    out->rows = n;
    out->order = malloc((n ? n : 1) * sizeof *out->order);
    out->row_offsets = malloc((n + 1) * sizeof *out->row_offsets);
    out->split = malloc((n ? n : 1) * sizeof *out->split);
    out->columns = malloc((nnz ? nnz : 1) * sizeof *out->columns);
    out->weights = malloc((nnz ? nnz : 1) * sizeof *out->weights);
    out->info = malloc((n ? n : 1) * 4 * sizeof *out->info);
    size_t *next = calloc(colours ? colours : 1, sizeof *next); /* rows placed a colour */
    out->colour_begin = calloc(colours + 1, sizeof *out->colour_begin);
    if (!where || !next || !out->colour_begin || !out->order || !out->row_offsets ||
        !out->split || !out->columns || !out->weights || !out->info) {
        free(where);
        free(next);
        sgs_table_free(out);
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for the Gauss-Seidel table");
    }
    out->colours = colours;
    order_rows(out, colour, next, where);
    for (size_t j = n; j < nc; j++)
        where[j] = (uint32_t)j; /* columns past the rows (MPI ghosts) stay */
    free(next);
    limn_status st = LIMN_OK;
    size_t e = 0;
    out->row_offsets[0] = 0;
    for (size_t t = 0; t < n && !st; t++)
        st = table_row(out, a, dinv, colour, where, t, &e);
    free(where);
    if (st)
        sgs_table_free(out);
    return st;
}
