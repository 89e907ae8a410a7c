/* SPDX-License-Identifier: MIT */
/*
 * Refinement over ranks (docs/mpi.md "Refinement over ranks"), no rank
 * holding the whole mesh. A rank's star is the patch of faces around its
 * block's vertices (every face incident to one of them) plus its own face
 * block: enough to compute, with the single process's refine/ code, the
 * vertex points of its block vertices (their whole ring is there), the edge
 * points of the edges whose lower vertex it holds (every face of such an
 * edge has that vertex) and the face points and child faces of its face
 * block. Patch vertices are in increasing global id and patch faces in
 * increasing global face id, so every row's entries come in the single
 * process's order and sum to its bits. Internal to the MPI layer.
 */
#ifndef LIMN_MPI_REFINE_H
#define LIMN_MPI_REFINE_H

#include "mpi/mpi_mesh.h"

/* A level of the refinement spread over the ranks. A rank keeps the points it
   computes, so its vertices stay where its faces are. The vertex ids are
   segments of the numbering: the input's vertices, then per step its face
   points and, for each segment of the level before, the points of the edges
   whose lower vertex lies in it (edges are numbered by their lower vertex,
   so those of one segment are one range). A segment is either split over the
   ranks in rank order (face points; edge points of such a segment) or a
   directory: owned as a partition says (an input vertex by the lowest rank
   whose face block uses it, so a rank's vertices are where its faces are;
   edge points of such a segment, by their lower vertex's owner), each id's
   owner held in even blocks of the segment. Segments: 2^L after L Loop steps,
   2^(L+1) - 1 for Catmull-Clark (63 at 5 levels). The faces are blocks in
   rank order as in limn_mpi_mesh. */
typedef struct mpi_rseg {
    size_t start, end;     /* ids [start, end) */
    size_t *dist;          /* size + 1: split: rank r owns [dist[r], dist[r+1]);
                              directory: the blocks of dir */
    int directory;
    uint32_t *dir;         /* directory: the owner of each id of this rank's block */
    size_t n_own;
    uint32_t *own;         /* directory: this rank's ids, increasing */
} mpi_rseg;

typedef struct mpi_rmesh {
    int segments;
    mpi_rseg *seg;
    size_t vertex_total, face_total;
    size_t n_owned;        /* this rank's vertices, by segment, then by id */
    double *pos;           /* 3 per owned vertex */
    size_t face_begin, face_count;
    uint32_t *face_offsets, *face_indices; /* CSR from 0, global vertex ids */
    int owns_faces;        /* else a limn_mpi_mesh's (not freed here) */
} mpi_rmesh;

/* The level of a distributed mesh: its vertices moved to their owners (the
   lowest rank whose faces use each), its face blocks borrowed. Collective. */
limn_status mpi_rmesh_of(mpi_part *p, const limn_mpi_mesh *mesh, mpi_rmesh *out);
/* The level moved to even vertex blocks as a new distributed mesh; collective. */
limn_status mpi_rmesh_to_mesh(mpi_part *p, const mpi_rmesh *m, limn_mpi_mesh **out);
void mpi_rmesh_free(mpi_rmesh *m);
/* Collective, agreed: a copy of m with its own segments, m's faces borrowed
   and pos (3 per owned vertex, taken: freed with the copy, also on failure)
   for positions: a second field refined on m's numbering (the texture). */
limn_status mpi_rmesh_borrow(mpi_part *p, const mpi_rmesh *m, double *pos, mpi_rmesh *out);
void mpi_rseg_free(mpi_rseg *s);
/* Collective: the owner of each of n ids (directories asked). */
limn_status mpi_rmesh_owners(mpi_part *p, const mpi_rmesh *m, size_t n, const uint32_t *ids,
                             int *owner);
/* The segment of id; this rank's vertices in segment s. */
int mpi_rmesh_segment(const mpi_rmesh *m, size_t id);
size_t mpi_rseg_count(const mpi_rseg *s, int rank);
/* The index of id among this rank's vertices (SIZE_MAX: not its), and the
   global id of this rank's vertex i. */
