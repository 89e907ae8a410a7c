/* SPDX-License-Identifier: MIT */
/*
 * Space-filling-curve partition (mpi_sfc.h): Hilbert keys of the block's
 * positions, the cut points selected over all ranks (a histogram of the
 * keys' top bits, then digit by digit in the few buckets that hold a cut,
 * sorted), each vertex's part from where its key falls among the cuts.
 */
#include "mpi/mpi_sfc.h"
#include "base/large_alloc.h"

#include "base/context.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define SFC_BITS 21                       /* per axis: 3 x 21 = 63-bit keys */
#define SFC_CELLS ((1u << SFC_BITS) - 1u) /* the largest coordinate */

/* The 21 low bits of x at every third bit (bit b to bit 3 b). */
static uint64_t spread3(uint32_t x)
{
    uint64_t v = x & SFC_CELLS;
    v = (v | v << 32) & 0x1f00000000ffffULL;
    v = (v | v << 16) & 0x1f0000ff0000ffULL;
    v = (v | v << 8) & 0x100f00f00f00f00fULL;
    v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
    v = (v | v << 2) & 0x1249249249249249ULL;
    return v;
}

uint64_t mpi_sfc_hilbert(uint32_t x, uint32_t y, uint32_t z)
{
    /* Skilling's transform ("Programming the Hilbert curve", 2004): axes to
       the transposed Hilbert index, whose bits interleaved are the key */
    uint32_t X[3] = {x, y, z};
    const uint32_t top = 1u << (SFC_BITS - 1);
    /* without branches: the bits are data, a branch on each mispredicts */
    for (uint32_t q = top; q > 1; q >>= 1) {
        uint32_t low = q - 1;
        for (int i = 0; i < 3; i++) {
            uint32_t set = 0u - ((X[i] & q) != 0); /* all ones when bit q is set */
            uint32_t t = (X[0] ^ X[i]) & low & ~set; /* set: invert X[0]'s low bits */
            X[0] ^= (low & set) | t;                 /* clear: exchange them */
            X[i] ^= t;
        }
    }
    X[1] ^= X[0];
    X[2] ^= X[1];
    uint32_t t = 0;
    for (uint32_t q = top; q > 1; q >>= 1)
        t ^= (q - 1) & (0u - ((X[2] & q) != 0));
    /* bit b of axis i goes to bit 3 b + 2 - i */
    return spread3(X[0] ^ t) << 2 | spread3(X[1] ^ t) << 1 | spread3(X[2] ^ t);
}

/* The transform Skilling's loop has applied to the bits below a level: axis
   j of the transformed point is bit (perm j) of the input, inverted when
   bit j of inv is set. A state of the key's state machine is that
   transform and the parity of the Gray code's bits above (mpi_sfc.h). */
static unsigned state_of(const int perm[3], unsigned inv, unsigned parity)
{
    return ((unsigned)(perm[0] * 9 + perm[1] * 3 + perm[2]) * 8 + inv) * 2 + parity;
}

static void pair_levels(mpi_sfc_table *t);

void mpi_sfc_table_init(mpi_sfc_table *t)
{
    memset(t, 0, sizeof *t);
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++)
            for (unsigned inv = 0; inv < 8; inv++)
                for (unsigned parity = 0; parity < 2; parity++) {
                    const int perm[3] = {a, b, 3 - a - b};
                    if (a == b)
                        continue;
                    for (unsigned col = 0; col < 8; col++) { /* x << 2 | y << 1 | z */
                        unsigned c[3], q[3] = {0, 0, 0};
                        for (int j = 0; j < 3; j++)
                            c[j] = (col >> (2 - perm[j]) & 1u) ^ (inv >> j & 1u);
                        int np[3] = {perm[0], perm[1], perm[2]};
                        unsigned ni = inv;
                        for (int i = 0; i < 3; i++) { /* the level's own steps */
                            if (c[i]) {
                                ni ^= 1u; /* invert axis 0 below */
                            } else if (i) { /* exchange axes 0 and i below */
                                int tp = np[0];
                                np[0] = np[i];
                                np[i] = tp;
                                unsigned b0 = ni & 1u, bi = ni >> i & 1u;
                                ni = (ni & ~(1u | 1u << i)) | bi | b0 << i;
                            }
                        }
                        q[0] = c[0]; /* Gray code, then the parity of the bits above */
                        q[1] = c[1] ^ q[0];
                        q[2] = c[2] ^ q[1];
                        unsigned digit = (q[0] ^ parity) << 2 | (q[1] ^ parity) << 1 |
                                         (q[2] ^ parity);
                        t->next[state_of(perm, inv, parity) * 8 + col] =
                            (uint16_t)(state_of(np, ni, parity ^ q[2]) << 3 | digit);
                    }
                }
    pair_levels(t);
}

