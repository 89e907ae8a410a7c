/* SPDX-License-Identifier: MIT */
/*
 * The topology's counts without the topology (`limn info`, the repair's
 * report when nothing else follows): the build's face checks and vertex
 * buckets (next and previous vertex of every corner; no corner ids, no wrap),
 * then each vertex's edges and fan from its bucket (topology_ring_edges and
 * topology_fan_walk, as the build classifies them), each edge counted at its
 * lower vertex, the components and boundary loops by a union-find fed as the
 * vertices go. Nothing per edge is stored: about a third of the build's
 * memory, and no edge or incidence arrays to write.
 */
#include "base/large_alloc.h"
#include "base/context.h"
#include "mesh/mesh.h"
#include "topology/topology_build.h"
#include "topology/topology_fan.h"
#include "topology/topology_sets.h"

#include <stdlib.h>
#include <string.h>

typedef struct census {
    topo_build b;
    _Atomic uint32_t *sets;   /* components: the cursors' array, free after the scatter */
    _Atomic uint32_t *loops;  /* boundary loops */
    uint8_t *on_boundary;     /* per vertex: on a boundary edge */
    size_t edges[PARALLEL_MAX], roots[PARALLEL_MAX], loop_roots[PARALLEL_MAX];
} census;

static int sets_init(void *arg, size_t begin, size_t end)
{
    census *c = arg;
    for (size_t v = begin; v < end; v++) {
        atomic_init(&c->sets[v], (uint32_t)v);
        atomic_init(&c->loops[v], (uint32_t)v);
    }
    return 0;
}

/* Whether v's n corners make one closed fan whose every edge two corners use,
   one each way (nearly every vertex of a closed mesh): each corner's next
   vertex is the previous vertex of exactly one corner (the one across that
   edge), and walking across from corner 0 visits all n. Then v has n
   neighbours, each edge flagged 0, and one fan: what the sort would find. */
static int closed_fan(const uint64_t *ring, uint32_t n)
{
    if (n < 2 || n > 16)
        return 0;
    uint8_t across[16];
    uint32_t hit = 0;
    for (uint32_t i = 0; i < n; i++) {
        uint32_t found = 0, at = 0;
        for (uint32_t j = 0; j < n; j++) {
            uint32_t same = (uint32_t)ring[j] == ring[i] >> 32;
            found += same;
            at = same ? j : at;
        }
        if (found != 1)
            return 0;
        across[i] = (uint8_t)at;
        hit |= 1u << at;
    }
    if (hit != (1u << n) - 1)
        return 0; /* two corners lead to one: a neighbour used more than twice */
    uint32_t i = 0, steps = 0;
    do {
        i = across[i];
        steps++;
    } while (i != 0 && steps < n);
    return i == 0 && steps == n;
}

/* Vertex v's edges (e, fwd, back: room for 2n, n, n; keys 2n) into k and
   the sets; returns its valence. */
static uint32_t census_vertex(census *c, uint32_t v, uint64_t *keys, ring_edge *e, uint32_t *fwd,
                              uint32_t *back, topo_counts *k, size_t *edges)
{
    const topo_build *b = &c->b;
    uint32_t s = b->t->vertex_corner_offsets[v], n = b->t->vertex_corner_offsets[v + 1] - s;
    const uint64_t *ring = b->ring + s;
    if (closed_fan(ring, n)) {
        for (uint32_t i = 0; i < n; i++)
            if (ring[i] >> 32 > v) {
                (*edges)++;
                topo_unite(c->sets, v, (uint32_t)(ring[i] >> 32));
            }
        c->on_boundary[v] = 0;
        k->referenced_vertices++;
        k->thin_vertices += n < 3;
        return n;
    }
    for (uint32_t i = 0; i < n; i++) {
        keys[2 * i] = (ring[i] >> 32) << 32 | (uint64_t)i << 1;
        keys[2 * i + 1] = ring[i] << 32 | (uint64_t)i << 1 | 1;
    }
    topo_sort_u64(keys, 2 * (size_t)n);
    uint32_t ne = topology_ring_edges(keys, n, e, fwd, back), nonmanifold = 0, boundary = 0;
    for (uint32_t i = 0; i < ne; i++) {
        uint8_t f = e[i].flags;
        nonmanifold |= f & EDGE_NONMANIFOLD;
        boundary |= f & EDGE_BOUNDARY;
        if (e[i].w < v)
            continue; /* counted and joined at its lower end */
        (*edges)++;
        k->boundary_edges += (f & EDGE_BOUNDARY) != 0;
        k->nonmanifold_edges += (f & EDGE_NONMANIFOLD) != 0;
        k->inconsistent_edges += (f & EDGE_INCONSISTENT) != 0;
        topo_unite(c->sets, v, e[i].w);
        if (f & EDGE_BOUNDARY)
            topo_unite(c->loops, v, e[i].w);
    }
    c->on_boundary[v] = boundary != 0;
    k->nonmanifold_vertices += nonmanifold || !topology_fan_walk(e, fwd, back, n, NULL, NULL);
    k->referenced_vertices++;
    k->thin_vertices += ne < 3;
    return ne;
}

