/* SPDX-License-Identifier: MIT */
/* Face repeats and vertex-set hashes, over ranges of faces (face_keys.h). */
#include "topology/face_keys.h"
#include "base/context.h"
#include "base/large_alloc.h"
#include "base/parallel.h"
#include "mesh/mesh.h"

#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#define BUCKETS 256

static int cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return (x > y) - (x < y);
}

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return (x > y) - (x < y);
}

const uint32_t *face_sorted_vertices(const limn_mesh *m, uint32_t f, uint32_t *buf, uint32_t *d)
{
    uint32_t b = m->face_offsets[f];
    *d = m->face_offsets[f + 1] - b;
    memcpy(buf, m->face_indices + b, *d * sizeof *buf);
    if (*d <= 8) {
        for (uint32_t i = 1; i < *d; i++)
            for (uint32_t j = i; j > 0 && buf[j - 1] > buf[j]; j--) {
                uint32_t t = buf[j];
                buf[j] = buf[j - 1];
                buf[j - 1] = t;
            }
    } else {
        qsort(buf, *d, sizeof *buf, cmp_u32);
    }
    return buf;
}

/* ---------------------------------------------------------------- repeats */

/* The first corner j of v (d corners) whose vertex came earlier in the face,
   or d: small faces pairwise, large ones by sorting (vertex, corner) pairs
   (scratch: room for d). */
static uint32_t first_repeated_corner(const uint32_t *v, uint32_t d, uint64_t *scratch)
{
    if (d <= 32) {
        for (uint32_t j = 1; j < d; j++)
            for (uint32_t i = 0; i < j; i++)
                if (v[i] == v[j])
                    return j;
        return d;
    }
    for (uint32_t j = 0; j < d; j++)
        scratch[j] = (uint64_t)v[j] << 32 | j;
    qsort(scratch, d, sizeof *scratch, cmp_u64);
    uint32_t first = d;
    for (uint32_t j = 1; j < d; j++)
        /* the second corner of a run is that vertex's first repeat */
        if (scratch[j] >> 32 == scratch[j - 1] >> 32 &&
            (j < 2 || scratch[j - 1] >> 32 != scratch[j - 2] >> 32) &&
            (uint32_t)scratch[j] < first)
            first = (uint32_t)scratch[j];
    return first;
}

typedef struct repeat_job {
    const limn_mesh *m;
    uint32_t maxd;
    size_t face[PARALLEL_MAX];
    uint32_t vertex[PARALLEL_MAX];
    unsigned parts;
} repeat_job;

static int repeat_range(void *arg, size_t begin, size_t end)
{
    repeat_job *j = arg;
    const limn_mesh *m = j->m;
    uint64_t *scratch = j->maxd > 32 ? malloc(j->maxd * sizeof *scratch) : NULL;
    if (j->maxd > 32 && !scratch)
        return 1;
    unsigned part = parallel_part(m->face_count, j->parts, begin);
    j->face[part] = SIZE_MAX;
    for (size_t f = begin; f < end; f++) {
        const uint32_t *v = m->face_indices + m->face_offsets[f];
        uint32_t d = m->face_offsets[f + 1] - m->face_offsets[f];
        uint32_t c = first_repeated_corner(v, d, scratch);
        if (c < d) {
            j->face[part] = f;
            j->vertex[part] = v[c];
            break;
        }
    }
    free(scratch);
    return 0;
}

/* The largest face of m. */
static uint32_t largest_face(const limn_mesh *m)
{
    uint32_t maxd = 0;
    for (size_t f = 0; f < m->face_count; f++)
        if (m->face_offsets[f + 1] - m->face_offsets[f] > maxd)
            maxd = m->face_offsets[f + 1] - m->face_offsets[f];
    return maxd;
}

limn_status face_first_repeat(limn_context *ctx, const limn_mesh *m, size_t *face,
                              uint32_t *vertex)
{
    repeat_job j = {.m = m, .maxd = largest_face(m)};
    size_t nf = m->face_count;
    j.parts = parallel_threads(ctx, (uint64_t)m->face_offsets[nf] * 16);
    if ((size_t)j.parts > nf)
        j.parts = nf ? (unsigned)nf : 1;
    if (parallel_run(nf, j.parts, repeat_range, &j))
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory repairing the mesh");
    *face = SIZE_MAX;
    *vertex = 0;
    for (unsigned p = 0; p < j.parts && nf; p++)
        if (j.face[p] != SIZE_MAX) {
            *face = j.face[p];
            *vertex = j.vertex[p];
            break;
        }
    return LIMN_OK;
}

/* ------------------------------------------------------------------ keys */

