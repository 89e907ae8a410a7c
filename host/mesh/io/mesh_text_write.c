/* SPDX-License-Identifier: MIT */
/*
 * The text writers: OBJ, OFF and the lines of ascii PLY (whose header is
 * mesh_ply_write.c's), positions as "%.17g" so that they round-trip. The
 * lines are formatted in parallel blocks (block_write.h) by number_format.h,
 * the same characters as printf's.
 */
#include "mesh/io/text_write.h"
#include "base/context.h"
#include "mesh/io/block_write.h"
#include "mesh/io/formats.h"
#include "mesh/io/number_format.h"
#include "mesh/io/toolkit.h"
#include "mesh/mesh.h"

#include <string.h>

typedef struct text_lines {
    const limn_mesh *m;
    const char *lead; /* faces: NULL for the corner count */
    size_t lead_len;
    const uint8_t *colors;
    unsigned base;
    int single;
} text_lines;

static size_t vertex_bound(const void *arg, size_t begin, size_t end)
{
    const text_lines *t = arg;
    return (end - begin) * (t->lead_len + 3 * NUMBER_G17_MAX + 12 + 1);
}

static size_t vertex_put(const void *arg, size_t begin, size_t end, unsigned char *out)
{
    const text_lines *t = arg;
    char *o = (char *)out;
    for (size_t v = begin; v < end; v++) {
        const double *p = t->m->positions + 3 * v;
        memcpy(o, t->lead, t->lead_len);
        o += t->lead_len;
        for (int j = 0; j < 3; j++) {
            if (j)
                *o++ = ' ';
            o += number_g17(t->single ? (double)(float)p[j] : p[j], o);
        }
        for (int j = 0; t->colors && j < 3; j++) {
            *o++ = ' ';
            o += number_u64(t->colors[3 * v + j], o);
        }
        *o++ = '\n';
    }
    return (size_t)(o - (char *)out);
}

static size_t face_bound(const void *arg, size_t begin, size_t end)
{
    const text_lines *t = arg;
    const uint32_t *off = t->m->face_offsets;
    return (end - begin) * (t->lead_len + 10 + 1) + (size_t)(off[end] - off[begin]) * 21;
}

static size_t face_put(const void *arg, size_t begin, size_t end, unsigned char *out)
{
    const text_lines *t = arg;
    const uint32_t *off = t->m->face_offsets, *idx = t->m->face_indices;
    char *o = (char *)out;
    for (size_t fc = begin; fc < end; fc++) {
        if (t->lead) {
            memcpy(o, t->lead, t->lead_len);
            o += t->lead_len;
        } else {
            o += number_u64(off[fc + 1] - off[fc], o);
        }
        for (uint32_t i = off[fc]; i < off[fc + 1]; i++) {
            *o++ = ' ';
            o += number_u64((uint64_t)idx[i] + t->base, o);
        }
        *o++ = '\n';
    }
    return (size_t)(o - (char *)out);
}

limn_status mio_write_vertices(limn_context *ctx, const limn_mesh *m, const char *path, FILE *f,
                               const char *lead, const uint8_t *colors, int single)
{
    text_lines t = {m, lead, strlen(lead), colors, 0, single};
    block_job job = {m->vertex_count, 60, vertex_bound, vertex_put, &t};
    return block_write(ctx, path, f, &job);
}

limn_status mio_write_faces(limn_context *ctx, const limn_mesh *m, const char *path, FILE *f,
                            const char *lead, unsigned base)
{
    text_lines t = {m, lead, lead ? strlen(lead) : 0, NULL, base, 0};
    block_job job = {m->face_count, 30, face_bound, face_put, &t};
    return block_write(ctx, path, f, &job);
}

limn_status obj_write(limn_context *ctx, const limn_mesh *m, const char *path, FILE *f)
{
    if (fprintf(f, "# limn: %zu vertices, %zu faces\n", m->vertex_count, m->face_count) < 0)
        return mio_write_failed(ctx, path);
    limn_status st = mio_write_vertices(ctx, m, path, f, "v ", NULL, 0);
    return st ? st : mio_write_faces(ctx, m, path, f, "f", 1);
}

limn_status off_write(limn_context *ctx, const limn_mesh *m, const char *path, FILE *f)
{
    if (fprintf(f, "OFF\n%zu %zu 0\n", m->vertex_count, m->face_count) < 0)
        return mio_write_failed(ctx, path);
    limn_status st = mio_write_vertices(ctx, m, path, f, "", NULL, 0);
    return st ? st : mio_write_faces(ctx, m, path, f, NULL, 0);
}
