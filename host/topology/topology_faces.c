/* SPDX-License-Identifier: MIT */
/* Topology passes over faces: face checks, vertex buckets, corner_face. */
#include "topology/topology_build.h"

#include <stdlib.h>

/* The first corner (offset in the face) whose vertex came earlier in the
   face, or d: what a mark per vertex finds, without one per thread. */
static size_t first_repeat(const uint32_t *v, size_t d, topo_scratch *s, int *no_memory)
{
    if (d <= 32) {
        for (size_t j = 1; j < d; j++)
            for (size_t i = 0; i < j; i++)
                if (v[i] == v[j])
                    return j;
        return d;
    }
    if (!topo_scratch_reserve(s, d, 0)) {
        *no_memory = 1;
        return d;
    }
    for (size_t j = 0; j < d; j++)
        s->keys[j] = (uint64_t)v[j] << 32 | j;
    topo_sort_u64(s->keys, d);
    size_t first = d;
    for (size_t j = 1; j < d; j++)
        if (s->keys[j] >> 32 == s->keys[j - 1] >> 32 &&
            (j < 2 || s->keys[j - 1] >> 32 != s->keys[j - 2] >> 32) &&
            (uint32_t)s->keys[j] < first)
            first = (uint32_t)s->keys[j]; /* the second use of this vertex */
    return first;
}

static int faces_range(void *arg, size_t begin, size_t end)
{
    topo_build *b = arg;
    topology *t = b->t;
    topo_counts *k = &b->counts[topo_range(b, t->face_count, begin)];
    topo_scratch s = {0};
    for (size_t f = begin; f < end; f++) {
        uint32_t fb = t->face_offsets[f], fe = t->face_offsets[f + 1], d = fe - fb;
        const uint32_t *v = t->face_indices + fb;
        size_t r = first_repeat(v, d, &s, &k->no_memory);
        if (k->no_memory)
            break;
        if (r < d) {
            k->bad_face = f;
            k->bad_vertex = v[r];
            break;
        }
        if (d > k->max_face_size)
            k->max_face_size = d;
        if (d == 3)
            k->triangles++;
        else if (d == 4)
            k->quads++;
        else
            k->other_faces++;
    }
    topo_scratch_free(&s);
    return k->no_memory || k->bad_face != SIZE_MAX;
}

int topo_faces(topo_build *b)
{
    return parallel_run(b->t->face_count, b->parts, faces_range, b);
}

/* Each range of vertices [lo, hi) reads every corner and takes its own:
   no two threads write one counter (no atomics, a plain bump behind each
   cache miss), and each bucket fills in increasing corner order, so it
   comes out sorted for any thread count. */
static inline uint32_t bump(_Atomic uint32_t *x)
{
    uint32_t v = atomic_load_explicit(x, memory_order_relaxed);
    atomic_store_explicit(x, v + 1, memory_order_relaxed);
    return v;
}

static int count_range(void *arg, size_t lo, size_t hi)
{
    topo_build *b = arg;
    const topology *t = b->t;
    uint32_t first = (uint32_t)lo, span = (uint32_t)(hi - lo);
    for (size_t c = 0; c < t->corner_count; c++) {
        uint32_t v = t->face_indices[c];
        if (v - first < span)
            bump(&b->cursor[v]);
    }
    return 0;
}

int topo_corner_counts(topo_build *b)
{
    return parallel_run(b->t->vertex_count, b->parts, count_range, b);
}

static int scatter_range(void *arg, size_t lo, size_t hi)
{
    topo_build *b = arg;
    topology *t = b->t;
    uint32_t first = (uint32_t)lo, span = (uint32_t)(hi - lo);
    const int census = b->ring != NULL; /* the census: next and previous vertex, one word */
    for (size_t f = 0; f < t->face_count; f++) {
        uint32_t fb = t->face_offsets[f], fe = t->face_offsets[f + 1];
        for (uint32_t c = fb; c < fe; c++) {
            uint32_t v = t->face_indices[c];
            if (v - first >= span)
                continue;
            uint32_t slot = bump(&b->cursor[v]);
            uint32_t next = t->face_indices[c + 1 < fe ? c + 1 : fb];
            uint32_t prev = t->face_indices[c > fb ? c - 1 : fe - 1];
            if (census) {
                b->ring[slot] = (uint64_t)next << 32 | prev;
            } else {
                b->next[slot] = next;
                b->prev[slot] = prev;
                t->vertex_corners[slot] = c;
                b->wrap[slot] = c > fb ? 0 : fe - 1 - c < 255 ? (uint8_t)(fe - 1 - c) : 255;
            }
        }
    }
    return 0;
}

static int corner_face_range(void *arg, size_t begin, size_t end)
{
    topology *t = ((topo_build *)arg)->t;
    for (size_t f = begin; f < end; f++)
        for (uint32_t c = t->face_offsets[f]; c < t->face_offsets[f + 1]; c++)
            t->corner_face[c] = (uint32_t)f;
    return 0;
}

int topo_corner_faces(topo_build *b)
{
    return parallel_run(b->t->face_count, b->parts, corner_face_range, b);
}

int topo_scatter(topo_build *b)
{
    return parallel_run(b->t->vertex_count, b->parts, scatter_range, b);
}
