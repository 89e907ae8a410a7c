/* SPDX-License-Identifier: MIT */
/* Meshes and scratch of the MPI tests (mpi_meshes.h). */
#include "mpi_meshes.h"

#include "support.h"

#include <mpi.h>

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* Appends b to a (indices shifted), with an offset in space; frees both. */
static limn_mesh *join(limn_context *ctx, limn_mesh *a, limn_mesh *b, double dx)
{
    size_t na = limn_mesh_vertex_count(a), nb = limn_mesh_vertex_count(b);
    size_t fa = limn_mesh_face_count(a), fb = limn_mesh_face_count(b);
    const uint32_t *oa = limn_mesh_face_offsets(a), *ob = limn_mesh_face_offsets(b);
    size_t ia = oa[fa], ib = ob[fb];
    double *pos = malloc(3 * (na + nb) * sizeof *pos);
    uint32_t *off = malloc((fa + fb + 1) * sizeof *off), *idx = malloc((ia + ib) * sizeof *idx);
    memcpy(pos, limn_mesh_positions(a), 3 * na * sizeof *pos);
    for (size_t i = 0; i < nb; i++)
        for (int c = 0; c < 3; c++)
            pos[3 * (na + i) + c] = limn_mesh_positions(b)[3 * i + c] + (c == 0 ? dx : 0.0);
    memcpy(off, oa, (fa + 1) * sizeof *off);
    for (size_t f = 1; f <= fb; f++)
        off[fa + f] = (uint32_t)ia + ob[f];
    memcpy(idx, limn_mesh_face_indices(a), ia * sizeof *idx);
    for (size_t k = 0; k < ib; k++)
        idx[ia + k] = (uint32_t)na + limn_mesh_face_indices(b)[k];
    limn_mesh *m = NULL;
    limn_mesh_create(ctx, na + nb, pos, fa + fb, off, idx, &m);
    free(pos);
    free(off);
    free(idx);
    limn_mesh_destroy(a);
    limn_mesh_destroy(b);
    return m;
}

/* Adds `count` isolated vertices and, with fin, a triangle on the interior
   edge (1, grid_stride + 1) of the first grid: three faces on one edge. */
static limn_mesh *extras(limn_context *ctx, limn_mesh *a, int count, int fin, uint32_t stride)
{
    size_t n = limn_mesh_vertex_count(a), nf = limn_mesh_face_count(a);
    const uint32_t *off = limn_mesh_face_offsets(a);
    size_t ni = off[nf];
    double *pos = malloc(3 * (n + (size_t)count + 1) * sizeof *pos);
    uint32_t *off2 = malloc((nf + 2) * sizeof *off2), *idx = malloc((ni + 3) * sizeof *idx);
    memcpy(pos, limn_mesh_positions(a), 3 * n * sizeof *pos);
    for (int i = 0; i <= count; i++) {
        pos[3 * (n + (size_t)i)] = -3.0 - i;
        pos[3 * (n + (size_t)i) + 1] = 0.5 * i;
        pos[3 * (n + (size_t)i) + 2] = 1.0;
    }
    memcpy(off2, off, (nf + 1) * sizeof *off2);
    memcpy(idx, limn_mesh_face_indices(a), ni * sizeof *idx);
    size_t nf2 = nf;
    if (fin) { /* the fin's apex is the last new vertex */
        idx[ni] = 1 + stride + 1;
        idx[ni + 1] = 1 + 1;
        idx[ni + 2] = (uint32_t)(n + (size_t)count);
        off2[++nf2] = (uint32_t)ni + 3;
    }
    limn_mesh *m = NULL;
    limn_mesh_create(ctx, n + (size_t)count + (fin ? 1 : 0), pos, nf2, off2, idx, &m);
    free(pos);
    free(off2);
    free(idx);
    limn_mesh_destroy(a);
    return m;
}

/* Several components, boundaries, corners, a non-manifold fin, isolated
   vertices; the last component shuffled (RCM runs on it). */
limn_mesh *mpi_test_composite(limn_context *ctx, int triangles)
{
    limn_mesh *m = test_mesh_grid(ctx, 30, 20, triangles);
    m = extras(ctx, m, 2, 1, 31);
    m = join(ctx, m, test_mesh_icosahedron(ctx), 40.0);
    if (!triangles)
        m = join(ctx, m, test_mesh_pyramid(ctx), 50.0);
    limn_mesh *big = test_mesh_shuffle(ctx, test_mesh_grid(ctx, 70, 60, triangles), 7);
    test_perturb(big, 0.05, 3);
    return join(ctx, m, big, 60.0);
}

