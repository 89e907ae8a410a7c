/* SPDX-License-Identifier: MIT */
/*
 * Topology passes over vertices: each vertex's bucket (its corners with their
 * next and previous vertex) holds everything about its edges, so the vertex
 * counts, writes and classifies them without reading another vertex.
 */
#include "topology/topology_build.h"
#include "topology/topology_fan.h"
#include "base/sorted_search.h"

#include <string.h>

static int count_range(void *arg, size_t begin, size_t end)
{
    topo_build *b = arg;
    topology *t = b->t;
    topo_counts *k = &b->counts[topo_range(b, t->vertex_count, begin)];
    topo_scratch sc = {0};
    for (size_t v = begin; v < end && !k->no_memory; v++) {
        uint32_t s = t->vertex_corner_offsets[v], n = t->vertex_corner_offsets[v + 1] - s;
        if (!topo_scratch_reserve(&sc, 0, 2 * (size_t)n)) {
            k->no_memory = 1;
            break;
        }
        /* neighbours: the next and previous vertices, each counted once */
        uint32_t *w = sc.words, entries = 0;
        for (uint32_t i = 0; i < n; i++) {
            w[2 * i] = b->next[s + i];
            w[2 * i + 1] = b->prev[s + i];
            entries += (w[2 * i] > v) + (w[2 * i + 1] > v);
        }
        topo_sort_u32(w, 2 * (size_t)n);
        uint32_t valence = 0, owned = 0;
        for (uint32_t i = 0; i < 2 * n; i++)
            if (i == 0 || w[i] != w[i - 1]) {
                valence++;
                owned += w[i] > v;
            }
        t->vertex_edge_offsets[v + 1] = valence;
        b->edge_base[v + 1] = owned;
        b->entry_base[v + 1] = entries;
    }
    topo_scratch_free(&sc);
    return k->no_memory;
}

int topo_count(topo_build *b)
{
    return parallel_run(b->t->vertex_count, b->parts, count_range, b);
}

/* ring edges live in the words of the scratch, 4 each */
_Static_assert(sizeof(ring_edge) <= 4 * sizeof(uint32_t), "ring_edge is 4 words");

/* The corner before c (at slot) in its face. */
static uint32_t corner_prev(const topo_build *b, uint32_t slot, uint32_t c)
{
    uint8_t r = b->wrap[slot];
    if (r == 0)
        return c - 1;
    if (r < 255)
        return c + r;
    /* c starts a face of 256 corners or more: the next face's start, found
       in face_offsets (corner_face comes later) */
    const uint32_t *fo = b->t->face_offsets;
    return fo[sorted_last_at_most_u32(fo, b->t->face_count, c) + 1] - 1;
}

/* Writes owned edge {v, w} (keys: its corners at v as slot << 1, and at w as
   slot << 1 | 1) with id id: vertices, corners in increasing order, flags
   (corner_edge, the inverse of the corners, only on request:
   topology_corner_edges). */
static void write_edge(topo_build *b, uint32_t v, const ring_edge *re, const uint64_t *keys,
                       uint32_t id, uint32_t *at, topo_counts *k)
{
    topology *t = b->t;
    uint32_t s = t->vertex_corner_offsets[v], *out = t->edge_corners + *at;
    for (uint32_t i = 0; i < re->total; i++) {
        uint32_t slot = (uint32_t)keys[i] >> 1, c = t->vertex_corners[s + slot];
        out[i] = keys[i] & 1 ? corner_prev(b, s + slot, c) : c;
    }
    topo_sort_u32(out, re->total);
    t->edge_vertices[2 * (size_t)id] = v;
    t->edge_vertices[2 * (size_t)id + 1] = re->w;
    t->edge_corner_offsets[id] = *at;
    t->edge_flags[id] = re->flags;
    *at += re->total;
    k->boundary_edges += (re->flags & EDGE_BOUNDARY) != 0;
    k->nonmanifold_edges += (re->flags & EDGE_NONMANIFOLD) != 0;
    k->inconsistent_edges += (re->flags & EDGE_INCONSISTENT) != 0;
}

