/* SPDX-License-Identifier: MIT */
/*
 * Local rows, the exchanges (mpi_local.h): every rank to every rank in one
 * MPI_Alltoallv with the counts exchanged first, values of vertices fetched
 * from the ranks whose input blocks hold them, the radix sort of the keys,
 * the bounding box over all blocks, and the global face and edge-cut counts.
 */
#include "mpi/mpi_local.h"
#include "base/large_alloc.h"

#include "base/context.h"
#include "base/sorted_search.h"
#include "mesh/mesh.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

void mpi_local_note(local_sub *s, size_t entries)
{
    if (s->stats && entries > s->stats->largest_vertex_array)
        s->stats->largest_vertex_array = entries;
}

/* The byte counts and displacements of an exchange of elem-byte elements
   (cnt[r] to send to rank r, rcnt[r] to receive from it) in rank order;
   without own, this rank's share is left out of the call (sent and received
   as 0 bytes, its place in the receive buffer kept). *so, *ro: the elements
   in the send and receive buffers. */
static limn_status exchange_plan(mpi_part *p, const int *cnt, const int *rcnt, size_t elem,
                                 int own, int *sb, int *sd, int *rb, int *rd, size_t *so,
                                 size_t *ro)
{
    size_t R = (size_t)p->size, me = (size_t)p->rank;
    *so = *ro = 0;
    for (size_t r = 0; r < R; r++) {
        int out = own || r != me;
        if ((*so + (size_t)cnt[r]) * elem > INT_MAX || (*ro + (size_t)rcnt[r]) * elem > INT_MAX)
            return ctx_fail(p->ctx, LIMN_ERR_MEMORY,
                            "a rank would exchange more than %d bytes in one MPI call: use more "
                            "ranks",
                            INT_MAX);
        sb[r] = out ? (int)((size_t)cnt[r] * elem) : 0;
        sd[r] = (int)(*so * elem);
        rb[r] = out ? (int)((size_t)rcnt[r] * elem) : 0;
        rd[r] = (int)(*ro * elem);
        *so += out ? (size_t)cnt[r] : 0;
        *ro += (size_t)rcnt[r];
    }
    return LIMN_OK;
}

limn_status mpi_local_alltoallv(mpi_part *p, const void *send, const int *cnt, size_t elem,
                                void **recv, int *rcnt, size_t *total)
{
    size_t R = (size_t)p->size;
    int *sb = large_malloc(4 * R * sizeof *sb), *sd = sb + R, *rb = sb + 2 * R, *rd = sb + 3 * R;
    *recv = NULL;
    *total = 0;
    limn_status st = sb ? LIMN_OK : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory");
    st = mpi_agree(p, st);
    if (st) {
        free(sb);
        return st;
    }
    MPI_Alltoall(cnt, 1, MPI_INT, rcnt, 1, MPI_INT, p->comm);
    size_t so = 0, ro = 0;
    st = exchange_plan(p, cnt, rcnt, elem, 1, sb, sd, rb, rd, &so, &ro);
    if (!st && !(*recv = large_malloc(ro ? ro * elem : 1)))
        st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu received entries", ro);
    st = mpi_agree(p, st);
    if (!st)
        MPI_Alltoallv(send, sb, sd, MPI_BYTE, *recv, rb, rd, MPI_BYTE, p->comm);
    if (st) {
        free(*recv);
        *recv = NULL;
    }
    *total = ro;
    free(sb);
    return st;
}

limn_status mpi_local_alltoallv_packed(mpi_part *p, const int *cnt, size_t elem,
                                       void (*pack)(void *user, char *const *to), void *user,
                                       void **recv, int *rcnt, size_t *total)
{
    size_t R = (size_t)p->size;
    int *sb = large_malloc(4 * R * sizeof *sb), *sd = sb + R, *rb = sb + 2 * R, *rd = sb + 3 * R;
    char **to = large_malloc(R * sizeof *to), *send = NULL;
    *recv = NULL;
    *total = 0;
    limn_status st = sb && to ? LIMN_OK : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory");
    st = mpi_agree(p, st);
    if (st) {
        free(sb);
        free(to);
        return st;
    }
    MPI_Alltoall(cnt, 1, MPI_INT, rcnt, 1, MPI_INT, p->comm);
    size_t so = 0, ro = 0; /* this rank's own share stays out of the call: packed in place */
    st = exchange_plan(p, cnt, rcnt, elem, 0, sb, sd, rb, rd, &so, &ro);
    if (!st && !(*recv = large_malloc(ro ? ro * elem : 1)))
        st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu received entries", ro);
    if (!st && !(send = large_malloc(so ? so * elem : 1)))
        st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu entries to send", so);
    st = mpi_agree(p, st);
    if (!st) {
        for (size_t r = 0; r < R; r++)
            to[r] = r == (size_t)p->rank ? (char *)*recv + rd[r] : send + sd[r];
        pack(user, to);
        MPI_Alltoallv(send, sb, sd, MPI_BYTE, *recv, rb, rd, MPI_BYTE, p->comm);
    }
    if (st) {
        free(*recv);
        *recv = NULL;
    }
    *total = ro;
    free(send);
    free(sb);
    free(to);
    return st;
}