/* A torus of nx x ny quads (or triangles), radii 3 and 1, at x = dx. */
static limn_mesh *torus(limn_context *ctx, int nx, int ny, int triangles, double dx)
{
    size_t n = (size_t)nx * (size_t)ny, nf = triangles ? 2 * n : n, per = triangles ? 3 : 4;
    double *pos = malloc(3 * n * sizeof *pos);
    uint32_t *off = malloc((nf + 1) * sizeof *off), *idx = malloc(nf * per * sizeof *idx);
    for (int i = 0; i < nx; i++)
        for (int j = 0; j < ny; j++) {
            double u = 6.283185307179586 * i / nx, v = 6.283185307179586 * j / ny;
            double *p = pos + 3 * ((size_t)i * (size_t)ny + (size_t)j);
            p[0] = dx + (3.0 + cos(v)) * cos(u);
            p[1] = (3.0 + cos(v)) * sin(u);
            p[2] = sin(v);
        }
    size_t f = 0, k = 0;
    off[0] = 0;
    for (int i = 0; i < nx; i++)
        for (int j = 0; j < ny; j++) {
            uint32_t a = (uint32_t)(i * ny + j), b = (uint32_t)(((i + 1) % nx) * ny + j);
            uint32_t c = (uint32_t)(((i + 1) % nx) * ny + (j + 1) % ny);
            uint32_t d = (uint32_t)(i * ny + (j + 1) % ny);
            uint32_t q[6] = {a, b, c, a, c, d}, quad[4] = {a, b, c, d};
            for (size_t t = 0; t < (triangles ? 2u : 1u); t++) {
                for (size_t e = 0; e < per; e++)
                    idx[k++] = triangles ? q[3 * t + e] : quad[e];
                off[++f] = (uint32_t)k;
            }
        }
    limn_mesh *m = NULL;
    limn_mesh_create(ctx, n, pos, nf, off, idx, &m);
    free(pos);
    free(off);
    free(idx);
    return m;
}

/* A hexagonal prism: two hexagons (n-gons) and six quads, closed. */
static limn_mesh *prism(limn_context *ctx)
{
    double pos[36];
    for (int i = 0; i < 12; i++) {
        double a = 1.0471975511965976 * (i % 6);
        pos[3 * i] = cos(a);
        pos[3 * i + 1] = sin(a);
        pos[3 * i + 2] = i < 6 ? 0.0 : 1.5;
    }
    uint32_t idx[36] = {5, 4, 3, 2, 1, 0, 6, 7, 8, 9, 10, 11}, off[9] = {0, 6, 12};
    for (uint32_t i = 0; i < 6; i++) {
        uint32_t *q = idx + 12 + 4 * i;
        q[0] = i;
        q[1] = (i + 1) % 6;
        q[2] = 6 + (i + 1) % 6;
        q[3] = 6 + i;
        off[3 + i] = 12 + 4 * (i + 1);
    }
    limn_mesh *m = NULL;
    limn_mesh_create(ctx, 12, pos, 8, off, idx, &m);
    return m;
}

limn_mesh *mpi_test_closed(limn_context *ctx, int triangles)
{
    limn_mesh *m = torus(ctx, 24, 12, triangles, 0.0);
    m = join(ctx, m, triangles ? test_mesh_icosahedron(ctx) : prism(ctx), 10.0);
    limn_mesh *big = test_mesh_shuffle(ctx, torus(ctx, 60, 30, triangles, 0.0), 5);
    test_perturb(big, 0.02, 9);
    return join(ctx, m, big, 20.0);
}

limn_mesh *mpi_test_turned(limn_context *ctx, const limn_mesh *m, size_t f)
{
    size_t nf = limn_mesh_face_count(m);
    const uint32_t *off = limn_mesh_face_offsets(m);
    uint32_t *idx = malloc(off[nf] * sizeof *idx);
    if (!idx)
        return NULL;
    memcpy(idx, limn_mesh_face_indices(m), off[nf] * sizeof *idx);
    for (uint32_t i = off[f], j = off[f + 1] - 1; i < j; i++, j--) {
        uint32_t x = idx[i];
        idx[i] = idx[j];
        idx[j] = x;
    }
    limn_mesh *t = NULL;
    limn_mesh_create(ctx, limn_mesh_vertex_count(m), limn_mesh_positions(m), nf, off, idx, &t);
    free(idx);
    return t;
}

void mpi_test_scratch_dir(char *dir, size_t cap, const char *name)
{
    int rank = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    if (rank == 0) {
        snprintf(dir, cap, "%s/limn_%s_XXXXXX", getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp",
                 name);
        if (!mkdtemp(dir))
            dir[0] = '\0';
    }
    MPI_Bcast(dir, (int)cap, MPI_CHAR, 0, MPI_COMM_WORLD);
}
