/* SPDX-License-Identifier: MIT */
/*
 * The PLY writer: binary little or big endian (doubles, lossless) or ascii
 * ("%.17g"), vertex colours when the mesh has them, the list count type
 * widened to uint only when a face has more than 255 corners. (The reader
 * is mesh_ply.c.)
 */
#include "mesh/io/formats.h"
#include "base/context.h"
#include "mesh/mesh.h"
#include "mesh/io/text_write.h"
#include "mesh/io/toolkit.h"

#include <stdlib.h>
#include <string.h>

typedef struct ply_out {
    FILE *f;
    int big;
    size_t n;
    unsigned char buf[1 << 16];
} ply_out;

static int out_flush(ply_out *o)
{
    size_t n = o->n;
    o->n = 0;
    return fwrite(o->buf, 1, n, o->f) == n;
}

static int out_put(ply_out *o, uint64_t v, unsigned size)
{
    if (o->n + size > sizeof o->buf && !out_flush(o))
        return 0;
    for (unsigned i = 0; i < size; i++)
        o->buf[o->n + (o->big ? size - 1 - i : i)] = (unsigned char)(v >> (8 * i));
    o->n += size;
    return 1;
}

static int put_double(ply_out *o, double d)
{
    uint64_t u;
    memcpy(&u, &d, 8);
    return out_put(o, u, 8);
}

limn_status ply_write(limn_context *ctx, const limn_mesh *m, const char *path, FILE *f,
                      limn_format format)
{
    uint32_t max_face = 0;
    for (size_t fc = 0; fc < m->face_count; fc++) {
        uint32_t n = m->face_offsets[fc + 1] - m->face_offsets[fc];
        if (n > max_face)
            max_face = n;
    }
    const char *count_type = max_face > 255 ? "uint" : "uchar";
    const char *index_type = m->vertex_count > 2147483647u ? "uint" : "int";
    const char *name = format == LIMN_FORMAT_PLY_ASCII       ? "ascii"
                       : format == LIMN_FORMAT_PLY_BINARY_BE ? "binary_big_endian"
                                                             : "binary_little_endian";
    if (fprintf(f, "ply\nformat %s 1.0\ncomment written by limn\nelement vertex %zu\n"
                   "property double x\nproperty double y\nproperty double z\n",
                name, m->vertex_count) < 0 ||
        (m->colors && fputs("property uchar red\nproperty uchar green\nproperty uchar blue\n",
                            f) == EOF) ||
        fprintf(f, "element face %zu\nproperty list %s %s vertex_indices\nend_header\n",
                m->face_count, count_type, index_type) < 0)
        return mio_write_failed(ctx, path);
    const double *p = m->positions;
    const uint8_t *c = m->colors;
    if (format == LIMN_FORMAT_PLY_ASCII) {
        limn_status st = mio_write_vertices(ctx, m, path, f, "", c);
        return st ? st : mio_write_faces(ctx, m, path, f, NULL, 0);
    }
    ply_out *o = malloc(sizeof *o);
    if (!o)
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory writing %s", path);
    o->f = f;
    o->n = 0;
    o->big = format == LIMN_FORMAT_PLY_BINARY_BE;
    int ok = 1;
    for (size_t v = 0; v < m->vertex_count && ok; v++, p += 3) {
        ok = put_double(o, p[0]) && put_double(o, p[1]) && put_double(o, p[2]);
        if (c && ok)
            ok = out_put(o, c[3 * v], 1) && out_put(o, c[3 * v + 1], 1) &&
                 out_put(o, c[3 * v + 2], 1);
    }
    unsigned count_size = max_face > 255 ? 4 : 1;
    for (size_t fc = 0; fc < m->face_count && ok; fc++) {
        uint32_t a = m->face_offsets[fc], b = m->face_offsets[fc + 1];
        ok = out_put(o, b - a, count_size);
        for (uint32_t i = a; i < b && ok; i++)
            ok = out_put(o, m->face_indices[i], 4);
    }
    ok = ok && out_flush(o);
    free(o);
    return ok ? LIMN_OK : mio_write_failed(ctx, path);
}
