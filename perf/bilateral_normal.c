/* SPDX-License-Identifier: MIT */
/*
 * Bilateral normal filtering, Zheng, Fu, Au, Tai, "Bilateral Normal
 * Filtering for Mesh Denoising", IEEE TVCG 17(10), 2011 (the local,
 * iterative scheme): n_i <- normalise(sum_{j in N(i)} A_j Ws(|c_i - c_j|)
 * Wr(|n_i - n_j|) n_j), N(i) the faces sharing a vertex with face i,
 * Gaussian kernels, then the vertex update of Sun et al. 2007,
 * x_v <- x_v + 1/|F_v| sum_{f in F_v} n_f (n_f . (c_f - x_v)). And Taubin
 * lambda|mu smoothing with the uniform Laplacian (MeshLab's default).
 * Plain C on one thread, independent of limn's own code.
 */
#include "bilateral_normal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct faces {
    size_t nv, nf;
    const uint32_t *off, *idx;
    uint32_t *vf_off, *vf;       /* faces of each vertex */
    uint32_t *ring_off, *ring;   /* faces sharing a vertex with each face */
    double *n, *c, *a;
} faces;

static void build_faces(const limn_mesh *m, faces *F)
{
    F->nv = limn_mesh_vertex_count(m);
    F->nf = limn_mesh_face_count(m);
    F->off = limn_mesh_face_offsets(m);
    F->idx = limn_mesh_face_indices(m);
    F->vf_off = calloc(F->nv + 1, sizeof *F->vf_off);
    F->vf = malloc(F->off[F->nf] * sizeof *F->vf);
    for (size_t k = 0; k < F->off[F->nf]; k++)
        F->vf_off[F->idx[k] + 1]++;
    for (size_t v = 0; v < F->nv; v++)
        F->vf_off[v + 1] += F->vf_off[v];
    uint32_t *fill = calloc(F->nv, sizeof *fill);
    for (size_t f = 0; f < F->nf; f++)
        for (uint32_t k = F->off[f]; k < F->off[f + 1]; k++)
            F->vf[F->vf_off[F->idx[k]] + fill[F->idx[k]]++] = (uint32_t)f;
    free(fill);
    /* rings without repeats, with a last-seen mark per face */
    uint32_t *mark = malloc(F->nf * sizeof *mark);
    for (size_t f = 0; f < F->nf; f++)
        mark[f] = UINT32_MAX;
    size_t cap = 0;
    for (size_t f = 0; f < F->nf; f++)
        for (uint32_t k = F->off[f]; k < F->off[f + 1]; k++)
            cap += F->vf_off[F->idx[k] + 1] - F->vf_off[F->idx[k]];
    F->ring_off = malloc((F->nf + 1) * sizeof *F->ring_off);
    F->ring = malloc(cap * sizeof *F->ring);
    size_t w = 0;
    F->ring_off[0] = 0;
    for (size_t f = 0; f < F->nf; f++) {
        for (uint32_t k = F->off[f]; k < F->off[f + 1]; k++)
            for (uint32_t j = F->vf_off[F->idx[k]]; j < F->vf_off[F->idx[k] + 1]; j++)
                if (mark[F->vf[j]] != f) {
                    mark[F->vf[j]] = (uint32_t)f;
                    F->ring[w++] = F->vf[j];
                }
        F->ring_off[f + 1] = (uint32_t)w;
    }
    free(mark);
    F->n = malloc(3 * F->nf * sizeof *F->n);
    F->c = malloc(3 * F->nf * sizeof *F->c);
    F->a = malloc(F->nf * sizeof *F->a);
}

static void free_faces(faces *F)
{
    free(F->vf_off);
    free(F->vf);
    free(F->ring_off);
    free(F->ring);
    free(F->n);
    free(F->c);
    free(F->a);
}

/* Normals (Newell, unit), centroids and areas of the faces at p. */
static void face_geometry(faces *F, const double *p)
{
    for (size_t f = 0; f < F->nf; f++) {
        double n[3] = {0, 0, 0}, c[3] = {0, 0, 0};
        uint32_t b = F->off[f], e = F->off[f + 1];
        for (uint32_t k = b; k < e; k++) {
            const double *u = p + 3 * F->idx[k], *v = p + 3 * F->idx[k + 1 < e ? k + 1 : b];
            n[0] += (u[1] - v[1]) * (u[2] + v[2]);
            n[1] += (u[2] - v[2]) * (u[0] + v[0]);
            n[2] += (u[0] - v[0]) * (u[1] + v[1]);
            for (int d = 0; d < 3; d++)
                c[d] += u[d] / (double)(e - b);
        }
        double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        F->a[f] = 0.5 * l;
        for (int d = 0; d < 3; d++) {
            F->n[3 * f + d] = l > 0 ? n[d] / l : 0;
            F->c[3 * f + d] = c[d];
        }
    }
}

