/* SPDX-License-Identifier: MIT */
/* Topology construction (the passes: topology_build.h), the mesh's cached
   topology, and the scratch the passes share (their sorts: topology_sort.c). */
#include "base/large_alloc.h"
#include "mesh/check.h"
#include "topology/topology_build.h"
#include "topology/topology_sets.h"
#include "base/context.h"
#include "mesh/mesh.h"

#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

/* Room for want items of size bytes at *p (doubling, at least least). */
static int grow(void **p, size_t *cap, size_t want, size_t size, size_t least)
{
    if (want <= *cap)
        return 1;
    size_t n = want < least ? least : 2 * want;
    void *q = realloc(*p, n * size);
    if (!q)
        return 0;
    *p = q;
    *cap = n;
    return 1;
}

int topo_scratch_reserve(topo_scratch *s, size_t keys, size_t words)
{
    void *k = s->keys, *w = s->words;
    int ok = grow(&k, &s->key_cap, keys, sizeof *s->keys, 64);
    s->keys = k;
    ok = ok && grow(&w, &s->word_cap, words, sizeof *s->words, 256);
    s->words = w;
    return ok;
}

void topo_scratch_free(topo_scratch *s)
{
    free(s->keys);
    free(s->words);
    memset(s, 0, sizeof *s);
}

unsigned topo_range(const topo_build *b, size_t n, size_t begin)
{
    return parallel_part(n, b->parts, begin);
}

void topology_free(topology *t);

static void topology_destroy(struct topology *t)
{
    topology_free(t);
    free(t);
}

void topology_free(topology *t)
{
    if (!t)
        return;
    if (t->lent) {
        /* the mesh's own: back into its slot (freed if the slot was filled
           meanwhile, which only a call changing the mesh could do) */
        struct topology *_Atomic *slot = &((limn_mesh *)t->lent_by)->topology;
        struct topology *expected = NULL;
        if (!atomic_compare_exchange_strong(slot, &expected, t->lent))
            topology_destroy(t->lent);
        memset(t, 0, sizeof *t);
        return;
    }
    free(t->corner_face);
    free(t->corner_edge);
    free(t->edge_vertices);
    free(t->edge_corner_offsets);
    free(t->edge_corners);
    free(t->vertex_corner_offsets);
    free(t->vertex_corners);
    free(t->vertex_edge_offsets);
    free(t->vertex_edges);
    free(t->edge_flags);
    free(t->vertex_flags);
    free(t->vertex_rule);
    free(t->crease_neighbors);
    memset(t, 0, sizeof *t);
}

typedef struct components_job {
    const topology *t;
    _Atomic uint32_t *parent;
    int boundary;            /* 0: every edge, faces' components; 1: boundary edges, loops */
    size_t roots[PARALLEL_MAX];
    unsigned parts;
} components_job;

static int components_init(void *arg, size_t begin, size_t end)
{
    components_job *j = arg;
    for (size_t v = begin; v < end; v++)
        atomic_init(&j->parent[v], (uint32_t)v);
    return 0;
}

static int components_unite(void *arg, size_t begin, size_t end)
{
    components_job *j = arg;
    const topology *t = j->t;
    for (size_t e = begin; e < end; e++)
        if (!j->boundary || (t->edge_flags[e] & EDGE_BOUNDARY))
            topo_unite(j->parent, t->edge_vertices[2 * e], t->edge_vertices[2 * e + 1]);
    return 0;
}

/* Roots after every union: each set has exactly one. */
static int components_roots(void *arg, size_t begin, size_t end)
{
    components_job *j = arg;
    const topology *t = j->t;
    size_t n = 0;
    for (size_t v = begin; v < end; v++) {
        int counted = j->boundary ? (t->vertex_flags[v] & VERTEX_BOUNDARY) != 0
                                  : t->vertex_corner_offsets[v + 1] > t->vertex_corner_offsets[v];
        n += counted && atomic_load_explicit(&j->parent[v], memory_order_relaxed) == v;
    }
    j->roots[parallel_part(t->vertex_count, j->parts, begin)] = n;
    return 0;
}

/* Sets of j->t's vertices joined by its edges (boundary edges when
   j->boundary), counted over the referenced (boundary) vertices. */
static size_t count_sets(components_job *j)
{
    size_t nv = j->t->vertex_count, total = 0;
    memset(j->roots, 0, sizeof j->roots);
    parallel_run(nv, j->parts, components_init, j);
    parallel_run(j->t->edge_count, j->parts, components_unite, j);
    parallel_run(nv, j->parts, components_roots, j);
    for (unsigned i = 0; i < PARALLEL_MAX; i++)
        total += j->roots[i];
    return total;
}

