/* SPDX-License-Identifier: MIT */
/* limn bench (cli_bench.c): its options, its figures, the mesh it builds and
   writes (cli_bench_mesh.c) and how it reports them (cli_bench_report.c). */
#ifndef LIMN_CLI_BENCH_H
#define LIMN_CLI_BENCH_H

#include "cli.h"

typedef struct bench_args {
    size_t vertices;          /* the size asked for */
    limn_scheme scheme;       /* LOOP or CATMARK */
    const char *device, *json;
    int host_threads;         /* 0: the default */
    int repeat;               /* triad runs */
    size_t triad_bytes;       /* each triad array */
    int quiet;
} bench_args;

typedef struct bench_figures {
    int levels;               /* refinement levels of the base mesh */
    size_t faces, file_bytes;
    double generate, write_input;                /* making the input, not the job */
    double read, repair, write, total;           /* the job's wall clock stages */
    limn_report r;            /* topology, stencil, solve, the loop, set-up */
    size_t peak_rss;          /* after the job, before the triad */
    limn_triad_report triad;
    int threads, host_threads;
    const char *threads_source, *host_threads_source;
} bench_figures;

/* The base mesh (loop: icosahedron, catmark: cube) refined to the level
   whose vertex count is nearest b->vertices (by ratio), its positions
   bumped deterministically; *levels the level. */
limn_status bench_mesh(limn_context *ctx, const bench_args *b, limn_mesh **out, int *levels);
/* The vertex count of the base mesh of `scheme` refined `levels` times. */
size_t bench_vertices_at(limn_scheme scheme, int levels);
/* mesh as scanners write it: binary little-endian PLY, float32 x y z,
   `uchar int` face lists; *bytes its size. */
limn_status bench_write_scanner_ply(const limn_mesh *mesh, const char *path, size_t *bytes);

/* Bytes the solve loop moves over the whole solve (the byte model of
   docs/performance.md). */
double bench_loop_bytes(const limn_report *r);

void bench_print(const bench_args *b, const bench_figures *f);
limn_status bench_json(limn_context *ctx, const bench_args *b, const bench_figures *f);

#endif
