/* SPDX-License-Identifier: MIT */
/*
 * limn_mpi_mesh_interpolate: the interpolation with no rank holding the
 * whole mesh. The vertex blocks are partitioned over the ranks in parallel
 * (mpi_sfc.c, a Hilbert curve, or mpi_dgraph.c, PT-Scotch), every rank
 * builds the rows of its vertices from the faces around them (mpi_local.c), the solve is the one of
 * limn_interpolate_mpi (mpi_interpolate.c), and the owned results go back to
 * the vertex blocks of a distributed control mesh with the input's faces.
 * Each row is summed in the single process's order, so the results are the
 * single process's, as limn_interpolate_mpi's are.
 */
#include "mpi/mpi_mesh.h"
#include "base/large_alloc.h"

#include "base/context.h"
#include "mpi/mpi_blocks.h"
#include "mpi/mpi_dgraph.h"
#include "mpi/mpi_local.h"
#include "mpi/mpi_sfc.h"

#include <stdlib.h>
#include <string.h>

limn_status mpi_mesh_control_of(mpi_part *p, const limn_mpi_mesh *mesh, double *positions,
                                limn_mpi_mesh **out)
{
    const mesh_slice *in = &mesh->slice;
    mesh_slice s = *in;
    size_t nc = in->face_offsets[in->face_count];
    s.positions = positions;
    s.face_offsets = large_malloc((in->face_count + 1) * sizeof *s.face_offsets);
    s.face_indices = large_malloc((nc ? nc : 1) * sizeof *s.face_indices);
    limn_status st = LIMN_OK;
    if (!s.face_offsets || !s.face_indices)
        st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for the control mesh's %zu faces",
                       in->face_count);
    st = mpi_agree(p, st);
    if (!st) {
        memcpy(s.face_offsets, in->face_offsets, (in->face_count + 1) * sizeof *s.face_offsets);
        memcpy(s.face_indices, in->face_indices, nc * sizeof *s.face_indices);
        st = mpi_mesh_adopt(p, &s, out);
    }
    mesh_slice_free(&s);
    return st;
}

limn_status mpi_mesh_results_to_blocks(mpi_part *p, const limn_mpi_mesh *mesh, const double *p4,
                                       double **block)
{
    size_t no = p->n_owned, nb = mesh->slice.vertex_count;
    double *xyz = large_malloc((no ? 3 * no : 1) * sizeof *xyz);
    *block = large_malloc((nb ? 3 * nb : 1) * sizeof **block);
    limn_status st = LIMN_OK;
    if (!xyz || !*block)
        st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu results", no + nb);
    st = mpi_agree(p, st);
    if (!st) {
        for (size_t i = 0; i < no; i++)
            memcpy(xyz + 3 * i, p4 + 4 * i, 3 * sizeof *xyz);
        st = mpi_blocks_store(p, mesh->vertex_dist, no, p->owned_ids, xyz, 3 * sizeof *xyz,
                              *block);
    }
    free(xyz);
    if (st) {
        free(*block);
        *block = NULL;
    }
    return st;
}

limn_status mpi_mesh_build_rows(mpi_part *p, const limn_mpi_mesh *mesh, limn_scheme scheme,
                                double alpha, double **m4)
{
    const mesh_slice *s = &mesh->slice;
    mpi_local_mesh *lm = mpi_mesh_take_sub(mesh);
    int have = lm && p->partition != LIMN_MPI_PARTITION_SCOTCH, all = 0;
    MPI_Allreduce(&have, &all, 1, MPI_INT, MPI_MIN, p->comm);
    if (all) { /* the repair's sub-mesh: partitioned and exchanged there */
        p->stats.seconds_partition = 0.0;
        limn_status st = mpi_local_build_on(p, mesh->vertex_dist, s->positions, lm, scheme,
                                            alpha, m4, NULL);
        free(lm);
        return st;
    }
    mpi_local_mesh_free(lm);
    free(lm);
    uint32_t *part_of = NULL;
    double t0 = MPI_Wtime();
    limn_status st;
    if (p->partition == LIMN_MPI_PARTITION_SCOTCH) {
        mpi_dgraph_stats ds;
        st = mpi_dgraph_partition(p->ctx, p->comm, mesh->vertex_dist, s->face_count,
                                  s->face_offsets, s->face_indices, p->size, &part_of, &ds);
    } else {
        st = mpi_sfc_partition(p, mesh->vertex_dist, s->positions, p->size, &part_of, NULL);
    }
    p->stats.seconds_partition = MPI_Wtime() - t0;
    if (!st) /* the edge cut comes from the local build (mpi_local_counts) */
        st = mpi_local_build(p, mesh->vertex_dist, s->positions, part_of, s->face_begin,
                             s->face_count, s->face_offsets, s->face_indices, scheme, alpha,
                             NULL, m4, NULL);
    free(part_of);
    return st;
}

