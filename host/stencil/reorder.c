/* SPDX-License-Identifier: MIT */
/* Reverse Cuthill-McKee ordering and CSR permutation. */
#include "stencil/reorder.h"
#include "base/context.h"

#include <stdlib.h>
#include <string.h>

static uint32_t degree(const topology *t, uint32_t v)
{
    return t->vertex_edge_offsets[v + 1] - t->vertex_edge_offsets[v];
}

/* A vertex far from `start` in its component (two BFS sweeps), as RCM's root. */
static uint32_t peripheral(const topology *t, uint32_t start, uint32_t *queue, uint32_t *mark,
                           uint32_t stamp)
{
    uint32_t root = start;
    for (int sweep = 0; sweep < 2; sweep++) {
        size_t head = 0, tail = 0;
        queue[tail++] = root;
        mark[root] = stamp + (uint32_t)sweep;
        uint32_t last = root;
        while (head < tail) {
            uint32_t v = queue[head++];
            last = v;
            for (uint32_t i = t->vertex_edge_offsets[v]; i < t->vertex_edge_offsets[v + 1]; i++) {
                uint32_t w = topology_edge_other(t, t->vertex_edges[i], v);
                if (mark[w] != stamp + (uint32_t)sweep) {
                    mark[w] = stamp + (uint32_t)sweep;
                    queue[tail++] = w;
                }
            }
        }
        root = last;
    }
    return root;
}

limn_status reorder_rcm(limn_context *ctx, const topology *t, uint32_t **order_out,
                        uint32_t **rank_out)
{
    size_t n = t->vertex_count;
    uint32_t *order = malloc((n ? n : 1) * sizeof *order);
    uint32_t *rank = malloc((n ? n : 1) * sizeof *rank);
    uint32_t *queue = malloc((n ? n : 1) * sizeof *queue);
    uint32_t *mark = calloc(n ? n : 1, sizeof *mark);
    unsigned char *placed = calloc(n ? n : 1, 1);
    if (!order || !rank || !queue || !mark || !placed) {
        free(order), free(rank), free(queue), free(mark), free(placed);
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory reordering %zu vertices", n);
    }
    size_t count = 0;
    uint32_t stamp = 1;
    for (uint32_t s = 0; s < n; s++) {
        if (placed[s])
            continue;
        uint32_t root = degree(t, s) ? peripheral(t, s, queue, mark, stamp) : s;
        stamp += 2;
        size_t head = count;
        order[count++] = root;
        placed[root] = 1;
        while (head < count) {
            uint32_t v = order[head++];
            size_t first = count;
            for (uint32_t i = t->vertex_edge_offsets[v]; i < t->vertex_edge_offsets[v + 1]; i++) {
                uint32_t w = topology_edge_other(t, t->vertex_edges[i], v);
                if (!placed[w]) {
                    placed[w] = 1;
                    order[count++] = w;
                }
            }
            /* neighbours by increasing degree (insertion sort: rings are short) */
            for (size_t i = first + 1; i < count; i++) {
                uint32_t w = order[i];
                size_t j = i;
                while (j > first && (degree(t, order[j - 1]) > degree(t, w) ||
                                     (degree(t, order[j - 1]) == degree(t, w) && order[j - 1] > w))) {
                    order[j] = order[j - 1];
                    j--;
                }
                order[j] = w;
            }
        }
    }
    /* reverse, then ranks */
    for (size_t i = 0; i < n / 2; i++) {
        uint32_t x = order[i];
        order[i] = order[n - 1 - i];
        order[n - 1 - i] = x;
    }
    for (size_t i = 0; i < n; i++)
        rank[order[i]] = (uint32_t)i;
    free(queue);
    free(mark);
    free(placed);
    *order_out = order;
    *rank_out = rank;
    return LIMN_OK;
}

limn_status stencil_permute(limn_context *ctx, const stencil_csr *a, const uint32_t *order,
                            const uint32_t *rank, stencil_csr *out)
{
    size_t n = a->rows, nnz = a->row_offsets[n];
    memset(out, 0, sizeof *out);
    out->rows = n;
    out->cols = a->cols;
    out->row_offsets = malloc((n + 1) * sizeof *out->row_offsets);
    out->columns = malloc((nnz ? nnz : 1) * sizeof *out->columns);
    out->weights = malloc((nnz ? nnz : 1) * sizeof *out->weights);
    if (!out->row_offsets || !out->columns || !out->weights) {
        stencil_free(out);
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory permuting %zu rows", n);
    }
    /* each row keeps its entries in the input order: the same sums as the
       rows of input order, whatever the numbering (docs/mpi.md "Local rows") */
    size_t e = 0;
    out->row_offsets[0] = 0;
    for (size_t k = 0; k < n; k++) {
        uint32_t old = order[k];
        for (uint32_t i = a->row_offsets[old]; i < a->row_offsets[old + 1]; i++, e++) {
            out->columns[e] = rank[a->columns[i]];
            out->weights[e] = a->weights[i];
        }
        out->row_offsets[k + 1] = (uint32_t)e;
    }
    return LIMN_OK;
}

double stencil_mean_row_jump(const stencil_csr *a)
{
    double sum = 0;
    uint32_t prev = 0;
    size_t counted = 0;
    for (size_t r = 0; r < a->rows; r++) {
        if (a->row_offsets[r + 1] == a->row_offsets[r])
            continue;
        uint32_t first = a->columns[a->row_offsets[r]];
        if (counted++)
            sum += first > prev ? (double)(first - prev) : (double)(prev - first);
        prev = first;
    }
    return counted > 1 ? sum / (double)(counted - 1) : 0.0;
}
