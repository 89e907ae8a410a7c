/* SPDX-License-Identifier: MIT */
/* CAD-like meshes with sharp edges for the feature-preserving denoiser's
   test and benchmark: a cube's surface grid (n x n cells a side) moved
   radially onto a convex shape. */
#ifndef LIMN_TEST_CAD_SHAPES_H
#define LIMN_TEST_CAD_SHAPES_H

#include "limn.h"

typedef enum cad_shape {
    CAD_CUBE,          /* the cube [-1, 1]^3 itself */
    CAD_BEVELLED_CUBE, /* the cube with its 12 edges chamfered */
    CAD_PART           /* a cylinder with flat, chamfered caps (a puck / bolt head) */
} cad_shape;

/* The shape's mesh: quads, or each quad split into two triangles. NULL and
   ctx's message on failure. */
limn_mesh *cad_shape_mesh(limn_context *ctx, cad_shape shape, int n, int triangles);

#endif