/* limn_mpi_mesh_interpolate on structs of this library's layout. */
static limn_status interpolate_sized(limn_context *ctx, const limn_mpi_mesh *mesh,
                                     const limn_interpolate_options *o,
                                     limn_mpi_mesh **control, limn_report *r,
                                     const limn_mpi_options *mpi, limn_mpi_result *result)
{
    memset(r, 0, sizeof *r);
    mpi_part p;
    limn_status st = mpi_mesh_part(ctx, mesh, mpi, &p);
    if (p.comm == MPI_COMM_NULL)
        return st;
    limn_method method;
    limn_scheme scheme = LIMN_SCHEME_AUTO;
    st = mpi_interpolate_method(&p, o, st || control ? st : ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                                "limn_mpi_mesh_interpolate: control is NULL"), &method, r);
    st = mpi_agree(&p, st);
    if (!st)
        st = mpi_mesh_check(&p, "limn_mpi_mesh_interpolate", mesh);
    if (!st)
        st = mpi_mesh_scheme(&p, mesh, o->scheme, &scheme);
    double *m4 = NULL, *p4 = NULL, *block = NULL;
    if (!st)
        st = mpi_mesh_build_rows(&p, mesh, scheme, o->alpha, &m4);
    double t0 = MPI_Wtime();
    if (!st) {
        MPI_REPORT_OPERATOR(r, &p);
        r->reordered = 0;
        r->omega = 1.0;
        size_t nl = p.n_owned + p.n_ghost;
        p4 = calloc(nl ? 4 * nl : 4, sizeof *p4);
        st = mpi_agree(&p, p4 ? LIMN_OK : ctx_fail(ctx, LIMN_ERR_MEMORY,
                                                   "out of memory for %zu vertices", nl));
    }
    if (!st)
        st = mpi_interpolate_rows(&p, o, &method, m4, p4, r);
    free(m4); /* the last product is done: the right-hand side and the rows go */
    m4 = NULL;
    mpi_part_drop_rows(&p);
    if (!st)
        st = mpi_mesh_results_to_blocks(&p, mesh, p4, &block);
    if (!st)
        st = mpi_mesh_control_of(&p, mesh, block, control);
    else
        free(block);
    r->seconds_solve = MPI_Wtime() - t0;
    r->max_rel_error = p.diag > 0 ? r->max_abs_error / p.diag : r->max_abs_error;
    r->mean_rel_error = p.diag > 0 ? r->mean_abs_error / p.diag : r->mean_abs_error;
    if (result)
        result->stats = p.stats;
    free(m4);
    free(p4);
    mpi_part_end(&p);
    if (!st)
        ctx_progress(ctx, "solve", 1.0);
    return st;
}

limn_status limn_mpi_mesh_interpolate(limn_context *ctx, const limn_mpi_mesh *mesh,
                                      const limn_interpolate_options *options,
                                      limn_mpi_mesh **control, limn_report *report,
                                      const limn_mpi_options *mpi, limn_mpi_result *result)
{
    if (!mesh)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "limn_mpi_mesh_interpolate: the mesh is NULL");
    mpi_call c;
    limn_status st = mpi_enter(&c, ctx, mesh->comm, "limn_mpi_mesh_interpolate",
                               &abi_interpolate_options, options, &abi_report, report, mpi,
                               result, NULL);
    return st ? st
              : mpi_leave(&c, interpolate_sized(ctx, mesh, c.abi.options, control,
                                                c.abi.report, c.mpi, c.result));
}
