/* SPDX-License-Identifier: MIT */
/*
 * Mesh topology: edges, vertex-face and vertex-edge incidence (ordered
 * around manifold vertices), boundary / non-manifold classification and the
 * subdivision rule of every vertex. Built once, in O(n), from the face lists.
 *
 * Classification follows OpenSubdiv (Far::TopologyRefinerFactory with
 * VTX_BOUNDARY_EDGE_AND_CORNER): boundary edges and non-manifold edges are
 * infinitely sharp; a topological corner (one face, two edges) and a
 * non-manifold vertex are pinned, except a vertex on an interior non-manifold
 * crease (exactly two non-manifold edges, no boundary edge, more faces than
 * edges); otherwise the rule follows the number of sharp edges:
 * 0 or 1 smooth, 2 crease, more corner.
 */
#ifndef LIMN_TOPOLOGY_H
#define LIMN_TOPOLOGY_H

#include "limn.h"

enum {
    EDGE_BOUNDARY = 1,       /* one incident face */
    EDGE_NONMANIFOLD = 2,    /* more than two faces, or two that disagree on direction */
    EDGE_INCONSISTENT = 4    /* two faces traverse it in the same direction */
};

enum {
    VERTEX_NONMANIFOLD = 1,  /* on a non-manifold edge, or faces form several fans */
    VERTEX_BOUNDARY = 2      /* on a boundary edge */
};

typedef enum vertex_rule {
    RULE_ISOLATED = 0,       /* no incident face: stays put */
    RULE_SMOOTH = 1,
    RULE_CREASE = 2,         /* exactly two sharp edges: B-spline curve rule */
    RULE_CORNER = 3          /* pinned */
} vertex_rule;

typedef struct topology {
    size_t vertex_count, face_count, edge_count, corner_count;
    const uint32_t *face_offsets;   /* borrowed from the mesh */
    const uint32_t *face_indices;
    uint32_t *corner_face;          /* face of each corner */
    uint32_t *corner_edge;          /* edge from corner k to corner k+1 of its face; NULL
                                       until topology_corner_edges */
    uint32_t *edge_vertices;        /* 2 per edge, lower index first */
    uint32_t *edge_corner_offsets;  /* edge_count + 1 */
    uint32_t *edge_corners;         /* corners whose outgoing edge is this edge */
    uint32_t *vertex_corner_offsets;/* vertex_count + 1 */
    uint32_t *vertex_corners;       /* corners at the vertex, in fan order if manifold */
    uint32_t *vertex_edge_offsets;  /* vertex_count + 1 */
    uint32_t *vertex_edges;
    uint8_t *edge_flags;
    uint8_t *vertex_flags;
    uint8_t *vertex_rule;
    uint32_t *crease_neighbors;     /* 2 per vertex, valid where rule is CREASE */
    /* statistics */
    size_t boundary_edges, nonmanifold_edges, inconsistent_edges, nonmanifold_vertices;
    size_t referenced_vertices, components, boundary_loops;
    size_t max_face_size, max_valence;
    size_t thin_vertices;           /* referenced, with fewer than 3 neighbours */
    size_t triangles, quads, other_faces;
    /* lent by a mesh (topology_get): topology_free puts it back there */
    const struct limn_mesh *lent_by;
    struct topology *lent;
} topology;

/*
 * Builds the topology of mesh (which must outlive it), in parallel over the
 * context's host threads, the same bytes for any count. Refuses, naming the
 * face, a face that uses one vertex twice.
 */
limn_status topology_build(limn_context *ctx, const limn_mesh *mesh, topology *out);
/*
 * The topology of mesh, read-only: the one limn_mesh_repair left on it, lent
 * (one topology per run: repair, info, measure and the operator share it),
 * else built into *out. Either way topology_free(out) after, which puts a
 * lent one back. Another thread's call on the same const mesh meanwhile
 * finds the slot empty and builds its own.
 */
limn_status topology_get(limn_context *ctx, const limn_mesh *mesh, topology *out);
/* check_mesh (the caller's name fn in its messages), then topology_get:
   the opening of the calls that count a caller's mesh (info, measure). */
limn_status topology_get_checked(limn_context *ctx, const char *fn, const limn_mesh *mesh,
                                 topology *out);
