/* SPDX-License-Identifier: MIT */
/*
 * Duplicate faces of a distributed mesh (limn_mpi_mesh_repair), the single
 * process's verdicts: faces with the same vertex set are copies, the lowest
 * face of each set the original and every other one a duplicate of it
 * (mesh_repair.c's find_duplicates). Every face goes, as its sorted vertex
 * list, to the block owner of one of its vertices picked by a hash of the
 * set, so all copies of a set meet on one rank and the faces spread over the
 * ranks as their vertices do (the lowest vertex would send most faces of a
 * refined mesh, whose coarse vertices come first, to rank 0: 87% of the
 * 2.1M scanner mesh's on 2 ranks); there the records are grouped by a hash
 * of their set (a sort of 64-bit keys: one pass by the top bits, the hash
 * being uniform, then each small bucket) and only records sharing a hash are sorted
 * (size, vertices, face): each set's later faces are duplicates of its
 * first, and each verdict goes back to the rank holding the face, which
 * drops it when asked.
 */
#include "mpi/mpi_blocks.h"
#include "base/large_alloc.h"
#include "mpi/mpi_local.h"
#include "mpi/mpi_mesh.h"

#include "base/context.h"

#include <limits.h>
#include <stdlib.h>
#include <string.h>

/* A record: face id (2 words, low first), size d, the d sorted vertices. */
static uint64_t rec_face(const uint32_t *r) { return (uint64_t)r[1] << 32 | r[0]; }

static int cmp_rec(const void *a, const void *b)
{
    const uint32_t *x = *(const uint32_t *const *)a, *y = *(const uint32_t *const *)b;
    if (x[2] != y[2])
        return x[2] < y[2] ? -1 : 1;
    int c = memcmp(x + 3, y + 3, x[2] * sizeof *x); /* any total order groups the sets */
    if (c)
        return c;
    uint64_t fx = rec_face(x), fy = rec_face(y);
    return fx < fy ? -1 : fx > fy;
}

static int cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return x < y ? -1 : x > y;
}

/* A face's corners sorted: insertion for the usual few, qsort past 16. */
static void sort_corners(uint32_t *v, uint32_t d)
{
    if (d > 16) {
        qsort(v, d, sizeof *v, cmp_u32);
        return;
    }
    for (uint32_t i = 1; i < d; i++) {
        uint32_t x = v[i], j = i;
        for (; j > 0 && v[j - 1] > x; j--)
            v[j] = v[j - 1];
        v[j] = x;
    }
}

/* A record's vertex set (its size and sorted vertices) as 64 bits: equal
   sets hash alike, so only records of equal hashes need comparing. */
static uint64_t rec_hash(const uint32_t *r)
{
    uint64_t h = 0x9e3779b97f4a7c15ULL ^ r[2];
    for (uint32_t c = 0; c < r[2]; c++) {
        h = (h ^ r[3 + c]) * 0xff51afd7ed558ccdULL;
        h ^= h >> 32;
    }
    return h;
}

/* This rank's faces as records grouped by the rank that judges their set:
   the block owner of the set's vertex at the place its hash picks (cnt[r]
   words to rank r). */
static limn_status records_out(mpi_part *p, const limn_mpi_mesh *mesh, uint32_t **out, int *cnt)
{
    const mesh_slice *s = &mesh->slice;
    size_t nf = s->face_count, words = 3 * nf + s->face_offsets[nf];
    uint32_t *w = large_malloc((words ? words : 1) * sizeof *w);
    uint32_t *tmp = large_malloc((words ? words : 1) * sizeof *tmp);
    size_t *at = calloc((size_t)p->size + 1, sizeof *at);
    int *dest = large_malloc((nf ? nf : 1) * sizeof *dest);
    limn_status st = w && tmp && at && dest
                         ? LIMN_OK
                         : ctx_fail(p->ctx, LIMN_ERR_MEMORY,
                                    "out of memory looking for duplicate faces");
    for (size_t f = 0, o = 0; !st && f < nf; f++) { /* records in face order, in tmp */
        uint32_t b = s->face_offsets[f], d = s->face_offsets[f + 1] - b;
        uint64_t g = s->face_begin + f;
        tmp[o] = (uint32_t)g;
        tmp[o + 1] = (uint32_t)(g >> 32);
        tmp[o + 2] = d;
        memcpy(tmp + o + 3, s->face_indices + b, d * sizeof *tmp);
        sort_corners(tmp + o + 3, d);
        dest[f] = mpi_blocks_owner(mesh->vertex_dist, p->size,
                                   d ? tmp[o + 3 + rec_hash(tmp + o) % d] : 0);
        at[dest[f] + 1] += 3 + d;
        o += 3 + d;
    }
    for (int r = 0; !st && r < p->size; r++) {
        if (at[r + 1] > INT_MAX)
            st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "too many face records for one MPI call");
        cnt[r] = (int)at[r + 1];
        at[r + 1] += at[r];
    }
    for (size_t f = 0, o = 0; !st && f < nf; f++) {
        uint32_t len = 3 + tmp[o + 2];
        memcpy(w + at[dest[f]], tmp + o, len * sizeof *w);
        at[dest[f]] += len;
        o += len;
    }
    free(tmp);
    free(at);
    free(dest);
    if (st) {
        free(w);
        w = NULL;
    }
    *out = w;
    return st;
}