/* The rank whose block holds vertex v. */
static int block_of(const mpi_part *p, const size_t *vtxdist, uint32_t v)
{
    return (int)sorted_last_at_most_size(vtxdist, (size_t)p->size, v);
}

/* dst[i] = src[at[i] - base], elem bytes each: the sizes the callers use
   copied as values (a memcpy call per element costs more than its bytes). */
static void gather_elems(void *dst, const void *src, const uint32_t *at, size_t n, size_t base,
                         size_t elem)
{
    if (elem == sizeof(uint32_t)) {
        uint32_t *d = dst;
        const uint32_t *v = src;
        for (size_t i = 0; i < n; i++)
            d[i] = v[at[i] - base];
    } else if (elem == 3 * sizeof(double)) {
        double *d = dst;
        const double *v = src;
        for (size_t i = 0; i < n; i++) {
            const double *x = v + 3 * (at[i] - base);
            d[3 * i] = x[0];
            d[3 * i + 1] = x[1];
            d[3 * i + 2] = x[2];
        }
    } else {
        for (size_t i = 0; i < n; i++)
            memcpy((char *)dst + i * elem, (const char *)src + (at[i] - base) * elem, elem);
    }
}

/* The requests of an exchange and the answers back, this rank's own share
   outside the MPI calls both ways (answered from mine straight into out,
   most of a rank's sub-mesh in its own block), the others' answers received
   straight into out: ids increase, so rank order is id order. */
static limn_status fetch_exchange(mpi_part *p, local_sub *s, const size_t *vtxdist,
                                  const uint32_t *ids, const void *mine, size_t elem, void *out,
                                  int *cnt)
{
    size_t R = (size_t)p->size, me = (size_t)p->rank, base = vtxdist[me];
    int *rcnt = cnt + R, *sb = large_malloc(8 * R * sizeof *sb);
    int *sd = sb + R, *rb = sb + 2 * R, *rd = sb + 3 * R;
    int *ab = sb + 4 * R, *ad = sb + 5 * R, *gb = sb + 6 * R, *gd = sb + 7 * R;
    limn_status st = sb ? LIMN_OK : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory");
    st = mpi_agree(p, st);
    if (st) {
        free(sb);
        return st;
    }
    MPI_Alltoall(cnt, 1, MPI_INT, rcnt, 1, MPI_INT, p->comm);
    size_t so = 0, ro = 0, ao = 0, go = 0;
    /* requests: ids holds this rank's own too (their place counted), sent
       to no one; answers: packed without them, received around their place */
    st = exchange_plan(p, cnt, rcnt, sizeof(uint32_t), 1, sb, sd, rb, rd, &so, &ro);
    sb[me] = rb[me] = 0;
    if (!st)
        st = exchange_plan(p, rcnt, cnt, elem, 0, ab, ad, gb, gd, &ao, &go);
    uint32_t *req = NULL;
    char *ans = NULL;
    if (!st && (!(req = large_malloc(ro ? ro * sizeof *req : 1)) ||
                !(ans = large_malloc(ao ? ao * elem : 1))))
        st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory answering %zu requests", ro);
    mpi_local_note(s, ro);
    st = mpi_agree(p, st);
    if (!st) {
        size_t own = (size_t)sd[me] / sizeof(uint32_t); /* this rank's ids start there */
        MPI_Alltoallv(ids, sb, sd, MPI_BYTE, req, rb, rd, MPI_BYTE, p->comm);
        gather_elems((char *)out + own * elem, mine, ids + own, (size_t)cnt[me], base, elem);
        for (size_t r = 0; r < R; r++) /* the others' requests, answered in their order */
            if (r != me)
                gather_elems(ans + ad[r], mine, req + rd[r] / sizeof(uint32_t),
                             (size_t)rcnt[r], base, elem);
        MPI_Alltoallv(ans, ab, ad, MPI_BYTE, out, gb, gd, MPI_BYTE, p->comm);
    }
    free(req);
    free(ans);
    free(sb);
    return st;
}

