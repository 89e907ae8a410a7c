/* SPDX-License-Identifier: MIT */
/*
 * Measures of a distributed mesh (mpi_mesh.h), the single process's bits
 * with no rank holding the mesh: closedness (mpi_mesh_census), the signed volume,
 * area and centroid of measure.c. Those are sums in face (or vertex) order;
 * the blocks follow that order, so each rank computes its terms on its own
 * (the costly part: corners fetched from their owners, cross products,
 * square roots), then the ranks add them in turn, each starting from the
 * previous rank's running sums: the additions of one process, in its order.
 * limn_mpi_mesh_measure and limn_mpi_mesh_volume_area are the public calls.
 */
#include "mpi/mpi_mesh.h"
#include "base/large_alloc.h"

#include "base/abi.h"
#include "base/context.h"
#include "mpi/mpi_blocks.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void mpi_mesh_chained_sums(mpi_part *p, const double *terms, size_t count, int n, double *sum)
{
    for (int j = 0; j < n; j++)
        sum[j] = 0.0;
    if (p->rank > 0)
        MPI_Recv(sum, n, MPI_DOUBLE, p->rank - 1, 1, p->comm, MPI_STATUS_IGNORE);
    for (size_t i = 0; i < count; i++)
        for (int j = 0; j < n; j++)
            sum[j] += terms[(size_t)n * i + j];
    if (p->rank + 1 < p->size)
        MPI_Send(sum, n, MPI_DOUBLE, p->rank + 1, 1, p->comm);
    MPI_Bcast(sum, n, MPI_DOUBLE, p->size - 1, p->comm);
}

/* The position of global vertex 0 (measure_volume_area's origin), from the
   first rank with vertices. */
static void first_position(mpi_part *p, const limn_mpi_mesh *mesh, const double *block,
                           double c[3])
{
    int from = 0;
    while (from + 1 < p->size && mesh->vertex_dist[from + 1] == 0)
        from++;
    c[0] = c[1] = c[2] = 0.0;
    if (p->rank == from && mesh->slice.vertex_count)
        memcpy(c, block, 3 * sizeof *c);
    MPI_Bcast(c, 3, MPI_DOUBLE, from, p->comm);
}

/* The volume and area terms of this rank's faces (2 per fan triangle, in
   order), each as measure_volume_area computes it; pos: each corner's
   position (3 per corner). */
static void face_terms(const mesh_slice *s, const double *pos, const double c[3], double *t)
{
    size_t k = 0;
    for (size_t f = 0; f < s->face_count; f++) {
        uint32_t b = s->face_offsets[f], e = s->face_offsets[f + 1];
        const double *p0 = pos + 3 * (size_t)b;
        double a[3] = {p0[0] - c[0], p0[1] - c[1], p0[2] - c[2]};
        for (uint32_t i = b + 1; i + 1 < e; i++) {
            const double *p1 = pos + 3 * (size_t)i, *p2 = pos + 3 * ((size_t)i + 1);
            double u[3] = {p1[0] - c[0], p1[1] - c[1], p1[2] - c[2]};
            double v[3] = {p2[0] - c[0], p2[1] - c[1], p2[2] - c[2]};
            double x[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                           u[0] * v[1] - u[1] * v[0]};
            t[k++] = (a[0] * x[0] + a[1] * x[1] + a[2] * x[2]) / 6.0;
            double e1[3] = {u[0] - a[0], u[1] - a[1], u[2] - a[2]};
            double e2[3] = {v[0] - a[0], v[1] - a[1], v[2] - a[2]};
            double y[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                           e1[0] * e2[1] - e1[1] * e2[0]};
            t[k++] = 0.5 * sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]);
        }
    }
}

limn_status mpi_mesh_volume_area(mpi_part *p, const limn_mpi_mesh *mesh, const double *block,
                                 double *volume, double *area)
{
    const mesh_slice *s = &mesh->slice;
    size_t nc = s->face_offsets[s->face_count], nt = 0;
    for (size_t f = 0; f < s->face_count; f++) /* fan triangles */
        nt += s->face_offsets[f + 1] - s->face_offsets[f] > 2
                  ? s->face_offsets[f + 1] - s->face_offsets[f] - 2
                  : 0;
    double *pos = large_malloc((nc ? nc : 1) * 3 * sizeof *pos);
    double *t = large_malloc((nt ? nt : 1) * 2 * sizeof *t);
    limn_status st = pos && t ? LIMN_OK
                              : ctx_fail(p->ctx, LIMN_ERR_MEMORY,
                                         "out of memory measuring %zu faces", s->face_count);
    st = mpi_agree(p, st);
    if (!st) /* every corner's position from its block's owner */
        st = mpi_blocks_fetch(p, mesh->vertex_dist, block, 3 * sizeof *pos, nc, s->face_indices,
                              pos);
    if (!st) {
        double c[3], sum[2];
        first_position(p, mesh, block, c);
        face_terms(s, pos, c, t);
        mpi_mesh_chained_sums(p, t, nt, 2, sum);
        *volume = sum[0];
        *area = sum[1];
    }
    free(pos);
    free(t);
    return st;
}

