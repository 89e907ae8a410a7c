/* SPDX-License-Identifier: MIT */
/* Face repeats and vertex-set hashes, over ranges of faces (face_keys.h). */
#include "topology/face_keys.h"
#include "base/context.h"
#include "base/parallel.h"
#include "mesh/mesh.h"

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

/* One sort: keys hashed and counted by their top byte per range of faces,
   scattered stably into the 256 buckets of that byte, then each bucket
   sorted (LSD, stable) on bits 32..55 while it is cache-sized. */
typedef struct key_job {
    const limn_mesh *m;
    uint32_t maxd;
    unsigned parts;
    face_key *k, *tmp;
    size_t count[PARALLEL_MAX][BUCKETS]; /* then each range's first slot per bucket */
    size_t bucket_start[BUCKETS + 1];
} key_job;

static unsigned part_of(const key_job *j, size_t begin)
{
    return parallel_part(j->m->face_count, j->parts, begin);
}

static int hash_range(void *arg, size_t begin, size_t end)
{
    key_job *j = arg;
    uint32_t *buf = malloc((j->maxd ? j->maxd : 1) * sizeof *buf);
    if (!buf)
        return 1;
    size_t *count = j->count[part_of(j, begin)];
    for (size_t f = begin; f < end; f++) {
        uint32_t d;
        const uint32_t *v = face_sorted_vertices(j->m, (uint32_t)f, buf, &d);
        uint64_t h = mix(d);
        for (uint32_t i = 0; i < d; i++)
            h = mix(h ^ (v[i] + 0x9e3779b97f4a7c15ULL));
        j->k[f].hash = h;
        j->k[f].face = (uint32_t)f;
        count[h >> 56]++;
    }
    free(buf);
    return 0;
}

static int scatter_range(void *arg, size_t begin, size_t end)
{
    key_job *j = arg;
    size_t *next = j->count[part_of(j, begin)];
    for (size_t f = begin; f < end; f++)
        j->tmp[next[j->k[f].hash >> 56]++] = j->k[f];
    return 0;
}

/* Buckets [begin, end): from tmp back into k, sorted on bits 32..55. */
static int bucket_range(void *arg, size_t begin, size_t end)
{
    key_job *j = arg;
    for (size_t b = begin; b < end; b++) {
        size_t lo = j->bucket_start[b], n = j->bucket_start[b + 1] - lo;
        face_key *from = j->tmp + lo, *to = j->k + lo;
        for (int shift = 32; shift < 56; shift += 8) {
            size_t count[BUCKETS + 1] = {0};
            for (size_t i = 0; i < n; i++)
                count[((from[i].hash >> shift) & 255) + 1]++;
            for (int c = 0; c < BUCKETS; c++)
                count[c + 1] += count[c];
            for (size_t i = 0; i < n; i++)
                to[count[(from[i].hash >> shift) & 255]++] = from[i];
            face_key *t = from;
            from = to;
            to = t;
        }
        /* three passes from tmp: the sorted keys end in k */
    }
    return 0;
}

/* Each range's first slot in every bucket (stable: ranges in face order). */
static void bucket_offsets(key_job *j)
{
    size_t at = 0;
    for (int b = 0; b < BUCKETS; b++) {
        j->bucket_start[b] = at;
        for (unsigned p = 0; p < j->parts; p++) {
            size_t c = j->count[p][b];
            j->count[p][b] = at;
            at += c;
        }
    }
    j->bucket_start[BUCKETS] = at;
}

limn_status face_keys_sorted(limn_context *ctx, const limn_mesh *m, uint32_t maxd,
                             face_key **out)
{
    size_t nf = m->face_count;
    key_job *j = calloc(1, sizeof *j);
    face_key *k = malloc((nf ? nf : 1) * sizeof *k), *tmp = malloc((nf ? nf : 1) * sizeof *tmp);
    limn_status st = LIMN_OK;
    if (!j || !k || !tmp) {
        st = ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory looking for duplicate faces");
    } else {
        j->m = m;
        j->maxd = maxd;
        j->k = k;
        j->tmp = tmp;
        j->parts = parallel_threads(ctx, (uint64_t)nf * 64);
        if ((size_t)j->parts > nf)
            j->parts = nf ? (unsigned)nf : 1;
        if (parallel_run(nf, j->parts, hash_range, j)) {
            st = ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory looking for duplicate faces");
        } else {
            ctx_progress(ctx, "repair", 0.4);
            bucket_offsets(j);
            parallel_run(nf, j->parts, scatter_range, j);
            ctx_progress(ctx, "repair", 0.55);
            parallel_run(BUCKETS, j->parts, bucket_range, j);
            ctx_progress(ctx, "repair", 0.8);
        }
    }
    free(j);
    free(tmp);
    if (st) {
        free(k);
        return st;
    }
    *out = k;
    return LIMN_OK;
}
