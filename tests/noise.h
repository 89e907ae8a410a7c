/* SPDX-License-Identifier: MIT */
/* Noise and its measure, for the denoising tests and benchmark. */
#ifndef LIMN_TEST_NOISE_H
#define LIMN_TEST_NOISE_H

#include "limn.h"
#include <stdint.h>

/* The mean length of the faces' edges. */
double test_mean_edge(const limn_mesh *mesh);
/* Seeded Gaussian noise of deviation sigma on every coordinate (Box-Muller). */
void test_gaussian_noise(limn_mesh *mesh, double sigma, uint64_t seed);

#endif
