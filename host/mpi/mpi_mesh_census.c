/* SPDX-License-Identifier: MIT */
/*
 * The topology's counts of a distributed mesh, no rank building it whole:
 * every corner (its vertex, the previous and the next one) goes to the
 * block owner of its vertex, which so holds the whole ring of each of its
 * vertices and classifies them as topology_rings.c does: each edge {v, w}
 * from v's corners (one use: boundary; more than two: non-manifold; two in
 * the same direction: non-manifold and inconsistent), counted at its lower
 * vertex; v non-manifold when an edge of it is, or its corners do not make
 * one fan (topology_fan_walk, as the topology walks it); v referenced when it has a corner. The counts
 * are summed over the ranks: exact.
 */
#include "mpi/mpi_blocks.h"
#include "base/large_alloc.h"
#include "mpi/mpi_local.h"
#include "mpi/mpi_mesh.h"

#include "base/context.h"
#include "topology/topology.h"
#include "topology/topology_fan.h"

#include <limits.h>
#include <stdlib.h>
#include <string.h>

/* This rank's corners as (v, prev, next), grouped by the owner of v. */
static limn_status corners_out(mpi_part *p, const limn_mpi_mesh *mesh, uint32_t **out, int *cnt)
{
    const mesh_slice *s = &mesh->slice;
    size_t nc = s->face_offsets[s->face_count];
    uint32_t *w = large_malloc((nc ? 3 * nc : 1) * sizeof *w);
    size_t *at = calloc((size_t)p->size + 1, sizeof *at);
    limn_status st = w && at ? LIMN_OK
                             : ctx_fail(p->ctx, LIMN_ERR_MEMORY,
                                        "out of memory for the corners of %zu faces",
                                        s->face_count);
    for (size_t c = 0; !st && c < nc; c++)
        at[mpi_blocks_owner(mesh->vertex_dist, p->size, s->face_indices[c]) + 1] += 3;
    for (int r = 0; !st && r < p->size; r++) {
        if (at[r + 1] > INT_MAX)
            st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "too many corners for one MPI call");
        cnt[r] = (int)at[r + 1];
        at[r + 1] += at[r];
    }
    for (size_t f = 0; !st && f < s->face_count; f++)
        for (uint32_t c = s->face_offsets[f], b = c, e = s->face_offsets[f + 1]; c < e; c++) {
            uint32_t v = s->face_indices[c];
            uint32_t *t = w + at[mpi_blocks_owner(mesh->vertex_dist, p->size, v)];
            t[0] = v;
            t[1] = s->face_indices[c > b ? c - 1 : e - 1];
            t[2] = s->face_indices[c + 1 < e ? c + 1 : b];
            at[mpi_blocks_owner(mesh->vertex_dist, p->size, v)] += 3;
        }
    free(at);
    if (st) {
        free(w);
        w = NULL;
    }
    *out = w;
    return st;
}

/* The scratch of one vertex's classification (n corners). */
typedef struct ring {
    uint64_t *key;          /* 2 n: w << 32 | k << 1 | (1: back) */
    ring_edge *edge;        /* per edge: the other vertex, uses, the corner going v -> w */
    uint32_t *back;         /* per corner: its edge to the previous vertex */
    uint32_t *next_edge;    /* per corner: its edge to the next vertex */
} ring;

/* Vertex v's corners t (prev, next pairs, n of them, in corner order). */
static void classify(ring *g, uint32_t v, const uint32_t *const *t, uint32_t n, uint64_t k[5])
{
    for (uint32_t i = 0; i < n; i++) {
        g->key[2 * i] = (uint64_t)t[i][2] << 32 | (uint64_t)i << 1;
        g->key[2 * i + 1] = (uint64_t)t[i][1] << 32 | (uint64_t)i << 1 | 1;
    }
    mpi_local_sort(g->key, 2 * (size_t)n);
    uint32_t ne = topology_ring_edges(g->key, n, g->edge, g->next_edge, g->back), nm = 0;
    for (uint32_t i = 0; i < ne; i++) {
        const ring_edge *re = &g->edge[i];
        nm += (re->flags & EDGE_NONMANIFOLD) != 0;
        if (re->w > v) { /* each edge counted once, at its lower vertex */
            k[0] += (re->flags & EDGE_BOUNDARY) != 0;
            k[1] += (re->flags & EDGE_NONMANIFOLD) != 0;
            k[2] += (re->flags & EDGE_INCONSISTENT) != 0;
        }
    }
    k[3] += nm || !topology_fan_walk(g->edge, g->next_edge, g->back, n, NULL, NULL);
    k[4]++; /* referenced */
}

