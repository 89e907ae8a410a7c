/* SPDX-License-Identifier: MIT */
/*
 * Local rows, the operator side (mpi_local.h): from a rank's sub-mesh
 * (mpi_local_sub.c) the global numbers (vertex and face counts, stencil
 * entries, bounding box, edge cut), the sub-mesh's operator and the owned
 * rows, classes and halo (mpi_local_rows.c) on the device.
 */
#include "mpi/mpi_local.h"
#include "base/large_alloc.h"

#include "base/context.h"
#include "mesh/mesh.h"

#include <stdlib.h>
#include <string.h>

/* The scheme over all ranks (AUTO: Loop when every face is a triangle), and
   a refusal naming a face Loop cannot take. */
static limn_status resolve_scheme(mpi_part *p, const local_sub *s, const limn_mesh *m,
                                  limn_scheme want, limn_scheme *out)
{
    size_t other = SIZE_MAX;
    for (size_t f = 0; f < m->face_count && other == SIZE_MAX; f++)
        if (m->face_offsets[f + 1] - m->face_offsets[f] != 3)
            other = f;
    int all_tri = other == SIZE_MAX, every = 0;
    MPI_Allreduce(&all_tri, &every, 1, MPI_INT, MPI_MIN, p->comm);
    if (want == LIMN_SCHEME_AUTO)
        want = every && p->faces_global > 0 ? LIMN_SCHEME_LOOP : LIMN_SCHEME_CATMARK;
    limn_status st = LIMN_OK;
    if (want == LIMN_SCHEME_LOOP && other != SIZE_MAX) {
        const uint32_t *v = m->face_indices + m->face_offsets[other];
        st = ctx_fail(p->ctx, LIMN_ERR_TOPOLOGY,
                      "a face with %u vertices (vertices %u, %u, %u, %u, ...) but Loop "
                      "subdivision needs triangles only: use --scheme catmark (or auto), or "
                      "triangulate the mesh",
                      m->face_offsets[other + 1] - m->face_offsets[other], s->ids[v[0]],
                      s->ids[v[1]], s->ids[v[2]], s->ids[v[3]]);
    }
    *out = want;
    return mpi_agree(p, st);
}

/* Global numbers, the scheme and the sub-mesh's operator (input order). */
static limn_status sub_operator(mpi_part *p, local_sub *s, const limn_mesh *m, limn_scheme want,
                                double alpha)
{
    limn_status st = mpi_local_counts(p, s, m);
    if (st)
        return st;
    st = resolve_scheme(p, s, m, want, &p->scheme);
    if (!st && s->n) /* a rank without vertices has no rows */
        st = operator_build_ex(p->ctx, m, p->scheme, alpha, OPERATOR_HOST_ONLY, &s->op);
    st = mpi_agree(p, st);
    if (st)
        return st;
    p->alpha = p->scheme == LIMN_SCHEME_CATMARK ? alpha : 0.0;
    uint64_t nnz = 0;
    for (size_t i = 0; i < s->n_owned; i++)
        nnz += s->op.host.row_offsets[s->owned[i] + 1] - s->op.host.row_offsets[s->owned[i]];
    MPI_Allreduce(MPI_IN_PLACE, &nnz, 1, MPI_UINT64_T, MPI_SUM, p->comm);
    p->nnz_global = nnz;
    return LIMN_OK;
}

/* Bytes of the build's own arrays alive when the operator is built
   (mpi_local_stats): every list of the sub-mesh's build and the census's
   face ids are freed by then, so what is left is lm's; the sub-mesh, the
   operator's input, aside. */
static size_t held_bytes(const mpi_local_mesh *lm)
{
    const local_sub *s = &lm->s;
    size_t w = sizeof(uint32_t);
    return 3 * s->n * sizeof(double) /* positions: the sub-mesh's, then lm->pos */ +
           (s->ids ? s->n * w : 0) + (s->part ? s->n * w : 0) +
           (s->owned ? s->n_owned * w : 0);
}

