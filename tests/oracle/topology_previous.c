/* SPDX-License-Identifier: MIT */
/* The previous topology construction (host/topology/topology.c before issue
   13: sequential, edges by bucketing half-edges on their lower vertex), kept
   as the test oracle of the parallel one; symbols renamed, logic unchanged. */
#include "topology_previous.h"
#include "base/context.h"
#include "mesh/mesh.h"

#include <stdlib.h>
#include <string.h>

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

void topology_previous_free(topology *t)
{
    if (!t)
        return;
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

/* Refuses faces that repeat a vertex; counts face kinds. */
static limn_status check_faces(limn_context *ctx, topology *t, uint32_t *mark)
{
    for (uint32_t f = 0; f < t->face_count; f++) {
        uint32_t b = t->face_offsets[f], e = t->face_offsets[f + 1], d = e - b;
        for (uint32_t c = b; c < e; c++) {
            uint32_t v = t->face_indices[c];
            if (mark[v] == f + 1)
                return ctx_fail(ctx, LIMN_ERR_TOPOLOGY,
                                 "face %u uses vertex %u twice (a degenerate face); remove it "
                                 "or repair the mesh",
                                 f, v);
            mark[v] = f + 1;
            t->corner_face[c] = f;
        }
        if (d > t->max_face_size)
            t->max_face_size = d;
        if (d == 3)
            t->triangles++;
        else if (d == 4)
            t->quads++;
        else
            t->other_faces++;
    }
    return LIMN_OK;
}

/* Assigns an id to every undirected edge: half-edges bucketed by lower vertex,
   then each bucket sorted by upper vertex, so ids are deterministic. */
static limn_status build_edges(limn_context *ctx, topology *t)
{
    size_t nv = t->vertex_count, nc = t->corner_count;
    uint32_t *bucket_off = calloc(nv + 1, sizeof *bucket_off);
    uint64_t *bucket = malloc((nc ? nc : 1) * sizeof *bucket); /* (upper << 32) | corner */
    if (!bucket_off || !bucket) {
        free(bucket_off);
        free(bucket);
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory building edges");
    }
    for (size_t c = 0; c < nc; c++) {
        uint32_t a = t->face_indices[c], b = t->face_indices[topology_corner_next(t, (uint32_t)c)];
        bucket_off[(a < b ? a : b) + 1]++;
    }
    for (size_t v = 0; v < nv; v++)
        bucket_off[v + 1] += bucket_off[v];
    uint32_t *fill = malloc((nv ? nv : 1) * sizeof *fill);
    if (!fill) {
        free(bucket_off);
        free(bucket);
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory building edges");
    }
    memcpy(fill, bucket_off, nv * sizeof *fill);
    for (size_t c = 0; c < nc; c++) {
        uint32_t a = t->face_indices[c], b = t->face_indices[topology_corner_next(t, (uint32_t)c)];
        uint32_t lo = a < b ? a : b, hi = a < b ? b : a;
        bucket[fill[lo]++] = ((uint64_t)hi << 32) | c;
    }
    free(fill);
    /* Upper bound on edges is the corner count. */
    t->edge_vertices = malloc((nc ? nc : 1) * 2 * sizeof *t->edge_vertices);
    t->edge_corner_offsets = malloc((nc + 1) * sizeof *t->edge_corner_offsets);
    t->edge_corners = malloc((nc ? nc : 1) * sizeof *t->edge_corners);
    if (!t->edge_vertices || !t->edge_corner_offsets || !t->edge_corners) {
        free(bucket_off);
        free(bucket);
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory building edges");
    }
    size_t ne = 0, k = 0;
    for (size_t v = 0; v < nv; v++) {
        uint64_t *b = bucket + bucket_off[v];
        size_t n = bucket_off[v + 1] - bucket_off[v];
        if (n > 1)
            qsort(b, n, sizeof *b, cmp_u64);
        for (size_t i = 0; i < n; i++) {
            uint32_t hi = (uint32_t)(b[i] >> 32), c = (uint32_t)b[i];
            if (i == 0 || (uint32_t)(b[i - 1] >> 32) != hi) {
                t->edge_corner_offsets[ne] = (uint32_t)k;
                t->edge_vertices[2 * ne] = (uint32_t)v;
                t->edge_vertices[2 * ne + 1] = hi;
                ne++;
            }
            t->edge_corners[k++] = c;
            t->corner_edge[c] = (uint32_t)(ne - 1);
        }
    }
    t->edge_corner_offsets[ne] = (uint32_t)k;
    t->edge_count = ne;
    free(bucket_off);
    free(bucket);
    return LIMN_OK;
}

static void classify_edges(topology *t)
{
    for (size_t e = 0; e < t->edge_count; e++) {
        uint32_t b = t->edge_corner_offsets[e], n = t->edge_corner_offsets[e + 1] - b;
        uint8_t flags = 0;
        if (n == 1) {
            flags = EDGE_BOUNDARY;
            t->boundary_edges++;
        } else if (n > 2) {
            flags = EDGE_NONMANIFOLD;
        } else {
            /* Both corners start at the same vertex: same direction. */
            uint32_t c0 = t->edge_corners[b], c1 = t->edge_corners[b + 1];
            if (t->face_indices[c0] == t->face_indices[c1]) {
                flags = EDGE_NONMANIFOLD | EDGE_INCONSISTENT;
                t->inconsistent_edges++;
            }
        }
        if (flags & EDGE_NONMANIFOLD)
            t->nonmanifold_edges++;
        t->edge_flags[e] = flags;
    }
}

/* Vertex -> corners and vertex -> edges as CSR. */
static limn_status build_vertex_incidence(limn_context *ctx, topology *t)
{
    size_t nv = t->vertex_count;
    t->vertex_corner_offsets = calloc(nv + 1, sizeof(uint32_t));
    t->vertex_corners = malloc((t->corner_count ? t->corner_count : 1) * sizeof(uint32_t));
    t->vertex_edge_offsets = calloc(nv + 1, sizeof(uint32_t));
    t->vertex_edges = malloc((t->edge_count ? 2 * t->edge_count : 1) * sizeof(uint32_t));
    uint32_t *fill = malloc((nv ? nv : 1) * sizeof(uint32_t));
    if (!t->vertex_corner_offsets || !t->vertex_corners || !t->vertex_edge_offsets ||
        !t->vertex_edges || !fill) {
        free(fill);
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory building vertex rings");
    }
    for (size_t c = 0; c < t->corner_count; c++)
        t->vertex_corner_offsets[t->face_indices[c] + 1]++;
    for (size_t e = 0; e < t->edge_count; e++) {
        t->vertex_edge_offsets[t->edge_vertices[2 * e] + 1]++;
        t->vertex_edge_offsets[t->edge_vertices[2 * e + 1] + 1]++;
    }
    for (size_t v = 0; v < nv; v++) {
        t->vertex_corner_offsets[v + 1] += t->vertex_corner_offsets[v];
        t->vertex_edge_offsets[v + 1] += t->vertex_edge_offsets[v];
    }
    memcpy(fill, t->vertex_corner_offsets, nv * sizeof(uint32_t));
    for (size_t c = 0; c < t->corner_count; c++)
        t->vertex_corners[fill[t->face_indices[c]]++] = (uint32_t)c;
    memcpy(fill, t->vertex_edge_offsets, nv * sizeof(uint32_t));
    for (size_t e = 0; e < t->edge_count; e++) {
        t->vertex_edges[fill[t->edge_vertices[2 * e]]++] = (uint32_t)e;
        t->vertex_edges[fill[t->edge_vertices[2 * e + 1]]++] = (uint32_t)e;
    }
    free(fill);
    return LIMN_OK;
}

/* The corner on the other face of the edge leaving v backwards from corner c
   (edge prev(c) -> c, i.e. between v and the previous vertex), or UINT32_MAX. */
static uint32_t across_prev_edge(const topology *t, uint32_t c)
{
    uint32_t pc = topology_corner_prev(t, c);
    uint32_t e = t->corner_edge[pc];
    uint32_t b = t->edge_corner_offsets[e], n = t->edge_corner_offsets[e + 1] - b;
    if (n != 2)
        return UINT32_MAX;
    uint32_t other = t->edge_corners[b] == pc ? t->edge_corners[b + 1] : t->edge_corners[b];
    /* other runs v -> prev vertex; its corner is at v. */
    return other;
}

/* Orders the corners of a vertex with only manifold edges into one fan
   (walking backwards across edges); returns 0 when they form several fans. */
static int order_fan(const topology *t, uint32_t v, uint32_t *scratch)
{
    uint32_t b = t->vertex_corner_offsets[v], n = t->vertex_corner_offsets[v + 1] - b;
    if (n <= 1)
        return 1;
    uint32_t *ring = t->vertex_corners + b;
    /* Start at a corner whose forward edge is a boundary, so the walk
       backwards covers the whole open fan. */
    uint32_t start = ring[0];
    for (uint32_t i = 0; i < n; i++) {
        uint32_t e = t->corner_edge[ring[i]];
        if (t->edge_flags[e] & EDGE_BOUNDARY) {
            start = ring[i];
            break;
        }
    }
    uint32_t count = 0, c = start;
    do {
        if (count == n)
            return 0;
        scratch[count++] = c;
        c = across_prev_edge(t, c);
    } while (c != UINT32_MAX && c != start);
    if (count != n)
        return 0;
    memcpy(ring, scratch, n * sizeof *ring);
    return 1;
}

static void classify_vertices(topology *t, uint32_t *scratch)
{
    for (uint32_t v = 0; v < t->vertex_count; v++) {
        uint32_t eb = t->vertex_edge_offsets[v], ne = t->vertex_edge_offsets[v + 1] - eb;
        uint32_t nf = t->vertex_corner_offsets[v + 1] - t->vertex_corner_offsets[v];
        uint32_t boundary = 0, nonmanifold = 0, sharp[2] = {0, 0}, nsharp = 0;
        for (uint32_t i = 0; i < ne; i++) {
            uint32_t e = t->vertex_edges[eb + i];
            uint8_t fl = t->edge_flags[e];
            boundary += (fl & EDGE_BOUNDARY) != 0;
            nonmanifold += (fl & EDGE_NONMANIFOLD) != 0;
            if (fl & (EDGE_BOUNDARY | EDGE_NONMANIFOLD)) {
                if (nsharp < 2)
                    sharp[nsharp] = topology_edge_other(t, e, v);
                nsharp++;
            }
        }
        if (ne > t->max_valence)
            t->max_valence = ne;
        uint8_t flags = boundary ? VERTEX_BOUNDARY : 0;
        if (nonmanifold || !order_fan(t, v, scratch))
            flags |= VERTEX_NONMANIFOLD;
        if (flags & VERTEX_NONMANIFOLD)
            t->nonmanifold_vertices++;
        t->vertex_flags[v] = flags;
        if (nf)
            t->referenced_vertices++;

        vertex_rule rule;
        int corner = nf == 1 && ne == 2;
        int pinned_nonmanifold = (flags & VERTEX_NONMANIFOLD) &&
                                 !(nonmanifold == 2 && boundary == 0 && nf > ne);
        if (nf == 0)
            rule = RULE_ISOLATED;
        else if (corner || pinned_nonmanifold || nsharp > 2)
            rule = RULE_CORNER;
        else if (nsharp == 2)
            rule = RULE_CREASE;
        else
            rule = RULE_SMOOTH;
        t->vertex_rule[v] = (uint8_t)rule;
        t->crease_neighbors[2 * v] = sharp[0];
        t->crease_neighbors[2 * v + 1] = sharp[1];
    }
}

static uint32_t find_root(uint32_t *parent, uint32_t x)
{
    while (parent[x] != x) {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    return x;
}

static void unite(uint32_t *parent, uint32_t a, uint32_t b)
{
    a = find_root(parent, a);
    b = find_root(parent, b);
    if (a != b)
        parent[a < b ? b : a] = a < b ? a : b;
}

/* Components of the faces (through shared vertices) and connected pieces of
   the boundary-edge graph (the boundary loops of a manifold mesh). */
static limn_status count_components(limn_context *ctx, topology *t)
{
    size_t nv = t->vertex_count;
    uint32_t *parent = malloc((nv ? nv : 1) * sizeof *parent);
    if (!parent)
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory counting components");
    for (uint32_t v = 0; v < nv; v++)
        parent[v] = v;
    for (size_t e = 0; e < t->edge_count; e++)
        unite(parent, t->edge_vertices[2 * e], t->edge_vertices[2 * e + 1]);
    for (uint32_t v = 0; v < nv; v++)
        if (t->vertex_corner_offsets[v + 1] > t->vertex_corner_offsets[v] && find_root(parent, v) == v)
            t->components++;
    for (uint32_t v = 0; v < nv; v++)
        parent[v] = v;
    for (size_t e = 0; e < t->edge_count; e++)
        if (t->edge_flags[e] & EDGE_BOUNDARY)
            unite(parent, t->edge_vertices[2 * e], t->edge_vertices[2 * e + 1]);
    for (uint32_t v = 0; v < nv; v++)
        if ((t->vertex_flags[v] & VERTEX_BOUNDARY) && find_root(parent, v) == v)
            t->boundary_loops++;
    free(parent);
    return LIMN_OK;
}

limn_status topology_previous_build(limn_context *ctx, const limn_mesh *mesh, topology *t)
{
    memset(t, 0, sizeof *t);
    t->vertex_count = mesh->vertex_count;
    t->face_count = mesh->face_count;
    t->face_offsets = mesh->face_offsets;
    t->face_indices = mesh->face_indices;
    t->corner_count = mesh->face_offsets[mesh->face_count];
    size_t nv = t->vertex_count, nc = t->corner_count;
    uint32_t *scratch = calloc(nv > nc ? (nv ? nv : 1) : nc, sizeof *scratch);
    t->corner_face = malloc((nc ? nc : 1) * sizeof *t->corner_face);
    t->corner_edge = malloc((nc ? nc : 1) * sizeof *t->corner_edge);
    t->vertex_flags = malloc(nv ? nv : 1);
    t->vertex_rule = malloc(nv ? nv : 1);
    t->crease_neighbors = malloc((nv ? nv : 1) * 2 * sizeof *t->crease_neighbors);
    limn_status st = LIMN_OK;
    if (!scratch || !t->corner_face || !t->corner_edge || !t->vertex_flags || !t->vertex_rule ||
        !t->crease_neighbors)
        st = ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for the topology of %zu vertices", nv);
    if (!st)
        st = check_faces(ctx, t, scratch);
    if (!st)
        st = build_edges(ctx, t);
    if (!st) {
        t->edge_flags = malloc(t->edge_count ? t->edge_count : 1);
        if (!t->edge_flags)
            st = ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for edge flags");
    }
    if (!st) {
        classify_edges(t);
        st = build_vertex_incidence(ctx, t);
    }
    if (!st) {
        classify_vertices(t, scratch);
        st = count_components(ctx, t);
    }
    free(scratch);
    if (st)
        topology_previous_free(t);
    return st;
}
