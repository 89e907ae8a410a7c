/* SPDX-License-Identifier: MIT */
/* Geometric measures shared by the series drivers (internal side of
   limn_mesh_measure / limn_mesh_compare). */
#ifndef LIMN_MEASURE_H
#define LIMN_MEASURE_H

#include "limn.h"

struct topology;

/* Newell normal of face f (twice the vector area of the polygon). */
void measure_face_normal(const double *pos, const uint32_t *off, const uint32_t *idx, size_t f,
                         double n[3]);
/* Signed volume and area of mesh's faces with positions pos (3 per vertex). */
void measure_volume_area(const limn_mesh *mesh, const double *pos, double *volume, double *area);
/* No boundary, non-manifold or inconsistently oriented edge: volume is defined. */
int measure_topology_closed(const struct topology *t);
/* Faces of ref's topology whose normal with pos points away from it with ref_pos. */
size_t measure_flipped(const limn_mesh *ref, const double *ref_pos, const double *pos);
/* LIMN_ERR_TOPOLOGY naming the first difference, with the meshes' names. */
limn_status measure_same_topology(limn_context *ctx, const limn_mesh *a, const limn_mesh *b,
                                  const char *name_a, const char *name_b);

#endif
