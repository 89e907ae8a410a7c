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
    limn_status st = check_mesh(ctx, "limn_mesh_info_compute", NULL, mesh);
    topology_counts k;
    if (!st)
        st = topology_counts_get(ctx, mesh, &k);
    if (st)
        return st;
    memset(info, 0, sizeof *info);
    info->vertices = mesh->vertex_count;
    info->faces = mesh->face_count;
    info->edges = k.edges;
    info->referenced_vertices = k.referenced_vertices;
    info->boundary_edges = k.boundary_edges;
    info->boundary_loops = k.boundary_loops;
    info->nonmanifold_edges = k.nonmanifold_edges;
    info->nonmanifold_vertices = k.nonmanifold_vertices;
    info->inconsistent_edges = k.inconsistent_edges;
    info->components = k.components;
    info->triangles = k.triangles;
    info->quads = k.quads;
    info->other_faces = k.other_faces;
    info->max_face_size = k.max_face_size;
    info->max_valence = k.max_valence;
    info->euler_characteristic =
        (long)k.referenced_vertices - (long)k.edges + (long)mesh->face_count;
    info->bbox_diagonal = mesh_bbox_diagonal(mesh, info->bbox_min, info->bbox_max);
    return LIMN_OK;
}

limn_status limn_mesh_info_compute(limn_context *ctx, const limn_mesh *mesh, limn_mesh_info *info)
{
    abi_call c;
    limn_status st = abi_enter_result(&c, ctx, "limn_mesh_info_compute", "info", &abi_mesh_info, info);
    return st ? st : abi_leave(&c, info_sized(ctx, mesh, c.report));
}
