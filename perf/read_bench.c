/* SPDX-License-Identifier: MIT */
/*
 * limn_mesh_read's fast paths (binary PLY; OBJ, OFF, ASCII PLY) against the
 * general readers on the same file (issue 13.1), in one run
 * (perf/read_bench.py drives it):
 *   read_bench --scanner IN OUT   writes IN as scanners write PLY (binary
 *                                 little endian, float x y z, `uchar int` lists)
 *   read_bench FILE [REPEAT [THREADS]]  best of REPEAT reads each way (THREADS
 *                                 host threads, else the default), the meshes
 *                                 compared bit for bit; one line per way
 */
#ifndef _POSIX_C_SOURCE
#define _POSIX_C_SOURCE 200809L /* setenv, clock_gettime */
#endif
#include "limn.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static limn_mesh *read_mesh(limn_context *ctx, const char *path)
{
    limn_mesh *m = NULL;
    if (limn_mesh_read(ctx, path, LIMN_FORMAT_AUTO, &m) != LIMN_OK) {
        fprintf(stderr, "read_bench: %s\n", limn_context_message(ctx));
        exit(1);
    }
    return m;
}

static void put_le(FILE *f, uint32_t v, int n)
{
    for (int i = 0; i < n; i++)
        fputc((int)(v >> (8 * i) & 0xff), f);
}

static int scanner(limn_context *ctx, const char *in, const char *out)
{
    limn_mesh *m = read_mesh(ctx, in);
    size_t nv = limn_mesh_vertex_count(m), nf = limn_mesh_face_count(m);
    const double *p = limn_mesh_positions(m);
    const uint32_t *off = limn_mesh_face_offsets(m), *idx = limn_mesh_face_indices(m);
    FILE *f = fopen(out, "wb");
    if (!f)
        return perror(out), 1;
    fprintf(f, "ply\nformat binary_little_endian 1.0\nelement vertex %zu\nproperty float x\n"
               "property float y\nproperty float z\nelement face %zu\n"
               "property list uchar int vertex_indices\nend_header\n", nv, nf);
    for (size_t i = 0; i < 3 * nv; i++) {
        float x = (float)p[i];
        uint32_t u;
        memcpy(&u, &x, 4);
        put_le(f, u, 4);
    }
    for (size_t i = 0; i < nf; i++) {
        put_le(f, off[i + 1] - off[i], 1);
        for (uint32_t c = off[i]; c < off[i + 1]; c++)
            put_le(f, idx[c], 4);
    }
    limn_mesh_destroy(m);
    return fclose(f) != 0;
}

static int same(const limn_mesh *a, const limn_mesh *b)
{
    size_t nv = limn_mesh_vertex_count(a), nf = limn_mesh_face_count(a);
    if (nv != limn_mesh_vertex_count(b) || nf != limn_mesh_face_count(b))
        return 0;
    const uint32_t *oa = limn_mesh_face_offsets(a), *ob = limn_mesh_face_offsets(b);
    return memcmp(limn_mesh_positions(a), limn_mesh_positions(b), 24 * nv) == 0 &&
           memcmp(oa, ob, 4 * (nf + 1)) == 0 &&
           memcmp(limn_mesh_face_indices(a), limn_mesh_face_indices(b), 4 * (size_t)oa[nf]) == 0 &&
           !limn_mesh_colors(a) == !limn_mesh_colors(b) &&
           (!limn_mesh_colors(a) || memcmp(limn_mesh_colors(a), limn_mesh_colors(b), 3 * nv) == 0);
}

int main(int argc, char **argv)
{
    limn_context *ctx = limn_context_create();
    if (argc == 4 && strcmp(argv[1], "--scanner") == 0)
        return scanner(ctx, argv[2], argv[3]);
    if (argc < 2 || argc > 4) {
        fprintf(stderr,
                "usage: read_bench FILE [REPEAT [THREADS]] | read_bench --scanner IN OUT\n");
        return 2;
    }
    int repeat = argc >= 3 ? atoi(argv[2]) : 3;
    if (argc == 4 && limn_context_set_host_threads(ctx, atoi(argv[3])) != LIMN_OK)
        return fprintf(stderr, "read_bench: %s\n", limn_context_message(ctx)), 2;
    static const char *const ways[2] = {"general", "fast"};
    limn_mesh *kept[2] = {NULL, NULL};
    for (int w = 0; w < 2; w++) {
        double best = 1e300;
        if (setenv("LIMN_TEST_PLY_GENERAL", w == 0 ? "1" : "0", 1) != 0 ||
            setenv("LIMN_TEST_TEXT_GENERAL", w == 0 ? "1" : "0", 1) != 0)
            return 1;
        for (int r = 0; r < (repeat > 0 ? repeat : 1); r++) {
            limn_mesh_destroy(kept[w]);
            double t = now();
            kept[w] = read_mesh(ctx, argv[1]);
            t = now() - t;
            best = t < best ? t : best;
        }
        size_t nv = limn_mesh_vertex_count(kept[w]);
        printf("limn %s: %.3f s, %.1f M vertices/s (%zu vertices, best of %d)\n", ways[w], best,
               (double)nv / best * 1e-6, nv, repeat);
    }
    int ok = same(kept[0], kept[1]);
    printf("meshes %s\n", ok ? "identical" : "DIFFER");
    limn_mesh_destroy(kept[0]);
    limn_mesh_destroy(kept[1]);
    limn_context_destroy(ctx);
    return !ok;
}
