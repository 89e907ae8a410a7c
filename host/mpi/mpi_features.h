/* SPDX-License-Identifier: MIT */
/*
 * limn_denoise_features over ranks, no rank holding the whole mesh
 * (docs/mpi.md "Feature-preserving denoising over ranks"). A rank owns its
 * face block (the rows of W) and its vertex block (the vertex fit); its
 * patch holds every face sharing a vertex with a block face (W's rows
 * complete), every face around a block vertex (the fit complete) and the
 * vertices of those faces. Patch vertices and faces are in increasing
 * global id, so every row, every vertex's faces and every sum come in the
 * single process's order: the same bits. The other ranks' faces and
 * vertices of the patch (its ghosts) are refreshed from their block owners
 * after each product of W (normals) and each vertex sweep (positions).
 * Internal to the MPI layer.
 */
#ifndef LIMN_MPI_FEATURES_H
#define LIMN_MPI_FEATURES_H

#include "mpi/mpi_mesh.h"

typedef struct mpi_feature_patch {
    limn_mesh *mesh;          /* local numbers; positions of every patch vertex */
    uint32_t *vertex_ids;     /* global id of each patch vertex, increasing */
    uint32_t *face_ids;       /* global id of each patch face, increasing */
    size_t vertex_base;       /* patch vertex of the block's first vertex */
    size_t face_base;         /* patch face of the block's first face */
    size_t vertex_ghosts, face_ghosts;
    uint32_t *vertex_ghost_ids, *face_ghost_ids; /* increasing */
    size_t *vertex_ghost_at, *face_ghost_at;     /* their patch indices */
    double *buf;              /* 3 per ghost, the more numerous kind */
} mpi_feature_patch;

/* Collective, agreed: this rank's patch of mesh (positions fetched). */
limn_status mpi_feature_patch_build(mpi_part *p, const limn_mpi_mesh *mesh,
                                    mpi_feature_patch *out);
void mpi_feature_patch_free(mpi_feature_patch *fp);

/* Collective, agreed: the ghosts' values (3 per vertex or face) from their
   block owners, into x (patch vertices) or n (patch faces). */
limn_status mpi_feature_sync_vertices(mpi_part *p, const limn_mpi_mesh *mesh,
                                      mpi_feature_patch *fp, double *x);
limn_status mpi_feature_sync_faces(mpi_part *p, const limn_mpi_mesh *mesh,
                                   mpi_feature_patch *fp, double *n);

#endif