/* The top level's state (no transform, no parity). */
static unsigned first_state(void)
{
    static const int identity[3] = {0, 1, 2};
    return state_of(identity, 0, 0);
}

/* t->dense and t->pair from t->next: the states reachable from the first,
   in the order a breadth-first walk meets them. */
static void pair_levels(mpi_sfc_table *t)
{
    unsigned order[MPI_SFC_STATES], count = 0;
    for (unsigned s = 0; s < MPI_SFC_STATES; s++)
        t->dense[s] = UINT16_MAX;
    t->dense[first_state()] = 0;
    order[count++] = first_state();
    for (unsigned i = 0; i < count; i++)
        for (unsigned col = 0; col < 8; col++) {
            unsigned ns = t->next[order[i] * 8 + col] >> 3;
            if (t->dense[ns] == UINT16_MAX && count < MPI_SFC_REACHABLE) {
                t->dense[ns] = (uint16_t)count;
                order[count++] = ns;
            }
        }
    for (unsigned i = 0; i < count; i++)
        for (unsigned c1 = 0; c1 < 8; c1++) {
            unsigned e1 = t->next[order[i] * 8 + c1];
            for (unsigned c2 = 0; c2 < 8; c2++) {
                unsigned e2 = t->next[(e1 >> 3) * 8 + c2];
                t->pair[i * 64 + (c1 << 3 | c2)] =
                    (uint16_t)(t->dense[e2 >> 3] << 6 | (e1 & 7u) << 3 | (e2 & 7u));
            }
        }
}

uint64_t mpi_sfc_hilbert_table(const mpi_sfc_table *t, uint32_t x, uint32_t y, uint32_t z)
{
    uint64_t m = spread3(x) << 2 | spread3(y) << 1 | spread3(z), key = 0;
    unsigned state = t->dense[first_state()];
    int level = SFC_BITS - 1;
    if (SFC_BITS % 2) { /* an odd level count: the top one alone */
        unsigned e = t->next[first_state() * 8 + (unsigned)(m >> 3 * level & 7u)];
        key = e & 7u;
        state = t->dense[e >> 3];
        level--;
    }
    for (; level > 0; level -= 2) { /* levels level and level - 1 */
        unsigned e = t->pair[state * 64 + (unsigned)(m >> 3 * (level - 1) & 63u)];
        key = key << 6 | (e & 63u);
        state = e >> 6;
    }
    return key;
}

void mpi_sfc_hilbert_table4(const mpi_sfc_table *t, const uint32_t cell[12], uint64_t key[4])
{
    /* four independent chains of lookups side by side, in locals the
       compiler keeps in registers: one key's chain is latency bound (each
       lookup waits for the last), four overlap */
    uint64_t m0 = spread3(cell[0]) << 2 | spread3(cell[1]) << 1 | spread3(cell[2]);
    uint64_t m1 = spread3(cell[3]) << 2 | spread3(cell[4]) << 1 | spread3(cell[5]);
    uint64_t m2 = spread3(cell[6]) << 2 | spread3(cell[7]) << 1 | spread3(cell[8]);
    uint64_t m3 = spread3(cell[9]) << 2 | spread3(cell[10]) << 1 | spread3(cell[11]);
    uint64_t k0 = 0, k1 = 0, k2 = 0, k3 = 0;
    unsigned s0 = t->dense[first_state()], s1 = s0, s2 = s0, s3 = s0;
    int level = SFC_BITS - 1;
    if (SFC_BITS % 2) { /* an odd level count: the top one alone */
        const uint16_t *top = t->next + first_state() * 8;
        unsigned sh = 3u * (unsigned)level, e0 = top[m0 >> sh & 7u], e1 = top[m1 >> sh & 7u],
                 e2 = top[m2 >> sh & 7u], e3 = top[m3 >> sh & 7u];
        k0 = e0 & 7u, k1 = e1 & 7u, k2 = e2 & 7u, k3 = e3 & 7u;
        s0 = t->dense[e0 >> 3], s1 = t->dense[e1 >> 3], s2 = t->dense[e2 >> 3];
        s3 = t->dense[e3 >> 3];
        level--;
    }
    for (; level > 0; level -= 2) { /* levels level and level - 1 */
        unsigned sh = 3u * (unsigned)(level - 1);
        unsigned e0 = t->pair[s0 * 64 + (unsigned)(m0 >> sh & 63u)];
        unsigned e1 = t->pair[s1 * 64 + (unsigned)(m1 >> sh & 63u)];
        unsigned e2 = t->pair[s2 * 64 + (unsigned)(m2 >> sh & 63u)];
        unsigned e3 = t->pair[s3 * 64 + (unsigned)(m3 >> sh & 63u)];
        k0 = k0 << 6 | (e0 & 63u), s0 = e0 >> 6;
        k1 = k1 << 6 | (e1 & 63u), s1 = e1 >> 6;
        k2 = k2 << 6 | (e2 & 63u), s2 = e2 >> 6;
        k3 = k3 << 6 | (e3 & 63u), s3 = e3 >> 6;
    }
    key[0] = k0, key[1] = k1, key[2] = k2, key[3] = k3;
}

