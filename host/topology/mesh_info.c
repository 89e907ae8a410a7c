/* SPDX-License-Identifier: MIT */
/* limn_mesh_info_compute: counts for `limn info` and for callers. */
#include "base/abi.h"
#include "mesh/check.h"
#include "base/context.h"
#include "mesh/mesh.h"
#include "topology/topology.h"

#include <string.h>

/* limn_mesh_info_compute into a result of this library's layout. */
static limn_status info_sized(limn_context *ctx, const limn_mesh *mesh, limn_mesh_info *info)
{
    limn_status begun = abi_begin(ctx, "limn_mesh_info_compute", "info", info);
    if (begun)
        return begun;
    topology t;
    limn_status st = topology_get_checked(ctx, "limn_mesh_info_compute", mesh, &t);
    if (st)
        return st;
    memset(info, 0, sizeof *info);
    info->vertices = mesh->vertex_count;
    info->faces = mesh->face_count;
    info->edges = t.edge_count;
    info->referenced_vertices = t.referenced_vertices;
    info->boundary_edges = t.boundary_edges;
    info->boundary_loops = t.boundary_loops;
    info->nonmanifold_edges = t.nonmanifold_edges;
    info->nonmanifold_vertices = t.nonmanifold_vertices;
    info->inconsistent_edges = t.inconsistent_edges;
    info->components = t.components;
    info->triangles = t.triangles;
    info->quads = t.quads;
    info->other_faces = t.other_faces;
    info->max_face_size = t.max_face_size;
    info->max_valence = t.max_valence;
    info->euler_characteristic =
        (long)t.referenced_vertices - (long)t.edge_count + (long)mesh->face_count;
    info->bbox_diagonal = mesh_bbox_diagonal(mesh, info->bbox_min, info->bbox_max);
    topology_free(&t);
    return LIMN_OK;
}

limn_status limn_mesh_info_compute(limn_context *ctx, const limn_mesh *mesh, limn_mesh_info *info)
{
    abi_call c;
    limn_status st = abi_enter_result(&c, ctx, "limn_mesh_info_compute", "info", &abi_mesh_info, info);
    return st ? st : abi_leave(&c, info_sized(ctx, mesh, c.report));
}
