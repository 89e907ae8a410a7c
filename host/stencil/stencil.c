/* SPDX-License-Identifier: MIT */
/* CSR tables built from the scheme's masks, rows sorted by column with
   repeated columns merged, so a table is a deterministic function of the
   topology. */
#include "stencil/stencil.h"
#include "base/large_alloc.h"
#include "base/context.h"
#include "base/parallel.h"
#include "scheme/scheme.h"
#include "topology/topology.h"

#include <stdlib.h>
#include <string.h>

void stencil_free(stencil_csr *csr)
{
    if (!csr)
        return;
    free(csr->row_offsets);
    free(csr->columns);
    free(csr->weights);
    memset(csr, 0, sizeof *csr);
}

/* Sorts (col, weight) pairs by column and merges repeats; returns the new count. */
static size_t sort_merge(uint32_t *cols, double *w, size_t n)
{
    for (size_t i = 1; i < n; i++) {
        uint32_t c = cols[i];
        double x = w[i];
        size_t j = i;
        while (j > 0 && cols[j - 1] > c) {
            cols[j] = cols[j - 1];
            w[j] = w[j - 1];
            j--;
        }
        cols[j] = c;
        w[j] = x;
    }
    size_t m = 0;
    for (size_t i = 0; i < n; i++) {
        if (m > 0 && cols[m - 1] == cols[i]) {
            w[m - 1] += w[i];
        } else {
            cols[m] = cols[i];
            w[m] = w[i];
            m++;
        }
    }
    return m;
}

/*
 * Rows are built in parallel over contiguous ranges, in three passes with no
 * per-row allocation: each range sums its rows' bounds (one prefix sum gives
 * each range a bound-sized block), each range fills and merges its rows into
 * its own block packed from the block's start, and the packed blocks move
 * down to their final offsets in range order. A row's entries depend only
 * on the row, so the table is the same bytes for any thread count.
 */
typedef struct stencil_job {
    limn_context *ctx;
    stencil_row_bound bound;
    stencil_row_fill fill;
    const void *user;
    stencil_csr *out;
    size_t rows;
    unsigned parts;
    size_t block[PARALLEL_MAX];  /* pass 1: the range's bound sum; then its block start */
    size_t packed[PARALLEL_MAX]; /* pass 2: where the range's packed entries end */
} stencil_job;

/* Bytes of work a row stands for when choosing threads (about ten entries of
   12 bytes, and the topology read to make them). */
#define STENCIL_ROW_BYTES 128

static unsigned range_index(const stencil_job *j, size_t begin)
{
    return parallel_part(j->rows, j->parts, begin);
}

static int bound_range(void *arg, size_t begin, size_t end)
{
    stencil_job *j = arg;
    size_t sum = 0;
    for (size_t r = begin; r < end; r++)
        sum += j->bound(j->user, r);
    j->block[range_index(j, begin)] = sum;
    return 0;
}

static int fill_range(void *arg, size_t begin, size_t end)
{
    stencil_job *j = arg;
    unsigned i = range_index(j, begin);
    uint32_t *cols = j->out->columns, *offsets = j->out->row_offsets;
    double *w = j->out->weights;
    size_t k = j->block[i];
    for (size_t r = begin; r < end; r++) {
        size_t n = j->fill(j->user, r, cols + k, w + k);
        k += sort_merge(cols + k, w + k, n);
        offsets[r + 1] = (uint32_t)k; /* in the range's block until the move */
        /* the calling thread runs range 0: progress from there only */
        if (begin == 0 && (r & 0xFFFFF) == 0xFFFFF)
            ctx_progress(j->ctx, "stencil", (double)r / (double)j->rows);
    }
    j->packed[i] = k;
    return 0;
}

limn_status stencil_build(limn_context *ctx, size_t rows, size_t cols, stencil_row_bound bound,
                          stencil_row_fill fill, const void *user, stencil_csr *out)
{
    memset(out, 0, sizeof *out);
    stencil_job job = {.ctx = ctx, .bound = bound, .fill = fill, .user = user, .out = out,
                       .rows = rows};
    stencil_job *j = &job;
    j->parts = parallel_threads(ctx, (uint64_t)rows * STENCIL_ROW_BYTES);
    if ((size_t)j->parts > rows)
        j->parts = rows ? (unsigned)rows : 1;
    parallel_run(rows, j->parts, bound_range, j);
    size_t total = 0;
    for (unsigned i = 0; i < j->parts; i++) {
        size_t sum = j->block[i];
        j->block[i] = total;
        total += sum;
    }
    if (total > UINT32_MAX)
        return ctx_fail(ctx, LIMN_ERR_MEMORY,
                        "a stencil table would hold %zu entries, more than 2^32", total);
    out->rows = rows;
    out->cols = cols;
    out->row_offsets = large_malloc((rows + 1) * sizeof *out->row_offsets);
    out->columns = large_malloc((total ? total : 1) * sizeof *out->columns);
    out->weights = large_malloc((total ? total : 1) * sizeof *out->weights);
    if (!out->row_offsets || !out->columns || !out->weights) {
        stencil_free(out);
        return ctx_fail(ctx, LIMN_ERR_MEMORY,
                        "out of memory for a stencil table of %zu entries", total);
    }
    out->row_offsets[0] = 0;
    parallel_run(rows, j->parts, fill_range, j);
    size_t k = 0; /* where the next range's packed entries go */
    for (unsigned i = 0; i < j->parts; i++) {
        size_t from = j->block[i], count = j->packed[i] - from;
        if (from != k) {
            memmove(out->columns + k, out->columns + from, count * sizeof *out->columns);
            memmove(out->weights + k, out->weights + from, count * sizeof *out->weights);
            uint32_t shift = (uint32_t)(from - k);
            for (size_t r = parallel_cut(rows, j->parts, i);
                 r < parallel_cut(rows, j->parts, i + 1); r++)
                out->row_offsets[r + 1] -= shift;
        }
        k += count;
    }
    /* Shrink to the merged size (keeps the old block if realloc fails). */
    uint32_t *c = realloc(out->columns, (k ? k : 1) * sizeof *c);
    if (c)
        out->columns = c;
    double *w = realloc(out->weights, (k ? k : 1) * sizeof *w);
    if (w)
        out->weights = w;
    return LIMN_OK;
}