typedef struct sfc_rec {
    uint64_t key;
    uint32_t at; /* index in the block: the global id is begin + at */
} sfc_rec;

/* The bounding cube's lower corner and the scale to SFC_CELLS (exact: min
   and max are the same in any reduction order). */
static void sfc_cube(mpi_part *p, const double *pos, size_t n, double lo[3], double *scale)
{
    double m[6] = {INFINITY, INFINITY, INFINITY, INFINITY, INFINITY, INFINITY};
    for (size_t v = 0; v < n; v++)
        for (int a = 0; a < 3; a++) {
            double x = pos[3 * v + a];
            if (isfinite(x)) {
                m[a] = x < m[a] ? x : m[a];
                m[3 + a] = -x < m[3 + a] ? -x : m[3 + a];
            }
        }
    MPI_Allreduce(MPI_IN_PLACE, m, 6, MPI_DOUBLE, MPI_MIN, p->comm);
    double extent = 0;
    for (int a = 0; a < 3; a++) {
        lo[a] = isfinite(m[a]) ? m[a] : 0.0;
        double e = isfinite(m[a]) ? -m[3 + a] - m[a] : 0.0;
        extent = e > extent ? e : extent;
    }
    *scale = extent > 0 && isfinite(extent) ? (double)SFC_CELLS / extent : 0.0;
}

static uint32_t sfc_cell(double x, double lo, double scale)
{
    double t = (x - lo) * scale;
    if (!(t > 0)) /* below, or not a number */
        return 0;
    return t >= (double)SFC_CELLS ? SFC_CELLS : (uint32_t)t;
}

/* Stable LSD radix sort by key, 8 bits a pass (records come in block
   order, so equal keys stay in id order): 256 buckets a pass keep the
   scatter's write streams in cache, 16-bit passes took 25% longer on a
   million records. tmp: n records. */
static void sfc_sort(sfc_rec *r, sfc_rec *tmp, size_t n, size_t *count)
{
    uint64_t diff = 0;
    for (size_t i = 1; i < n; i++)
        diff |= r[i].key ^ r[0].key;
    sfc_rec *src = r, *dst = tmp;
    for (int shift = 0; shift < 64; shift += 8) {
        if (!((diff >> shift) & 0xff))
            continue;
        memset(count, 0, 257 * sizeof *count);
        for (size_t i = 0; i < n; i++)
            count[((src[i].key >> shift) & 0xff) + 1]++;
        for (size_t d = 0; d < 256; d++)
            count[d + 1] += count[d];
        for (size_t i = 0; i < n; i++)
            dst[count[(src[i].key >> shift) & 0xff]++] = src[i];
        sfc_rec *t = src;
        src = dst;
        dst = t;
    }
    if (src != r)
        memcpy(r, src, n * sizeof *r);
}

/*
 * The cut points by selection, not by sorting the block. Cut q is the
 * element of rank T_q = total (q + 1) / parts (from 0) of all vertices in
 * (key, id) order: the largest (key, id) with at most T_q vertices below
 * it, so a vertex's part is the number of cuts at or below it and the parts
 * are the sorted order's shares. A histogram of the keys' top SFC_TOP_BITS
 * over all ranks names the bucket holding each cut and its rank there; only
 * those buckets' vertices are gathered and sorted, and the rest of the cut
 * is settled digit by digit over all ranks, counting below each candidate
 * in the sorted buckets (one Allreduce a digit for all cuts).
 */
