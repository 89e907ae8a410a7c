/* SPDX-License-Identifier: MIT */
/*
 * The parallel stencil builder (host/stencil/stencil.c) against the
 * sequential one it replaced, kept here as the oracle: the same row_offsets,
 * columns and weights byte for byte (memcmp) with 1, 2 and 4 host threads,
 * for limit tables (Loop, Catmull-Clark alpha 0 and 0.5) of generated and
 * shared meshes, RCM-permuted tables, and synthetic rows whose fills repeat
 * columns, leave slack under their bounds and are empty, so that the ranges'
 * blocks move down by different amounts.
 */
#include "support.h"

#include "scheme/scheme.h"
#include "scheme/scheme_refine.h"
#include "stencil/reorder.h"
#include "stencil/stencil.h"
#include "topology/topology.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

/* ------------------------------------------------ the previous builder */

static size_t oracle_sort_merge(uint32_t *cols, double *w, size_t n)
{
    for (size_t i = 1; i < n; i++) {
        uint32_t c = cols[i];
        double x = w[i];
        size_t j = i;
        while (j > 0 && cols[j - 1] > c) {
            cols[j] = cols[j - 1];
            w[j] = w[j - 1];
            j--;
        }
        cols[j] = c;
        w[j] = x;
    }
    size_t m = 0;
    for (size_t i = 0; i < n; i++) {
        if (m > 0 && cols[m - 1] == cols[i]) {
            w[m - 1] += w[i];
        } else {
            cols[m] = cols[i];
            w[m] = w[i];
            m++;
        }
    }
    return m;
}

/* One row after another into one bound-sized block (the builder before issue 13). */
static void oracle_build(size_t rows, size_t cols, stencil_row_bound bound,
                         stencil_row_fill fill, const void *user, stencil_csr *out)
{
    memset(out, 0, sizeof *out);
    size_t total = 0;
    for (size_t r = 0; r < rows; r++)
        total += bound(user, r);
    out->rows = rows;
    out->cols = cols;
    out->row_offsets = malloc((rows + 1) * sizeof *out->row_offsets);
    out->columns = malloc((total ? total : 1) * sizeof *out->columns);
    out->weights = malloc((total ? total : 1) * sizeof *out->weights);
    assert_non_null(out->row_offsets);
    assert_non_null(out->columns);
    assert_non_null(out->weights);
    size_t k = 0;
    out->row_offsets[0] = 0;
    for (size_t r = 0; r < rows; r++) {
        size_t n = fill(user, r, out->columns + k, out->weights + k);
        k += oracle_sort_merge(out->columns + k, out->weights + k, n);
        out->row_offsets[r + 1] = (uint32_t)k;
    }
}

static void assert_same_table(const char *what, int threads, const stencil_csr *a,
                              const stencil_csr *b)
{
    assert_int_equal(a->rows, b->rows);
    assert_int_equal(a->cols, b->cols);
    if (memcmp(a->row_offsets, b->row_offsets, (a->rows + 1) * sizeof *a->row_offsets))
        fail_msg("%s, %d host threads: row_offsets differ from the sequential builder's", what,
                 threads);
    size_t nnz = a->row_offsets[a->rows];
    if (memcmp(a->columns, b->columns, nnz * sizeof *a->columns) ||
        memcmp(a->weights, b->weights, nnz * sizeof *a->weights))
        fail_msg("%s, %d host threads: entries differ from the sequential builder's", what,
                 threads);
}

static const int thread_counts[] = {1, 2, 4};

/* ------------------------------------------------------- limit tables */

typedef struct limit_user {
    const topology *t;
    limn_scheme scheme;
    double alpha;
} limit_user;

static size_t limit_bound(const void *user, size_t r)
{
    const limit_user *u = user;
    return scheme_limit_mask_bound(u->t, u->scheme, (uint32_t)r);
}

static size_t limit_fill(const void *user, size_t r, uint32_t *cols, double *w)
{
    const limit_user *u = user;
    size_t n = scheme_limit_mask(u->t, u->scheme, u->alpha, (uint32_t)r, cols, w);
    /* the bound holds every row, and is exact for smooth ones */
    size_t bound = scheme_limit_mask_bound(u->t, u->scheme, (uint32_t)r);
    assert_true(n <= bound);
    if (u->t->vertex_rule[r] == RULE_SMOOTH)
        assert_int_equal(n, bound);
    return n;
}

/* P A P^T with each row's entries in their input order (columns renamed):
   what stencil_permute must give, so that a permuted row sums as the input
   row does. */