/* The (face, original) pairs of the sets among the nr records r: records
   are grouped by hash (the high bits of a radix-sorted key whose low `ib`
   bits are the record's index), and only a group of two or more is sorted
   in full (size, vertices, face): each set's later faces are duplicates of
   its first, as the single process finds. *np pairs into pairs. */
static limn_status find_sets(mpi_part *p, const uint32_t **r, size_t nr, uint64_t *pairs,
                             size_t *np)
{
    int ib = 1;
    while (ib < 40 && ((size_t)1 << ib) < nr)
        ib++;
    uint64_t low = ((uint64_t)1 << ib) - 1;
    uint64_t *key = large_malloc((nr ? nr : 1) * sizeof *key);
    const uint32_t **group = large_malloc((nr ? nr : 1) * sizeof *group);
    *np = 0;
    if (!key || !group) {
        free(key);
        free(group);
        return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory looking for duplicate faces");
    }
    for (size_t k = 0; k < nr; k++)
        key[k] = (rec_hash(r[k]) & ~low) | k;
    mpi_local_sort_uniform(key, nr);
    for (size_t i = 0, j; i < nr; i = j) {
        for (j = i + 1; j < nr && (key[j] & ~low) == (key[i] & ~low); j++)
            ;
        if (j - i < 2)
            continue; /* a hash of its own: no copy of this set here */
        size_t g = j - i;
        for (size_t k = 0; k < g; k++)
            group[k] = r[key[i + k] & low];
        qsort(group, g, sizeof *group, cmp_rec);
        for (size_t a = 0, b; a < g; a = b) { /* a set's first face is the original */
            uint64_t of = rec_face(group[a]);
            for (b = a + 1; b < g && group[b][2] == group[a][2] &&
                            memcmp(group[b] + 3, group[a] + 3, group[a][2] * sizeof **group) == 0;
                 b++) {
                pairs[2 * *np] = rec_face(group[b]);
                pairs[2 * *np + 1] = of;
                (*np)++;
            }
        }
    }
    free(key);
    free(group);
    return LIMN_OK;
}

/* The verdicts on the records received (n words): (face, original) pairs
   grouped by the rank holding the face, vcnt[r] pairs to rank r. */
static limn_status verdicts(mpi_part *p, const limn_mpi_mesh *mesh, const uint32_t *rec, size_t n,
                            uint64_t **out, int *vcnt)
{
    size_t nr = 0;
    for (size_t o = 0; o < n; o += 3 + rec[o + 2])
        nr++;
    const uint32_t **r = large_malloc((nr ? nr : 1) * sizeof *r);
    uint64_t *pairs = large_malloc((nr ? 2 * nr : 1) * sizeof *pairs);
    size_t *at = calloc((size_t)p->size + 1, sizeof *at), np = 0;
    *out = NULL;
    limn_status st = r && pairs && at ? LIMN_OK
                                      : ctx_fail(p->ctx, LIMN_ERR_MEMORY,
                                                 "out of memory looking for duplicate faces");
    for (size_t o = 0, k = 0; !st && o < n; o += 3 + rec[o + 2])
        r[k++] = rec + o;
    if (!st)
        st = find_sets(p, r, nr, pairs, &np);
    free(r);
    int *dest = st ? NULL : large_malloc((np ? np : 1) * sizeof *dest);
    uint64_t *sorted = st ? NULL : large_malloc((np ? 2 * np : 1) * sizeof *sorted);
    if (!st && (!dest || !sorted))
        st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory");
    for (size_t k = 0; !st && k < np; k++) {
        dest[k] = mpi_blocks_owner(mesh->face_dist, p->size, (size_t)pairs[2 * k]);
        at[dest[k] + 1]++;
    }
    for (int q = 0; !st && q < p->size; q++) {
        vcnt[q] = (int)at[q + 1];
        at[q + 1] += at[q];
    }
    for (size_t k = 0; !st && k < np; k++) {
        size_t to = at[dest[k]]++;
        sorted[2 * to] = pairs[2 * k];
        sorted[2 * to + 1] = pairs[2 * k + 1];
    }
    free(pairs);
    free(at);
    free(dest);
    if (st)
        free(sorted);
    else
        *out = sorted;
    return st;
}

