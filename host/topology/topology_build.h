/* SPDX-License-Identifier: MIT */
/*
 * The passes of topology_build (topology.c runs them in order):
 *  1. faces (parallel over faces): face kinds and faces that use a vertex
 *     twice; then (parallel over vertex ranges, each reading every corner)
 *     the corner count of every vertex;
 *  2. scatter (parallel over vertex ranges, each reading every face): every
 *     corner with its next and previous vertex into its vertex's bucket, in
 *     increasing corner order (vertex_corners order);
 *  3. count (parallel over vertices): the vertex's valence, its owned edges
 *     (the lower end owns an edge) and their corners;
 *  4. edges (parallel over vertices): everything about edge {v, w} is in v's
 *     bucket, so each vertex writes its owned edges, classifies itself and
 *     orders its fan without looking at another vertex;
 *  5. vertex edges: owned edges in place, the others through fill cursors,
 *     then each vertex's list sorted; corner_face (parallel over faces), last
 *     so that it is not held beside the buckets.
 * A vertex is only ever written by the thread of its range, buckets fill in
 * corner order and lists are ordered by value, so every array is the same
 * for any thread count (and equal to the sequential build's: tests/oracle).
 */
#ifndef LIMN_TOPOLOGY_BUILD_H
#define LIMN_TOPOLOGY_BUILD_H

#include "base/parallel.h"
#include "topology/topology.h"

#include <stdatomic.h>

/* What one range counted; summed (or maxed) after each pass. */
typedef struct topo_counts {
    size_t boundary_edges, nonmanifold_edges, inconsistent_edges, nonmanifold_vertices;
    size_t referenced_vertices, max_valence, thin_vertices;
    size_t max_face_size, triangles, quads, other_faces;
    size_t bad_face;          /* first face using a vertex twice, or SIZE_MAX */
    uint32_t bad_vertex;
    int no_memory;
} topo_counts;

typedef struct topo_build {
    topology *t;
    unsigned parts;             /* ranges of every pass */
    _Atomic uint32_t *cursor;   /* vertex_count: counts, then fill cursors */
    uint32_t *next, *prev;      /* per vertex_corners slot: the corner's next and previous vertex */
    uint64_t *ring;             /* the census's instead: next << 32 | previous, one store a corner */
    uint8_t *wrap;              /* per slot: the previous corner is c - 1 (0), c + wrap (1..254),
                                   or the face's last (255: looked up); saves two cache misses.
                                   The census has neither it, next, prev nor t->vertex_corners */
    uint32_t *edge_base;        /* vertex_count + 1: the first edge v owns */
    uint32_t *entry_base;       /* vertex_count + 1: v's first edge_corners entry */
    topo_counts counts[PARALLEL_MAX];
} topo_build;

/* Which range of b->parts over [0, n) starts at begin. */
unsigned topo_range(const topo_build *b, size_t n, size_t begin);

/* Growable per-range scratch (a few allocations per range, none per vertex). */
typedef struct topo_scratch {
    uint64_t *keys;
    uint32_t *words;
    size_t key_cap, word_cap;
} topo_scratch;
/* Room for keys 64-bit and words 32-bit values; 0 when out of memory. */
int topo_scratch_reserve(topo_scratch *s, size_t keys, size_t words);
void topo_scratch_free(topo_scratch *s);
void topo_sort_u64(uint64_t *a, size_t n);
void topo_sort_u32(uint32_t *a, size_t n);

/* LIMN_OK, or the ranges' first failure (out of memory, a face using a
   vertex twice: the first such face), said in ctx. */
limn_status topo_gather(limn_context *ctx, topo_build *b);
/* Passes 1 and 2: the face checks and kinds into the counts, every vertex's
   bucket (vertex_corner_offsets; next, prev and, where allocated,
   vertex_corners and wrap). The cursors hold each bucket's end after. */
limn_status topo_place_corners(limn_context *ctx, topo_build *b);

/* Passes 1, 2 (topology_faces.c), 3, 4 (topology_rings.c) and 5
   (topology_vertex_edges.c); each returns nonzero on a range's failure
   (recorded in its counts). */
int topo_faces(topo_build *b);
int topo_corner_counts(topo_build *b);
int topo_scatter(topo_build *b);
int topo_corner_faces(topo_build *b);
int topo_count(topo_build *b);
int topo_edges(topo_build *b);
int topo_vertex_edges(topo_build *b);

#endif
