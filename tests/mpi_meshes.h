/* SPDX-License-Identifier: MIT */
/* Generated meshes shared by the MPI tests (test_mpi, test_mpi_mesh). */
#ifndef LIMN_TEST_MPI_MESHES_H
#define LIMN_TEST_MPI_MESHES_H

#include "limn.h"

#include <stdint.h>

/* Appends b to a (indices shifted), with an offset dx in x; frees both. */
limn_mesh *test_mpi_join(limn_context *ctx, limn_mesh *a, limn_mesh *b, double dx);
/* Renumbers the vertices by a fixed pseudo-random permutation; frees a. */
limn_mesh *test_mpi_shuffle(limn_context *ctx, limn_mesh *a, unsigned seed);
/* Adds `count` isolated vertices and, with fin, a triangle on the interior
   edge (1, stride + 1) of the first grid: three faces on one edge; frees a. */
limn_mesh *test_mpi_extras(limn_context *ctx, limn_mesh *a, int count, int fin, uint32_t stride);
/* Several components, boundaries, corners, a non-manifold fin, isolated
   vertices; the last component shuffled (RCM runs on it). */
limn_mesh *test_mpi_composite(limn_context *ctx, int triangles);

#endif
