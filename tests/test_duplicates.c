/* SPDX-License-Identifier: MIT */
/*
 * The repair's duplicate faces (topology/face_keys.c: hashed buckets and a
 * table per bucket) against brute force: every face's sorted vertex list
 * sorted with qsort, each run of equal lists a face and its later copies.
 * The count, the first copy and the face it copies, and the faces left
 * after --drop-duplicate-faces, for 1, 2 and 4 host threads, on a generated
 * mesh full of copies (rotated, reversed, shuffled, faces of 3 to 40
 * corners) and on every shared mesh.
 */
#include "support.h"
#include "mesh/mesh.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

/* ------------------------------------------------------------ the oracle */

typedef struct oracle_face {
    const uint32_t *v; /* sorted */
    uint32_t d, face;
} oracle_face;

static int cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return (x > y) - (x < y);
}

static int cmp_face(const void *a, const void *b)
{
    const oracle_face *x = a, *y = b;
    if (x->d != y->d)
        return x->d < y->d ? -1 : 1;
    int c = memcmp(x->v, y->v, x->d * sizeof *x->v);
    return c ? c : (x->face > y->face) - (x->face < y->face);
}

/* dup[f] for every later copy; the count, the first copy and its original. */
static size_t oracle_duplicates(const limn_mesh *m, uint8_t *dup, size_t *first, size_t *of)
{
    size_t nf = m->face_count, nc = m->face_offsets[nf], count = 0;
    uint32_t *sorted = malloc((nc ? nc : 1) * sizeof *sorted);
    oracle_face *f = malloc((nf ? nf : 1) * sizeof *f);
    assert_non_null(sorted);
    assert_non_null(f);
    memcpy(sorted, m->face_indices, nc * sizeof *sorted);
    for (size_t i = 0; i < nf; i++) {
        uint32_t b = m->face_offsets[i], d = m->face_offsets[i + 1] - b;
        qsort(sorted + b, d, sizeof *sorted, cmp_u32);
        f[i] = (oracle_face){sorted + b, d, (uint32_t)i};
    }
    qsort(f, nf, sizeof *f, cmp_face);
    memset(dup, 0, nf);
    *first = SIZE_MAX;
    for (size_t i = 0, j; i < nf; i = j) {
        for (j = i + 1; j < nf && f[j].d == f[i].d && !memcmp(f[j].v, f[i].v, f[i].d * 4); j++) {
            dup[f[j].face] = 1;
            count++;
            if (f[j].face < *first) {
                *first = f[j].face;
                *of = f[i].face;
            }
        }
    }
    free(sorted);
    free(f);
    return count;
}

/* The repair's report and faces against the oracle, for 1, 2 and 4 threads;
   returns the duplicates found. */
static size_t check_mesh(limn_context *ctx, const limn_mesh *m, const char *what)
{
    size_t nf = m->face_count, first = 0, of = 0;
    uint8_t *dup = malloc(nf ? nf : 1);
    assert_non_null(dup);
    size_t count = oracle_duplicates(m, dup, &first, &of);
    static const int threads[] = {1, 2, 4};
    for (size_t t = 0; t < 3; t++) {
        assert_int_equal(limn_context_set_host_threads(ctx, threads[t]), LIMN_OK);
        limn_mesh *c = NULL;
        assert_int_equal(limn_mesh_copy(ctx, m, &c), LIMN_OK);
        limn_repair_options o;
        limn_repair_options_default(&o);
        o.duplicate_faces = 1;
        limn_repair_report r = {.size = sizeof r};
        assert_int_equal(limn_mesh_repair(ctx, c, &o, &r), LIMN_OK);
        if (r.duplicate_faces != count || (count && (r.first_duplicate_face != first ||
                                                     r.first_duplicate_of != of)))
            fail_msg("%s, %d threads: %zu duplicates (first %zu of %zu), brute force %zu "
                     "(first %zu of %zu)",
                     what, threads[t], r.duplicate_faces, r.first_duplicate_face,
                     r.first_duplicate_of, count, first, of);
        assert_int_equal(c->face_count, nf - count);
        size_t kept = 0;
        for (size_t f = 0; f < nf; f++) {
            if (dup[f])
                continue;
            uint32_t b = m->face_offsets[f], d = m->face_offsets[f + 1] - b;
            assert_int_equal(c->face_offsets[kept + 1] - c->face_offsets[kept], d);
            assert_memory_equal(c->face_indices + c->face_offsets[kept], m->face_indices + b,
                                d * sizeof(uint32_t));
            kept++;
        }
        limn_mesh_destroy(c);
    }
    free(dup);
    return count;
}

