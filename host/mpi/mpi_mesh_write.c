/* SPDX-License-Identifier: MIT */
/* limn_mpi_mesh_write: a distributed mesh's blocks written in parallel
   (mpi_write.c), the vertex block being what this rank owns. */
#include "mpi/mpi_mesh.h"

#include "base/context.h"
#include "mpi/mpi_write.h"

#include <stdlib.h>

limn_status limn_mpi_mesh_write(limn_context *ctx, const limn_mpi_mesh *mesh, const char *path,
                                const limn_write_options *options)
{
    mpi_part p;
    limn_status st = mpi_mesh_part(ctx, mesh, NULL, &p);
    if (p.comm == MPI_COMM_NULL)
        return st;
    const mesh_slice *s = &mesh->slice;
    uint32_t *ids = malloc((s->vertex_count ? s->vertex_count : 1) * sizeof *ids);
    if (!st && !ids)
        st = ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for %zu vertices", s->vertex_count);
    st = mpi_agree(&p, st);
    mpi_part_end(&p);
    if (st) {
        free(ids);
        return st;
    }
    for (size_t i = 0; i < s->vertex_count; i++)
        ids[i] = (uint32_t)(s->vertex_begin + i);
    mpi_write_part part = {.vtxdist = mesh->vertex_dist,
                           .n_owned = s->vertex_count,
                           .owned_ids = ids,
                           .pos = s->positions,
                           .face_begin = s->face_begin,
                           .face_count = s->face_count,
                           .face_offsets = s->face_offsets,
                           .face_indices = s->face_indices};
    st = mpi_write_mesh_part(ctx, mesh->comm, path, LIMN_FORMAT_AUTO, options, &part);
    free(ids);
    return st;
}
