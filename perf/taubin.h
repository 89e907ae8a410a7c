/* SPDX-License-Identifier: MIT */
/* Taubin lambda|mu smoothing (uniform Laplacian, MeshLab's weights), written
   independently of limn for the denoising benchmarks. */
#ifndef LIMN_PERF_TAUBIN_H
#define LIMN_PERF_TAUBIN_H

#include "limn.h"
#include <stddef.h>
#include <stdint.h>

typedef struct adjacency {
    size_t n;
    uint32_t *off, *nbr;
} adjacency;

/* Vertex neighbours over face edges, without repeats. */
adjacency build_adjacency(const limn_mesh *m);
void adjacency_free(adjacency *a);
/* `applications` steps of x += f (mean(neighbours) - x), f = lambda, mu,
   lambda, ... (pairs of steps are Taubin's lambda|mu pairs). */
void taubin_steps(const adjacency *a, double *p, int applications, double lambda, double mu);

#endif