/*
 * Rows made and used at once (stencil_build_apply3): each range fills a row
 * into its own scratch, merges it as fill_range does and takes its product
 * with x as stencil_apply3 does (the device's spmv: the same order), so y is
 * the same bytes as through a stored table, for any thread count.
 */
typedef struct apply_job {
    stencil_row_bound bound;
    stencil_row_fill fill;
    const void *user;
    const double *x;
    double *y;
    size_t rows;
    unsigned parts;
    size_t entries[PARALLEL_MAX];  /* the merged entries of the range's rows */
    int no_memory[PARALLEL_MAX];
} apply_job;

static int apply_range(void *arg, size_t begin, size_t end)
{
    apply_job *j = arg;
    unsigned part = parallel_part(j->rows, j->parts, begin);
    uint32_t *cols = NULL;
    double *w = NULL;
    size_t cap = 0, entries = 0;
    for (size_t r = begin; r < end; r++) {
        size_t want = j->bound(j->user, r);
        if (want > cap) {
            cap = 2 * want < 64 ? 64 : 2 * want;
            free(cols);
            free(w);
            cols = malloc(cap * sizeof *cols);
            w = malloc(cap * sizeof *w);
            if (!cols || !w) {
                j->no_memory[part] = 1;
                break;
            }
        }
        size_t n = sort_merge(cols, w, j->fill(j->user, r, cols, w));
        double s0 = 0, s1 = 0, s2 = 0;
        for (size_t k = 0; k < n; k++) {
            const double *p = j->x + 3 * (size_t)cols[k];
            s0 += w[k] * p[0];
            s1 += w[k] * p[1];
            s2 += w[k] * p[2];
        }
        j->y[3 * r] = s0;
        j->y[3 * r + 1] = s1;
        j->y[3 * r + 2] = s2;
        entries += n;
    }
    free(cols);
    free(w);
    j->entries[part] = entries;
    return j->no_memory[part];
}

limn_status stencil_build_apply3(limn_context *ctx, size_t rows, stencil_row_bound bound,
                                 stencil_row_fill fill, const void *user, const double *x,
                                 double *y, size_t *entries)
{
    apply_job job = {.bound = bound, .fill = fill, .user = user, .x = x, .y = y, .rows = rows};
    job.parts = parallel_threads(ctx, (uint64_t)rows * STENCIL_ROW_BYTES);
    if ((size_t)job.parts > rows)
        job.parts = rows ? (unsigned)rows : 1;
    int failed = parallel_run(rows, job.parts, apply_range, &job);
    *entries = 0;
    for (unsigned i = 0; i < job.parts; i++)
        *entries += job.entries[i];
    return failed ? ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for the rows of %zu vertices",
                             rows)
                  : LIMN_OK;
}

typedef struct limit_rows {
    const topology *t;
    limn_scheme scheme;
    double alpha;
} limit_rows;

static size_t limit_bound(const void *user, size_t r)
{
    const limit_rows *lr = user;
    return scheme_limit_mask_bound(lr->t, lr->scheme, (uint32_t)r);
}

static size_t limit_fill(const void *user, size_t r, uint32_t *cols, double *w)
{
    const limit_rows *lr = user;
    return scheme_limit_mask(lr->t, lr->scheme, lr->alpha, (uint32_t)r, cols, w);
}

limn_status stencil_limit_build(limn_context *ctx, const topology *t, limn_scheme scheme,
                                double alpha, stencil_csr *out)
{
    limit_rows lr = {t, scheme, alpha};
    return stencil_build(ctx, t->vertex_count, t->vertex_count, limit_bound, limit_fill, &lr, out);
}

void stencil_apply3(const stencil_csr *a, const double *x, double *y)
{
    for (size_t i = 0; i < a->rows; i++) {
        double s0 = 0, s1 = 0, s2 = 0;
        for (uint32_t k = a->row_offsets[i]; k < a->row_offsets[i + 1]; k++) {
            const double *p = x + 3 * (size_t)a->columns[k];
            double wk = a->weights[k];
            s0 += wk * p[0];
            s1 += wk * p[1];
            s2 += wk * p[2];
        }
        y[3 * i] = s0;
        y[3 * i + 1] = s1;
        y[3 * i + 2] = s2;
    }
}