/* The nc corners got (v, prev, next) by vertex, each vertex's in arrival
   (= corner) order, as v << 32 | corner: a counting sort over the block
   [begin, begin + nb) that holds every v. */
static limn_status corners_by_vertex(mpi_part *p, const uint32_t *got, size_t nc, size_t begin,
                                     size_t nb, uint64_t *order)
{
    size_t *at = calloc(nb + 1, sizeof *at);
    if (!at)
        return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu vertices", nb);
    for (size_t c = 0; c < nc; c++)
        at[got[3 * c] - begin + 1]++;
    for (size_t v = 0; v < nb; v++)
        at[v + 1] += at[v];
    for (size_t c = 0; c < nc; c++)
        order[at[got[3 * c] - begin]++] = (uint64_t)got[3 * c] << 32 | c;
    free(at);
    return LIMN_OK;
}

/* The classification of every vertex whose corners arrived (n words). */
static limn_status classify_all(mpi_part *p, const limn_mpi_mesh *mesh, const uint32_t *got,
                                size_t n, uint64_t k[5])
{
    size_t nc = n / 3, longest = 0;
    uint64_t *order = large_malloc((nc ? nc : 1) * sizeof *order);
    const uint32_t **t = large_malloc((nc ? nc : 1) * sizeof *t);
    limn_status cs = order && t ? corners_by_vertex(p, got, nc, mesh->vertex_dist[p->rank],
                                                    mesh->slice.vertex_count, order)
                                : ctx_fail(p->ctx, LIMN_ERR_MEMORY,
                                           "out of memory for %zu corners", nc);
    if (cs) {
        free(order);
        free(t);
        return cs;
    }
    for (size_t i = 0, j; i < nc; i = j) {
        for (j = i; j < nc && order[j] >> 32 == order[i] >> 32; j++)
            ;
        longest = j - i > longest ? j - i : longest;
    }
    ring g;
    size_t e = 2 * longest + 1;
    g.key = large_malloc(e * sizeof *g.key);
    g.edge = large_malloc(e * sizeof *g.edge);
    uint32_t *words = large_malloc(2 * e * sizeof *words);
    limn_status st = g.key && g.edge && words
                         ? LIMN_OK
                         : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory");
    if (!st) {
        g.back = words;
        g.next_edge = words + e;
    }
    for (size_t i = 0, j; !st && i < nc; i = j) {
        for (j = i; j < nc && order[j] >> 32 == order[i] >> 32; j++)
            t[j - i] = got + 3 * (uint32_t)order[j];
        classify(&g, (uint32_t)(order[i] >> 32), t, (uint32_t)(j - i), k);
    }
    free(order);
    free(t);
    free(g.key);
    free(g.edge);
    free(words);
    return st;
}

limn_status mpi_mesh_census(mpi_part *p, const limn_mpi_mesh *mesh, mpi_mesh_counts *out)
{
    memset(out, 0, sizeof *out);
    int *cnt = calloc(2 * (size_t)p->size, sizeof *cnt);
    uint32_t *send = NULL;
    void *got = NULL;
    size_t n = 0;
    uint64_t k[5] = {0, 0, 0, 0, 0};
    limn_status st = cnt ? LIMN_OK : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory");
    if (!st)
        st = corners_out(p, mesh, &send, cnt);
    st = mpi_agree(p, st);
    if (!st)
        st = mpi_local_alltoallv(p, send, cnt, sizeof *send, &got, cnt + p->size, &n);
    free(send);
    free(cnt);
    if (!st)
        st = classify_all(p, mesh, got, n, k);
    free(got);
    st = mpi_agree(p, st);
    if (st)
        return st;
    MPI_Allreduce(MPI_IN_PLACE, k, 5, MPI_UINT64_T, MPI_SUM, p->comm);
    out->boundary_edges = (size_t)k[0];
    out->nonmanifold_edges = (size_t)k[1];
    out->inconsistent_edges = (size_t)k[2];
    out->nonmanifold_vertices = (size_t)k[3];
    out->referenced_vertices = (size_t)k[4];
    return LIMN_OK;
}
