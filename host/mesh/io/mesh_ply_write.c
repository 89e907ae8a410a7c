/* SPDX-License-Identifier: MIT */
/*
 * The PLY writer: binary little or big endian or ascii ("%.17g"), positions
 * as doubles (lossless) or, when asked, float32 (ascii: "%.17g" of the
 * float), vertex colours when the mesh has them, the list count type widened
 * to uint only when a face has more than 255 corners: its parts
 * (mesh_parts.h), the binary blocks formatted in parallel (block_write.h).
 * (The reader is mesh_ply.c.)
 */
#include "mesh/io/formats.h"
#include "base/context.h"
#include "mesh/io/mesh_parts.h"
#include "mesh/mesh.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

typedef struct ply_blocks {
    const mesh_block *m;
    int big, single, colors;
    unsigned count_size; /* bytes of a face's corner count: 1 or 4 */
} ply_blocks;

static unsigned char *put(unsigned char *o, uint64_t v, unsigned size, int big)
{
    for (unsigned i = 0; i < size; i++)
        o[big ? size - 1 - i : i] = (unsigned char)(v >> (8 * i));
    return o + size;
}

static size_t vertex_bytes(const ply_blocks *b)
{
    return (b->single ? 12 : 24) + (b->colors ? 3 : 0);
}

static size_t vertex_bound(const void *arg, size_t begin, size_t end)
{
    return (end - begin) * vertex_bytes(arg);
}

static size_t vertex_put(const void *arg, size_t begin, size_t end, unsigned char *out)
{
    const ply_blocks *b = arg;
    const uint8_t *c = b->colors ? b->m->colors : NULL;
    unsigned char *o = out;
    for (size_t v = begin; v < end; v++) {
        const double *p = b->m->positions + 3 * v;
        for (int j = 0; j < 3; j++) {
            if (b->single) {
                float x = (float)p[j];
                uint32_t u;
                memcpy(&u, &x, sizeof u);
                o = put(o, u, 4, b->big);
            } else {
                uint64_t u;
                memcpy(&u, &p[j], sizeof u);
                o = put(o, u, 8, b->big);
            }
        }
        for (int j = 0; c && j < 3; j++)
            *o++ = c[3 * v + j];
    }
    return (size_t)(o - out);
}

static size_t face_bound(const void *arg, size_t begin, size_t end)
{
    const ply_blocks *b = arg;
    const uint32_t *off = b->m->face_offsets;
    return (end - begin) * b->count_size + (size_t)(off[end] - off[begin]) * 4;
}

static size_t face_put(const void *arg, size_t begin, size_t end, unsigned char *out)
{
    const ply_blocks *b = arg;
    const uint32_t *off = b->m->face_offsets, *idx = b->m->face_indices;
    unsigned char *o = out;
    for (size_t fc = begin; fc < end; fc++) {
        o = put(o, off[fc + 1] - off[fc], b->count_size, b->big);
        for (uint32_t i = off[fc]; i < off[fc + 1]; i++)
            o = put(o, idx[i], 4, b->big);
    }
    return (size_t)(o - out);
}

limn_status ply_header(limn_context *ctx, const char *path, const mesh_layout *l,
                       const block_sink *sink)
{
    const char *count_type = l->max_face > 255 ? "uint" : "uchar";
    const char *index_type = l->vertex_total > 2147483647u ? "uint" : "int";
    const char *name = l->format == LIMN_FORMAT_PLY_ASCII       ? "ascii"
                       : l->format == LIMN_FORMAT_PLY_BINARY_BE ? "binary_big_endian"
                                                                : "binary_little_endian";
    const char *type = l->single ? "float" : "double";
    char head[512];
    int n = snprintf(head, sizeof head,
                     "ply\nformat %s 1.0\ncomment written by limn\nelement vertex %zu\n"
                     "property %s x\nproperty %s y\nproperty %s z\n%s"
                     "element face %zu\nproperty list %s %s vertex_indices\nend_header\n",
                     name, l->vertex_total, type, type, type,
                     l->colors ? "property uchar red\nproperty uchar green\nproperty uchar blue\n"
                               : "",
                     l->face_total, count_type, index_type);
    if (n < 0 || (size_t)n >= sizeof head)
        return ctx_fail(ctx, LIMN_ERR_IO, "cannot write %s: header too long", path);
    return sink->put(sink->arg, ctx, path, head, (size_t)n);
}

static ply_blocks blocks_of(const mesh_layout *l, const mesh_block *b)
{
    return (ply_blocks){b, l->format == LIMN_FORMAT_PLY_BINARY_BE, l->single, l->colors,
                        l->max_face > 255 ? 4 : 1};
}

limn_status ply_vertices(limn_context *ctx, const char *path, const mesh_layout *l,
                         const mesh_block *b, const block_sink *sink)
{
    if (l->format == LIMN_FORMAT_PLY_ASCII)
        return text_vertices(ctx, path, l, b, sink);
    ply_blocks pb = blocks_of(l, b);
    block_job job = {b->vertex_count, vertex_bytes(&pb), vertex_bound, vertex_put, &pb};
    return block_emit(ctx, path, &job, sink);
}

limn_status ply_faces(limn_context *ctx, const char *path, const mesh_layout *l,
                      const mesh_block *b, const block_sink *sink)
{
    if (l->format == LIMN_FORMAT_PLY_ASCII)
        return text_faces(ctx, path, l, b, sink);
    ply_blocks pb = blocks_of(l, b);
    block_job job = {b->face_count, pb.count_size + 12, face_bound, face_put, &pb};
    return block_emit(ctx, path, &job, sink);
}

limn_status ply_write(limn_context *ctx, const limn_mesh *m, const char *path, FILE *f,
                      limn_format format, int single)
{
    return mesh_parts_write(ctx, m, path, f, format, single);
}

void ply_float_error(const limn_mesh *m, double *max_error, double *mean_error)
{
    double most = 0, sum = 0; /* in vertex order: the same sum for any thread count */
    for (size_t v = 0; v < m->vertex_count; v++) {
        const double *p = m->positions + 3 * v;
        double dx = p[0] - (double)(float)p[0], dy = p[1] - (double)(float)p[1],
               dz = p[2] - (double)(float)p[2];
        double d = sqrt(dx * dx + dy * dy + dz * dz);
        sum += d;
        if (d > most)
            most = d;
    }
    *max_error = most;
    *mean_error = m->vertex_count ? sum / (double)m->vertex_count : 0;
}