uint32_t topology_ring_edges(const uint64_t *keys, uint32_t n, ring_edge *e, uint32_t *fwd,
                             uint32_t *back)
{
    uint32_t count = 0;
    for (uint32_t i = 0; i < 2 * n;) {
        uint32_t w = (uint32_t)(keys[i] >> 32), j = i, at_v = 0;
        ring_edge *re = &e[count++];
        re->forward = UINT32_MAX;
        for (; j < 2 * n && (uint32_t)(keys[j] >> 32) == w; j++) {
            uint32_t slot = (uint32_t)keys[j] >> 1;
            if (keys[j] & 1) {
                back[slot] = count - 1;
            } else {
                at_v++;
                re->forward = slot;
                fwd[slot] = count - 1;
            }
        }
        re->w = w;
        re->total = j - i;
        re->flags = re->total == 1  ? EDGE_BOUNDARY
                    : re->total > 2 ? EDGE_NONMANIFOLD
                    /* both corners start at the same vertex: same direction */
                    : at_v != 1 ? EDGE_NONMANIFOLD | EDGE_INCONSISTENT
                                : 0;
        i = j;
    }
    return count;
}

/* v's edges, sorted by neighbour, into e (keys: scratch of 2 n), and for
   each slot the index in e of its forward (fwd) and backward (back) edge;
   writes the owned ones; returns the count. */
static uint32_t ring_edges(topo_build *b, uint32_t v, uint64_t *keys, ring_edge *e,
                           uint32_t *fwd, uint32_t *back, topo_counts *k)
{
    topology *t = b->t;
    uint32_t s = t->vertex_corner_offsets[v], n = t->vertex_corner_offsets[v + 1] - s;
    /* slot << 1 fits: a vertex is in at most one corner of a face of >= 3,
       so n <= UINT32_MAX / 3 */
    for (uint32_t i = 0; i < n; i++) {
        keys[2 * i] = (uint64_t)b->next[s + i] << 32 | (uint64_t)i << 1;
        keys[2 * i + 1] = (uint64_t)b->prev[s + i] << 32 | (uint64_t)i << 1 | 1;
    }
    topo_sort_u64(keys, 2 * (size_t)n);
    uint32_t count = topology_ring_edges(keys, n, e, fwd, back);
    uint32_t id = b->edge_base[v], at = b->entry_base[v], i = 0;
    for (uint32_t c = 0; c < count; c++) {
        if (e[c].w > v)
            write_edge(b, v, &e[c], keys + i, id++, &at, k);
        i += e[c].total;
    }
    return count;
}

int topology_fan_walk(const ring_edge *e, const uint32_t *fwd, const uint32_t *back, uint32_t n,
                      const uint32_t *ids, uint32_t *order)
{
    if (n <= 1)
        return 1;
    uint32_t start = 0;
    for (uint32_t i = 0; i < n; i++)
        if (e[fwd[i]].total == 1) { /* a boundary */
            start = i;
            break;
        }
    uint32_t count = 0, i = start;
    do {
        if (count == n)
            return 0;
        if (order)
            order[count] = ids[i];
        count++;
        /* across the edge to the previous vertex: its corner that leaves v */
        const ring_edge *across = &e[back[i]];
        i = across->total == 2 ? across->forward : UINT32_MAX;
    } while (i != UINT32_MAX && i != start);
    return count == n;
}

/* Orders v's corners into one fan (topology_fan_walk); 0 when they form
   several fans. ring: scratch of n; fwd, back: ring_edges'. */
static int order_fan(topo_build *b, uint32_t v, const ring_edge *e, const uint32_t *fwd,
                     const uint32_t *back, uint32_t *ring)
{
    topology *t = b->t;
    uint32_t s = t->vertex_corner_offsets[v], n = t->vertex_corner_offsets[v + 1] - s;
    if (!topology_fan_walk(e, fwd, back, n, t->vertex_corners + s, ring))
        return 0;
    if (n > 1)
        memcpy(t->vertex_corners + s, ring, n * sizeof *ring);
    return 1;
}

