/* SPDX-License-Identifier: MIT */
/*
 * The binary STL writer: faces fan-triangulated, coordinates rounded to
 * float, the facet normal from the rounded-from doubles. (The reader is
 * mesh_stl.c.)
 */
#include "mesh/io/formats.h"
#include "base/context.h"
#include "mesh/mesh.h"
#include "mesh/io/toolkit.h"

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

limn_status stl_write(limn_context *ctx, const limn_mesh *m, const char *path, FILE *f)
{
    uint64_t count = 0;
    for (size_t fc = 0; fc < m->face_count; fc++)
        count += m->face_offsets[fc + 1] - m->face_offsets[fc] - 2;
    if (count > UINT32_MAX)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "cannot write %s: %llu triangles do not fit STL",
                         path, (unsigned long long)count);
    for (size_t i = 0; i < 3 * m->vertex_count; i++)
        if (!isfinite((float)m->positions[i]))
            return ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                             "cannot write %s: vertex %zu does not fit STL's 32-bit floats", path,
                             i / 3);
    unsigned char head[STL_HEADER];
    memset(head, ' ', 80);
    memcpy(head, "binary STL written by limn", 26);
    put_le32(head + 80, (uint32_t)count);
    if (fwrite(head, 1, sizeof head, f) != sizeof head)
        return mio_write_failed(ctx, path);
    const double *p = m->positions;
    for (size_t fc = 0; fc < m->face_count; fc++) {
        const uint32_t *v = m->face_indices + m->face_offsets[fc];
        uint32_t d = m->face_offsets[fc + 1] - m->face_offsets[fc];
        for (uint32_t k = 1; k + 1 < d; k++) {
            const double *a = p + 3 * v[0], *b = p + 3 * v[k], *c = p + 3 * v[k + 1];
            double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
            double w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
            double n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
                           u[0] * w[1] - u[1] * w[0]};
            double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
            unsigned char rec[STL_RECORD];
            for (int j = 0; j < 3; j++) {
                put_float(rec + 4 * j, len > 0 && isfinite(len) ? n[j] / len : 0.0);
                put_float(rec + 12 + 4 * j, a[j]);
                put_float(rec + 24 + 4 * j, b[j]);
                put_float(rec + 36 + 4 * j, c[j]);
            }
            rec[48] = rec[49] = 0;
            if (fwrite(rec, 1, sizeof rec, f) != sizeof rec)
                return mio_write_failed(ctx, path);
        }
    }
    return LIMN_OK;
}