/* topology_get, but the mesh's topology is handed over for good (the
   operator, which slims it after its stencils: the mesh's memory stays
   lean through the solve); a later call builds its own. */
limn_status topology_take(limn_context *ctx, const limn_mesh *mesh, topology *out);
/* Frees what an operator no longer reads once its stencils and order are
   built: keeps vertex_rule, vertex_edge_offsets (the row scales) and the
   statistics. */
void topology_slim(topology *t);
/* topology_get after building the cache when it is missing (limn_mesh_repair). */
limn_status topology_cache(limn_context *ctx, limn_mesh *mesh, topology *out);
/* Drops the cached topology and counts: before anything changes the faces. */
void topology_uncache(limn_mesh *mesh);
/* Fills t->corner_edge (the inverse of edge_corners) when it is NULL, over
   the context's host threads; a lent topology's owner keeps it. Refinement
   calls it: the build leaves it out (no other caller reads it). */
limn_status topology_corner_edges(limn_context *ctx, topology *t);
void topology_free(topology *topo);
/* How many times topology_build ran in this process (tests: one per run). */
size_t topology_build_count(void);

/* The topology's counts (limn info, the repair's report). */
typedef struct topology_counts {
    size_t edges, boundary_edges, nonmanifold_edges, inconsistent_edges, nonmanifold_vertices;
    size_t referenced_vertices, components, boundary_loops;
    size_t max_face_size, max_valence, triangles, quads, other_faces;
    size_t thin_vertices; /* referenced, with fewer than 3 neighbours */
} topology_counts;

/*
 * Whether the counts prove that no two faces have the same vertex set, so
 * that the repair's duplicate search can be skipped: every face a triangle or
 * a quad, every edge used at most twice and then both ways, every vertex one
 * fan with at least 3 neighbours. Why: two faces on one vertex set S (3 or 4
 * vertices, none repeated) are either the same cycle (every edge used twice
 * the same way: inconsistent), or one reversed (at each vertex of S their two
 * corners close a fan of 2 corners over edges no other face may use, so the
 * vertex has only those: 2 neighbours), or, for quads, one of the four other
 * orders, each of which uses an edge of the first in its direction. The
 * inconsistent edges need no count of their own: fans follow the corners'
 * orientation, so an edge used twice the same way ends two fans at each of
 * its vertices, which are then non-manifold (a quad of a one-quad-wide ring
 * copied in another order, the copies sharing boundary edges only:
 * tests/test_duplicates.c).
 */
static inline int topology_counts_no_duplicates(const topology_counts *k)
{
    return k->other_faces == 0 && k->nonmanifold_edges == 0 && k->nonmanifold_vertices == 0 &&
           k->thin_vertices == 0;
}

/* The statistics of a built topology as counts. */
void topology_counts_of(const topology *t, topology_counts *out);
/*
 * The counts topology_build's statistics give, without building it: every
 * vertex's bucket of next and previous vertices, its edges and fan from
 * them, the sets by a union-find as the corners go (topology_census.c;
 * about a third of the build's memory). The same counts for any thread
 * count; refuses a face that uses one vertex twice as the build does.
 */
limn_status topology_census(limn_context *ctx, const limn_mesh *mesh, topology_counts *out);
/* The mesh's counts: from its topology when it has one, else the census
   it keeps (made here the first time, then kept until the faces change). */
limn_status topology_counts_get(limn_context *ctx, const limn_mesh *mesh, topology_counts *out);

static inline uint32_t topology_face_size(const topology *t, uint32_t f)
{
    return t->face_offsets[f + 1] - t->face_offsets[f];
}
/* The vertex at corner c of its face, and the corners before/after it. */
static inline uint32_t topology_corner_next(const topology *t, uint32_t c)
{
    uint32_t f = t->corner_face[c];
    return c + 1 < t->face_offsets[f + 1] ? c + 1 : t->face_offsets[f];
}
static inline uint32_t topology_corner_prev(const topology *t, uint32_t c)
{
    uint32_t f = t->corner_face[c];
    return c > t->face_offsets[f] ? c - 1 : t->face_offsets[f + 1] - 1;
}
static inline uint32_t topology_edge_other(const topology *t, uint32_t e, uint32_t v)
{
    return t->edge_vertices[2 * e] == v ? t->edge_vertices[2 * e + 1] : t->edge_vertices[2 * e];
}

#endif