static uint64_t mix(uint64_t h)
{
    h ^= h >> 33;
    h *= 0xff51afd7ed558ccdULL;
    h ^= h >> 33;
    h *= 0xc4ceb9fe1a85ec53ULL;
    h ^= h >> 33;
    return h;
}

/* The duplicate search: every face's vertex-set hash, counted by its top
   byte per range of faces; (hash bits 24..55, face) scattered stably into
   the 256 buckets of that byte, so each bucket holds its faces in increasing
   order; then each bucket, cache-sized, through an open-addressing table of
   the faces kept so far. */
typedef struct dup_job {
    const limn_mesh *m;
    uint32_t maxd;
    unsigned parts;
    uint64_t *hash;  /* per face */
    uint64_t *entry; /* per face, bucket order: key << 32 | face */
    uint8_t *dup;
    size_t count[PARALLEL_MAX][BUCKETS]; /* then each range's first slot per bucket */
    size_t bucket_start[BUCKETS + 1], largest_bucket;
    face_duplicates found[PARALLEL_MAX];
    int no_memory[PARALLEL_MAX];
} dup_job;

static unsigned part_of(const dup_job *j, size_t n, size_t begin)
{
    return parallel_part(n, j->parts, begin);
}

/* The hash of a sorted vertex set: a sum of products, one odd multiplier a
   place (independent multiplications, not a chain of mixes: a triangle's
   hash was a third of the duplicate search), then one mix. Only the
   buckets and the table's keys depend on it; which faces are duplicates,
   and of which, does not. */
static uint64_t set_hash(const uint32_t *v, uint32_t d)
{
    uint64_t h = (uint64_t)d * 0x9e3779b97f4a7c15ULL;
    for (uint32_t i = 0; i < d; i++)
        h += ((uint64_t)v[i] + 0x632be59bd9b4e019ULL) * (0xff51afd7ed558ccdULL + 2 * (uint64_t)i);
    return mix(h);
}

static int hash_range(void *arg, size_t begin, size_t end)
{
    dup_job *j = arg;
    uint32_t *buf = malloc((j->maxd ? j->maxd : 1) * sizeof *buf);
    if (!buf)
        return 1;
    const uint32_t *off = j->m->face_offsets, *idx = j->m->face_indices;
    size_t *count = j->count[part_of(j, j->m->face_count, begin)];
    for (size_t f = begin; f < end; f++) {
        uint64_t h;
        if (off[f + 1] - off[f] == 3) { /* most faces: sorted in registers */
            uint32_t a = idx[off[f]], b = idx[off[f] + 1], c = idx[off[f] + 2], t;
            if (a > b) { t = a; a = b; b = t; }
            if (b > c) { t = b; b = c; c = t; }
            if (a > b) { t = a; a = b; b = t; }
            const uint32_t v[3] = {a, b, c};
            h = set_hash(v, 3);
        } else {
            uint32_t d;
            const uint32_t *v = face_sorted_vertices(j->m, (uint32_t)f, buf, &d);
            h = set_hash(v, d);
        }
        j->hash[f] = h;
        count[h >> 56]++;
    }
    free(buf);
    return 0;
}

static int scatter_range(void *arg, size_t begin, size_t end)
{
    dup_job *j = arg;
    size_t *next = j->count[part_of(j, j->m->face_count, begin)];
    for (size_t f = begin; f < end; f++) {
        uint64_t h = j->hash[f];
        j->entry[next[h >> 56]++] = (h >> 24 & 0xffffffffu) << 32 | f;
    }
    return 0;
}

/* Faces a and b have the same vertex set (buf: room for 2 maxd). */
static int same_set(const dup_job *j, uint32_t a, uint32_t b, uint32_t *buf)
{
    uint32_t da, db;
    const uint32_t *va = face_sorted_vertices(j->m, a, buf, &da);
    const uint32_t *vb = face_sorted_vertices(j->m, b, buf + j->maxd, &db);
    return da == db && memcmp(va, vb, da * sizeof *va) == 0;
}

/* One bucket's faces, in increasing order, against the table of those kept
   (slot: key << 32 | face + 1, 0 empty; cap a power of two > 2 n): a face
   whose set is there is a duplicate of the one found (the earliest with that
   set: only the first of each set is kept), else it is kept. */
static void bucket_duplicates(dup_job *j, size_t b, uint64_t *table, size_t cap, uint32_t *buf,
                              face_duplicates *found)
{
    size_t lo = j->bucket_start[b], n = j->bucket_start[b + 1] - lo, mask = cap - 1;
    memset(table, 0, cap * sizeof *table);
    for (size_t i = 0; i < n; i++) {
        uint64_t e = j->entry[lo + i];
        uint32_t key = (uint32_t)(e >> 32), f = (uint32_t)e;
        for (size_t at = key & mask;; at = (at + 1) & mask) {
            uint64_t s = table[at];
            if (!s) {
                table[at] = (uint64_t)key << 32 | ((uint64_t)f + 1);
                break;
            }
            uint32_t g = (uint32_t)s - 1;
            if ((uint32_t)(s >> 32) == key && same_set(j, g, f, buf)) {
                j->dup[f] = 1;
                found->count++;
                if (f < found->first) {
                    found->first = f;
                    found->first_of = g;
                }
                break;
            }
        }
    }
}

