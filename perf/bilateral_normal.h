/* SPDX-License-Identifier: MIT */
/* Independent comparisons for perf/feature_bench: bilateral normal filtering
   (Zheng et al. 2011, vertex updates of Sun et al. 2007) and Taubin lambda|mu
   smoothing, written from the papers without limn's code. */
#ifndef LIMN_PERF_BILATERAL_NORMAL_H
#define LIMN_PERF_BILATERAL_NORMAL_H

#include "limn.h"

typedef struct bnf_params {
    int outer;          /* rounds of (normal filtering, vertex update); Zheng: 1 */
    int normal_iters;   /* Zheng: 20 */
    int vertex_iters;   /* Sun et al.: ~10 */
    double sigma_r;     /* range width on |n_i - n_j|; Zheng: ~0.35 */
    double sigma_s;     /* 0: the mean distance between edge-adjacent face centroids */
} bnf_params;

/* Filters the positions p (3 per vertex) of mesh's topology in place. */
void bnf_denoise(const limn_mesh *mesh, double *p, const bnf_params *params);
/* pairs x (lambda then mu) steps of p += f (mean of the edge neighbours - p). */
void taubin_denoise(const limn_mesh *mesh, double *p, int pairs, double lambda, double mu);

#endif
