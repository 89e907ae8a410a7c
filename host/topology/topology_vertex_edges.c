/* SPDX-License-Identifier: MIT */
/*
 * vertex_edges: each vertex's edges in increasing id. Ids follow the lower
 * vertex, so the edges of v to lower neighbours (owned by them) come first
 * and its own edges, ids edge_base[v] on, last: those go in place, the
 * others through a fill cursor per vertex, in increasing id: each range of
 * vertices reads every edge and takes those whose upper end is its own (no
 * atomics, the same lists for any thread count).
 */
#include "topology/topology_build.h"

static int lists_range(void *arg, size_t lo, size_t hi)
{
    topo_build *b = arg;
    topology *t = b->t;
    uint32_t first = (uint32_t)lo, span = (uint32_t)(hi - lo);
    for (size_t e = 0; e < t->edge_count; e++) {
        uint32_t v = t->edge_vertices[2 * e + 1];
        if (v - first >= span)
            continue;
        uint32_t slot = atomic_load_explicit(&b->cursor[v], memory_order_relaxed);
        atomic_store_explicit(&b->cursor[v], slot + 1, memory_order_relaxed);
        t->vertex_edges[t->vertex_edge_offsets[v] + slot] = (uint32_t)e;
    }
    for (size_t v = lo; v < hi; v++) {
        uint32_t owned = b->edge_base[v + 1] - b->edge_base[v];
        uint32_t *list = t->vertex_edges + t->vertex_edge_offsets[v + 1] - owned;
        for (uint32_t i = 0; i < owned; i++)
            list[i] = b->edge_base[v] + i;
    }
    return 0;
}

int topo_vertex_edges(topo_build *b)
{
    size_t nv = b->t->vertex_count;
    for (size_t v = 0; v < nv; v++)
        atomic_store_explicit(&b->cursor[v], 0, memory_order_relaxed);
    return parallel_run(nv, b->parts, lists_range, b);
}