/* Removes the marked faces of the block and renumbers the face blocks. */
static void drop_marked(mpi_part *p, limn_mpi_mesh *mesh, const uint8_t *dup)
{
    mesh_slice *s = &mesh->slice;
    uint32_t kept = 0, o = 0;
    for (size_t f = 0; f < s->face_count; f++) {
        uint32_t b = s->face_offsets[f], e = s->face_offsets[f + 1];
        if (dup[f])
            continue;
        memmove(s->face_indices + o, s->face_indices + b, (e - b) * sizeof *s->face_indices);
        o += e - b;
        s->face_offsets[++kept] = o;
    }
    s->face_count = kept;
    unsigned long long c = kept, before = 0;
    MPI_Exscan(&c, &before, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, p->comm);
    s->face_begin = p->rank ? (size_t)before : 0;
    mpi_blocks_dist(p, s->face_count, mesh->face_dist);
    s->face_total = mesh->face_dist[p->size];
}

limn_status mpi_mesh_duplicates(mpi_part *p, limn_mpi_mesh *mesh, int remove,
                                limn_repair_report *r)
{
    int *cnt = calloc(4 * (size_t)p->size, sizeof *cnt);
    uint32_t *send = NULL;
    void *got = NULL, *back = NULL;
    uint64_t *v = NULL;
    size_t n = 0, nv = 0, nf = mesh->slice.face_count;
    uint8_t *dup = calloc(nf ? nf : 1, 1);
    limn_status st = cnt && dup ? LIMN_OK : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory");
    if (!st)
        st = records_out(p, mesh, &send, cnt);
    st = mpi_agree(p, st);
    if (!st)
        st = mpi_local_alltoallv(p, send, cnt, sizeof *send, &got, cnt + p->size, &n);
    free(send);
    if (!st)
        st = verdicts(p, mesh, got, n, &v, cnt + 2 * p->size);
    free(got);
    st = mpi_agree(p, st);
    if (!st)
        st = mpi_local_alltoallv(p, v, cnt + 2 * p->size, 2 * sizeof *v, &back, cnt + 3 * p->size,
                                 &nv);
    free(v);
    unsigned long long count = 0, first = ULLONG_MAX, of = 0;
    for (size_t k = 0; !st && k < nv; k++) {
        const uint64_t *pair = (const uint64_t *)back + 2 * k;
        dup[pair[0] - mesh->slice.face_begin] = 1;
        count++;
        if (pair[0] < first) {
            first = pair[0];
            of = pair[1];
        }
    }
    free(back);
    free(cnt);
    st = mpi_agree(p, st);
    if (!st) { /* the counts summed, the first duplicate the lowest face's */
        unsigned long long gfirst = ULLONG_MAX;
        MPI_Allreduce(MPI_IN_PLACE, &count, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, p->comm);
        MPI_Allreduce(&first, &gfirst, 1, MPI_UNSIGNED_LONG_LONG, MPI_MIN, p->comm);
        if (gfirst != ULLONG_MAX)
            MPI_Bcast(&of, 1, MPI_UNSIGNED_LONG_LONG,
                      mpi_blocks_owner(mesh->face_dist, p->size, (size_t)gfirst), p->comm);
        r->duplicate_faces = (size_t)count;
        r->first_duplicate_face = gfirst == ULLONG_MAX ? SIZE_MAX : (size_t)gfirst;
        r->first_duplicate_of = (size_t)of;
        if (remove && count) {
            drop_marked(p, mesh, dup);
            r->duplicates_removed = r->duplicate_faces;
        }
    }
    free(dup);
    return st;
}