static void oracle_permute(const stencil_csr *a, const uint32_t *order, const uint32_t *rank,
                           stencil_csr *out)
{
    size_t n = a->rows, nnz = a->row_offsets[n], e = 0;
    out->rows = n;
    out->cols = a->cols;
    out->row_offsets = malloc((n + 1) * sizeof *out->row_offsets);
    out->columns = malloc((nnz ? nnz : 1) * sizeof *out->columns);
    out->weights = malloc((nnz ? nnz : 1) * sizeof *out->weights);
    assert_non_null(out->row_offsets);
    assert_non_null(out->columns);
    assert_non_null(out->weights);
    out->row_offsets[0] = 0;
    for (size_t k = 0; k < n; k++) {
        for (uint32_t i = a->row_offsets[order[k]]; i < a->row_offsets[order[k] + 1]; i++, e++) {
            out->columns[e] = rank[a->columns[i]];
            out->weights[e] = a->weights[i];
        }
        out->row_offsets[k + 1] = (uint32_t)e;
    }
}

/* The limit table and its RCM permutation, each thread count against the oracle. */
/* The refinement masks stay within their bounds, exactly at smooth vertices
   and at edges between two faces. */
static void check_refine_bounds(const topology *t, limn_scheme scheme, double alpha)
{
    size_t room = 16 + 2 * t->max_valence * (t->max_face_size + 1);
    uint32_t *cols = malloc(room * sizeof *cols);
    double *w = malloc(room * sizeof *w);
    assert_non_null(cols);
    assert_non_null(w);
    for (uint32_t v = 0; v < t->vertex_count; v++) {
        size_t bound = scheme_refine_vertex_bound(t, scheme, v);
        assert_true(bound <= room);
        size_t n = scheme_refine_vertex_mask(t, scheme, alpha, v, cols, w);
        assert_true(n <= bound);
        if (t->vertex_rule[v] == RULE_SMOOTH)
            assert_int_equal(n, bound);
    }
    for (uint32_t e = 0; e < t->edge_count; e++) {
        size_t bound = scheme_refine_edge_bound(t, scheme, e);
        size_t n = scheme_refine_edge_mask(t, scheme, e, cols, w);
        assert_true(n <= bound);
        if (!(t->edge_flags[e] & (EDGE_BOUNDARY | EDGE_NONMANIFOLD)))
            assert_int_equal(n, bound);
    }
    free(cols);
    free(w);
}

static void check_mesh(limn_context *ctx, const char *name, const limn_mesh *mesh,
                       limn_scheme scheme, double alpha)
{
    topology t;
    if (topology_build(ctx, mesh, &t))
        fail_msg("%s: %s", name, limn_context_message(ctx));
    check_refine_bounds(&t, scheme, alpha);
    limit_user lu = {&t, scheme, alpha};
    stencil_csr want, want_p;
    oracle_build(t.vertex_count, t.vertex_count, limit_bound, limit_fill, &lu, &want);
    uint32_t *order = NULL, *rank = NULL;
    assert_int_equal(reorder_rcm(ctx, &t, &order, &rank), LIMN_OK);
    oracle_permute(&want, order, rank, &want_p);
    for (size_t i = 0; i < sizeof thread_counts / sizeof *thread_counts; i++) {
        assert_int_equal(limn_context_set_host_threads(ctx, thread_counts[i]), LIMN_OK);
        stencil_csr got, got_p;
        if (stencil_limit_build(ctx, &t, scheme, alpha, &got) ||
            stencil_permute(ctx, &got, order, rank, &got_p))
            fail_msg("%s: %s", name, limn_context_message(ctx));
        assert_same_table(name, thread_counts[i], &got, &want);
        assert_same_table(name, thread_counts[i], &got_p, &want_p);
        stencil_free(&got);
        stencil_free(&got_p);
    }
    printf("  %-40s %-7s alpha %.1f: %zu rows, %u entries, same bytes for 1, 2, 4 threads\n",
           name, limn_scheme_name(scheme), alpha, want.rows, want.row_offsets[want.rows]);
    assert_int_equal(limn_context_set_host_threads(ctx, 0), LIMN_OK);
    stencil_free(&want);
    stencil_free(&want_p);
    free(order);
    free(rank);
    topology_free(&t);
}

