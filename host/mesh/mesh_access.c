/* SPDX-License-Identifier: MIT */
/*
 * A mesh's data to and from the caller's own buffers (embedding, README
 * "Embedding limn"): results copied out, new positions copied in. Sizes are
 * checked before anything is written, so a refused call leaves the caller's
 * buffer and the mesh as they were.
 */
#include "mesh/check.h"
#include "base/context.h"
#include "mesh/mesh.h"

#include <string.h>

size_t limn_mesh_index_count(const limn_mesh *mesh)
{
    return mesh ? mesh->face_offsets[mesh->face_count] : 0;
}

limn_status limn_mesh_copy_positions(limn_context *ctx, const limn_mesh *mesh, double *dst,
                                     size_t capacity_vertices)
{
    ctx_clear(ctx);
    if (!mesh || !dst)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "limn_mesh_copy_positions: %s is NULL",
                         !mesh ? "mesh" : "dst");
    if (capacity_vertices < mesh->vertex_count)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                         "limn_mesh_copy_positions: the buffer holds %zu vertices but the mesh "
                         "has %zu; nothing was copied",
                         capacity_vertices, mesh->vertex_count);
    memcpy(dst, mesh->positions, mesh->vertex_count * 3 * sizeof(double));
    return LIMN_OK;
}

limn_status limn_mesh_copy_faces(limn_context *ctx, const limn_mesh *mesh, uint32_t *offsets,
                                 size_t offsets_capacity, uint32_t *indices,
                                 size_t indices_capacity)
{
    ctx_clear(ctx);
    if (!mesh || !offsets || !indices)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "limn_mesh_copy_faces: %s is NULL",
                         !mesh ? "mesh" : !offsets ? "offsets" : "indices");
    size_t n_off = mesh->face_count + 1, n_idx = mesh->face_offsets[mesh->face_count];
    if (offsets_capacity < n_off || indices_capacity < n_idx)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                         "limn_mesh_copy_faces: the buffers hold %zu offsets and %zu indices but "
                         "the mesh needs %zu (face_count + 1) and %zu "
                         "(limn_mesh_index_count); nothing was copied",
                         offsets_capacity, indices_capacity, n_off, n_idx);
    memcpy(offsets, mesh->face_offsets, n_off * sizeof(uint32_t));
    memcpy(indices, mesh->face_indices, n_idx * sizeof(uint32_t));
    return LIMN_OK;
}

limn_status limn_mesh_copy_colors(limn_context *ctx, const limn_mesh *mesh, uint8_t *dst,
                                  size_t capacity_vertices)
{
    ctx_clear(ctx);
    if (!mesh || !dst)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "limn_mesh_copy_colors: %s is NULL",
                         !mesh ? "mesh" : "dst");
    if (!mesh->colors)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                         "limn_mesh_copy_colors: the mesh has no colours; nothing was copied");
    if (capacity_vertices < mesh->vertex_count)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                         "limn_mesh_copy_colors: the buffer holds %zu vertices but the mesh has "
                         "%zu; nothing was copied",
                         capacity_vertices, mesh->vertex_count);
    memcpy(dst, mesh->colors, mesh->vertex_count * 3);
    return LIMN_OK;
}

limn_status limn_mesh_set_positions(limn_context *ctx, limn_mesh *mesh, const double *positions,
                                    size_t vertex_count)
{
    ctx_clear(ctx);
    if (!mesh || (!positions && vertex_count))
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "limn_mesh_set_positions: %s is NULL",
                         !mesh ? "mesh" : "positions");
    if (vertex_count != mesh->vertex_count)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                         "limn_mesh_set_positions: %zu vertices given but the mesh has %zu; "
                         "nothing was changed",
                         vertex_count, mesh->vertex_count);
    limn_status st = check_positions(ctx, "limn_mesh_set_positions", positions, vertex_count);
    if (st)
        return st; /* the mesh unchanged */
    if (vertex_count)
        memcpy(mesh->positions, positions, vertex_count * 3 * sizeof(double));
    return LIMN_OK;
}
