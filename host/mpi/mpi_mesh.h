/* SPDX-License-Identifier: MIT */
/*
 * The distributed mesh of limn_mpi.h (limn_mpi_mesh): this rank's vertex
 * and face blocks (a mesh_slice, global numbering) and where every rank's
 * blocks begin. Internal to the MPI layer.
 */
#ifndef LIMN_MPI_MESH_H
#define LIMN_MPI_MESH_H

#include "limn_mpi.h"

#include "mesh/io/mesh_slice.h"
#include "mpi/mpi_part.h"

/* The whole mesh's topology counts as topology.h has them
   (mpi_mesh_census.c: each vertex's ring on its block owner). */
typedef struct mpi_mesh_counts {
    size_t boundary_edges;       /* one face */
    size_t nonmanifold_edges;    /* more than two, or two in the same direction */
    size_t inconsistent_edges;   /* two in the same direction */
    size_t nonmanifold_vertices; /* on such an edge, or faces in several fans */
    size_t referenced_vertices;  /* used by a face */
} mpi_mesh_counts;

struct limn_mpi_mesh {
    MPI_Comm comm;        /* the caller's, duplicated */
    int rank, size;
    size_t *vertex_dist;  /* size + 1: rank r holds vertices [dist[r], dist[r+1]) */
    size_t *face_dist;    /* size + 1: the same for faces */
    mesh_slice slice;
    uint8_t *colors;      /* 3 per vertex of the block, or NULL (limn_mpi_mesh_texture) */
    /* The sub-mesh of this rank under the default partition, with its
       topology, left by limn_mpi_mesh_repair (which counted from it) for the
       next call that builds rows (mpi_mesh_build_rows takes it), as the
       single process's repair leaves the topology; NULL when none. */
    struct mpi_local_mesh *_Atomic sub;
    /* The census limn_mpi_mesh_repair took (valid when has_counts): the
       counts a call needs later (subdivide's estimate) without another. */
    mpi_mesh_counts counts;
    int has_counts;
};

/* The repair's sub-mesh out of the mesh (NULL when none): the caller's. */
struct mpi_local_mesh *mpi_mesh_take_sub(const limn_mpi_mesh *mesh);
/* Frees the repair's sub-mesh, if any: calls that never build rows from
   it (refinement) drop it before their own memory peak. */
void mpi_mesh_drop_sub(const limn_mpi_mesh *mesh);

/* A handle over comm taking the slice (zeroed in *slice on success);
   collective (the blocks' beginnings are gathered and checked). */
limn_status mpi_mesh_adopt(mpi_part *p, mesh_slice *slice, limn_mpi_mesh **out);

/* An mpi_part over the mesh's communicator (mpi_part_begin). */
limn_status mpi_mesh_part(limn_context *ctx, const limn_mpi_mesh *mesh,
                          const limn_mpi_options *mpi, mpi_part *p);

/* The bounding box diagonal of the whole mesh, as mesh_bbox_diagonal
   computes it (min and max are exact under any reduction order). */
double mpi_mesh_bbox_diagonal(mpi_part *p, const limn_mpi_mesh *mesh);

/* The checks of check_mesh_magnitude over the ranks (non-finite or too large
   coordinates, named by global vertex); agreed. */
limn_status mpi_mesh_check(mpi_part *p, const char *fn, const limn_mpi_mesh *mesh);

/* operator_resolve_scheme over the ranks: auto is Loop when every face of
   every rank is a triangle (and there are faces); agreed. */
limn_status mpi_mesh_scheme(mpi_part *p, const limn_mpi_mesh *mesh, limn_scheme want,
                            limn_scheme *out);

/* The rows of a distributed mesh (mpi_mesh_interpolate.c; shared with the
   series, mpi_mesh_series.c): the partition (p->partition: the Hilbert
   curve or PT-Scotch), then p filled by mpi_local_build; or, under the
   curve, from the sub-mesh limn_mpi_mesh_repair left (no partition or
   face exchange again). *m4 the owned rows of M (4 doubles a row, caller
   frees). */
limn_status mpi_mesh_build_rows(mpi_part *p, const limn_mpi_mesh *mesh, limn_scheme scheme,
                                double alpha, double **m4);

/* The owned rows of p4 (4 doubles a row, p's local order) into the vertex
   blocks of a new positions array *block (3 per block vertex, caller's). */
limn_status mpi_mesh_results_to_blocks(mpi_part *p, const limn_mpi_mesh *mesh, const double *p4,
                                       double **block);

/* A copy of mesh's blocks (faces copied) with new positions (3 per block
   vertex, taken even on failure) as a new distributed mesh *out. */
limn_status mpi_mesh_control_of(mpi_part *p, const limn_mpi_mesh *mesh, double *positions,
                                limn_mpi_mesh **out);

/* mesh_repair.c's duplicate faces over the ranks (mpi_mesh_duplicates.c):
   r->duplicate_faces, first_duplicate_face (SIZE_MAX when none) and _of in
   global face numbers, the duplicates dropped when remove (face blocks
   renumbered, duplicates_removed). Collective, agreed. */
limn_status mpi_mesh_duplicates(mpi_part *p, limn_mpi_mesh *mesh, int remove,
                                limn_repair_report *r);

/* Collective, agreed. */
limn_status mpi_mesh_census(mpi_part *p, const limn_mpi_mesh *mesh, mpi_mesh_counts *out);
/* limn_denoise's refusal of a mesh whose volume is not defined (its
   message), from the census (mpi_mesh_series.c). Collective, agreed. */
limn_status mpi_mesh_check_closed(mpi_part *p, const limn_mpi_mesh *mesh);

/* ------------------------------------------------------ mpi_mesh_measure.c */

/* n running sums carried from rank to rank in rank order: this rank adds
   its terms (count of them, n each, in order) to what the previous rank
   passed on, so the additions are one process's in its order; every rank
   gets the totals in sum. Collective. */
void mpi_mesh_chained_sums(mpi_part *p, const double *terms, size_t count, int n, double *sum);

/* measure_volume_area of the whole mesh with the vertex blocks' positions
   `block` (3 per block vertex): the same bits (terms on every rank, added
   in face order from rank to rank). Collective, agreed. */
limn_status mpi_mesh_volume_area(mpi_part *p, const limn_mpi_mesh *mesh, const double *block,
                                 double *volume, double *area);

/* The mean of the vertices of block, summed in input order as
   limn_mesh_measure sums them (from rank to rank). Collective. */
void mpi_mesh_centroid(mpi_part *p, const limn_mpi_mesh *mesh, const double *block, double c[3]);

/* series_keep_volume on distributed meshes: out (same blocks as in) scaled
   about the mean of its vertices back to in's volume; the same bits, the
   same refusal. Collective; every rank gets the same status. */
limn_status mpi_mesh_keep_volume(mpi_part *p, const limn_mpi_mesh *in, limn_mpi_mesh *out);

#endif
