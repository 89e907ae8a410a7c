/* SPDX-License-Identifier: MIT */
/* Meshes and scratch of the MPI tests (test_mpi*.c). */
#ifndef LIMN_TEST_MPI_MESHES_H
#define LIMN_TEST_MPI_MESHES_H

#include "limn.h"

#include <stddef.h>

/*
 * Several components, boundaries, corners, a non-manifold fin, isolated
 * vertices; the last component shuffled (RCM runs on it). triangles: Loop
 * grids and no pyramid, else quads with the pyramid (triangles and quads).
 */
limn_mesh *mpi_test_composite(limn_context *ctx, int triangles);

/* Closed components (a volume is defined): tori (quads or triangles), an
   icosahedron (triangles) or a hexagonal prism (hexagons and quads), the
   last torus shuffled and perturbed. */
limn_mesh *mpi_test_closed(limn_context *ctx, int triangles);

/* m with face f's corners in reverse order (NULL when memory runs out). */
limn_mesh *mpi_test_turned(limn_context *ctx, const limn_mesh *m, size_t f);

/* A new directory $TMPDIR/limn_NAME_XXXXXX made by rank 0 and its path on
   every rank of MPI_COMM_WORLD (collective); "" when it cannot be made. */
void mpi_test_scratch_dir(char *dir, size_t cap, const char *name);

#endif
