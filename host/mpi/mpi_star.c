/* SPDX-License-Identifier: MIT */
/*
 * The star of a rank (mpi_refine.h): every face of the face blocks goes to
 * each other rank owning one of its corners (one Alltoallv of face
 * records), the faces received and this rank's own block make the patch, in
 * increasing global face id; its vertices (the corners and every vertex this
 * rank owns, isolated ones included) in increasing global id, their
 * positions fetched from their owners.
 */
#include "mpi/mpi_refine.h"
#include "base/large_alloc.h"

#include "base/context.h"
#include "mesh/mesh.h"
#include "mpi/mpi_local.h"

#include <stdlib.h>
#include <string.h>

/* A face of the patch: its global id and its corners (global ids). */
typedef struct star_face {
    size_t id;
    const uint32_t *corners;
    uint32_t size;
} star_face;

static int face_cmp(const void *a, const void *b)
{
    size_t x = ((const star_face *)a)->id, y = ((const star_face *)b)->id;
    return (x > y) - (x < y);
}

void mpi_star_free(mpi_star *s)
{
    if (!s)
        return;
    limn_mesh_destroy(s->mesh);
    free(s->ids);
    free(s->face_ids);
    free(s->block_face);
    memset(s, 0, sizeof *s);
}

size_t mpi_star_local(const mpi_star *s, uint32_t v)
{
    size_t lo = 0, hi = s->mesh ? s->mesh->vertex_count : 0;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (s->ids[mid] < v)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo < (s->mesh ? s->mesh->vertex_count : 0) && s->ids[lo] == v ? lo : SIZE_MAX;
}

/* The distinct other ranks owning a corner of face f (owner: of each
   corner of the block), into to (at most d); returns how many. */
static int face_targets(const mpi_part *p, const mpi_rmesh *s, const int *owner, size_t f,
                        int *to)
{
    int n = 0;
    for (uint32_t c = s->face_offsets[f]; c < s->face_offsets[f + 1]; c++) {
        int r = owner[c];
        int seen = r == p->rank;
        for (int k = 0; k < n && !seen; k++)
            seen = to[k] == r;
        if (!seen)
            to[n++] = r;
    }
    return n;
}

/* Face records (id low, id high, size, corners) for the ranks that need
   them, grouped by rank. Collective (the corners' owners). */
static limn_status pack_faces(mpi_part *p, const mpi_rmesh *s, int *cnt, uint32_t **send)
{
    size_t nc = s->face_offsets[s->face_count];
    int *to = large_malloc(((size_t)p->size + 1) * sizeof *to);
    int *owner = large_malloc((nc ? nc : 1) * sizeof *owner);
    size_t *at = calloc((size_t)p->size + 1, sizeof *at);
    limn_status st = to && at && owner ? LIMN_OK
                                       : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory");
    st = mpi_agree(p, st);
    if (!st)
        st = mpi_rmesh_owners(p, s, nc, s->face_indices, owner);
    memset(cnt, 0, (size_t)p->size * sizeof *cnt);
    size_t total = 0;
    for (size_t f = 0; !st && f < s->face_count; f++) {
        uint32_t d = s->face_offsets[f + 1] - s->face_offsets[f];
        int n = face_targets(p, s, owner, f, to);
        for (int k = 0; k < n; k++) {
            at[to[k] + 1] += 3 + (size_t)d;
            total += 3 + (size_t)d;
        }
    }
    if (!st && !(*send = large_malloc((total ? total : 1) * sizeof **send)))
        st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu face words", total);
    for (int r = 0; !st && r < p->size; r++) {
        if (at[r + 1] > (size_t)INT32_MAX)
            st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "too many faces for one exchange");
        cnt[r] = (int)at[r + 1];
        at[r + 1] += at[r];
    }
    for (size_t f = 0; !st && f < s->face_count; f++) {
        uint32_t b = s->face_offsets[f], d = s->face_offsets[f + 1] - b;
        size_t id = s->face_begin + f;
        int n = face_targets(p, s, owner, f, to);
        for (int k = 0; k < n; k++) {
            uint32_t *w = *send + at[to[k]];
            w[0] = (uint32_t)id;
            w[1] = (uint32_t)((uint64_t)id >> 32);
            w[2] = d;
            memcpy(w + 3, s->face_indices + b, d * sizeof *w);
            at[to[k]] += 3 + (size_t)d;
        }
    }
    free(to);
    free(at);
    free(owner);
    return st;
}

