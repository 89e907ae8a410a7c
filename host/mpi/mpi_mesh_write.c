/* SPDX-License-Identifier: MIT */
/* limn_mpi_mesh_write and limn_mpi_output_set_add_mesh: a distributed mesh's
   blocks written in parallel (mpi_write.c), the vertex block being what this
   rank owns. */
#include "mpi/mpi_mesh.h"
#include "base/large_alloc.h"

#include "base/abi.h"
#include "base/context.h"
#include "mesh/io/output_set.h"
#include "mpi/mpi_write.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The float32 rounding error of the positions (ply_float_error over the ranks). */
static void float_error(mpi_part *p, const limn_mpi_mesh *mesh, const limn_write_options *o,
                        limn_write_report *r)
{
    double most = 0, sum = 0, gmost = 0;
    const mesh_slice *s = &mesh->slice;
    for (size_t v = 0; o && o->precision == LIMN_OUTPUT_FLOAT && v < s->vertex_count; v++) {
        const double *x = s->positions + 3 * v;
        double dx = x[0] - (double)(float)x[0], dy = x[1] - (double)(float)x[1],
               dz = x[2] - (double)(float)x[2];
        double d = sqrt(dx * dx + dy * dy + dz * dz);
        sum += d;
        most = d > most ? d : most;
    }
    MPI_Allreduce(&most, &gmost, 1, MPI_DOUBLE, MPI_MAX, p->comm);
    double total = mpi_sum(p, sum);
    r->max_error = gmost;
    r->mean_error = s->vertex_total ? total / (double)s->vertex_total : 0;
    r->bbox_diagonal = mpi_mesh_bbox_diagonal(p, mesh);
}

/* limn_mpi_mesh_write on structs of this library's layout (never NULL). */
static limn_status write_sized(limn_context *ctx, mpi_part *p, const limn_mpi_mesh *mesh,
                               const char *path, limn_format format,
                               const limn_write_options *o, limn_write_report *r,
                               limn_output_set *stage)
{
    const mesh_slice *s = &mesh->slice;
    uint32_t *ids = large_malloc((s->vertex_count ? s->vertex_count : 1) * sizeof *ids);
    limn_status st = mpi_agree(p, ids ? LIMN_OK
                                      : ctx_fail(ctx, LIMN_ERR_MEMORY,
                                                 "out of memory for %zu vertices",
                                                 s->vertex_count));
    if (st) {
        free(ids);
        return st;
    }
    float_error(p, mesh, o, r);
    for (size_t i = 0; i < s->vertex_count; i++)
        ids[i] = (uint32_t)(s->vertex_begin + i);
    mpi_write_part part = {.vtxdist = mesh->vertex_dist,
                           .n_owned = s->vertex_count,
                           .owned_ids = ids,
                           .pos = s->positions,
                           .colors = mesh->colors,
                           .face_begin = s->face_begin,
                           .face_count = s->face_count,
                           .face_offsets = s->face_offsets,
                           .face_indices = s->face_indices};
    st = mpi_write_mesh_part(ctx, mesh->comm, path, format, o, &part, stage);
    free(ids);
    return st;
}

/* limn_mpi_mesh_write (stage NULL) and limn_mpi_output_set_add_mesh. */
static limn_status write_called(limn_context *ctx, const char *fn, const limn_mpi_mesh *mesh,
                                const char *path, limn_format format,
                                const limn_write_options *options, limn_write_report *report,
                                limn_output_set *stage, int staged)
{
    mpi_part p;
    limn_status st = mpi_mesh_part(ctx, mesh, NULL, &p);
    if (p.comm == MPI_COMM_NULL)
        return st;
    abi_call c;
    if (!st)
        st = abi_enter(&c, ctx, fn, &abi_write_options, options, &abi_write_report, report,
                       NULL);
    int entered = !st;
    if (!st && staged && p.rank == 0)
        st = output_set_room(ctx, fn, stage, path);
    st = mpi_agree(&p, st);
    if (!st)
        st = write_sized(ctx, &p, mesh, path, format, c.options, c.report,
                         p.rank == 0 ? stage : NULL);
    if (entered)
        st = abi_leave(&c, st);
    mpi_part_end(&p);
    return st;
}

limn_status limn_mpi_mesh_write(limn_context *ctx, const limn_mpi_mesh *mesh, const char *path,
                                limn_format format, const limn_write_options *options,
                                limn_write_report *report)
{
    return write_called(ctx, "limn_mpi_mesh_write", mesh, path, format, options, report, NULL,
                        0);
}

limn_status limn_mpi_output_set_add_mesh(limn_context *ctx, limn_output_set *set,
                                         const limn_mpi_mesh *mesh, const char *path,
                                         limn_format format, const limn_write_options *options,
                                         limn_write_report *report)
{
    return write_called(ctx, "limn_mpi_output_set_add_mesh", mesh, path, format, options, report,
                        set, 1);
}