/* Flags, rule and crease neighbours of v from its edges (OpenSubdiv's rules:
   topology.h); orders its fan (ring, fwd, back: order_fan's). */
static void classify(topo_build *b, uint32_t v, const ring_edge *e, uint32_t ne, uint32_t *ring,
                     const uint32_t *fwd, const uint32_t *back, topo_counts *k)
{
    topology *t = b->t;
    uint32_t nf = t->vertex_corner_offsets[v + 1] - t->vertex_corner_offsets[v];
    uint32_t boundary = 0, nonmanifold = 0, sharp[2] = {0, 0}, nsharp = 0;
    for (uint32_t i = 0; i < ne; i++) {
        boundary += (e[i].flags & EDGE_BOUNDARY) != 0;
        nonmanifold += (e[i].flags & EDGE_NONMANIFOLD) != 0;
        if (e[i].flags & (EDGE_BOUNDARY | EDGE_NONMANIFOLD)) {
            if (nsharp < 2)
                sharp[nsharp] = e[i].w;
            nsharp++;
        }
    }
    if (ne > k->max_valence)
        k->max_valence = ne;
    k->thin_vertices += nf > 0 && ne < 3;
    uint8_t flags = boundary ? VERTEX_BOUNDARY : 0;
    if (nonmanifold || !order_fan(b, v, e, fwd, back, ring))
        flags |= VERTEX_NONMANIFOLD;
    k->nonmanifold_vertices += (flags & VERTEX_NONMANIFOLD) != 0;
    t->vertex_flags[v] = flags;
    k->referenced_vertices += nf > 0;
    vertex_rule rule;
    int corner = nf == 1 && ne == 2;
    int pinned_nonmanifold =
        (flags & VERTEX_NONMANIFOLD) && !(nonmanifold == 2 && boundary == 0 && nf > ne);
    if (nf == 0)
        rule = RULE_ISOLATED;
    else if (corner || pinned_nonmanifold || nsharp > 2)
        rule = RULE_CORNER;
    else if (nsharp == 2)
        rule = RULE_CREASE;
    else
        rule = RULE_SMOOTH;
    t->vertex_rule[v] = (uint8_t)rule;
    t->crease_neighbors[2 * (size_t)v] = sharp[0];
    t->crease_neighbors[2 * (size_t)v + 1] = sharp[1];
}

static int edges_range(void *arg, size_t begin, size_t end)
{
    topo_build *b = arg;
    topology *t = b->t;
    /* counted here, stored at the end: the ranges' slots share cache lines */
    topo_counts *slot = &b->counts[topo_range(b, t->vertex_count, begin)], local = *slot;
    topo_counts *k = &local;
    topo_scratch sc = {0};
    for (size_t v = begin; v < end; v++) {
        uint32_t n = t->vertex_corner_offsets[v + 1] - t->vertex_corner_offsets[v];
        /* keys 2n, then ring edges (4 words each, at most 2n), the fan, fwd
           and back (n each) */
        if (!topo_scratch_reserve(&sc, 2 * (size_t)n, 11 * (size_t)n + 1)) {
            k->no_memory = 1;
            break;
        }
        ring_edge *e = (ring_edge *)(void *)sc.words;
        uint32_t *ring = sc.words + 8 * (size_t)n + 1, *fwd = ring + n, *back = fwd + n;
        uint32_t ne = ring_edges(b, (uint32_t)v, sc.keys, e, fwd, back, k);
        classify(b, (uint32_t)v, e, ne, ring, fwd, back, k);
    }
    topo_scratch_free(&sc);
    *slot = local;
    return k->no_memory;
}

int topo_edges(topo_build *b)
{
    return parallel_run(b->t->vertex_count, b->parts, edges_range, b);
}
