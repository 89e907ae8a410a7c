/* SPDX-License-Identifier: MIT */
/*
 * The text writers' parts (mesh_parts.h): OBJ and OFF headers, the vertex
 * and face lines of OBJ, OFF and ascii PLY (whose header is
 * mesh_ply_write.c's), positions as "%.17g" so that they round-trip. The
 * lines are formatted in parallel blocks (block_write.h) by number_format.h,
 * the same characters as printf's.
 */
#include "mesh/io/mesh_parts.h"
#include "base/context.h"
#include "mesh/io/formats.h"
#include "mesh/io/number_format.h"

#include <stdio.h>
#include <string.h>

typedef struct text_lines {
    const mesh_block *b;
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
        const double *p = t->b->positions + 3 * v;
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
    const uint32_t *off = t->b->face_offsets;
    return (end - begin) * (t->lead_len + 10 + 1) + (size_t)(off[end] - off[begin]) * 21;
}

static size_t face_put(const void *arg, size_t begin, size_t end, unsigned char *out)
{
    const text_lines *t = arg;
    const uint32_t *off = t->b->face_offsets, *idx = t->b->face_indices;
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

limn_status text_header(limn_context *ctx, const char *path, const mesh_layout *l,
                        const block_sink *sink)
{
    char head[96];
    int n = l->format == LIMN_FORMAT_OBJ
                ? snprintf(head, sizeof head, "# limn: %zu vertices, %zu faces\n",
                           l->vertex_total, l->face_total)
                : snprintf(head, sizeof head, "OFF\n%zu %zu 0\n", l->vertex_total,
                           l->face_total);
    if (n < 0 || (size_t)n >= sizeof head)
        return ctx_fail(ctx, LIMN_ERR_IO, "cannot write %s: header too long", path);
    return sink->put(sink->arg, ctx, path, head, (size_t)n);
}

/* One line per vertex: "v " (OBJ) or nothing, x y z (%.17g; single: of the
   float32 rounding, which reads back as that float exactly), and " r g b"
   when the layout has colours (ascii PLY only). */
limn_status obj_write(limn_context *ctx, const limn_mesh *m, const char *path, FILE *f)
{
    return mesh_parts_write(ctx, m, path, f, LIMN_FORMAT_OBJ, 0);
}

limn_status off_write(limn_context *ctx, const limn_mesh *m, const char *path, FILE *f)
{
    return mesh_parts_write(ctx, m, path, f, LIMN_FORMAT_OFF, 0);
}

limn_status text_vertices(limn_context *ctx, const char *path, const mesh_layout *l,
                          const mesh_block *b, const block_sink *sink)
{
    const char *lead = l->format == LIMN_FORMAT_OBJ ? "v " : "";
    const uint8_t *colors = l->format == LIMN_FORMAT_PLY_ASCII && l->colors ? b->colors : NULL;
    text_lines t = {b, lead, strlen(lead), colors, 0, l->single};
    block_job job = {b->vertex_count, 60, vertex_bound, vertex_put, &t};
    return block_emit(ctx, path, &job, sink);
}

/* One line per face: "f" (OBJ) or the corner count (OFF, PLY), then " v"
   for each corner, numbered from 1 in OBJ, from 0 otherwise. */
limn_status text_faces(limn_context *ctx, const char *path, const mesh_layout *l,
                       const mesh_block *b, const block_sink *sink)
{
    int obj = l->format == LIMN_FORMAT_OBJ;
    text_lines t = {b, obj ? "f" : NULL, obj ? 1 : 0, NULL, obj ? 1 : 0, 0};
    block_job job = {b->face_count, 30, face_bound, face_put, &t};
    return block_emit(ctx, path, &job, sink);
}