limn_status mpi_local_fetch(mpi_part *p, local_sub *s, const size_t *vtxdist,
                            const uint32_t *ids, size_t n, const void *mine, size_t elem,
                            void *out)
{
    size_t R = (size_t)p->size;
    int *cnt = calloc(2 * R, sizeof *cnt);
    limn_status st = cnt ? LIMN_OK : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory");
    for (size_t i = 0; cnt && i < n; i++)
        cnt[block_of(p, vtxdist, ids[i])]++;
    if (!st)
        st = fetch_exchange(p, s, vtxdist, ids, mine, elem, out, cnt);
    else
        st = mpi_agree(p, st);
    free(cnt);
    return st;
}

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

void mpi_local_sort(uint64_t *a, size_t n)
{
    if (n <= 32) { /* a vertex's ring and the like: insertion, no calls */
        for (size_t i = 1; i < n; i++) {
            uint64_t x = a[i];
            size_t j = i;
            for (; j > 0 && a[j - 1] > x; j--)
                a[j] = a[j - 1];
            a[j] = x;
        }
        return;
    }
    uint64_t diff = 0;
    for (size_t i = 1; i < n; i++)
        diff |= a[i] ^ a[0];
    uint64_t *b = n > 256 ? large_malloc(n * sizeof *b) : NULL, *src = a, *dst = b;
    size_t *count = b ? large_malloc(65537 * sizeof *count) : NULL;
    if (!count) { /* short lists, or no room for the radix passes */
        free(b);
        qsort(a, n, sizeof *a, cmp_u64);
        return;
    }
    for (int shift = 0; shift < 64; shift += 16) { /* stable LSD passes, 16 bits each */
        if (!((diff >> shift) & 0xffff))
            continue; /* every key has the same digit here */
        memset(count, 0, 65537 * sizeof *count);
        for (size_t i = 0; i < n; i++)
            count[((src[i] >> shift) & 0xffff) + 1]++;
        for (size_t d = 0; d < 65536; d++)
            count[d + 1] += count[d];
        for (size_t i = 0; i < n; i++)
            dst[count[(src[i] >> shift) & 0xffff]++] = src[i];
        uint64_t *t = src;
        src = dst;
        dst = t;
    }
    if (src != a)
        memcpy(a, src, n * sizeof *a);
    free(b);
    free(count);
}

void mpi_local_sort_uniform(uint64_t *a, size_t n)
{
    int bb = 1; /* top bits: about 8 keys a bucket, 16 bits at most */
    while (bb < 16 && ((size_t)8 << bb) < n)
        bb++;
    uint64_t *b = n > 256 ? large_malloc(n * sizeof *b) : NULL;
    size_t nbk = (size_t)1 << bb, *at = b ? calloc(nbk + 1, sizeof *at) : NULL;
    if (!at) { /* short lists, or no room: the radix passes */
        free(b);
        mpi_local_sort(a, n);
        return;
    }
    int shift = 64 - bb;
    for (size_t i = 0; i < n; i++)
        at[(a[i] >> shift) + 1]++;
    for (size_t k = 0; k < nbk; k++)
        at[k + 1] += at[k];
    for (size_t i = 0; i < n; i++)
        b[at[a[i] >> shift]++] = a[i]; /* at[k]: now the end of bucket k */
    for (size_t k = 0, begin = 0; k < nbk; begin = at[k++])
        mpi_local_sort(b + begin, at[k] - begin);
    memcpy(a, b, n * sizeof *a);
    free(b);
    free(at);
}

/* Bits enough for the values 0 .. n (at most 32: n below 2^32). */
static int bits_for(size_t n)
{
    int b = 1;
    while (b < 32 && ((size_t)1 << b) <= n)
        b++;
    return b;
}

static int lowest_bit(uint64_t x) /* x != 0 */
{
#if defined(__GNUC__)
    return __builtin_ctzll(x);
#else
    int b = 0;
    while (!(x & 1)) {
        x >>= 1;
        b++;
    }
    return b;
#endif
}