#define SFC_TOP_BITS 16
#define SFC_TOP_SHIFT (3 * SFC_BITS - SFC_TOP_BITS) /* keys have 3 SFC_BITS bits */
#define SFC_BUCKETS ((size_t)1 << SFC_TOP_BITS)

/* (key, id) of r below the cut point c = {key, id}. */
static int sfc_below(const sfc_rec *r, size_t begin, const uint64_t *c)
{
    return r->key < c[0] || (r->key == c[0] && begin + r->at < c[1]);
}

static uint64_t sfc_count_below(const sfc_rec *r, size_t n, size_t begin, const uint64_t *c)
{
    size_t lo = 0, hi = n;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (sfc_below(r + mid, begin, c))
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

/* The digits the search settles below the bucket, one Allreduce each: the
   key's low 47 bits, then the id's 32 in 8-bit digits. */
static const struct sfc_digit {
    int word, shift, width;
} sfc_digits[] = {{0, 40, 7}, {0, 32, 8}, {0, 24, 8}, {0, 16, 8}, {0, 8, 8},
                  {0, 0, 8},  {1, 24, 8}, {1, 16, 8}, {1, 8, 8},  {1, 0, 8}};
#define SFC_CANDIDATES 255 /* nonzero values of the widest digit */

typedef struct sfc_work {
    uint64_t *key;      /* per block vertex */
    uint64_t *hist;     /* SFC_BUCKETS: the block's, then the sum over ranks */
    int32_t *slot;      /* SFC_BUCKETS: the gathered list of a bucket, or -1 */
    sfc_rec *rec, *tmp; /* the gathered buckets, one after another */
    size_t *list;       /* parts: where each gathered bucket's list starts (+ 1) */
    size_t *radix;
    uint64_t *cut, *count, *below, *rank_in;
    size_t *bucket_of;  /* per cut: its slot */
} sfc_work;

/* Which bucket holds each cut and its rank there (bucket_of: the bucket's
   list; rank_in; below: the bucket's prefix), over all ranks; the sizes of
   the lists of the block's vertices in those buckets (list[s + 1]);
   returns the number of lists. */
static size_t sfc_buckets(mpi_part *p, sfc_work *w, size_t n, size_t total, int parts)
{
    size_t m = (size_t)parts - 1, k = 0;
    memset(w->hist, 0, SFC_BUCKETS * sizeof *w->hist);
    for (size_t v = 0; v < n; v++)
        w->hist[w->key[v] >> SFC_TOP_SHIFT]++;
    MPI_Allreduce(MPI_IN_PLACE, w->hist, (int)SFC_BUCKETS, MPI_UINT64_T, MPI_SUM, p->comm);
    for (size_t b = 0; b < SFC_BUCKETS; b++)
        w->slot[b] = -1;
    uint64_t before = 0; /* vertices in the buckets below b */
    for (size_t b = 0, q = 0; b < SFC_BUCKETS && q < m; b++) {
        for (; q < m; q++) {
            uint64_t target = (uint64_t)total * (q + 1) / (uint64_t)parts;
            if (target >= before + w->hist[b])
                break;
            if (w->slot[b] < 0)
                w->slot[b] = (int32_t)k++;
            w->bucket_of[q] = (size_t)w->slot[b];
            w->rank_in[q] = target - before;
            w->below[q] = (uint64_t)b << SFC_TOP_SHIFT;
        }
        before += w->hist[b];
    }
    memset(w->list, 0, (k + 1) * sizeof *w->list);
    for (size_t v = 0; v < n; v++) {
        int32_t s = w->slot[w->key[v] >> SFC_TOP_SHIFT];
        if (s >= 0)
            w->list[s + 1]++;
    }
    for (size_t s = 0; s < k; s++)
        w->list[s + 1] += w->list[s];
    return k;
}

/* The block's vertices of those buckets, each bucket's sorted by (key, id)
   (gathered in block order: the stable sort keeps ids increasing). */
static void sfc_gather(sfc_work *w, size_t n, size_t k)
{
    size_t *at = w->radix + 257; /* a cursor a list */
    for (size_t s = 0; s < k; s++)
        at[s] = w->list[s];
    for (size_t v = 0; v < n; v++) {
        int32_t s = w->slot[w->key[v] >> SFC_TOP_SHIFT];
        if (s >= 0)
            w->rec[at[s]++] = (sfc_rec){w->key[v], (uint32_t)v};
    }
    for (size_t s = 0; s < k; s++)
        sfc_sort(w->rec + w->list[s], w->tmp, w->list[s + 1] - w->list[s], w->radix);
}

/* cut[2q], cut[2q+1]: the element of rank rank_in[q] in its bucket, settled
   digit by digit below the bucket's prefix: for each candidate value of the
   digit, the count below it in the bucket over all ranks. */
static void sfc_cuts(mpi_part *p, sfc_work *w, size_t begin, size_t m)
{
    for (size_t q = 0; q < m; q++) {
        w->cut[2 * q] = w->below[q];
        w->cut[2 * q + 1] = 0;
    }
    for (size_t k = 0; k < sizeof sfc_digits / sizeof *sfc_digits; k++) {
        const struct sfc_digit *g = sfc_digits + k;
        uint64_t values = ((uint64_t)1 << g->width) - 1;
        for (size_t q = 0; q < m; q++) {
            const sfc_rec *r = w->rec + w->list[w->bucket_of[q]];
            size_t n = w->list[w->bucket_of[q] + 1] - w->list[w->bucket_of[q]];
            for (uint64_t d = 1; d <= values; d++) {
                uint64_t c[2] = {w->cut[2 * q], w->cut[2 * q + 1]};
                c[g->word] |= d << g->shift;
                w->count[q * SFC_CANDIDATES + d - 1] = sfc_count_below(r, n, begin, c);
            }
        }
        MPI_Allreduce(MPI_IN_PLACE, w->count, (int)(m * SFC_CANDIDATES), MPI_UINT64_T, MPI_SUM,
                      p->comm);
        for (size_t q = 0; q < m; q++) {
            uint64_t best = 0;
            for (uint64_t d = 1; d <= values; d++) /* the counts grow with d */
                if (w->count[q * SFC_CANDIDATES + d - 1] <= w->rank_in[q])
                    best = d;
            w->cut[2 * q + g->word] |= best << g->shift;
        }
    }
}

/* Each vertex's part: the number of cut points at or below its (key, id). */
static void sfc_assign(const sfc_work *w, size_t n, size_t begin, size_t m, uint32_t *part_of)
{
    for (size_t v = 0; v < n; v++) {
        sfc_rec r = {w->key[v], (uint32_t)v};
        size_t lo = 0, hi = m; /* the cuts increase with q */
        while (lo < hi) {
            size_t mid = lo + (hi - lo) / 2;
            if (sfc_below(&r, begin, w->cut + 2 * mid))
                hi = mid;
            else
                lo = mid + 1;
        }
        part_of[v] = (uint32_t)lo;
    }
}

/* Part sizes over the ranks (count: parts entries, scratch). */
static void sfc_stats(mpi_part *p, const uint32_t *part_of, size_t n, size_t total, int parts,
                      uint64_t *count, mpi_sfc_stats *s)
{
    memset(count, 0, (size_t)parts * sizeof *count);
    for (size_t v = 0; v < n; v++)
        count[part_of[v]]++;
    MPI_Allreduce(MPI_IN_PLACE, count, parts, MPI_UINT64_T, MPI_SUM, p->comm);
    s->part_max = 0;
    s->part_min = SIZE_MAX;
    for (int q = 0; q < parts; q++) {
        s->part_max = count[q] > s->part_max ? (size_t)count[q] : s->part_max;
        s->part_min = count[q] < s->part_min ? (size_t)count[q] : s->part_min;
    }
    s->imbalance = total ? (double)s->part_max * parts / (double)total : 1.0;
}

static limn_status sfc_alloc(mpi_part *p, size_t n, int parts, sfc_work *w)
{
    size_t m = (size_t)parts;
    w->key = large_malloc((n ? n : 1) * sizeof *w->key);
    w->hist = large_malloc(SFC_BUCKETS * sizeof *w->hist);
    w->slot = large_malloc(SFC_BUCKETS * sizeof *w->slot);
    w->list = large_malloc((m + 1) * sizeof *w->list);
    w->radix = large_malloc((257 + m) * sizeof *w->radix);
    w->cut = large_malloc(2 * m * sizeof *w->cut);
    w->count = large_malloc(m * SFC_CANDIDATES * sizeof *w->count);
    w->below = large_malloc(m * sizeof *w->below);
    w->rank_in = large_malloc(m * sizeof *w->rank_in);
    w->bucket_of = large_malloc(m * sizeof *w->bucket_of);
    if (w->key && w->hist && w->slot && w->list && w->radix && w->cut && w->count &&
        w->below && w->rank_in && w->bucket_of)
        return LIMN_OK;
    return ctx_fail(p->ctx, LIMN_ERR_MEMORY,
                    "space-filling-curve partition: out of memory for %zu vertices on rank %d",
                    n, p->rank);
}

/* The gathered buckets' records (their sizes known after the histogram). */
static limn_status sfc_alloc_lists(mpi_part *p, sfc_work *w, size_t n)
{
    w->rec = large_malloc((n ? n : 1) * sizeof *w->rec);
    w->tmp = large_malloc((n ? n : 1) * sizeof *w->tmp);
    if (w->rec && w->tmp)
        return LIMN_OK;
    return ctx_fail(p->ctx, LIMN_ERR_MEMORY,
                    "space-filling-curve partition: out of memory for %zu vertices on rank %d",
                    n, p->rank);
}

static void sfc_free(sfc_work *w)
{
    free(w->key);
    free(w->hist);
    free(w->slot);
    free(w->rec);
    free(w->tmp);
    free(w->list);
    free(w->radix);
    free(w->cut);
    free(w->count);
    free(w->below);
    free(w->rank_in);
    free(w->bucket_of);
}

limn_status mpi_sfc_partition(mpi_part *p, const size_t *vtxdist, const double *positions,
                              int parts, uint32_t **part_of, mpi_sfc_stats *stats)
{
    double t0 = MPI_Wtime();
    size_t begin = vtxdist[p->rank], n = vtxdist[p->rank + 1] - begin, total = vtxdist[p->size];
    sfc_work w = {0};
    *part_of = NULL;
    limn_status st = parts >= 1 ? LIMN_OK
                                : ctx_fail(p->ctx, LIMN_ERR_ARGUMENT,
                                           "space-filling-curve partition: %d parts (needs >= 1)",
                                           parts);
    if (!st)
        st = sfc_alloc(p, n, parts, &w);
    if (!st && !(*part_of = large_malloc((n ? n : 1) * sizeof **part_of)))
        st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu parts", n);
    st = mpi_agree(p, st);
    if (!st) {
        double lo[3], scale;
        sfc_cube(p, positions, n, lo, &scale);
        mpi_sfc_table table;
        mpi_sfc_table_init(&table);
        size_t v = 0;
        for (; v + 4 <= n; v += 4) {
            uint32_t cell[12];
            for (int j = 0; j < 4; j++)
                for (int c = 0; c < 3; c++)
                    cell[3 * j + c] = sfc_cell(positions[3 * (v + j) + c], lo[c], scale);
            mpi_sfc_hilbert_table4(&table, cell, w.key + v);
        }
        for (; v < n; v++) {
            const double *x = positions + 3 * v;
            w.key[v] = mpi_sfc_hilbert_table(&table, sfc_cell(x[0], lo[0], scale),
                                             sfc_cell(x[1], lo[1], scale),
                                             sfc_cell(x[2], lo[2], scale));
        }
        size_t m = (size_t)parts - 1, lists = m && total ? sfc_buckets(p, &w, n, total, parts) : 0;
        st = mpi_agree(p, sfc_alloc_lists(p, &w, lists ? w.list[lists] : 0));
        if (!st) {
            if (lists) {
                sfc_gather(&w, n, lists);
                sfc_cuts(p, &w, begin, m);
            }
            sfc_assign(&w, n, begin, lists ? m : 0, *part_of);
            if (stats)
                sfc_stats(p, *part_of, n, total, parts, w.count, stats);
        }
    }
    if (st) {
        free(*part_of);
        *part_of = NULL;
    }
    sfc_free(&w);
    double t = MPI_Wtime() - t0;
    MPI_Allreduce(MPI_IN_PLACE, &t, 1, MPI_DOUBLE, MPI_MAX, p->comm);
    if (stats)
        stats->seconds = t;
    return st;
}