void mpi_mesh_centroid(mpi_part *p, const limn_mpi_mesh *mesh, const double *block, double c[3])
{
    mpi_mesh_chained_sums(p, block, mesh->slice.vertex_count, 3, c);
    size_t n = mesh->vertex_dist[p->size];
    for (int j = 0; j < 3; j++)
        c[j] /= n ? (double)n : 1.0;
}

limn_status mpi_mesh_keep_volume(mpi_part *p, const limn_mpi_mesh *in, limn_mpi_mesh *out)
{
    double v0 = 0.0, v1 = 0.0, a;
    limn_status st = mpi_mesh_volume_area(p, in, in->slice.positions, &v0, &a);
    if (!st)
        st = mpi_mesh_volume_area(p, out, out->slice.positions, &v1, &a);
    if (st)
        return st;
    /* series_keep_volume's test and scaling, on every rank's block */
    if (!(v1 != 0.0 && (v0 > 0.0) == (v1 > 0.0)))
        return ctx_fail(p->ctx, LIMN_ERR_NO_CONVERGENCE,
                        "cannot keep the volume: it went from %.6g to %.6g", v0, v1);
    double scale = cbrt(v0 / v1), c[3];
    double *q = out->slice.positions;
    mpi_mesh_centroid(p, out, q, c);
    for (size_t i = 0; i < out->slice.vertex_count; i++)
        for (int j = 0; j < 3; j++)
            q[3 * i + j] = c[j] + scale * (q[3 * i + j] - c[j]);
    return LIMN_OK;
}

/* limn_mpi_mesh_measure into a result of this library's layout. */
static limn_status measure_sized(mpi_part *p, const limn_mpi_mesh *mesh, limn_mesh_measures *out)
{
    mpi_mesh_counts k;
    limn_status st = mpi_mesh_census(p, mesh, &k);
    double vol = 0.0;
    if (!st)
        st = mpi_mesh_volume_area(p, mesh, mesh->slice.positions, &vol, &out->area);
    if (st)
        return st;
    out->closed = mesh->face_dist[p->size] > 0 && k.boundary_edges == 0 &&
                  k.nonmanifold_edges == 0 && k.inconsistent_edges == 0;
    out->volume = out->closed ? vol : NAN;
    mpi_mesh_centroid(p, mesh, mesh->slice.positions, out->centroid);
    return LIMN_OK;
}

limn_status limn_mpi_mesh_measure(limn_context *ctx, const limn_mpi_mesh *mesh,
                                  limn_mesh_measures *out)
{
    mpi_part p;
    limn_status st = mpi_mesh_part(ctx, mesh, NULL, &p);
    if (p.comm == MPI_COMM_NULL)
        return st;
    abi_call c;
    if (!st)
        st = abi_enter_result(&c, ctx, "limn_mpi_mesh_measure", "out", &abi_mesh_measures, out);
    int entered = !st;
    st = mpi_agree(&p, st);
    if (!st)
        st = measure_sized(&p, mesh, c.report);
    if (entered)
        st = abi_leave(&c, st);
    mpi_part_end(&p);
    return st;
}

limn_status limn_mpi_mesh_volume_area(limn_context *ctx, const limn_mpi_mesh *mesh,
                                      double *volume, double *area)
{
    mpi_part p;
    limn_status st = mpi_mesh_part(ctx, mesh, NULL, &p);
    if (p.comm == MPI_COMM_NULL)
        return st;
    double v = NAN, a = NAN;
    if (!st)
        st = mpi_mesh_volume_area(&p, mesh, mesh->slice.positions, &v, &a);
    if (volume)
        *volume = st ? NAN : v;
    if (area)
        *area = st ? NAN : a;
    mpi_part_end(&p);
    return st;
}
