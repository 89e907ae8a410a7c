/* SPDX-License-Identifier: MIT */
/* The polygon mesh container: positions, faces as CSR, optional colours. */
#ifndef LIMN_MESH_H
#define LIMN_MESH_H

#include "limn.h"

struct topology;
struct topology_counts;

struct limn_mesh {
    size_t vertex_count;
    double *positions;        /* 3 * vertex_count */
    size_t face_count;
    uint32_t *face_offsets;   /* face_count + 1 */
    uint32_t *face_indices;   /* face_offsets[face_count] */
    uint8_t *colors;          /* 3 * vertex_count, or NULL */
    /* The topology limn_mesh_repair built (topology/topology.h): lent to one
       call at a time (taken out of the slot atomically and put back, so calls
       on a const mesh from several threads never share it; a call finding the
       slot empty builds its own) and handed over for good to the first
       operator, which frees it once its stencils are built. Dropped when the
       faces change, never copied. The drop function comes with it (the
       topology layer sits above this one). */
    struct topology *_Atomic topology;
    void (*topology_drop)(struct topology *);
    /* The topology's counts without it (topology_counts_get; a plain struct,
       freed with free()): set once, read by any thread, dropped with the
       topology when the faces change. */
    struct topology_counts *_Atomic counts;
    /* Faces never change once a mesh is made, except through
       mesh_faces_own / mesh_faces_replace, so copies share them:
       face_shares is NULL while this mesh alone holds face_offsets and
       face_indices, else the count of meshes holding them (installed on the
       original by the first copy, atomically: copies of a const mesh may run
       on several threads). The last holder frees them. */
    _Atomic size_t *_Atomic face_shares;
};

/* Allocates a mesh with room for the given counts (contents uninitialised,
   face_offsets[0] = 0). Fails with a message on overflow or no memory. */
limn_status mesh_alloc(limn_context *ctx, size_t vertex_count, size_t face_count,
                       size_t index_count, limn_mesh **out);

/* Faces this mesh alone holds, before they change: a private copy when
   they are shared (fails only without memory, the mesh unchanged). */
limn_status mesh_faces_own(limn_context *ctx, limn_mesh *mesh);
/* New faces (malloc'd, taken over) in place of the mesh's, which are
   released (freed by their last holder). */
void mesh_faces_replace(limn_mesh *mesh, size_t face_count, uint32_t *face_offsets,
                        uint32_t *face_indices);

/* The end of a call that makes a mesh: on LIMN_OK *out = made, otherwise
   made is destroyed (and *out left as it is); returns st. */
limn_status mesh_hand_over(limn_status st, limn_mesh *made, limn_mesh **out);

/* Device rows (4 doubles a vertex, malloc'd) made positions in place: the
   first 3 of every 4 doubles moved down and the block shrunk; returns the
   block (never NULL: the unshrunk one if realloc fails). */
double *mesh_rows4_to_xyz(double *rows4, size_t vertices);
/* limn_mesh_copy with other positions: mesh's faces shared, colours copied, and
   `positions` (3 doubles a vertex, malloc'd) taken over, freed on failure
   too. For results whose positions already lie in memory of their own. */
limn_status mesh_copy_with_positions(limn_context *ctx, const limn_mesh *mesh, double *positions,
                                     limn_mesh **out);

/* The bounding box (lo, hi; zeros for no vertices) and its diagonal. */
double mesh_bbox_diagonal(const limn_mesh *mesh, double lo[3], double hi[3]);

#endif