int mpi_id_rank_init(mpi_id_rank *r, uint32_t lo, uint32_t hi)
{
    r->lo = lo;
    r->words = (size_t)(((uint64_t)hi - lo + 1 + 63) / 64);
    r->bits = calloc(r->words, sizeof *r->bits);
    r->below = large_malloc(r->words * sizeof *r->below);
    if (r->bits && r->below)
        return 1;
    mpi_id_rank_free(r);
    return 0;
}

size_t mpi_id_rank_finish(mpi_id_rank *r)
{
    size_t k = 0;
    for (size_t w = 0; w < r->words; w++) {
        r->below[w] = k;
        k += (size_t)mpi_ones64(r->bits[w]);
    }
    return k;
}

void mpi_id_rank_list(const mpi_id_rank *r, uint32_t *out)
{
    size_t k = 0;
    for (size_t w = 0; w < r->words; w++)
        for (uint64_t x = r->bits[w]; x; x &= x - 1)
            out[k++] = r->lo + (uint32_t)(64 * w) + (uint32_t)lowest_bit(x);
}

void mpi_id_rank_free(mpi_id_rank *r)
{
    free(r->bits);
    free(r->below);
    r->bits = NULL;
    r->below = NULL;
}

/* index[i]: the rank of ids[i] (each added to r) for i < n. */
MPI_POPCNT_CLONES static void rank_all(const mpi_id_rank *r, const uint32_t *ids, size_t n,
                                       uint32_t *index)
{
    for (size_t i = 0; i < n; i++)
        index[i] = mpi_id_rank_of(r, ids[i]);
}

/* mpi_local_distinct by a bitmap of [lo, hi] (mpi_id_rank); 0 when out of
   memory. */
static int distinct_bitmap(const uint32_t *ids, size_t n, uint32_t lo, uint32_t hi,
                           uint32_t *distinct, size_t *nd, uint32_t *index)
{
    mpi_id_rank r;
    if (!mpi_id_rank_init(&r, lo, hi))
        return 0;
    for (size_t i = 0; i < n; i++)
        mpi_id_rank_add(&r, ids[i]);
    *nd = mpi_id_rank_finish(&r);
    mpi_id_rank_list(&r, distinct);
    rank_all(&r, ids, n, index);
    mpi_id_rank_free(&r);
    return 1;
}

limn_status mpi_local_distinct(limn_context *ctx, const uint32_t *ids, size_t n,
                               uint32_t *distinct, size_t *nd, uint32_t *index)
{
    *nd = 0;
    if (n == 0)
        return LIMN_OK;
    uint32_t lo = UINT32_MAX, hi = 0;
    for (size_t i = 0; i < n; i++) {
        lo = ids[i] < lo ? ids[i] : lo;
        hi = ids[i] > hi ? ids[i] : hi;
    }
    uint64_t range = (uint64_t)hi - lo + 1;
    /* the bitmap and its counts (range / 4 bytes) below the sort's n keys */
    if (range <= 32 * (uint64_t)n && distinct_bitmap(ids, n, lo, hi, distinct, nd, index))
        return LIMN_OK;
    /* key: the id above the element, packed (id - lowest id, then cb bits of
       element), so the radix sort skips the digits no key uses */
    uint64_t *key = large_malloc(n * sizeof *key);
    if (!key)
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory sorting %zu vertex ids", n);
    int cb = bits_for(n);
    uint64_t mask = ((uint64_t)1 << cb) - 1;
    for (size_t i = 0; i < n; i++)
        key[i] = (uint64_t)(ids[i] - lo) << cb | i;
    mpi_local_sort(key, n);
    size_t k = 0;
    for (size_t i = 0; i < n; i++) {
        uint32_t v = (uint32_t)(key[i] >> cb) + lo;
        if (i == 0 || v != distinct[k - 1])
            distinct[k++] = v;
        index[key[i] & mask] = (uint32_t)(k - 1);
    }
    free(key);
    *nd = k;
    return LIMN_OK;
}

/* The bounding box diagonal of all vertices, as mesh_bbox_diagonal gives it
   for the whole mesh (min and max are exact in any order). */
double mpi_local_diagonal(mpi_part *p, const double *pos, size_t nb)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t i = 0; i < nb; i++)
        for (int c = 0; c < 3; c++) {
            double x = pos[3 * i + c];
            lo[c] = x < lo[c] ? x : lo[c];
            hi[c] = x > hi[c] ? x : hi[c];
        }
    double glo[3], ghi[3];
    MPI_Allreduce(lo, glo, 3, MPI_DOUBLE, MPI_MIN, p->comm);
    MPI_Allreduce(hi, ghi, 3, MPI_DOUBLE, MPI_MAX, p->comm);
    if (!(glo[0] <= ghi[0]))
        return 0.0; /* no vertices */
    return sqrt((ghi[0] - glo[0]) * (ghi[0] - glo[0]) + (ghi[1] - glo[1]) * (ghi[1] - glo[1]) +
                (ghi[2] - glo[2]) * (ghi[2] - glo[2]));
}

