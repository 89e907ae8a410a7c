/* SPDX-License-Identifier: MIT */
/*
 * Space-filling-curve partition (mpi_sfc.h): Hilbert keys of the block's
 * positions, a stable radix sort of them on each rank, the cut points found
 * digit by digit over all ranks, each vertex's part from where its key falls.
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

/* The digits the cut search settles, one Allreduce each, from the top:
   the key's 63 bits in 7-bit digits, then the id's 32 in 8-bit ones. */
static const struct sfc_digit {
    int word, shift, width;
} sfc_digits[] = {{0, 56, 7}, {0, 49, 7}, {0, 42, 7}, {0, 35, 7}, {0, 28, 7}, {0, 21, 7},
                  {0, 14, 7}, {0, 7, 7},  {0, 0, 7},  {1, 24, 8}, {1, 16, 8}, {1, 8, 8},
                  {1, 0, 8}};
#define SFC_CANDIDATES 255 /* nonzero values of the widest digit */

/* cut[2q], cut[2q+1]: the largest (key, id) with exactly total * (q + 1) /
   parts vertices of the whole mesh below it, q < parts - 1; settled digit
   by digit from the top: for each candidate value of the digit, the count
   below it over all ranks (count: (parts - 1) * SFC_CANDIDATES). */
static void sfc_cuts(mpi_part *p, const sfc_rec *r, size_t n, size_t begin, size_t total,
                     int parts, uint64_t *cut, uint64_t *count)
{
    size_t m = (size_t)parts - 1;
    if (m == 0)
        return;
    memset(cut, 0, 2 * m * sizeof *cut);
    for (size_t k = 0; k < sizeof sfc_digits / sizeof *sfc_digits; k++) {
        const struct sfc_digit *g = sfc_digits + k;
        uint64_t values = ((uint64_t)1 << g->width) - 1;
        for (size_t q = 0; q < m; q++)
            for (uint64_t d = 1; d <= values; d++) {
                uint64_t c[2] = {cut[2 * q], cut[2 * q + 1]};
                c[g->word] |= d << g->shift;
                count[q * SFC_CANDIDATES + d - 1] = sfc_count_below(r, n, begin, c);
            }
        MPI_Allreduce(MPI_IN_PLACE, count, (int)(m * SFC_CANDIDATES), MPI_UINT64_T, MPI_SUM,
                      p->comm);
        for (size_t q = 0; q < m; q++) {
            uint64_t target = (uint64_t)total * (q + 1) / (uint64_t)parts, best = 0;
            for (uint64_t d = 1; d <= values; d++) /* the counts grow with d */
                if (count[q * SFC_CANDIDATES + d - 1] <= target)
                    best = d;
            cut[2 * q + g->word] |= best << g->shift;
        }
    }
}

/* Each vertex's part: the number of cut points at or below its (key, id). */
static void sfc_assign(const sfc_rec *r, size_t n, size_t begin, const uint64_t *cut, int parts,
                       uint32_t *part_of)
{
    size_t s = 0, m = (size_t)parts - 1;
    for (size_t i = 0; i < n; i++) {
        while (s < m && !sfc_below(r + i, begin, cut + 2 * s))
            s++;
        part_of[r[i].at] = (uint32_t)s;
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

typedef struct sfc_work {
    sfc_rec *rec, *tmp;
    size_t *radix;
    uint64_t *cut, *count;
} sfc_work;

static limn_status sfc_alloc(mpi_part *p, size_t n, int parts, sfc_work *w)
{
    w->rec = large_malloc((n ? n : 1) * sizeof *w->rec);
    w->tmp = large_malloc((n ? n : 1) * sizeof *w->tmp);
    w->radix = large_malloc(257 * sizeof *w->radix);
    w->cut = large_malloc(2 * (size_t)parts * sizeof *w->cut);
    w->count = large_malloc((size_t)parts * SFC_CANDIDATES * sizeof *w->count);
    if (w->rec && w->tmp && w->radix && w->cut && w->count)
        return LIMN_OK;
    return ctx_fail(p->ctx, LIMN_ERR_MEMORY,
                    "space-filling-curve partition: out of memory for %zu vertices on rank %d",
                    n, p->rank);
}

static void sfc_free(sfc_work *w)
{
    free(w->rec);
    free(w->tmp);
    free(w->radix);
    free(w->cut);
    free(w->count);
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
        for (size_t v = 0; v < n; v++) {
            const double *x = positions + 3 * v;
            w.rec[v] = (sfc_rec){mpi_sfc_hilbert_table(&table, sfc_cell(x[0], lo[0], scale),
                                                       sfc_cell(x[1], lo[1], scale),
                                                       sfc_cell(x[2], lo[2], scale)),
                                 (uint32_t)v};
        }
        sfc_sort(w.rec, w.tmp, n, w.radix);
        sfc_cuts(p, w.rec, n, begin, total, parts, w.cut, w.count);
        sfc_assign(w.rec, n, begin, w.cut, parts, *part_of);
        if (stats)
            sfc_stats(p, *part_of, n, total, parts, w.count, stats);
    } else {
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
