/* SPDX-License-Identifier: MIT */
/*
 * A refinement level spread over the ranks (mpi_refine.h's mpi_rmesh): who
 * owns a vertex id (a segment of the numbering, then its split over the
 * ranks), the level of a distributed mesh, and the last level moved to the
 * even vertex blocks of a limn_mpi_mesh (one store exchange).
 */
#include "mpi/mpi_refine.h"

#include "base/context.h"
#include "mesh/io/mesh_slice.h"
#include "mpi/mpi_blocks.h"

#include <stdlib.h>
#include <string.h>

int mpi_rmesh_segment(const mpi_rmesh *m, int size, size_t id)
{
    size_t w = (size_t)size + 1;
    int lo = 0, hi = m->segments - 1; /* the last segment starting at or before id */
    while (lo < hi) {
        int mid = lo + (hi - lo + 1) / 2;
        if (m->dist[(size_t)mid * w] <= id)
            lo = mid;
        else
            hi = mid - 1;
    }
    return lo;
}

int mpi_rmesh_owner(const mpi_rmesh *m, int size, size_t id)
{
    size_t w = (size_t)size + 1;
    return mpi_blocks_owner(m->dist + (size_t)mpi_rmesh_segment(m, size, id) * w, size, id);
}

size_t mpi_rmesh_local(const mpi_rmesh *m, int rank, int size, size_t id)
{
    size_t w = (size_t)size + 1, at = 0;
    for (int s = 0; s < m->segments; s++) {
        size_t lo = m->dist[(size_t)s * w + (size_t)rank], hi = m->dist[(size_t)s * w + (size_t)rank + 1];
        if (id >= lo && id < hi)
            return at + (id - lo);
        at += hi - lo;
    }
    return SIZE_MAX;
}

size_t mpi_rmesh_id(const mpi_rmesh *m, int rank, int size, size_t i)
{
    size_t w = (size_t)size + 1;
    for (int s = 0; s < m->segments; s++) {
        size_t lo = m->dist[(size_t)s * w + (size_t)rank], hi = m->dist[(size_t)s * w + (size_t)rank + 1];
        if (i < hi - lo)
            return lo + i;
        i -= hi - lo;
    }
    return SIZE_MAX;
}

void mpi_rmesh_free(mpi_rmesh *m)
{
    if (!m)
        return;
    if (m->owns_pos)
        free(m->pos);
    if (m->owns_faces) {
        free(m->face_offsets);
        free(m->face_indices);
    }
    free(m->dist);
    memset(m, 0, sizeof *m);
}

limn_status mpi_rmesh_of(mpi_part *p, const limn_mpi_mesh *mesh, mpi_rmesh *out)
{
    memset(out, 0, sizeof *out);
    size_t w = (size_t)p->size + 1;
    out->dist = malloc(w * sizeof *out->dist);
    limn_status st = mpi_agree(p, out->dist ? LIMN_OK
                                            : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory"));
    if (st)
        return st;
    const mesh_slice *s = &mesh->slice;
    memcpy(out->dist, mesh->vertex_dist, w * sizeof *out->dist);
    out->segments = 1;
    out->vertex_total = mesh->vertex_dist[p->size];
    out->face_total = mesh->face_dist[p->size];
    out->n_owned = s->vertex_count;
    out->pos = s->positions;
    out->face_begin = s->face_begin;
    out->face_count = s->face_count;
    out->face_offsets = s->face_offsets;
    out->face_indices = s->face_indices;
    return LIMN_OK;
}

/* A copy of the faces of m into s. */
static limn_status take_faces(mpi_part *p, const mpi_rmesh *m, mesh_slice *s)
{
    size_t nc = m->face_offsets[m->face_count];
    s->face_begin = m->face_begin;
    s->face_count = m->face_count;
    s->face_offsets = malloc((m->face_count + 1) * sizeof *s->face_offsets);
    s->face_indices = malloc((nc ? nc : 1) * sizeof *s->face_indices);
    if (!s->face_offsets || !s->face_indices)
        return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu faces", m->face_count);
    memcpy(s->face_offsets, m->face_offsets, (m->face_count + 1) * sizeof *s->face_offsets);
    memcpy(s->face_indices, m->face_indices, nc * sizeof *s->face_indices);
    return LIMN_OK;
}

limn_status mpi_rmesh_to_mesh(mpi_part *p, const mpi_rmesh *m, limn_mpi_mesh **out)
{
    mesh_slice s = {0};
    size_t *dist = malloc(((size_t)p->size + 1) * sizeof *dist);
    uint32_t *ids = malloc((m->n_owned ? m->n_owned : 1) * sizeof *ids);
    limn_status st = dist && ids ? LIMN_OK : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory");
    for (int r = 0; !st && r <= p->size; r++)
        dist[r] = mesh_slice_cut(m->vertex_total, (unsigned)p->size, (unsigned)r);
    for (size_t i = 0; !st && i < m->n_owned; i++)
        ids[i] = (uint32_t)mpi_rmesh_id(m, p->rank, p->size, i);
    if (!st) {
        s.vertex_begin = dist[p->rank];
        s.vertex_count = dist[p->rank + 1] - dist[p->rank];
        s.positions = malloc((s.vertex_count ? 3 * s.vertex_count : 1) * sizeof *s.positions);
        st = s.positions ? take_faces(p, m, &s)
                         : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu vertices",
                                    s.vertex_count);
    }
    st = mpi_agree(p, st);
    if (!st)
        st = mpi_blocks_store(p, dist, m->n_owned, ids, m->pos, 3 * sizeof(double), s.positions);
    free(ids);
    free(dist);
    if (!st)
        st = mpi_mesh_adopt(p, &s, out);
    mesh_slice_free(&s);
    return st;
}