/* ------------------------------------------------------ the global counts */

/* This rank's share of the edge cut from the faces whose vertices are in
   more than one part (mixed, nm of them; no other face has a cut edge):
   distinct edges between parts whose lower part is this rank (each counted
   on one rank). */
static limn_status local_cut(mpi_part *p, const local_sub *s, const limn_mesh *m,
                             const uint32_t *mixed, size_t nm, size_t corners, size_t *cut)
{
    size_t n = 0;
    uint64_t *e = large_malloc((corners ? corners : 1) * sizeof *e);
    *cut = 0;
    if (!e)
        return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for the edge cut");
    for (size_t i = 0; i < nm; i++) {
        uint32_t b = m->face_offsets[mixed[i]], end = m->face_offsets[mixed[i] + 1];
        for (uint32_t c = b; c < end; c++) {
            uint32_t u = m->face_indices[c], v = m->face_indices[c + 1 < end ? c + 1 : b];
            uint32_t pu = s->part[u], pv = s->part[v];
            if (pu == pv || (pu < pv ? pu : pv) != (uint32_t)p->rank)
                continue;
            uint32_t a = s->ids[u] < s->ids[v] ? s->ids[u] : s->ids[v];
            e[n++] = (uint64_t)a << 32 | (s->ids[u] ^ s->ids[v] ^ a);
        }
    }
    mpi_local_sort(e, n);
    for (size_t i = 0; i < n; i++)
        *cut += i == 0 || e[i] != e[i - 1];
    free(e);
    return LIMN_OK;
}

/* Sums over ranks of 64-bit counts (in place). */
static void sum_counts(mpi_part *p, uint64_t *v, int n)
{
    MPI_Allreduce(MPI_IN_PLACE, v, n, MPI_UINT64_T, MPI_SUM, p->comm);
}

/* The owned vertices of the mixed faces (s->near, a bit each). */
static void mark_near(local_sub *s, const limn_mesh *m, const uint32_t *mixed, size_t nm,
                      uint32_t me)
{
    for (size_t i = 0; i < nm; i++)
        for (uint32_t c = m->face_offsets[mixed[i]]; c < m->face_offsets[mixed[i] + 1]; c++) {
            uint32_t v = m->face_indices[c];
            if (s->part[v] == me)
                s->near[v >> 6] |= (uint64_t)1 << (v & 63);
        }
}

limn_status mpi_local_counts(mpi_part *p, local_sub *s, const limn_mesh *m)
{
    size_t cut = 0, nm = 0, corners = 0;
    uint64_t counts[2] = {0, 0};
    /* pages past the mixed faces' entries (few: those across the cut) are
       never touched */
    uint32_t *mixed = large_malloc((m->face_count ? m->face_count : 1) * sizeof *mixed);
    free(s->near);
    s->near = calloc((s->n + 63) / 64 + 1, sizeof *s->near);
    limn_status st = mixed && s->near
                         ? LIMN_OK
                         : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for the edge cut");
    for (size_t f = 0; !st && f < m->face_count; f++) {
        uint32_t b = m->face_offsets[f], end = m->face_offsets[f + 1];
        uint32_t low = s->part[m->face_indices[b]], high = low;
        for (uint32_t c = b + 1; c < end; c++) {
            uint32_t q = s->part[m->face_indices[c]];
            low = q < low ? q : low;
            high = q > high ? q : high;
        }
        counts[0] += low == (uint32_t)p->rank; /* the lowest part counts the face */
        mixed[nm] = (uint32_t)f;
        nm += low != high;
        corners += low != high ? end - b : 0;
    }
    if (!st) {
        mark_near(s, m, mixed, nm, (uint32_t)p->rank);
        st = local_cut(p, s, m, mixed, nm, corners, &cut);
    }
    free(mixed);
    counts[1] = cut;
    st = mpi_agree(p, st);
    if (st)
        return st;
    sum_counts(p, counts, 2);
    p->faces_global = counts[0];
    p->edge_cut = counts[1];
    return LIMN_OK;
}
