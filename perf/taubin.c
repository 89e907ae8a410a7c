/* SPDX-License-Identifier: MIT */
/* Taubin lambda|mu smoothing for the benchmarks (taubin.h). */
#include "taubin.h"

#include <stdlib.h>
#include <string.h>

static int cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return x < y ? -1 : x > y;
}

adjacency build_adjacency(const limn_mesh *m)
{
    adjacency a = {limn_mesh_vertex_count(m), NULL, NULL};
    const uint32_t *off = limn_mesh_face_offsets(m), *idx = limn_mesh_face_indices(m);
    size_t nf = limn_mesh_face_count(m), corners = off[nf];
    uint32_t *count = calloc(a.n + 1, sizeof *count);
    for (size_t f = 0; f < nf; f++)
        for (uint32_t k = off[f]; k < off[f + 1]; k++)
            count[idx[k]] += 2;
    a.off = calloc(a.n + 1, sizeof *a.off);
    for (size_t i = 0; i < a.n; i++)
        a.off[i + 1] = a.off[i] + count[i];
    uint32_t *fill = calloc(a.n, sizeof *fill), *tmp = malloc((2 * corners + 1) * sizeof *tmp);
    for (size_t f = 0; f < nf; f++)
        for (uint32_t k = off[f]; k < off[f + 1]; k++) {
            uint32_t v = idx[k], nx = idx[k + 1 < off[f + 1] ? k + 1 : off[f]],
                     pv = idx[k > off[f] ? k - 1 : off[f + 1] - 1];
            tmp[a.off[v] + fill[v]++] = nx;
            tmp[a.off[v] + fill[v]++] = pv;
        }
    a.nbr = malloc((2 * corners + 1) * sizeof *a.nbr);
    uint32_t w = 0;
    uint32_t *newoff = calloc(a.n + 1, sizeof *newoff);
    for (size_t i = 0; i < a.n; i++) {
        uint32_t *s = tmp + a.off[i];
        qsort(s, fill[i], sizeof *s, cmp_u32);
        for (uint32_t k = 0; k < fill[i]; k++)
            if (k == 0 || s[k] != s[k - 1])
                a.nbr[w++] = s[k];
        newoff[i + 1] = w;
    }
    free(a.off);
    a.off = newoff;
    free(count);
    free(fill);
    free(tmp);
    return a;
}

void adjacency_free(adjacency *a)
{
    free(a->off);
    free(a->nbr);
    a->off = a->nbr = NULL;
}

void taubin_steps(const adjacency *a, double *p, int applications, double lambda, double mu)
{
    double *q = malloc(3 * a->n * sizeof *q);
    for (int s = 0; s < applications; s++) {
        double f = s % 2 == 0 ? lambda : mu;
        for (size_t i = 0; i < a->n; i++) {
            uint32_t b = a->off[i], e = a->off[i + 1];
            for (int c = 0; c < 3; c++) {
                if (b == e) {
                    q[3 * i + c] = p[3 * i + c];
                    continue;
                }
                double sum = 0;
                for (uint32_t k = b; k < e; k++)
                    sum += p[3 * (size_t)a->nbr[k] + c];
                q[3 * i + c] = p[3 * i + c] + f * (sum / (double)(e - b) - p[3 * i + c]);
            }
        }
        memcpy(p, q, 3 * a->n * sizeof *p);
    }
    free(q);
}