/* Components of the faces (through shared vertices) and connected pieces of
   the boundary-edge graph (the boundary loops of a manifold mesh), over the
   host threads. */
static limn_status count_components(limn_context *ctx, topology *t, unsigned parts)
{
    size_t nv = t->vertex_count;
    components_job j = {.t = t, .parts = parts};
    j.parent = large_malloc((nv ? nv : 1) * sizeof *j.parent);
    if (!j.parent)
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory counting components");
    t->components = count_sets(&j);
    j.boundary = 1;
    t->boundary_loops = count_sets(&j);
    free((void *)j.parent);
    return LIMN_OK;
}

limn_status topo_gather(limn_context *ctx, topo_build *b)
{
    topology *t = b->t;
    for (unsigned i = 0; i < PARALLEL_MAX; i++) {
        const topo_counts *k = &b->counts[i];
        if (k->no_memory)
            return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for the topology of %zu vertices",
                            t->vertex_count);
        /* ranges are in face order: the first range's bad face is the first one */
        if (k->bad_face != SIZE_MAX)
            return ctx_fail(ctx, LIMN_ERR_TOPOLOGY,
                            "face %zu uses vertex %u twice (a degenerate face); remove it "
                            "or repair the mesh",
                            k->bad_face, k->bad_vertex);
    }
    return LIMN_OK;
}

static void sum_counts(topo_build *b)
{
    topology *t = b->t;
    for (unsigned i = 0; i < PARALLEL_MAX; i++) {
        const topo_counts *k = &b->counts[i];
        t->boundary_edges += k->boundary_edges;
        t->nonmanifold_edges += k->nonmanifold_edges;
        t->inconsistent_edges += k->inconsistent_edges;
        t->nonmanifold_vertices += k->nonmanifold_vertices;
        t->referenced_vertices += k->referenced_vertices;
        t->triangles += k->triangles;
        t->quads += k->quads;
        t->other_faces += k->other_faces;
        t->thin_vertices += k->thin_vertices;
        if (k->max_valence > t->max_valence)
            t->max_valence = k->max_valence;
        if (k->max_face_size > t->max_face_size)
            t->max_face_size = k->max_face_size;
    }
}

static limn_status no_memory(limn_context *ctx, const topology *t)
{
    return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for the topology of %zu vertices",
                    t->vertex_count);
}

/* The vertices' cursors: cleared, then their corner counts copied out
   (offsets to be), then set to where each vertex's bucket starts. */
static int cursor_clear(void *arg, size_t begin, size_t end)
{
    topo_build *b = arg;
    for (size_t v = begin; v < end; v++)
        atomic_store_explicit(&b->cursor[v], 0, memory_order_relaxed);
    return 0;
}

static int cursor_counts(void *arg, size_t begin, size_t end)
{
    topo_build *b = arg;
    for (size_t v = begin; v < end; v++)
        b->t->vertex_corner_offsets[v + 1] =
            atomic_load_explicit(&b->cursor[v], memory_order_relaxed);
    return 0;
}

static int cursor_starts(void *arg, size_t begin, size_t end)
{
    topo_build *b = arg;
    for (size_t v = begin; v < end; v++)
        atomic_store_explicit(&b->cursor[v], b->t->vertex_corner_offsets[v],
                              memory_order_relaxed);
    return 0;
}

limn_status topo_place_corners(limn_context *ctx, topo_build *b)
{
    topology *t = b->t;
    size_t nv = t->vertex_count;
    parallel_run(nv, b->parts, cursor_clear, b);
    topo_faces(b);
    limn_status st = topo_gather(ctx, b);
    if (st)
        return st;
    topo_corner_counts(b);
    ctx_progress(ctx, "topology", 0.15);
    parallel_run(nv, b->parts, cursor_counts, b);
    parallel_prefix_u32(t->vertex_corner_offsets, nv, b->parts);
    parallel_run(nv, b->parts, cursor_starts, b);
    topo_scatter(b);
    ctx_progress(ctx, "topology", 0.3);
    return LIMN_OK;
}

/* Passes 1-3: face checks, vertex buckets, and the counts that place edges. */
static limn_status place(limn_context *ctx, topo_build *b)
{
    topology *t = b->t;
    size_t nv = t->vertex_count;
    limn_status st = topo_place_corners(ctx, b);
    if (st)
        return st;
    topo_count(b);
    st = topo_gather(ctx, b);
    if (st)
        return st;
    parallel_prefix_u32(t->vertex_edge_offsets, nv, b->parts);
    parallel_prefix_u32(b->edge_base, nv, b->parts);
    parallel_prefix_u32(b->entry_base, nv, b->parts);
    ctx_progress(ctx, "topology", 0.5);
    return LIMN_OK;
}