/* The positions of the owned rows, 4 doubles a row (w = 0), local order. */
static limn_status owned_positions(mpi_part *p, const local_sub *s, const double *pos,
                                   double **rows4)
{
    size_t no = p->n_owned;
    /* page aligned: the solve's device buffer of M uses it in place */
    double *r = device_host_alloc((no ? 4 * no : 4) * sizeof *r);
    if (!r)
        return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu rows", no);
    memset(r, 0, (no ? 4 * no : 4) * sizeof *r);
    /* ids increase within each class (mpi_part.h): one walk over the
       sub-mesh's increasing ids per class, no search per row */
    const size_t cls[5] = {0, p->send_begin, p->n_interior, p->send_end, no};
    for (int c = 0; c < 4; c++)
        for (size_t l = cls[c], k = 0; l < cls[c + 1]; l++) {
            while (k < s->n && s->ids[k] < p->owned_ids[l])
                k++;
            memcpy(r + 4 * l, pos + 3 * k, 3 * sizeof *r);
        }
    *rows4 = r;
    return LIMN_OK;
}

limn_status mpi_local_build_on(mpi_part *p, const size_t *vtxdist, const double *positions,
                               mpi_local_mesh *lm, limn_scheme scheme, double alpha,
                               double **owned_rows4, mpi_local_stats *stats)
{
    double t0 = MPI_Wtime();
    local_sub *s = &lm->s;
    s->stats = stats;
    if (owned_rows4)
        *owned_rows4 = NULL;
    size_t nb = vtxdist[p->rank + 1] - vtxdist[p->rank];
    p->n_global = vtxdist[p->size];
    p->diag = mpi_local_diagonal(p, positions, nb);
    p->reordered = 0;
    free(lm->face_ids); /* the census's (mpi_local_census): not read from here on */
    lm->face_ids = NULL;
    if (stats)
        stats->bytes_held_at_operator = held_bytes(lm);
    limn_status st = sub_operator(p, s, lm->mesh, scheme, alpha);
    lm->pos = lm->mesh->positions; /* kept for owned_positions */
    lm->mesh->positions = NULL;
    limn_mesh_destroy(lm->mesh); /* the rows are built: its last reader is done */
    lm->mesh = NULL;
    if (!st)
        st = mpi_local_rows(p, s);
    if (!st && owned_rows4)
        st = owned_positions(p, s, lm->pos, owned_rows4);
    st = mpi_agree(p, st);
    mpi_local_mesh_free(lm);
    if (!st)
        st = mpi_open_rows(p);
    p->stats.seconds_distribute = MPI_Wtime() - t0;
    st = mpi_agree(p, st);
    if (st && owned_rows4) {
        free(*owned_rows4);
        *owned_rows4 = NULL;
    }
    return st;
}

limn_status mpi_local_build(mpi_part *p, const size_t *vtxdist, const double *positions,
                            const uint32_t *part_of, size_t face_begin, size_t face_count,
                            const uint32_t *face_offsets, const uint32_t *face_indices,
                            limn_scheme scheme, double alpha, const limn_repair_options *repair,
                            double **owned_rows4, mpi_local_stats *stats)
{
    double t0 = MPI_Wtime();
    if (stats)
        memset(stats, 0, sizeof *stats);
    if (owned_rows4)
        *owned_rows4 = NULL;
    mpi_local_mesh lm;
    limn_status st = mpi_local_mesh_build(p, vtxdist, positions, part_of, face_begin, face_count,
                                          face_offsets, face_indices, repair, 0, &lm, stats);
    if (!st)
        st = mpi_local_build_on(p, vtxdist, positions, &lm, scheme, alpha, owned_rows4, stats);
    p->stats.seconds_distribute = MPI_Wtime() - t0;
    if (stats)
        stats->seconds = p->stats.seconds_distribute;
    return st;
}