/* -------------------------------------------------------------- the meshes */

static uint32_t lcg(uint64_t *s)
{
    *s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
    return (uint32_t)(*s >> 33);
}

/* nf faces over nv vertices: random faces of distinct vertices (3 to 6
   corners, now and then 40), and about a third copies of an earlier face,
   rotated, reversed or shuffled. */
static limn_mesh *copies_mesh(limn_context *ctx, size_t nv, size_t nf, uint64_t seed)
{
    uint32_t *off = malloc((nf + 1) * sizeof *off), *idx = malloc(nf * 40 * sizeof *idx);
    double *pos = calloc(3 * nv, sizeof *pos);
    assert_non_null(off);
    assert_non_null(idx);
    assert_non_null(pos);
    off[0] = 0;
    for (size_t f = 0; f < nf; f++) {
        uint32_t *v = idx + off[f], d;
        if (f > 0 && lcg(&seed) % 3 == 0) {
            size_t g = lcg(&seed) % f;
            d = off[g + 1] - off[g];
            uint32_t rot = lcg(&seed) % d, how = lcg(&seed) % 3;
            for (uint32_t i = 0; i < d; i++)
                v[i] = idx[off[g] + (how == 1 ? (rot + d - i) % d : (rot + i) % d)];
            for (uint32_t i = d - 1; how == 2 && i > 0; i--) {
                uint32_t j = lcg(&seed) % (i + 1), x = v[i];
                v[i] = v[j];
                v[j] = x;
            }
        } else {
            d = lcg(&seed) % 50 == 0 ? 40 : 3 + lcg(&seed) % 4;
            for (uint32_t i = 0; i < d; i++) {
                uint32_t x, again;
                do {
                    x = lcg(&seed) % (uint32_t)nv;
                    again = 0;
                    for (uint32_t k = 0; k < i; k++)
                        again |= v[k] == x;
                } while (again);
                v[i] = x;
            }
        }
        off[f + 1] = off[f] + d;
    }
    limn_mesh *m = NULL;
    assert_int_equal(limn_mesh_create(ctx, nv, pos, nf, off, idx, &m), LIMN_OK);
    free(off);
    free(idx);
    free(pos);
    return m;
}

static void generated_copies(void **state)
{
    limn_context *ctx = *state;
    /* few vertices: many sets alike in their first vertices; many faces:
       buckets of thousands, long probes */
    limn_mesh *m = copies_mesh(ctx, 300, 200000, 7);
    assert_true(check_mesh(ctx, m, "200k faces over 300 vertices") > 60000);
    limn_mesh_destroy(m);
    m = copies_mesh(ctx, 100000, 30000, 11);
    assert_true(check_mesh(ctx, m, "30k faces over 100k vertices") > 9000);
    limn_mesh_destroy(m);
    m = copies_mesh(ctx, 10, 2, 3); /* two faces: fewer faces than threads */
    check_mesh(ctx, m, "two faces");
    limn_mesh_destroy(m);
}

static void shared_meshes(void **state)
{
    limn_context *ctx = *state;
    if (!test_shared_meshes())
        skip();
    static const char *subs[] = {"small", "medium", "opensubdiv", "large"};
    int checked = 0;
    for (int s = 0; s < 4; s++) {
        const char *names[64];
        size_t n = test_list_meshes(subs[s], names, 64);
        for (size_t i = 0; i < n; i++) {
            limn_mesh *m = NULL;
            if (limn_mesh_read(ctx, test_shared_path(names[i]), LIMN_FORMAT_AUTO, &m) != LIMN_OK)
                continue;
            /* the repair fixes repeated vertices first: the oracle sees the faces after it */
            limn_repair_report r = {.size = sizeof r};
            if (limn_mesh_repair(ctx, m, NULL, &r) == LIMN_OK) {
                check_mesh(ctx, m, names[i]);
                checked++;
            }
            limn_mesh_destroy(m);
        }
    }
    printf("  %d shared meshes as brute force\n", checked);
    assert_true(checked >= 30);
}

TEST_MAIN(NULL, NULL, CONTEXT_TEST(generated_copies), CONTEXT_TEST(shared_meshes))
