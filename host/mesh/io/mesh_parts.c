/* SPDX-License-Identifier: MIT */
/* A mesh file in parts (mesh_parts.h): the layout of a mesh, each part by
   format, and the single process's whole file. */
#include "mesh/io/mesh_parts.h"
#include "base/context.h"
#include "mesh/io/formats.h"
#include "mesh/mesh.h"

void mesh_layout_faces(const uint32_t *face_offsets, size_t face_count, uint32_t *max_face,
                       uint64_t *triangles)
{
    uint32_t most = 0;
    uint64_t count = 0;
    for (size_t fc = 0; fc < face_count; fc++) {
        uint32_t d = face_offsets[fc + 1] - face_offsets[fc];
        if (d > most)
            most = d;
        count += d > 2 ? d - 2 : 0;
    }
    *max_face = most;
    *triangles = count;
}

limn_status mesh_layout_check(limn_context *ctx, const char *path, const mesh_layout *l)
{
    if (l->format == LIMN_FORMAT_STL && l->triangles > UINT32_MAX)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "cannot write %s: %llu triangles do not fit STL",
                         path, (unsigned long long)l->triangles);
    return LIMN_OK;
}

static int is_ply(limn_format f)
{
    return f == LIMN_FORMAT_PLY || f == LIMN_FORMAT_PLY_ASCII || f == LIMN_FORMAT_PLY_BINARY_BE;
}

limn_status mesh_part_header(limn_context *ctx, const char *path, const mesh_layout *l,
                             const block_sink *sink)
{
    if (is_ply(l->format))
        return ply_header(ctx, path, l, sink);
    if (l->format == LIMN_FORMAT_STL)
        return stl_header(ctx, path, l, sink);
    return text_header(ctx, path, l, sink);
}

limn_status mesh_part_vertices(limn_context *ctx, const char *path, const mesh_layout *l,
                               const mesh_block *block, size_t first, const block_sink *sink)
{
    if (is_ply(l->format))
        return ply_vertices(ctx, path, l, block, sink);
    if (l->format == LIMN_FORMAT_STL)
        return stl_vertices(ctx, path, block, first);
    return text_vertices(ctx, path, l, block, sink);
}

limn_status mesh_part_faces(limn_context *ctx, const char *path, const mesh_layout *l,
                            const mesh_block *block, const block_sink *sink)
{
    if (is_ply(l->format))
        return ply_faces(ctx, path, l, block, sink);
    if (l->format == LIMN_FORMAT_STL)
        return stl_faces(ctx, path, block, sink);
    return text_faces(ctx, path, l, block, sink);
}

limn_status mesh_parts_write(limn_context *ctx, const limn_mesh *m, const char *path, FILE *f,
                             limn_format format, int single)
{
    mesh_layout l = {format, single, m->colors != NULL, m->vertex_count, m->face_count, 0, 0};
    mesh_layout_faces(m->face_offsets, m->face_count, &l.max_face, &l.triangles);
    mesh_block b = {m->vertex_count, m->positions, m->colors,
                    m->face_count, m->face_offsets, m->face_indices};
    block_sink sink = block_sink_file(f);
    limn_status st = mesh_layout_check(ctx, path, &l);
    if (!st && format == LIMN_FORMAT_STL) /* STL: refused before any byte */
        st = stl_vertices(ctx, path, &b, 0);
    if (!st)
        st = mesh_part_header(ctx, path, &l, &sink);
    if (!st && format != LIMN_FORMAT_STL)
        st = mesh_part_vertices(ctx, path, &l, &b, 0, &sink);
    return st ? st : mesh_part_faces(ctx, path, &l, &b, &sink);
}
