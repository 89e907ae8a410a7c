/* SPDX-License-Identifier: MIT */
/*
 * vertex_edges: each vertex's edges in increasing id. Ids follow the lower
 * vertex, so the edges of v to lower neighbours (owned by them) come first
 * and its own edges, ids edge_base[v] on, last: those go in place, the
 * others through a fill cursor per vertex and a sort of each short list.
 */
#include "topology/topology_build.h"

static int lower_range(void *arg, size_t begin, size_t end)
{
    topo_build *b = arg;
    topology *t = b->t;
    int shared = b->parts > 1;
    for (size_t w = begin; w < end; w++)
        for (uint32_t e = b->edge_base[w]; e < b->edge_base[w + 1]; e++) {
            uint32_t v = t->edge_vertices[2 * (size_t)e + 1], slot;
            if (shared) {
                slot = atomic_fetch_add_explicit(&b->cursor[v], 1, memory_order_relaxed);
            } else {
                slot = atomic_load_explicit(&b->cursor[v], memory_order_relaxed);
                atomic_store_explicit(&b->cursor[v], slot + 1, memory_order_relaxed);
            }
            t->vertex_edges[t->vertex_edge_offsets[v] + slot] = e;
        }
    return 0;
}

static int own_range(void *arg, size_t begin, size_t end)
{
    topo_build *b = arg;
    topology *t = b->t;
    for (size_t v = begin; v < end; v++) {
        uint32_t owned = b->edge_base[v + 1] - b->edge_base[v];
        uint32_t *list = t->vertex_edges + t->vertex_edge_offsets[v];
        uint32_t lower = t->vertex_edge_offsets[v + 1] - t->vertex_edge_offsets[v] - owned;
        topo_sort_u32(list, lower);
        for (uint32_t i = 0; i < owned; i++)
            list[lower + i] = b->edge_base[v] + i;
    }
    return 0;
}

int topo_vertex_edges(topo_build *b)
{
    size_t nv = b->t->vertex_count;
    for (size_t v = 0; v < nv; v++)
        atomic_store_explicit(&b->cursor[v], 0, memory_order_relaxed);
    return parallel_run(nv, b->parts, lower_range, b) | parallel_run(nv, b->parts, own_range, b);
}
