/* SPDX-License-Identifier: MIT */
/* limn bench's input: a refined icosahedron or cube, written as a scanner
   writes its files (float32 binary PLY), through the public API only. */
#include "cli_bench.h"

#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* Levels beyond this are > 10^9 vertices: more than --vertices allows. */
#define BENCH_MAX_LEVELS 15

size_t bench_vertices_at(limn_scheme scheme, int levels)
{
    /* V = F_0 4^L + 2 on a closed genus-0 mesh refined L times: Loop splits a
       triangle in 4 (icosahedron: 20 faces, V = 10 4^L + 2), Catmull-Clark a
       quad in 4 (cube: 6 faces, V = 6 4^L + 2) */
    size_t grow = (size_t)1 << (2 * levels);
    return (scheme == LIMN_SCHEME_LOOP ? 10 : 6) * grow + 2;
}

static int nearest_levels(limn_scheme scheme, size_t n)
{
    int best = 0;
    for (int l = 1; l <= BENCH_MAX_LEVELS; l++)
        if (fabs(log((double)bench_vertices_at(scheme, l) / (double)n)) <
            fabs(log((double)bench_vertices_at(scheme, best) / (double)n)))
            best = l;
    return best;
}

static limn_status base_mesh(limn_context *ctx, limn_scheme scheme, limn_mesh **out)
{
    if (scheme == LIMN_SCHEME_CATMARK) {
        static const double v[] = {-1, -1, -1, 1, -1, -1, 1, 1, -1, -1, 1, -1,
                                   -1, -1, 1,  1, -1, 1,  1, 1, 1,  -1, 1, 1};
        static const uint32_t off[] = {0, 4, 8, 12, 16, 20, 24};
        static const uint32_t idx[] = {0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4,
                                       1, 2, 6, 5, 2, 3, 7, 6, 3, 0, 4, 7};
        return limn_mesh_create(ctx, 8, v, 6, off, idx, out);
    }
    const double p = (1 + sqrt(5.0)) / 2; /* the golden ratio */
    const double v[] = {-1, p, 0, 1, p, 0, -1, -p, 0, 1, -p, 0, 0, -1, p, 0, 1, p,
                        0, -1, -p, 0, 1, -p, p, 0, -1, p, 0, 1, -p, 0, -1, -p, 0, 1};
    static const uint32_t idx[] = {0, 11, 5,  0, 5,  1, 0, 1, 7, 0, 7,  10, 0, 10, 11,
                                   1, 5,  9,  5, 11, 4, 11, 10, 2, 10, 7, 6, 7, 1, 8,
                                   3, 9,  4,  3, 4,  2, 3, 2, 6, 3, 6,  8,  3, 8,  9,
                                   4, 9,  5,  2, 4,  11, 6, 2, 10, 8, 6, 7, 9, 8, 1};
    uint32_t off[21];
    for (uint32_t f = 0; f <= 20; f++)
        off[f] = 3 * f;
    return limn_mesh_create(ctx, 12, v, 20, off, idx, out);
}

/* Smooth bumps of a few percent, so that the solve has work like a scan's
   (the refined base alone is nearly its own limit surface). */
static void bump(limn_mesh *mesh)
{
    double *x = limn_mesh_positions_mutable(mesh);
    size_t n = limn_mesh_vertex_count(mesh);
    for (size_t i = 0; i < n; i++) {
        double *q = x + 3 * i;
        double s = 1 + 0.04 * sin(5 * q[0] + 1) * sin(4 * q[1] + 2) * sin(3 * q[2] + 3);
        q[0] *= s;
        q[1] *= s;
        q[2] *= s;
    }
}

limn_status bench_mesh(limn_context *ctx, const bench_args *b, limn_mesh **out, int *levels)
{
    limn_mesh *base = NULL;
    *out = NULL;
    *levels = nearest_levels(b->scheme, b->vertices);
    limn_status st = base_mesh(ctx, b->scheme, &base);
    if (!st && *levels == 0) {
        *out = base;
        base = NULL;
    } else if (!st) {
        limn_subdivide_options o;
        limn_subdivide_options_default(&o);
        o.scheme = b->scheme;
        o.levels = *levels;
        st = limn_subdivide(ctx, base, &o, out, NULL);
    }
    limn_mesh_destroy(base);
    if (!st)
        bump(*out);
    return st;
}

/* Little-endian bytes of v at p. */
static unsigned char *put_u32(unsigned char *p, uint32_t v)
{
    for (int k = 0; k < 4; k++)
        p[k] = (unsigned char)(v >> (8 * k));
    return p + 4;
}

static unsigned char *put_f32(unsigned char *p, double v)
{
    float f = (float)v;
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    return put_u32(p, u);
}

/* Vertices then faces, in blocks of at most BLOCK bytes. */
#define BLOCK ((size_t)1 << 20)
static int write_body(FILE *fp, const limn_mesh *mesh, unsigned char *buf)
{
    const double *x = limn_mesh_positions(mesh);
    const uint32_t *off = limn_mesh_face_offsets(mesh), *idx = limn_mesh_face_indices(mesh);
    size_t n = limn_mesh_vertex_count(mesh), nf = limn_mesh_face_count(mesh);
    unsigned char *p = buf;
    for (size_t i = 0; i < 3 * n; i++) {
        p = put_f32(p, x[i]);
        if ((size_t)(p - buf) > BLOCK - 16 || i + 1 == 3 * n) {
            if (fwrite(buf, 1, (size_t)(p - buf), fp) != (size_t)(p - buf))
                return -1;
            p = buf;
        }
    }
    for (size_t f = 0; f < nf; f++) {
        *p++ = (unsigned char)(off[f + 1] - off[f]); /* 3 or 4 here */
        for (uint32_t k = off[f]; k < off[f + 1]; k++)
            p = put_u32(p, idx[k]);
        if ((size_t)(p - buf) > BLOCK - 1024 || f + 1 == nf) {
            if (fwrite(buf, 1, (size_t)(p - buf), fp) != (size_t)(p - buf))
                return -1;
            p = buf;
        }
    }
    return 0;
}

limn_status bench_write_scanner_ply(const limn_mesh *mesh, const char *path, size_t *bytes)
{
    unsigned char *buf = malloc(BLOCK);
    FILE *fp = buf ? fopen(path, "wb") : NULL;
    if (!fp) {
        free(buf);
        return buf ? cli_error(LIMN_ERR_IO, "cannot write %s: %s", path, strerror(errno))
                   : cli_error(LIMN_ERR_MEMORY, "out of memory");
    }
    int bad = fprintf(fp,
                      "ply\nformat binary_little_endian 1.0\nelement vertex %zu\n"
                      "property float x\nproperty float y\nproperty float z\n"
                      "element face %zu\nproperty list uchar int vertex_indices\n"
                      "end_header\n",
                      limn_mesh_vertex_count(mesh), limn_mesh_face_count(mesh)) < 0;
    bad = bad || write_body(fp, mesh, buf) != 0;
    long end = ftell(fp);
    bad = fclose(fp) != 0 || bad || end < 0;
    free(buf);
    if (bad)
        return cli_error(LIMN_ERR_IO, "writing %s failed: %s", path, strerror(errno));
    *bytes = (size_t)end;
    return LIMN_OK;
}
