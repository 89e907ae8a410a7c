/* SPDX-License-Identifier: MIT */
/*
 * Steps of limn_mesh_repair (mesh_repair.c) that the MPI layer runs on its
 * slices of a mesh, with the counts reduced over the ranks.
 */
#ifndef LIMN_TOPOLOGY_MESH_REPAIR_H
#define LIMN_TOPOLOGY_MESH_REPAIR_H

#include "limn.h"

/* Rebuilds m's faces without repeated vertices (mesh_repair.c's comment says
   how), counting into r's repeat fields; the topology is dropped. */
limn_status repair_fix_repeats(limn_context *ctx, limn_mesh *m, limn_repair_report *r);

/* The warning saying what repair_fix_repeats changed (r's repeat fields and
   first_repeat_face / _vertex; faces_left: the faces after the repair). */
void repair_warn_repeats(limn_context *ctx, const limn_repair_report *r, size_t faces_left);
/* Warns of the duplicate faces in r (none: says nothing). */
void repair_warn_duplicates(limn_context *ctx, const limn_repair_report *r);
/* Warns of the non-manifold edges/vertices, inconsistent edges and unused vertices in r. */
void repair_warn_kept(limn_context *ctx, const limn_repair_report *r);

#endif