size_t mpi_rmesh_local(const mpi_rmesh *m, int rank, size_t id);
size_t mpi_rmesh_id(const mpi_rmesh *m, int rank, size_t i);
/* Collective: a directory segment [start, end) owned by this rank's ids own
   (n, increasing, taken): its even blocks and their owners. */
limn_status mpi_rseg_directory(mpi_part *p, size_t start, size_t end, uint32_t *own, size_t n,
                               mpi_rseg *out);

/* This rank's star. */
typedef struct mpi_star {
    limn_mesh *mesh;      /* the patch (positions fetched from the owners) */
    uint32_t *ids;        /* global id of each patch vertex, increasing */
    size_t *face_ids;     /* global id of each patch face, increasing */
    size_t *block_face;   /* patch face of each face of this rank's block */
    size_t largest_vertex_array; /* vertices of the patch (its largest per-vertex array) */
} mpi_star;

/* Collective, agreed: the star of this rank over m (mpi_star.c). */
limn_status mpi_star_build(mpi_part *p, const mpi_rmesh *m, mpi_star *out);
void mpi_star_free(mpi_star *s);

/* The patch vertex of global id v (SIZE_MAX when not in the patch). */
size_t mpi_star_local(const mpi_star *s, uint32_t v);

/* What one level cost this rank (mpi_refine.c). */
typedef struct mpi_refine_stats {
    size_t stencil_nonzeros;     /* entries of the step rows this rank keeps */
    size_t largest_vertex_array; /* entries of the largest per-vertex array: the patch,
                                    the refined patch, the kept points, the new block */
    double share;                /* the largest such array over its level's global vertex
                                    count (the finer level's for a step), any level */
    size_t owned;                /* the finest level's vertices this rank computed */
    double seconds_plan, seconds_apply;
} mpi_refine_stats;

/* Collective, agreed: one uniform refinement step of mesh (scheme resolved,
   LOOP or CATMARK; alpha the first step's) as a new distributed mesh *out
   whose vertices and faces are numbered as refine_plan_build numbers level 1
   of the whole mesh: old vertices, face points (Catmull-Clark) in face
   order, edge points in edge order; each rank owning what it computed.
   mesh's segments move to *out. */
limn_status mpi_refine_level(mpi_part *p, mpi_rmesh *mesh, limn_scheme scheme,
                             double alpha, mpi_rmesh *out, mpi_refine_stats *stats);

/* Collective, agreed: limn_limit_positions of the whole mesh, each rank's
   vertices from its star, in place of m's positions. */
limn_status mpi_refine_limit(mpi_part *p, mpi_rmesh *m, limn_scheme scheme, double alpha,
                             mpi_refine_stats *stats);

/* limn_mpi_mesh_subdivide with this rank's figures (*stats, may be NULL):
   the per-rank memory test's probe (stats->share < 1: no rank allocated an
   array of a level's global vertex count). */
limn_status mpi_mesh_subdivide(limn_context *ctx, const limn_mpi_mesh *mesh,
                               const limn_subdivide_options *options, limn_mpi_mesh **surface,
                               limn_subdivide_report *report, const limn_mpi_options *mpi,
                               limn_mpi_result *result, mpi_refine_stats *stats);

/* limn_subdivide's memory check per rank (mpi_mesh_subdivide.c): the single
   process's estimate of refining mesh `levels` times (with the limit's
   table when `limit`) from the global counts (edges (corners + boundary
   edges) / 2: exact on manifold meshes, above otherwise), its per-vertex
   part times a rank's share (1/P + 0.2, at most 1), the runtime whole;
   refused (LIMN_ERR_MEMORY, the sizes named "a rank") above max_memory,
   else three quarters of physical memory over the ranks on this node.
   *estimate: a rank's estimate. Collective, agreed. */
limn_status mpi_refine_budget(mpi_part *p, const limn_mpi_mesh *mesh, limn_scheme scheme,
                              int levels, int limit, size_t max_memory, size_t *estimate);

#endif
