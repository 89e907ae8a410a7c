/* SPDX-License-Identifier: MIT */
/*
 * A refinement level spread over the ranks (mpi_refine.h's mpi_rmesh): who
 * owns a vertex id (a segment of the numbering, then its split over the
 * ranks or its directory), the first level from a distributed mesh (each
 * input vertex to the lowest rank whose faces use it), and the last level moved
 * to the even vertex blocks of a limn_mpi_mesh (one store exchange).
 */
#include "mpi/mpi_refine.h"
#include "base/large_alloc.h"

#include "base/context.h"
#include "mesh/io/mesh_slice.h"
#include "mpi/mpi_blocks.h"
#include "mpi/mpi_local.h"

#include <stdlib.h>
#include <string.h>

int mpi_rmesh_segment(const mpi_rmesh *m, size_t id)
{
    int lo = 0, hi = m->segments - 1; /* the last segment starting at or before id */
    while (lo < hi) {
        int mid = lo + (hi - lo + 1) / 2;
        if (m->seg[mid].start <= id)
            lo = mid;
        else
            hi = mid - 1;
    }
    return lo;
}

size_t mpi_rseg_count(const mpi_rseg *s, int rank)
{
    return s->directory ? s->n_own : s->dist[rank + 1] - s->dist[rank];
}

