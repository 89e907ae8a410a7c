/* SPDX-License-Identifier: MIT */
/* Meshes of the MPI tests (test_mpi.c, test_mpi_cmds.c). */
#ifndef LIMN_TEST_MPI_MESHES_H
#define LIMN_TEST_MPI_MESHES_H

#include "limn.h"

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

#endif
