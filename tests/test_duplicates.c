/* SPDX-License-Identifier: MIT */
/*
 * The repair's duplicate faces (topology/face_keys.c: hashed buckets and a
 * table per bucket) against brute force: every face's sorted vertex list
 * sorted with qsort, each run of equal lists a face and its later copies.
 * The count, the first copy and the face it copies, and the faces left
 * after --drop-duplicate-faces, for 1, 2 and 4 host threads, on a generated
 * mesh full of copies (rotated, reversed, shuffled, faces of 3 to 40
 * corners) and on every shared mesh; the search skipped only where the
 * topology's counts rule copies out (closed triangle and quad meshes), never
 * where a copy hides (every order of a face added to a closed mesh, pillows).
 */
#include "support.h"
#include "mesh/mesh.h"
#include "topology/topology.h"

#include <math.h>
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

/* m with one more face: face 0's vertices in the order `order` gives
   (indices into face 0, -1 ending it). */
static limn_mesh *with_copy(limn_context *ctx, limn_mesh *m, const int *order)
{
    size_t nf = m->face_count, nc = m->face_offsets[nf], d = 0;
    while (order[d] >= 0)
        d++;
    uint32_t *off = malloc((nf + 2) * sizeof *off), *idx = malloc((nc + d) * sizeof *idx);
    assert_non_null(off);
    assert_non_null(idx);
    memcpy(off, m->face_offsets, (nf + 1) * sizeof *off);
    memcpy(idx, m->face_indices, nc * sizeof *idx);
    for (size_t i = 0; i < d; i++)
        idx[nc + i] = m->face_indices[m->face_offsets[0] + (size_t)order[i]];
    off[nf + 1] = (uint32_t)(nc + d);
    limn_mesh *c = NULL;
    assert_int_equal(limn_mesh_create(ctx, m->vertex_count, m->positions, nf + 1, off, idx, &c),
                     LIMN_OK);
    free(off);
    free(idx);
    limn_mesh_destroy(m);
    return c;
}

/* Whether the counts let the repair skip the search (topology.h says why). */
static int skips_search(limn_context *ctx, const limn_mesh *m)
{
    topology_counts k;
    assert_int_equal(topology_census(ctx, m, &k), LIMN_OK);
    return topology_counts_no_duplicates(&k);
}

/* The repair skips the duplicate search where the counts rule copies out:
   on closed triangle and quad meshes it must; a copy of a face in any order,
   on its own (a pillow) or added to a closed mesh, must stop the skip, and
   the search then finds it (brute force agrees). */
static void skipped_search(void **state)
{
    limn_context *ctx = *state;
    limn_mesh *closed[] = {test_mesh_icosahedron(ctx), test_mesh_cube(ctx)};
    for (int i = 0; i < 2; i++) {
        assert_true(skips_search(ctx, closed[i]));
        assert_int_equal(check_mesh(ctx, closed[i], "closed"), 0);
        limn_mesh_destroy(closed[i]);
    }
    /* every order of face 0 (up to the rotation that keeps it the same cycle) */
    static const int orders[][5] = {
        {0, 1, 2, -1}, {1, 2, 0, -1}, {0, 2, 1, -1}, {2, 1, 0, -1},               /* triangle */
        {0, 1, 2, 3, -1}, {3, 2, 1, 0, -1}, {0, 1, 3, 2, -1}, {0, 2, 1, 3, -1}, /* quad */
        {0, 2, 3, 1, -1}, {0, 3, 1, 2, -1}, {1, 2, 3, 0, -1}, {2, 0, 3, 1, -1}};
    char what[64];
    for (size_t i = 0; i < sizeof orders / sizeof *orders; i++) {
        int quad = orders[i][3] >= 0;
        limn_mesh *m = with_copy(ctx, quad ? test_mesh_cube(ctx) : test_mesh_icosahedron(ctx),
                                 orders[i]);
        assert_false(skips_search(ctx, m));
        snprintf(what, sizeof what, "%s + copy %zu", quad ? "cube" : "icosahedron", i);
        assert_int_equal(check_mesh(ctx, m, what), 1);
        limn_mesh_destroy(m);
    }
    /* pillows: a triangle and a quad with their reversed copies, alone */
    static const double pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
    static const uint32_t off3[] = {0, 3, 6}, idx3[] = {0, 1, 2, 2, 1, 0};
    static const uint32_t off4[] = {0, 4, 8}, idx4[] = {0, 1, 3, 2, 2, 3, 1, 0};
    limn_mesh *p3 = NULL, *p4 = NULL;
    assert_int_equal(limn_mesh_create(ctx, 3, pos, 2, off3, idx3, &p3), LIMN_OK);
    assert_int_equal(limn_mesh_create(ctx, 4, pos, 2, off4, idx4, &p4), LIMN_OK);
    assert_false(skips_search(ctx, p3));
    assert_false(skips_search(ctx, p4));
    assert_int_equal(check_mesh(ctx, p3, "triangle pillow"), 1);
    assert_int_equal(check_mesh(ctx, p4, "quad pillow"), 1);
    limn_mesh_destroy(p3);
    limn_mesh_destroy(p4);
    /* a ring of six quads one quad wide (each vertex 3 neighbours), quad 0
       copied in each order: its edges on the ring's two boundary loops are used
       by the copy alone or in its own direction, so no edge has three faces;
       only the orientation (fans ended at an edge used twice the same way)
       stops the skip */
    double ring_pos[36];
    uint32_t ring_off[7], ring_idx[24];
    for (uint32_t k = 0; k < 6; k++) {
        double a = k * 3.14159265358979323846 / 3.0;
        for (uint32_t up = 0; up < 2; up++) {
            ring_pos[3 * (k + 6 * up)] = cos(a);
            ring_pos[3 * (k + 6 * up) + 1] = sin(a);
            ring_pos[3 * (k + 6 * up) + 2] = up;
        }
        uint32_t q[4] = {k, (k + 1) % 6, 6 + (k + 1) % 6, 6 + k};
        memcpy(ring_idx + 4 * k, q, sizeof q);
        ring_off[k] = 4 * k;
    }
    ring_off[6] = 24;
    for (size_t i = 4; i < sizeof orders / sizeof *orders; i++) {
        limn_mesh *m = NULL;
        assert_int_equal(limn_mesh_create(ctx, 12, ring_pos, 6, ring_off, ring_idx, &m), LIMN_OK);
        assert_true(skips_search(ctx, m));
        m = with_copy(ctx, m, orders[i]);
        assert_false(skips_search(ctx, m));
        snprintf(what, sizeof what, "ring + copy %zu", i);
        assert_int_equal(check_mesh(ctx, m, what), 1);
        limn_mesh_destroy(m);
    }
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

TEST_MAIN(NULL, NULL, CONTEXT_TEST(generated_copies), CONTEXT_TEST(skipped_search),
          CONTEXT_TEST(shared_meshes))