static double d2(const double *a, const double *b)
{
    return (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
           (a[2] - b[2]) * (a[2] - b[2]);
}

/* Zheng's sigma_s: the mean centroid distance of faces sharing an edge
   (approximated by sharing two vertices within the ring). */
static double mean_adjacent_distance(const faces *F)
{
    double sum = 0;
    size_t count = 0;
    for (size_t f = 0; f < F->nf; f++)
        for (uint32_t k = F->ring_off[f]; k < F->ring_off[f + 1]; k++) {
            uint32_t g = F->ring[k];
            int shared = 0;
            for (uint32_t a = F->off[f]; a < F->off[f + 1]; a++)
                for (uint32_t b = F->off[g]; b < F->off[g + 1]; b++)
                    shared += F->idx[a] == F->idx[b];
            if (g != f && shared == 2) {
                sum += sqrt(d2(F->c + 3 * f, F->c + 3 * (size_t)g));
                count++;
            }
        }
    return count ? sum / (double)count : 1.0;
}

static void filter_normals(const faces *F, double *n, double *tmp, int iters, double ss,
                           double sr)
{
    for (int it = 0; it < iters; it++) {
        for (size_t i = 0; i < F->nf; i++) {
            double s[3] = {0, 0, 0};
            for (uint32_t k = F->ring_off[i]; k < F->ring_off[i + 1]; k++) {
                size_t j = F->ring[k];
                double w = F->a[j] * exp(-d2(F->c + 3 * i, F->c + 3 * j) / (2 * ss * ss)) *
                           exp(-d2(n + 3 * i, n + 3 * j) / (2 * sr * sr));
                for (int d = 0; d < 3; d++)
                    s[d] += w * n[3 * j + d];
            }
            double l = sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
            for (int d = 0; d < 3; d++)
                tmp[3 * i + d] = l > 0 ? s[d] / l : n[3 * i + d];
        }
        memcpy(n, tmp, 3 * F->nf * sizeof *n);
    }
}

static void update_vertices(faces *F, const double *n, double *p, double *q, int iters)
{
    for (int it = 0; it < iters; it++) {
        face_geometry(F, p); /* centroids of the current positions */
        for (size_t v = 0; v < F->nv; v++) {
            double d[3] = {0, 0, 0};
            uint32_t b = F->vf_off[v], e = F->vf_off[v + 1];
            for (uint32_t k = b; k < e; k++) {
                size_t f = F->vf[k];
                double h = 0;
                for (int c = 0; c < 3; c++)
                    h += n[3 * f + c] * (F->c[3 * f + c] - p[3 * v + c]);
                for (int c = 0; c < 3; c++)
                    d[c] += h * n[3 * f + c];
            }
            for (int c = 0; c < 3; c++)
                q[3 * v + c] = p[3 * v + c] + (e > b ? d[c] / (double)(e - b) : 0);
        }
        memcpy(p, q, 3 * F->nv * sizeof *p);
    }
}

void bnf_denoise(const limn_mesh *mesh, double *p, const bnf_params *pr)
{
    faces F;
    build_faces(mesh, &F);
    double *n = malloc(3 * F.nf * sizeof *n), *tmp = malloc(3 * F.nf * sizeof *tmp);
    double *q = malloc(3 * F.nv * sizeof *q);
    face_geometry(&F, p);
    double ss = pr->sigma_s > 0 ? pr->sigma_s : mean_adjacent_distance(&F);
    for (int o = 0; o < pr->outer; o++) {
        face_geometry(&F, p);
        memcpy(n, F.n, 3 * F.nf * sizeof *n);
        filter_normals(&F, n, tmp, pr->normal_iters, ss, pr->sigma_r);
        update_vertices(&F, n, p, q, pr->vertex_iters);
    }
    free(n);
    free(tmp);
    free(q);
    free_faces(&F);
}

void taubin_denoise(const limn_mesh *mesh, double *p, int pairs, double lambda, double mu)
{
    faces F;
    build_faces(mesh, &F);
    /* edge neighbours: the two corners next to each corner, repeats kept
       out with a last-seen mark */
    size_t nv = F.nv;
    uint32_t *mark = malloc(nv * sizeof *mark), *nb_off = calloc(nv + 1, sizeof *nb_off);
    uint32_t *nb = malloc(2 * F.off[F.nf] * sizeof *nb);
    for (size_t v = 0; v < nv; v++)
        mark[v] = UINT32_MAX;
    size_t w = 0;
    for (size_t v = 0; v < nv; v++) {
        for (uint32_t k = F.vf_off[v]; k < F.vf_off[v + 1]; k++) {
            uint32_t f = F.vf[k], b = F.off[f], e = F.off[f + 1];
            for (uint32_t c = b; c < e; c++)
                if (F.idx[c] == v) {
                    uint32_t nx = F.idx[c + 1 < e ? c + 1 : b], pv = F.idx[c > b ? c - 1 : e - 1];
                    if (mark[nx] != v)
                        mark[nx] = (uint32_t)v, nb[w++] = nx;
                    if (mark[pv] != v)
                        mark[pv] = (uint32_t)v, nb[w++] = pv;
                }
        }
        nb_off[v + 1] = (uint32_t)w;
    }
    double *q = malloc(3 * nv * sizeof *q);
    for (int s = 0; s < 2 * pairs; s++) {
        double f = s % 2 ? mu : lambda;
        for (size_t v = 0; v < nv; v++) {
            uint32_t b = nb_off[v], e = nb_off[v + 1];
            for (int c = 0; c < 3; c++) {
                double sum = 0;
                for (uint32_t k = b; k < e; k++)
                    sum += p[3 * nb[k] + c];
                q[3 * v + c] = e > b ? p[3 * v + c] + f * (sum / (e - b) - p[3 * v + c])
                                     : p[3 * v + c];
            }
        }
        memcpy(p, q, 3 * nv * sizeof *p);
    }
    free(q);
    free(mark);
    free(nb_off);
    free(nb);
    free_faces(&F);
}
