/* SPDX-License-Identifier: MIT */
/* Noise, its measure and the sphere of seed 000 Fig. 5, for the denoising
   tests and benchmark. */
#ifndef LIMN_TEST_NOISE_H
#define LIMN_TEST_NOISE_H

#include "limn.h"
#include <stdint.h>

/* The mean length of the faces' edges. */
double test_mean_edge(const limn_mesh *mesh);
/* Seeded Gaussian noise of deviation sigma on every coordinate (Box-Muller). */
void test_gaussian_noise(limn_mesh *mesh, double sigma, uint64_t seed);
/* Seeded Gaussian noise of deviation sigma along each vertex's normal (the
   sum of its faces' Newell normals, normalised): a range scanner's noise. */
void test_normal_noise(limn_mesh *mesh, double sigma, uint64_t seed);
/* Moves every vertex onto the sphere about centroid whose radius is the
   vertices' mean distance from it (a vertex at the centroid stays). */
void test_spherize(limn_mesh *mesh, const double centroid[3]);

#endif
