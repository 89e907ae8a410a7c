/* SPDX-License-Identifier: MIT */
/*
 * The PLY writer: binary little or big endian or ascii ("%.17g"), positions
 * as doubles (lossless) or, when asked, float32 (ascii: "%.17g" of the
 * float), vertex colours when the mesh has them, the list count type widened
 * to uint only when a face has more than 255 corners. The binary blocks are
 * formatted in parallel (block_write.h). (The reader is mesh_ply.c.)
 */
#include "mesh/io/formats.h"
#include "base/context.h"
#include "mesh/io/block_write.h"
#include "mesh/io/text_write.h"
#include "mesh/io/toolkit.h"
#include "mesh/mesh.h"

#include <math.h>
#include <string.h>

typedef struct ply_blocks {
    const limn_mesh *m;
    int big, single;
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
    return (b->single ? 12 : 24) + (b->m->colors ? 3 : 0);
}

static size_t vertex_bound(const void *arg, size_t begin, size_t end)
{
    return (end - begin) * vertex_bytes(arg);
}

static size_t vertex_put(const void *arg, size_t begin, size_t end, unsigned char *out)
{
    const ply_blocks *b = arg;
    const uint8_t *c = b->m->colors;
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

static limn_status ply_header(limn_context *ctx, const limn_mesh *m, const char *path, FILE *f,
                              limn_format format, int single, uint32_t max_face)
{
    const char *count_type = max_face > 255 ? "uint" : "uchar";
    const char *index_type = m->vertex_count > 2147483647u ? "uint" : "int";
    const char *name = format == LIMN_FORMAT_PLY_ASCII       ? "ascii"
                       : format == LIMN_FORMAT_PLY_BINARY_BE ? "binary_big_endian"
                                                             : "binary_little_endian";
    const char *type = single ? "float" : "double";
    if (fprintf(f, "ply\nformat %s 1.0\ncomment written by limn\nelement vertex %zu\n"
                   "property %s x\nproperty %s y\nproperty %s z\n",
                name, m->vertex_count, type, type, type) < 0 ||
        (m->colors && fputs("property uchar red\nproperty uchar green\nproperty uchar blue\n",
                            f) == EOF) ||
        fprintf(f, "element face %zu\nproperty list %s %s vertex_indices\nend_header\n",
                m->face_count, count_type, index_type) < 0)
        return mio_write_failed(ctx, path);
    return LIMN_OK;
}

limn_status ply_write(limn_context *ctx, const limn_mesh *m, const char *path, FILE *f,
                      limn_format format, int single)
{
    uint32_t max_face = 0;
    for (size_t fc = 0; fc < m->face_count; fc++) {
        uint32_t n = m->face_offsets[fc + 1] - m->face_offsets[fc];
        if (n > max_face)
            max_face = n;
    }
    limn_status st = ply_header(ctx, m, path, f, format, single, max_face);
    if (st)
        return st;
    if (format == LIMN_FORMAT_PLY_ASCII) {
        st = mio_write_vertices(ctx, m, path, f, "", m->colors, single);
        return st ? st : mio_write_faces(ctx, m, path, f, NULL, 0);
    }
    ply_blocks b = {m, format == LIMN_FORMAT_PLY_BINARY_BE, single, max_face > 255 ? 4 : 1};
    block_job vertices = {m->vertex_count, vertex_bytes(&b), vertex_bound, vertex_put, &b};
    block_job faces = {m->face_count, b.count_size + 12, face_bound, face_put, &b};
    st = block_write(ctx, path, f, &vertices);
    return st ? st : block_write(ctx, path, f, &faces);
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
