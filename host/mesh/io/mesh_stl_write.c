/* SPDX-License-Identifier: MIT */
/*
 * The binary STL writer: faces fan-triangulated, coordinates rounded to
 * float, the facet normal from the rounded-from doubles; its parts
 * (mesh_parts.h), the triangles formatted in parallel (block_write.h). (The
 * reader is mesh_stl.c.)
 */
#include "mesh/io/formats.h"
#include "base/context.h"
#include "mesh/mesh.h"
#include "mesh/io/mesh_parts.h"

#include <math.h>
#include <string.h>

#define STL_HEADER 84 /* as mesh_stl.c: 80 bytes of header, the uint32 count */
#define STL_RECORD 50

static void put_le32(unsigned char *b, uint32_t u)
{
    b[0] = (unsigned char)u;
    b[1] = (unsigned char)(u >> 8);
    b[2] = (unsigned char)(u >> 16);
    b[3] = (unsigned char)(u >> 24);
}

static void put_float(unsigned char *b, double d)
{
    float f = (float)d;
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    put_le32(b, u);
}

limn_status stl_header(limn_context *ctx, const char *path, const mesh_layout *l,
                       const block_sink *sink)
{
    unsigned char head[STL_HEADER];
    memset(head, ' ', 80);
    memcpy(head, "binary STL written by limn", 26);
    put_le32(head + 80, (uint32_t)l->triangles); /* mesh_layout_check: it fits */
    return sink->put(sink->arg, ctx, path, head, sizeof head);
}

limn_status stl_vertices(limn_context *ctx, const char *path, const mesh_block *b, size_t first)
{
    for (size_t i = 0; i < 3 * b->vertex_count; i++)
        if (!isfinite((float)b->positions[i]))
            return ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                             "cannot write %s: vertex %zu does not fit STL's 32-bit floats", path,
                             first + i / 3);
    return LIMN_OK;
}

static size_t face_bound(const void *arg, size_t begin, size_t end)
{
    const mesh_block *b = arg;
    size_t n = 0;
    for (size_t fc = begin; fc < end; fc++) {
        uint32_t d = b->face_offsets[fc + 1] - b->face_offsets[fc];
        n += d > 2 ? d - 2 : 0;
    }
    return n * STL_RECORD;
}

static unsigned char *triangle(unsigned char *rec, const double *a, const double *b,
                               const double *c)
{
    double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    double n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
                   u[0] * w[1] - u[1] * w[0]};
    double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int j = 0; j < 3; j++) {
        put_float(rec + 4 * j, len > 0 && isfinite(len) ? n[j] / len : 0.0);
        put_float(rec + 12 + 4 * j, a[j]);
        put_float(rec + 24 + 4 * j, b[j]);
        put_float(rec + 36 + 4 * j, c[j]);
    }
    rec[48] = rec[49] = 0;
    return rec + STL_RECORD;
}

static size_t face_put(const void *arg, size_t begin, size_t end, unsigned char *out)
{
    const mesh_block *m = arg;
    const double *p = m->positions;
    unsigned char *o = out;
    for (size_t fc = begin; fc < end; fc++) {
        const uint32_t *v = m->face_indices + m->face_offsets[fc];
        uint32_t d = m->face_offsets[fc + 1] - m->face_offsets[fc];
        for (uint32_t k = 1; k + 1 < d; k++)
            o = triangle(o, p + 3 * v[0], p + 3 * v[k], p + 3 * v[k + 1]);
    }
    return (size_t)(o - out);
}

limn_status stl_faces(limn_context *ctx, const char *path, const mesh_block *b,
                      const block_sink *sink)
{
    block_job job = {b->face_count, STL_RECORD, face_bound, face_put, b};
    return block_emit(ctx, path, &job, sink);
}

limn_status stl_write(limn_context *ctx, const limn_mesh *m, const char *path, FILE *f)
{
    return mesh_parts_write(ctx, m, path, f, LIMN_FORMAT_STL, 0);
}