/* The patch's faces: the records received and this rank's block, sorted. */
static limn_status collect_faces(mpi_part *p, const mpi_rmesh *s, const uint32_t *recv,
                                 size_t words, star_face **out, size_t *n)
{
    size_t count = s->face_count;
    for (size_t w = 0; w < words; w += 3 + (size_t)recv[w + 2])
        count++;
    star_face *f = large_malloc((count ? count : 1) * sizeof *f);
    if (!f)
        return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu star faces", count);
    size_t k = 0;
    for (size_t i = 0; i < s->face_count; i++)
        f[k++] = (star_face){s->face_begin + i, s->face_indices + s->face_offsets[i],
                             s->face_offsets[i + 1] - s->face_offsets[i]};
    for (size_t w = 0; w < words; w += 3 + (size_t)recv[w + 2])
        f[k++] = (star_face){(size_t)((uint64_t)recv[w + 1] << 32 | recv[w]), recv + w + 3,
                             recv[w + 2]};
    qsort(f, count, sizeof *f, face_cmp);
    *out = f;
    *n = count;
    return LIMN_OK;
}

/* The patch's vertex ids: every corner and the owned vertices, increasing, once. */
static limn_status collect_vertices(mpi_part *p, const mpi_rmesh *m, const star_face *f,
                                    size_t nf, mpi_star *s)
{
    size_t nb = m->n_owned, n = nb;
    for (size_t i = 0; i < nf; i++)
        n += f[i].size;
    uint64_t *keys = large_malloc((n ? n : 1) * sizeof *keys);
    if (!keys)
        return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu star corners", n);
    size_t k = 0;
    for (size_t v = 0; v < nb; v++)
        keys[k++] = mpi_rmesh_id(m, p->rank, v);
    for (size_t i = 0; i < nf; i++)
        for (uint32_t c = 0; c < f[i].size; c++)
            keys[k++] = f[i].corners[c];
    mpi_local_sort(keys, n);
    size_t u = 0;
    for (size_t i = 0; i < n; i++)
        if (u == 0 || keys[i] != keys[u - 1])
            keys[u++] = keys[i];
    s->ids = large_malloc((u ? u : 1) * sizeof *s->ids);
    for (size_t i = 0; s->ids && i < u; i++)
        s->ids[i] = (uint32_t)keys[i];
    free(keys);
    if (!s->ids)
        return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu star vertices", u);
    s->largest_vertex_array = u;
    return mesh_alloc(p->ctx, u, nf, n - nb, &s->mesh);
}

/* The patch's faces in local numbers, and where the block's faces are. */
static limn_status fill_faces(mpi_part *p, const mpi_rmesh *m, const star_face *f, size_t nf,
                              mpi_star *s)
{
    limn_mesh *pm = s->mesh;
    s->face_ids = large_malloc((nf ? nf : 1) * sizeof *s->face_ids);
    s->block_face = large_malloc((m->face_count ? m->face_count : 1) * sizeof *s->block_face);
    if (!s->face_ids || !s->block_face)
        return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu star faces", nf);
    size_t k = 0;
    pm->face_offsets[0] = 0;
    for (size_t i = 0; i < nf; i++) {
        s->face_ids[i] = f[i].id;
        if (f[i].id >= m->face_begin && f[i].id - m->face_begin < m->face_count)
            s->block_face[f[i].id - m->face_begin] = i;
        for (uint32_t c = 0; c < f[i].size; c++)
            pm->face_indices[k++] = (uint32_t)mpi_star_local(s, f[i].corners[c]);
        pm->face_offsets[i + 1] = (uint32_t)k;
    }
    return LIMN_OK;
}