limn_status mpi_rmesh_owners(mpi_part *p, const mpi_rmesh *m, size_t n, const uint32_t *ids,
                             int *owner)
{
    uint32_t *ask = large_malloc((n ? n : 1) * sizeof *ask);
    uint32_t *got = large_malloc((n ? n : 1) * sizeof *got);
    limn_status st = mpi_agree(p, ask && got ? LIMN_OK
                                             : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory"));
    for (int s = 0; !st && s < m->segments; s++) {
        const mpi_rseg *g = &m->seg[s];
        size_t k = 0;
        for (size_t i = 0; i < n; i++) {
            if (ids[i] < g->start || ids[i] >= g->end)
                continue;
            if (g->directory)
                ask[k++] = ids[i];
            else
                owner[i] = mpi_blocks_owner(g->dist, p->size, ids[i]);
        }
        if (!g->directory)
            continue;
        st = mpi_blocks_fetch(p, g->dist, g->dir, sizeof *got, k, ask, got);
        for (size_t i = 0, j = 0; !st && i < n; i++)
            if (ids[i] >= g->start && ids[i] < g->end)
                owner[i] = (int)got[j++];
    }
    free(ask);
    free(got);
    return st;
}

size_t mpi_rmesh_local(const mpi_rmesh *m, int rank, size_t id)
{
    int seg = mpi_rmesh_segment(m, id);
    size_t at = 0;
    for (int s = 0; s < seg; s++)
        at += mpi_rseg_count(&m->seg[s], rank);
    const mpi_rseg *g = &m->seg[seg];
    if (!g->directory)
        return id >= g->dist[rank] && id < g->dist[rank + 1] ? at + (id - g->dist[rank])
                                                             : SIZE_MAX;
    size_t lo = 0, hi = g->n_own;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (g->own[mid] < id)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo < g->n_own && g->own[lo] == id ? at + lo : SIZE_MAX;
}

size_t mpi_rmesh_id(const mpi_rmesh *m, int rank, size_t i)
{
    for (int s = 0; s < m->segments; s++) {
        const mpi_rseg *g = &m->seg[s];
        size_t n = mpi_rseg_count(g, rank);
        if (i < n)
            return g->directory ? g->own[i] : g->dist[rank] + i;
        i -= n;
    }
    return SIZE_MAX;
}

void mpi_rseg_free(mpi_rseg *s)
{
    free(s->dist);
    free(s->dir);
    free(s->own);
    memset(s, 0, sizeof *s);
}

void mpi_rmesh_free(mpi_rmesh *m)
{
    if (!m)
        return;
    free(m->pos);
    if (m->owns_faces) {
        free(m->face_offsets);
        free(m->face_indices);
    }
    for (int s = 0; m->seg && s < m->segments; s++)
        mpi_rseg_free(&m->seg[s]);
    free(m->seg);
    memset(m, 0, sizeof *m);
}

limn_status mpi_rseg_directory(mpi_part *p, size_t start, size_t end, uint32_t *own, size_t n,
                               mpi_rseg *out)
{
    memset(out, 0, sizeof *out);
    out->start = start;
    out->end = end;
    out->directory = 1;
    out->own = own;
    out->n_own = n;
    out->dist = large_malloc(((size_t)p->size + 1) * sizeof *out->dist);
    uint32_t *mine = large_malloc((n ? n : 1) * sizeof *mine);
    limn_status st = out->dist && mine ? LIMN_OK
                                       : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory");
    for (int r = 0; !st && r <= p->size; r++)
        out->dist[r] = start + mesh_slice_cut(end - start, (unsigned)p->size, (unsigned)r);
    size_t nb = st ? 0 : out->dist[p->rank + 1] - out->dist[p->rank];
    if (!st && !(out->dir = large_malloc((nb ? nb : 1) * sizeof *out->dir)))
        st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for a directory of %zu", nb);
    for (size_t i = 0; !st && i < n; i++)
        mine[i] = (uint32_t)p->rank;
    st = mpi_agree(p, st);
    if (!st)
        st = mpi_blocks_store(p, out->dist, n, own, mine, sizeof *mine, out->dir);
    free(mine);
    return st;
}

/* This rank's input vertices (part = rank) from the vertex blocks' parts. */
static limn_status gather_own(mpi_part *p, const limn_mpi_mesh *mesh, const uint32_t *part,
                              uint32_t **own, size_t *n)
{
    size_t nb = mesh->slice.vertex_count, R = (size_t)p->size;
    int *cnt = calloc(2 * R, sizeof *cnt);
    size_t *at = calloc(R + 1, sizeof *at);
    uint32_t *send = large_malloc((nb ? nb : 1) * sizeof *send);
    limn_status st = cnt && at && send ? LIMN_OK
                                       : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory");
    for (size_t i = 0; !st && i < nb; i++)
        at[part[i] + 1]++;
    for (size_t r = 0; !st && r < R; r++) {
        cnt[r] = (int)at[r + 1];
        at[r + 1] += at[r];
    }
    for (size_t i = 0; !st && i < nb; i++)
        send[at[part[i]]++] = (uint32_t)(mesh->slice.vertex_begin + i);
    st = mpi_agree(p, st);
    /* blocks arrive in rank order, each increasing: *own is increasing */
    if (!st)
        st = mpi_local_alltoallv(p, send, cnt, sizeof *send, (void **)own, cnt + R, n);
    free(cnt);
    free(at);
    free(send);
    return st;
}

/* The part of each vertex of this rank's block: the lowest rank whose face
   block uses it (so a rank's vertices are those of its faces, less those an
   earlier rank's faces take), this rank for a vertex no face uses. Each
   rank sends its faces' distinct corners to their block owners, which take
   the first sender (they arrive in rank order). Collective. */
static limn_status face_parts(mpi_part *p, const limn_mpi_mesh *mesh, uint32_t **part)
{
    const mesh_slice *s = &mesh->slice;
    size_t nc = s->face_offsets[s->face_count], R = (size_t)p->size, n = 0, got_n = 0;
    uint64_t *keys = large_malloc((nc ? nc : 1) * sizeof *keys);
    uint32_t *send = large_malloc((nc ? nc : 1) * sizeof *send), *got = NULL;
    int *cnt = calloc(2 * R, sizeof *cnt);
    *part = large_malloc((s->vertex_count ? s->vertex_count : 1) * sizeof **part);
    limn_status st = keys && send && cnt && *part
                         ? LIMN_OK
                         : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory");
    for (size_t c = 0; !st && c < nc; c++)
        keys[c] = s->face_indices[c];
    if (!st)
        mpi_local_sort(keys, nc);
    for (size_t c = 0; !st && c < nc; c++)
        if (c == 0 || keys[c] != keys[c - 1]) {
            send[n++] = (uint32_t)keys[c];
            cnt[mpi_blocks_owner(mesh->vertex_dist, p->size, keys[c])]++;
        }
    st = mpi_agree(p, st);
    if (!st)
        st = mpi_local_alltoallv(p, send, cnt, sizeof *send, (void **)&got, cnt + R, &got_n);
    for (size_t v = 0; !st && v < s->vertex_count; v++)
        (*part)[v] = UINT32_MAX;
    for (size_t r = 0, k = 0; !st && r < R; r++)
        for (int i = 0; i < cnt[R + r]; i++, k++) {
            uint32_t *to = *part + (got[k] - s->vertex_begin);
            if (*to == UINT32_MAX)
                *to = (uint32_t)r;
        }
    for (size_t v = 0; !st && v < s->vertex_count; v++)
        if ((*part)[v] == UINT32_MAX)
            (*part)[v] = (uint32_t)p->rank;
    free(keys);
    free(send);
    free(got);
    free(cnt);
    return st;
}

limn_status mpi_rmesh_of(mpi_part *p, const limn_mpi_mesh *mesh, mpi_rmesh *out)
{
    memset(out, 0, sizeof *out);
    const mesh_slice *s = &mesh->slice;
    uint32_t *part = NULL, *own = NULL;
    size_t n = 0;
    out->seg = calloc(1, sizeof *out->seg);
    limn_status st = mpi_agree(p, out->seg ? LIMN_OK
                                           : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory"));
    if (!st)
        st = face_parts(p, mesh, &part);
    if (!st)
        st = gather_own(p, mesh, part, &own, &n);
    free(part); /* the directory is rebuilt in even blocks (the same as the vertex blocks'
                   only when they are even) */
    if (!st) {
        out->segments = 1;
        st = mpi_rseg_directory(p, 0, mesh->vertex_dist[p->size], own, n, &out->seg[0]);
        own = NULL;
    }
    free(own);
    out->vertex_total = mesh->vertex_dist[p->size];
    out->face_total = mesh->face_dist[p->size];
    out->face_begin = s->face_begin;
    out->face_count = s->face_count;
    out->face_offsets = s->face_offsets;
    out->face_indices = s->face_indices;
    out->n_owned = n;
    if (!st) {
        out->pos = large_malloc((n ? 3 * n : 1) * sizeof *out->pos);
        st = mpi_agree(p, out->pos ? LIMN_OK
                                   : ctx_fail(p->ctx, LIMN_ERR_MEMORY,
                                              "out of memory for %zu vertices", n));
    }
    if (!st)
        st = mpi_blocks_fetch(p, mesh->vertex_dist, s->positions, 3 * sizeof(double), n,
                              out->seg[0].own, out->pos);
    if (st)
        mpi_rmesh_free(out);
    return st;
}

/* A copy of the faces of m into s. */
static limn_status take_faces(mpi_part *p, const mpi_rmesh *m, mesh_slice *s)
{
    size_t nc = m->face_offsets[m->face_count];
    s->face_begin = m->face_begin;
    s->face_count = m->face_count;
    s->face_offsets = large_malloc((m->face_count + 1) * sizeof *s->face_offsets);
    s->face_indices = large_malloc((nc ? nc : 1) * sizeof *s->face_indices);
    if (!s->face_offsets || !s->face_indices)
        return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu faces", m->face_count);
    memcpy(s->face_offsets, m->face_offsets, (m->face_count + 1) * sizeof *s->face_offsets);
    memcpy(s->face_indices, m->face_indices, nc * sizeof *s->face_indices);
    return LIMN_OK;
}
limn_status mpi_rmesh_to_mesh(mpi_part *p, const mpi_rmesh *m, limn_mpi_mesh **out)
{
    mesh_slice s = {0};
    size_t *dist = large_malloc(((size_t)p->size + 1) * sizeof *dist);
    uint32_t *ids = large_malloc((m->n_owned ? m->n_owned : 1) * sizeof *ids);
    limn_status st = dist && ids ? LIMN_OK : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory");
    for (int r = 0; !st && r <= p->size; r++)
        dist[r] = mesh_slice_cut(m->vertex_total, (unsigned)p->size, (unsigned)r);
    for (size_t i = 0; !st && i < m->n_owned; i++)
        ids[i] = (uint32_t)mpi_rmesh_id(m, p->rank, i);
    if (!st) {
        s.vertex_begin = dist[p->rank];
        s.vertex_count = dist[p->rank + 1] - dist[p->rank];
        s.positions = large_malloc((s.vertex_count ? 3 * s.vertex_count : 1) * sizeof *s.positions);
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

limn_status mpi_rmesh_borrow(mpi_part *p, const mpi_rmesh *m, double *pos, mpi_rmesh *out)
{
    *out = *m;
    out->owns_faces = 0;
    out->pos = pos;
    out->seg = calloc((size_t)m->segments, sizeof *out->seg);
    size_t R = (size_t)p->size + 1;
    limn_status st = out->seg ? LIMN_OK : LIMN_ERR_MEMORY;
    for (int k = 0; !st && k < m->segments; k++) {
        const mpi_rseg *a = &m->seg[k];
        mpi_rseg *b = &out->seg[k];
        *b = *a;
        b->dir = b->own = NULL; /* nothing of a's freed with the copy */
        b->dist = large_malloc(R * sizeof *b->dist);
        size_t nd = a->directory ? a->dist[p->rank + 1] - a->dist[p->rank] : 0;
        b->dir = a->dir ? large_malloc((nd ? nd : 1) * sizeof *b->dir) : NULL;
        b->own = a->own ? large_malloc((a->n_own ? a->n_own : 1) * sizeof *b->own) : NULL;
        if (!b->dist || (a->dir && !b->dir) || (a->own && !b->own)) {
            st = LIMN_ERR_MEMORY;
            break;
        }
        memcpy(b->dist, a->dist, R * sizeof *b->dist);
        if (a->dir)
            memcpy(b->dir, a->dir, nd * sizeof *b->dir);
        if (a->own)
            memcpy(b->own, a->own, a->n_own * sizeof *b->own);
    }
    if (st) {
        mpi_rmesh_free(out); /* frees pos too: the caller's array is the copy's */
        st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for a copy of the segments");
    }
    return mpi_agree(p, st);
}
