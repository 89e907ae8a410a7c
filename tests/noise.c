/* SPDX-License-Identifier: MIT */
/* Noisy meshes for the series tests and perf/denoise_bench (which builds
   this file into itself, without the rest of the test support). */
#include "noise.h"

#include <math.h>
#include <stdlib.h>

double test_mean_edge(const limn_mesh *m)
{
    const double *p = limn_mesh_positions(m);
    const uint32_t *off = limn_mesh_face_offsets(m), *idx = limn_mesh_face_indices(m);
    double sum = 0;
    size_t count = 0;
    for (size_t f = 0; f < limn_mesh_face_count(m); f++)
        for (uint32_t k = off[f]; k < off[f + 1]; k++) {
            const double *a = p + 3 * idx[k], *b = p + 3 * idx[k + 1 < off[f + 1] ? k + 1 : off[f]];
            sum += sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                        (a[2] - b[2]) * (a[2] - b[2]));
            count++;
        }
    return sum / (double)count;
}

void test_gaussian_noise(limn_mesh *m, double sigma, uint64_t seed)
{
    double *p = limn_mesh_positions_mutable(m);
    uint64_t s = seed;
    for (size_t i = 0; i < 3 * limn_mesh_vertex_count(m); i += 2) {
        double u[2];
        for (int k = 0; k < 2; k++) {
            uint64_t z = (s += 0x9E3779B97F4A7C15ULL);
            z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
            z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
            z ^= z >> 31;
            u[k] = ((double)(z >> 11) + 0.5) / 9007199254740992.0;
        }
        double r = sqrt(-2.0 * log(u[0]));
        p[i] += sigma * r * cos(6.283185307179586 * u[1]);
        if (i + 1 < 3 * limn_mesh_vertex_count(m))
            p[i + 1] += sigma * r * sin(6.283185307179586 * u[1]);
    }
}

void test_normal_noise(limn_mesh *m, double sigma, uint64_t seed)
{
    size_t n = limn_mesh_vertex_count(m), nf = limn_mesh_face_count(m);
    const uint32_t *off = limn_mesh_face_offsets(m), *idx = limn_mesh_face_indices(m);
    double *p = limn_mesh_positions_mutable(m), *nrm = calloc(3 * n, sizeof *nrm);
    double *g = calloc(3 * n, sizeof *g);
    if (!nrm || !g)
        abort();
    for (size_t f = 0; f < nf; f++) {
        double fn[3] = {0, 0, 0}; /* Newell: the area-weighted normal of any polygon */
        for (uint32_t k = off[f]; k < off[f + 1]; k++) {
            const double *a = p + 3 * idx[k], *b = p + 3 * idx[k + 1 < off[f + 1] ? k + 1 : off[f]];
            fn[0] += (a[1] - b[1]) * (a[2] + b[2]);
            fn[1] += (a[2] - b[2]) * (a[0] + b[0]);
            fn[2] += (a[0] - b[0]) * (a[1] + b[1]);
        }
        for (uint32_t k = off[f]; k < off[f + 1]; k++)
            for (int c = 0; c < 3; c++)
                nrm[3 * idx[k] + c] += fn[c];
    }
    /* the Gaussians of test_gaussian_noise's stream, one per vertex */
    uint64_t s = seed;
    for (size_t i = 0; i < n; i += 2) {
        double u[2];
        for (int k = 0; k < 2; k++) {
            uint64_t z = (s += 0x9E3779B97F4A7C15ULL);
            z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
            z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
            z ^= z >> 31;
            u[k] = ((double)(z >> 11) + 0.5) / 9007199254740992.0;
        }
        double r = sqrt(-2.0 * log(u[0]));
        g[i] = r * cos(6.283185307179586 * u[1]);
        if (i + 1 < n)
            g[i + 1] = r * sin(6.283185307179586 * u[1]);
    }
    for (size_t v = 0; v < n; v++) {
        const double *q = nrm + 3 * v;
        double len = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
        for (int c = 0; len > 0 && c < 3; c++)
            p[3 * v + c] += sigma * g[v] * q[c] / len;
    }
    free(nrm);
    free(g);
}

void test_spherize(limn_mesh *mesh, const double centroid[3])
{
    double *p = limn_mesh_positions_mutable(mesh), rsum = 0;
    size_t n = limn_mesh_vertex_count(mesh);
    for (size_t i = 0; i < n; i++) {
        double d[3] = {p[3 * i] - centroid[0], p[3 * i + 1] - centroid[1],
                       p[3 * i + 2] - centroid[2]};
        rsum += sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    }
    for (size_t i = 0; i < n; i++) {
        double d[3] = {p[3 * i] - centroid[0], p[3 * i + 1] - centroid[1],
                       p[3 * i + 2] - centroid[2]};
        double l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        for (int c = 0; c < 3; c++)
            p[3 * i + c] = centroid[c] + d[c] * (rsum / (double)n) / (l > 0 ? l : 1);
    }
}