static int table_range(void *arg, size_t begin, size_t end)
{
    dup_job *j = arg;
    unsigned part = part_of(j, BUCKETS, begin);
    size_t cap = 16;
    while (cap < 2 * j->largest_bucket + 1)
        cap *= 2;
    uint64_t *table = malloc(cap * sizeof *table);
    uint32_t *buf = malloc(2 * (size_t)(j->maxd ? j->maxd : 1) * sizeof *buf);
    if (!table || !buf) {
        free(table);
        free(buf);
        j->no_memory[part] = 1;
        return 1;
    }
    for (size_t b = begin; b < end; b++)
        bucket_duplicates(j, b, table, cap, buf, &j->found[part]);
    free(table);
    free(buf);
    return 0;
}

/* Each range's first slot in every bucket (stable: ranges in face order). */
static void bucket_offsets(dup_job *j)
{
    size_t at = 0;
    for (int b = 0; b < BUCKETS; b++) {
        j->bucket_start[b] = at;
        for (unsigned p = 0; p < j->parts; p++) {
            size_t c = j->count[p][b];
            j->count[p][b] = at;
            at += c;
        }
        if (at - j->bucket_start[b] > j->largest_bucket)
            j->largest_bucket = at - j->bucket_start[b];
    }
    j->bucket_start[BUCKETS] = at;
}

/* The three passes; nonzero when out of memory. */
static int dup_passes(limn_context *ctx, dup_job *j)
{
    size_t nf = j->m->face_count;
    if (parallel_run(nf, j->parts, hash_range, j))
        return 1;
    ctx_progress(ctx, "repair", 0.5);
    bucket_offsets(j);
    parallel_run(nf, j->parts, scatter_range, j);
    ctx_progress(ctx, "repair", 0.65);
    return parallel_run(BUCKETS, j->parts, table_range, j);
}

static atomic_size_t searches;

size_t face_duplicate_search_count(void)
{
    return atomic_load(&searches);
}

limn_status face_find_duplicates(limn_context *ctx, const limn_mesh *m, uint32_t maxd,
                                 uint8_t *dup, face_duplicates *out)
{
    atomic_fetch_add(&searches, 1);
    size_t nf = m->face_count;
    out->count = 0;
    out->first = SIZE_MAX;
    out->first_of = 0;
    dup_job *j = calloc(1, sizeof *j);
    uint64_t *hash = large_malloc((nf ? nf : 1) * sizeof *hash);
    uint64_t *entry = large_malloc((nf ? nf : 1) * sizeof *entry);
    int failed = !j || !hash || !entry;
    if (!failed) {
        j->m = m;
        j->maxd = maxd;
        j->hash = hash;
        j->entry = entry;
        j->dup = dup;
        j->parts = parallel_threads(ctx, (uint64_t)nf * 64);
        if ((size_t)j->parts > nf)
            j->parts = nf ? (unsigned)nf : 1;
        for (unsigned p = 0; p < PARALLEL_MAX; p++)
            j->found[p].first = SIZE_MAX;
        failed = dup_passes(ctx, j);
    }
    for (unsigned p = 0; !failed && p < PARALLEL_MAX; p++) {
        const face_duplicates *k = &j->found[p];
        out->count += k->count;
        if (k->first < out->first) {
            out->first = k->first;
            out->first_of = k->first_of;
        }
    }
    free(j);
    free(hash);
    free(entry);
    return failed ? ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory looking for duplicate faces")
                  : LIMN_OK;
}

limn_status face_duplicates_marked(limn_context *ctx, const limn_mesh *m, uint8_t **dup,
                                   face_duplicates *out)
{
    size_t nf = m->face_count;
    *dup = NULL;
    out->count = 0;
    out->first = SIZE_MAX;
    out->first_of = 0;
    if (nf < 2)
        return LIMN_OK;
    uint32_t maxd = 0;
    for (size_t f = 0; f < nf; f++)
        if (m->face_offsets[f + 1] - m->face_offsets[f] > maxd)
            maxd = m->face_offsets[f + 1] - m->face_offsets[f];
    if (!(*dup = calloc(nf, 1)))
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory looking for duplicate faces");
    limn_status st = face_find_duplicates(ctx, m, maxd, *dup, out);
    if (st) {
        free(*dup);
        *dup = NULL;
    }
    return st;
}