/* The buckets' vertices are done with: their pages, already faulted in,
   become corner_face (the same size) and vertex_edges where 2 edges a
   corner fit (any closed triangle mesh), instead of fresh ones; both are
   written whole. Where they do not fit (a boundary), a fresh array: a grown
   realloc would copy the buckets into unadvised 4 KiB pages, since the
   huge-page advice splits a large block's mapping (large_advise) and the
   kernel then refuses glibc's mremap of the whole block. */
static void reuse_buckets(topo_build *b)
{
    topology *t = b->t;
    size_t ve = t->edge_count ? 2 * t->edge_count : 1, nc = t->corner_count ? t->corner_count : 1;
    free(b->wrap);
    t->corner_face = b->prev;
    if (ve <= nc) {
        uint32_t *shrunk = realloc(b->next, ve * sizeof *shrunk);
        t->vertex_edges = shrunk ? shrunk : b->next;
    } else {
        free(b->next);
        t->vertex_edges = large_malloc(ve * sizeof *t->vertex_edges);
    }
    b->next = b->prev = NULL;
    b->wrap = NULL;
}

/* Passes 4-5 and the components, once the edges are counted. */
static limn_status connect(limn_context *ctx, topo_build *b)
{
    topology *t = b->t;
    size_t ne = b->edge_base[t->vertex_count], nc = t->corner_count;
    t->edge_count = ne;
    t->edge_vertices = large_malloc((ne ? ne : 1) * 2 * sizeof *t->edge_vertices);
    t->edge_corner_offsets = large_malloc((ne + 1) * sizeof *t->edge_corner_offsets);
    t->edge_flags = large_malloc(ne ? ne : 1);
    t->edge_corners = large_malloc((nc ? nc : 1) * sizeof *t->edge_corners);
    if (!t->edge_vertices || !t->edge_corner_offsets || !t->edge_flags || !t->edge_corners)
        return no_memory(ctx, t);
    topo_edges(b);
    limn_status st = topo_gather(ctx, b);
    if (st)
        return st;
    t->edge_corner_offsets[ne] = (uint32_t)nc;
    ctx_progress(ctx, "topology", 0.8);
    reuse_buckets(b);
    if (!t->vertex_edges || !t->corner_face)
        return no_memory(ctx, t);
    topo_vertex_edges(b);
    topo_corner_faces(b);
    sum_counts(b);
    ctx_progress(ctx, "topology", 0.9);
    return count_components(ctx, t, b->parts);
}

static atomic_size_t builds;

size_t topology_build_count(void)
{
    return atomic_load(&builds);
}

limn_status topology_build(limn_context *ctx, const limn_mesh *mesh, topology *t)
{
    atomic_fetch_add(&builds, 1);
    memset(t, 0, sizeof *t);
    t->vertex_count = mesh->vertex_count;
    t->face_count = mesh->face_count;
    t->face_offsets = mesh->face_offsets;
    t->face_indices = mesh->face_indices;
    t->corner_count = mesh->face_offsets[mesh->face_count];
    size_t nv = t->vertex_count, nc = t->corner_count;
    topo_build b;
    memset(&b, 0, sizeof b);
    b.t = t;
    /* about 60 bytes a corner are read and written */
    b.parts = parallel_threads(ctx, (uint64_t)nc * 60);
    for (unsigned i = 0; i < PARALLEL_MAX; i++)
        b.counts[i].bad_face = SIZE_MAX;
    t->vertex_corner_offsets = large_malloc((nv + 1) * sizeof *t->vertex_corner_offsets);
    t->vertex_corners = large_malloc((nc ? nc : 1) * sizeof *t->vertex_corners);
    t->vertex_edge_offsets = large_malloc((nv + 1) * sizeof *t->vertex_edge_offsets);
    t->vertex_flags = large_malloc(nv ? nv : 1);
    t->vertex_rule = large_malloc(nv ? nv : 1);
    t->crease_neighbors = large_malloc((nv ? nv : 1) * 2 * sizeof *t->crease_neighbors);
    b.cursor = large_malloc((nv ? nv : 1) * sizeof *b.cursor);
    b.next = large_malloc((nc ? nc : 1) * sizeof *b.next);
    b.prev = large_malloc((nc ? nc : 1) * sizeof *b.prev);
    b.wrap = large_malloc(nc ? nc : 1);
    b.edge_base = large_malloc((nv + 1) * sizeof *b.edge_base);
    b.entry_base = large_malloc((nv + 1) * sizeof *b.entry_base);
    limn_status st = LIMN_OK;
    if (!t->vertex_corner_offsets || !t->vertex_corners ||
        !t->vertex_edge_offsets || !t->vertex_flags || !t->vertex_rule || !t->crease_neighbors ||
        !b.cursor || !b.next || !b.prev || !b.wrap || !b.edge_base || !b.entry_base)
        st = no_memory(ctx, t);
    if (!st)
        st = place(ctx, &b);
    if (!st)
        st = connect(ctx, &b);
    free(b.cursor);
    free(b.next);
    free(b.prev);
    free(b.wrap);
    free(b.edge_base);
    free(b.entry_base);
    if (st)
        topology_free(t);
    else
        ctx_progress(ctx, "topology", 1.0);
    return st;
}