/* The patch's positions from the vertices' owners: the ids grouped by owner
   (one exchange), each owner answering in the order asked (another). */
static limn_status fetch_positions(mpi_part *p, const mpi_rmesh *m, mpi_star *s)
{
    size_t n = s->mesh->vertex_count, R = (size_t)p->size;
    int *cnt = calloc(4 * R, sizeof *cnt), *owner = large_malloc((n ? n : 1) * sizeof *owner);
    size_t *at = calloc(R + 1, sizeof *at);
    uint32_t *ask = large_malloc((n ? n : 1) * sizeof *ask), *got = NULL;
    size_t *where = large_malloc((n ? n : 1) * sizeof *where), asked = 0, answered = 0;
    double *ans = NULL, *back = NULL;
    limn_status st = cnt && at && ask && where && owner
                         ? LIMN_OK
                         : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu requests", n);
    st = mpi_agree(p, st);
    if (!st)
        st = mpi_rmesh_owners(p, m, n, s->ids, owner);
    for (size_t i = 0; !st && i < n; i++)
        at[owner[i] + 1]++;
    for (size_t r = 0; !st && r < R; r++) {
        cnt[r] = (int)at[r + 1];
        at[r + 1] += at[r];
    }
    for (size_t i = 0; !st && i < n; i++) {
        size_t k = at[owner[i]]++;
        ask[k] = s->ids[i];
        where[k] = i;
    }
    st = mpi_agree(p, st);
    if (!st)
        st = mpi_local_alltoallv(p, ask, cnt, sizeof *ask, (void **)&got, cnt + R, &asked);
    if (!st && !(ans = large_malloc((asked ? 3 * asked : 1) * sizeof *ans)))
        st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu answers", asked);
    for (size_t k = 0; !st && k < asked; k++) {
        size_t v = mpi_rmesh_local(m, p->rank, got[k]);
        if (v == SIZE_MAX)
            st = ctx_fail(p->ctx, LIMN_ERR_ARGUMENT, "rank %d was asked for vertex %u, not its",
                          p->rank, got[k]);
        else
            memcpy(ans + 3 * k, m->pos + 3 * v, 3 * sizeof *ans);
    }
    st = mpi_agree(p, st);
    if (!st)
        st = mpi_local_alltoallv(p, ans, cnt + R, 3 * sizeof *ans, (void **)&back, cnt + 2 * R,
                                 &answered);
    for (size_t k = 0; !st && k < answered; k++)
        memcpy(s->mesh->positions + 3 * where[k], back + 3 * k, 3 * sizeof *back);
    free(cnt);
    free(owner);
    free(at);
    free(ask);
    free(where);
    free(got);
    free(ans);
    free(back);
    return st;
}

limn_status mpi_star_build(mpi_part *p, const mpi_rmesh *mesh, mpi_star *out)
{
    memset(out, 0, sizeof *out);
    int *cnt = large_malloc(2 * (size_t)p->size * sizeof *cnt);
    uint32_t *send = NULL, *recv = NULL;
    star_face *faces = NULL;
    size_t words = 0, nf = 0;
    limn_status st = cnt ? LIMN_OK : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory");
    st = mpi_agree(p, st);
    if (!st)
        st = pack_faces(p, mesh, cnt, &send);
    st = mpi_agree(p, st);
    if (!st)
        st = mpi_local_alltoallv(p, send, cnt, sizeof *send, (void **)&recv, cnt + p->size,
                                 &words);
    free(send);
    if (!st)
        st = collect_faces(p, mesh, recv, words, &faces, &nf);
    if (!st)
        st = collect_vertices(p, mesh, faces, nf, out);
    if (!st)
        st = fill_faces(p, mesh, faces, nf, out);
    free(faces);
    free(recv);
    free(cnt);
    st = mpi_agree(p, st);
    if (!st)
        st = fetch_positions(p, mesh, out);
    if (st)
        mpi_star_free(out);
    return st;
}
