/* SPDX-License-Identifier: MIT */
/*
 * The text writers: OBJ, OFF and the lines of ascii PLY (whose header is
 * mesh_ply_write.c's), positions as "%.17g" so that they round-trip.
 */
#include "mesh/io/text_write.h"
#include "base/context.h"
#include "mesh/io/formats.h"
#include "mesh/io/toolkit.h"
#include "mesh/mesh.h"

limn_status mio_write_vertices(limn_context *ctx, const limn_mesh *m, const char *path, FILE *f,
                               const char *lead, const uint8_t *colors)
{
    const double *p = m->positions;
    const uint8_t *c = colors;
    for (size_t v = 0; v < m->vertex_count; v++, p += 3)
        if (fprintf(f, "%s%.17g %.17g %.17g", lead, p[0], p[1], p[2]) < 0 ||
            (c && fprintf(f, " %u %u %u", c[3 * v], c[3 * v + 1], c[3 * v + 2]) < 0) ||
            fputc('\n', f) == EOF)
            return mio_write_failed(ctx, path);
    return LIMN_OK;
}

limn_status mio_write_faces(limn_context *ctx, const limn_mesh *m, const char *path, FILE *f,
                            const char *lead, unsigned base)
{
    for (size_t fc = 0; fc < m->face_count; fc++) {
        uint32_t a = m->face_offsets[fc], b = m->face_offsets[fc + 1];
        if ((lead ? fputs(lead, f) == EOF : fprintf(f, "%lu", (unsigned long)(b - a)) < 0))
            return mio_write_failed(ctx, path);
        for (uint32_t i = a; i < b; i++)
            if (fprintf(f, " %lu", (unsigned long)m->face_indices[i] + base) < 0)
                return mio_write_failed(ctx, path);
        if (fputc('\n', f) == EOF)
            return mio_write_failed(ctx, path);
    }
    return LIMN_OK;
}

limn_status obj_write(limn_context *ctx, const limn_mesh *m, const char *path, FILE *f)
{
    if (fprintf(f, "# limn: %zu vertices, %zu faces\n", m->vertex_count, m->face_count) < 0)
        return mio_write_failed(ctx, path);
    limn_status st = mio_write_vertices(ctx, m, path, f, "v ", NULL);
    return st ? st : mio_write_faces(ctx, m, path, f, "f", 1);
}

limn_status off_write(limn_context *ctx, const limn_mesh *m, const char *path, FILE *f)
{
    if (fprintf(f, "OFF\n%zu %zu 0\n", m->vertex_count, m->face_count) < 0)
        return mio_write_failed(ctx, path);
    limn_status st = mio_write_vertices(ctx, m, path, f, "", NULL);
    return st ? st : mio_write_faces(ctx, m, path, f, NULL, 0);
}