/* ------------------------------------------------ the mesh's cached one */


/* The mesh's topology out of its slot (NULL when empty or out on loan). */
static topology *slot_take(const limn_mesh *mesh)
{
    return atomic_exchange(&((limn_mesh *)mesh)->topology, NULL);
}

limn_status topology_get(limn_context *ctx, const limn_mesh *mesh, topology *out)
{
    topology *t = slot_take(mesh);
    if (!t)
        return topology_build(ctx, mesh, out);
    *out = *t;
    out->lent_by = mesh;
    out->lent = t;
    return LIMN_OK;
}

limn_status topology_take(limn_context *ctx, const limn_mesh *mesh, topology *out)
{
    topology *t = slot_take(mesh);
    if (!t)
        return topology_build(ctx, mesh, out);
    *out = *t;
    free(t);
    return LIMN_OK;
}

void topology_slim(topology *t)
{
    if (t->lent)
        return; /* the mesh's: it stays whole */
    uint32_t **arrays[] = {&t->corner_face,         &t->corner_edge,  &t->edge_vertices,
                           &t->edge_corner_offsets, &t->edge_corners, &t->vertex_corner_offsets,
                           &t->vertex_corners,      &t->vertex_edges, &t->crease_neighbors};
    for (size_t i = 0; i < sizeof arrays / sizeof *arrays; i++) {
        free(*arrays[i]);
        *arrays[i] = NULL;
    }
    free(t->edge_flags);
    free(t->vertex_flags);
    t->edge_flags = t->vertex_flags = NULL;
}

limn_status topology_get_checked(limn_context *ctx, const char *fn, const limn_mesh *mesh,
                                 topology *out)
{
    limn_status st = check_mesh(ctx, fn, NULL, mesh);
    return st ? st : topology_get(ctx, mesh, out);
}

limn_status topology_cache(limn_context *ctx, limn_mesh *mesh, topology *out)
{
    if (!mesh->topology) {
        topology *t = malloc(sizeof *t);
        if (!t)
            return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for a topology");
        limn_status st = topology_build(ctx, mesh, t);
        if (st) {
            free(t);
            return st;
        }
        mesh->topology_drop = topology_destroy;
        atomic_store(&mesh->topology, t);
    }
    return topology_get(ctx, mesh, out);
}

void topology_uncache(limn_mesh *mesh)
{
    topology *t = slot_take(mesh);
    if (t)
        topology_destroy(t);
    free(atomic_exchange(&mesh->counts, NULL));
}

void topology_counts_of(const topology *t, topology_counts *out)
{
    *out = (topology_counts){.edges = t->edge_count,
                             .boundary_edges = t->boundary_edges,
                             .nonmanifold_edges = t->nonmanifold_edges,
                             .inconsistent_edges = t->inconsistent_edges,
                             .nonmanifold_vertices = t->nonmanifold_vertices,
                             .referenced_vertices = t->referenced_vertices,
                             .components = t->components,
                             .boundary_loops = t->boundary_loops,
                             .max_face_size = t->max_face_size,
                             .max_valence = t->max_valence,
                             .thin_vertices = t->thin_vertices,
                             .triangles = t->triangles,
                             .quads = t->quads,
                             .other_faces = t->other_faces};
}

limn_status topology_counts_get(limn_context *ctx, const limn_mesh *mesh, topology_counts *out)
{
    limn_mesh *m = (limn_mesh *)mesh; /* the slots change, the mesh does not */
    const topology_counts *kept = atomic_load(&m->counts);
    if (kept) {
        *out = *kept;
        return LIMN_OK;
    }
    topology *t = slot_take(mesh);
    if (t) {
        topology_counts_of(t, out);
        topology lent = {.lent_by = mesh, .lent = t};
        topology_free(&lent); /* back into its slot */
        return LIMN_OK;
    }
    limn_status st = topology_census(ctx, mesh, out);
    if (st)
        return st;
    topology_counts *keep = malloc(sizeof *keep);
    topology_counts *expected = NULL;
    if (keep) { /* else counted again next time */
        *keep = *out;
        if (!atomic_compare_exchange_strong(&m->counts, &expected, keep))
            free(keep); /* another thread kept its own */
    }
    return LIMN_OK;
}