static int census_range(void *arg, size_t begin, size_t end)
{
    census *c = arg;
    const topology *t = c->b.t;
    unsigned part = topo_range(&c->b, t->vertex_count, begin);
    /* counted here, stored at the end: the ranges' slots share cache lines */
    topo_counts local = c->b.counts[part], *k = &local;
    size_t edges = 0;
    topo_scratch sc = {0};
    for (size_t v = begin; v < end; v++) {
        uint32_t n = t->vertex_corner_offsets[v + 1] - t->vertex_corner_offsets[v];
        if (n == 0) {
            c->on_boundary[v] = 0;
            continue;
        }
        /* keys 2n, ring edges (4 words each, at most 2n), fwd and back (n each) */
        if (!topo_scratch_reserve(&sc, 2 * (size_t)n, 10 * (size_t)n)) {
            k->no_memory = 1;
            break;
        }
        ring_edge *e = (ring_edge *)(void *)sc.words;
        uint32_t *fwd = sc.words + 8 * (size_t)n, *back = fwd + n;
        uint32_t ne = census_vertex(c, (uint32_t)v, sc.keys, e, fwd, back, k, &edges);
        if (ne > k->max_valence)
            k->max_valence = ne;
    }
    topo_scratch_free(&sc);
    c->b.counts[part] = local;
    c->edges[part] = edges;
    return k->no_memory;
}

/* Roots once every union is done: one per set, counted over the referenced
   vertices (components) and the boundary ones (loops). */
static int census_roots(void *arg, size_t begin, size_t end)
{
    census *c = arg;
    const uint32_t *off = c->b.t->vertex_corner_offsets;
    size_t roots = 0, loop_roots = 0;
    for (size_t v = begin; v < end; v++) {
        roots += off[v + 1] > off[v] &&
                 atomic_load_explicit(&c->sets[v], memory_order_relaxed) == v;
        loop_roots += c->on_boundary[v] &&
                      atomic_load_explicit(&c->loops[v], memory_order_relaxed) == v;
    }
    unsigned part = topo_range(&c->b, c->b.t->vertex_count, begin);
    c->roots[part] = roots;
    c->loop_roots[part] = loop_roots;
    return 0;
}

/* The ranges' counts summed into out. */
static void census_sum(const census *c, topology_counts *out)
{
    memset(out, 0, sizeof *out);
    for (unsigned i = 0; i < PARALLEL_MAX; i++) {
        const topo_counts *k = &c->b.counts[i];
        out->edges += c->edges[i];
        out->components += c->roots[i];
        out->boundary_loops += c->loop_roots[i];
        out->boundary_edges += k->boundary_edges;
        out->nonmanifold_edges += k->nonmanifold_edges;
        out->inconsistent_edges += k->inconsistent_edges;
        out->nonmanifold_vertices += k->nonmanifold_vertices;
        out->referenced_vertices += k->referenced_vertices;
        out->thin_vertices += k->thin_vertices;
        out->triangles += k->triangles;
        out->quads += k->quads;
        out->other_faces += k->other_faces;
        if (k->max_valence > out->max_valence)
            out->max_valence = k->max_valence;
        if (k->max_face_size > out->max_face_size)
            out->max_face_size = k->max_face_size;
    }
}

/* The buckets placed, the vertices counted: every array allocated. */
static limn_status census_run(limn_context *ctx, census *c, topology_counts *out)
{
    topo_build *b = &c->b;
    size_t nv = b->t->vertex_count;
    limn_status st = topo_place_corners(ctx, b);
    if (st)
        return st;
    c->sets = b->cursor; /* the cursors are done with */
    parallel_run(nv, b->parts, sets_init, c);
    parallel_run(nv, b->parts, census_range, c);
    st = topo_gather(ctx, b);
    if (st)
        return st;
    parallel_run(nv, b->parts, census_roots, c);
    census_sum(c, out);
    return LIMN_OK;
}

limn_status topology_census(limn_context *ctx, const limn_mesh *mesh, topology_counts *out)
{
    topology t;
    memset(&t, 0, sizeof t);
    t.vertex_count = mesh->vertex_count;
    t.face_count = mesh->face_count;
    t.face_offsets = mesh->face_offsets;
    t.face_indices = mesh->face_indices;
    t.corner_count = mesh->face_offsets[mesh->face_count];
    size_t nv = t.vertex_count, nc = t.corner_count;
    census *c = calloc(1, sizeof *c);
    if (!c)
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory counting the topology");
    c->b.t = &t;
    /* about 40 bytes a corner are read and written */
    c->b.parts = parallel_threads(ctx, (uint64_t)nc * 40);
    for (unsigned i = 0; i < PARALLEL_MAX; i++)
        c->b.counts[i].bad_face = SIZE_MAX;
    t.vertex_corner_offsets = large_malloc((nv + 1) * sizeof *t.vertex_corner_offsets);
    c->b.cursor = large_malloc((nv ? nv : 1) * sizeof *c->b.cursor);
    c->b.ring = large_malloc((nc ? nc : 1) * sizeof *c->b.ring);
    c->loops = large_malloc((nv ? nv : 1) * sizeof *c->loops);
    c->on_boundary = large_malloc(nv ? nv : 1);
    limn_status st = LIMN_OK;
    if (!t.vertex_corner_offsets || !c->b.cursor || !c->b.ring || !c->loops ||
        !c->on_boundary)
        st = ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for the topology of %zu vertices",
                      nv);
    if (!st)
        st = census_run(ctx, c, out);
    free(t.vertex_corner_offsets);
    free((void *)c->b.cursor);
    free(c->b.ring);
    free((void *)c->loops);
    free(c->on_boundary);
    free(c);
    if (!st)
        ctx_progress(ctx, "topology", 1.0);
    return st;
}