static void generated(void **st)
{
    limn_context *ctx = *st;
    /* 160k and 102k rows: four ranges at one thread per 4 MiB of work */
    limn_mesh *tri = test_keep_mesh(test_mesh_grid(ctx, 400, 400, 1));
    limn_mesh *quad = test_keep_mesh(test_mesh_grid(ctx, 320, 320, 0));
    limn_mesh *pyr = test_keep_mesh(test_mesh_pyramid(ctx));
    check_mesh(ctx, "triangle grid 400 x 400", tri, LIMN_SCHEME_LOOP, 0.0);
    check_mesh(ctx, "quad grid 320 x 320", quad, LIMN_SCHEME_CATMARK, 0.0);
    check_mesh(ctx, "quad grid 320 x 320", quad, LIMN_SCHEME_CATMARK, 0.5);
    check_mesh(ctx, "pyramid (mixed faces)", pyr, LIMN_SCHEME_CATMARK, 0.0);
}

static void shared(void **st)
{
    if (!test_shared_meshes())
        skip();
    static const struct {
        const char *path;
        limn_scheme scheme;
        double alpha;
    } real[] = {{"large/igea.ply", LIMN_SCHEME_LOOP, 0.0},
                {"large/dragon_vrip_res2.ply", LIMN_SCHEME_LOOP, 0.0},
                {"medium/bob_quad.obj", LIMN_SCHEME_CATMARK, 0.5},
                {"medium/bun_zipper.ply", LIMN_SCHEME_LOOP, 0.0},    /* holes, unreferenced */
                {"medium/horse.ply", LIMN_SCHEME_CATMARK, 0.0},
                {"small/bun_zipper_res4.ply", LIMN_SCHEME_LOOP, 0.0}, /* non-manifold */
                {"opensubdiv/catmark_nonman_edges.obj", LIMN_SCHEME_CATMARK, 0.5},
                {"opensubdiv/loop_nonman_edges.obj", LIMN_SCHEME_LOOP, 0.0}};
    limn_context *ctx = *st;
    for (size_t k = 0; k < sizeof real / sizeof *real; k++) {
        limn_mesh *m = NULL;
        if (limn_mesh_read(ctx, test_shared_path(real[k].path), LIMN_FORMAT_AUTO, &m) != LIMN_OK)
            continue; /* a mesh the shared set may not have */
        test_keep_mesh(m);
        assert_int_equal(limn_mesh_repair(ctx, m, NULL, NULL), LIMN_OK);
        check_mesh(ctx, real[k].path, m, real[k].scheme, real[k].alpha);
    }
}

/* ------------------------------------------------------ synthetic rows */

/* Row r: bound 0-11 entries, filled with up to that many columns drawn from
   a small set around r (so repeats merge), every seventh row empty. */
static uint32_t mix(size_t r)
{
    unsigned long long s = (unsigned long long)r * 6364136223846793005ULL + 1442695040888963407ULL;
    return (uint32_t)(s >> 33);
}

static size_t synthetic_bound(const void *user, size_t r)
{
    (void)user;
    return r % 7 == 0 ? 0 : 1 + mix(r) % 11;
}

static size_t synthetic_fill(const void *user, size_t r, uint32_t *cols, double *w)
{
    size_t cap = synthetic_bound(user, r), n = cap ? mix(r + 1) % (cap + 1) : 0;
    for (size_t i = 0; i < n; i++) {
        cols[i] = (uint32_t)((r + mix(r * 13 + i) % 5) % 300000);
        w[i] = 1.0 / (double)(1 + (mix(r * 29 + i) % 97));
    }
    return n;
}

static void synthetic(void **st)
{
    limn_context *ctx = *st;
    static const size_t sizes[] = {0, 1, 5, 300000};
    for (size_t s = 0; s < sizeof sizes / sizeof *sizes; s++) {
        stencil_csr want;
        oracle_build(sizes[s], 300000, synthetic_bound, synthetic_fill, NULL, &want);
        for (size_t i = 0; i < sizeof thread_counts / sizeof *thread_counts; i++) {
            assert_int_equal(limn_context_set_host_threads(ctx, thread_counts[i]), LIMN_OK);
            stencil_csr got;
            assert_int_equal(stencil_build(ctx, sizes[s], 300000, synthetic_bound,
                                           synthetic_fill, NULL, &got),
                             LIMN_OK);
            assert_same_table("synthetic rows", thread_counts[i], &got, &want);
            stencil_free(&got);
        }
        stencil_free(&want);
    }
}

TEST_MAIN(NULL, NULL, CONTEXT_TEST(generated), CONTEXT_TEST(shared), CONTEXT_TEST(synthetic))
