/* SPDX-License-Identifier: MIT */
/*
 * Limit masks against brute-force refinement: limn's limit position of every
 * vertex (A P) must equal where repeated uniform subdivision (an independent
 * implementation in tests/oracle/refine_oracle.c) sends that vertex.
 *
 * Tolerance: the refined position of a vertex converges geometrically; with a
 * ratio r <= 3/4 per level (1/4..1/2 for these schemes), the distance to the
 * limit after L levels is at most r/(1-r) * |V_L - V_{L-1}| <= 3 |V_L - V_{L-1}|.
 * The test asserts |limn - V_L| <= 3 |V_L - V_{L-1}| + 1e-12 diag, and that the
 * bound itself is tight (< 1e-4 diag), so a wrong weight cannot hide in it.
 * Positions are perturbed pseudo-randomly so that equal limits imply equal
 * mask rows.
 */
#include "support.h"
#include "refine_oracle.h"
#include "scheme/scheme.h"
#include "scheme/scheme_refine.h"
#include "stencil/stencil.h"
#include "topology/topology.h"
#include "mesh/mesh.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

static double *refine(const limn_mesh *m, int scheme, double alpha, int levels)
{
    int *sizes, *idx, onv, onf, *osz, *oidx;
    double *opos;
    char err[256];
    test_oracle_faces(m, &sizes, &idx);
    int rc = refine_oracle(scheme, alpha, levels, (int)limn_mesh_vertex_count(m),
                           limn_mesh_positions(m), (int)limn_mesh_face_count(m), sizes, idx, &onv,
                           &opos, &onf, &osz, &oidx, err, sizeof err);
    if (rc)
        fail_msg("refine_oracle: %s", err);
    free(sizes);
    free(idx);
    free(osz);
    free(oidx);
    return opos;
}

static void check(const char *name, limn_mesh *m, limn_scheme scheme, double alpha, int levels)
{
    limn_context *ctx = limn_context_create();
    assert_int_equal(limn_context_set_device(ctx, "reference"), LIMN_OK);
    size_t n = limn_mesh_vertex_count(m);
    double *lim = malloc(3 * n * sizeof *lim);
    if (limn_limit_positions(ctx, m, scheme, alpha, lim) != LIMN_OK)
        fail_msg("%s: %s", name, limn_context_message(ctx));
    int os = scheme == LIMN_SCHEME_LOOP ? 0 : 1;
    double *fine = refine(m, os, alpha, levels), *coarse = refine(m, os, alpha, levels - 1);
    double diag = test_bbox_diagonal(m), worst = 0, worst_est = 0;
    for (size_t i = 0; i < n; i++) {
        double d = 0, e = 0;
        for (int c = 0; c < 3; c++) {
            d += pow(lim[3 * i + c] - fine[3 * i + c], 2);
            e += pow(fine[3 * i + c] - coarse[3 * i + c], 2);
        }
        d = sqrt(d);
        e = sqrt(e);
        worst = fmax(worst, d / diag);
        worst_est = fmax(worst_est, e / diag);
        if (d > 3 * e + 1e-12 * diag)
            fail_msg("%s (%s, alpha %g): vertex %zu is %.3g from the %d-level refinement, "
                     "whose own step is %.3g",
                     name, limn_scheme_name(scheme), alpha, i, d, levels, e);
    }
    assert_true(worst_est < 1e-4);
    printf("  %-22s %-7s alpha %.1f: %zu vertices, max |limn - V_%d| %.2e diag (last step %.2e)\n",
           name, limn_scheme_name(scheme), alpha, n, levels, worst, worst_est);
    free(lim);
    free(fine);
    free(coarse);
    limn_context_destroy(ctx);
}

typedef limn_mesh *(*maker)(limn_context *);
static limn_mesh *grid_quads(limn_context *c) { return test_mesh_grid(c, 4, 3, 0); }
static limn_mesh *grid_tris(limn_context *c) { return test_mesh_grid(c, 4, 3, 1); }
static limn_mesh *fan5_quads(limn_context *c) { return test_mesh_fan(c, 5, 0); }
static limn_mesh *fan3_quads(limn_context *c) { return test_mesh_fan(c, 3, 0); }
static limn_mesh *fan7_tris(limn_context *c) { return test_mesh_fan(c, 7, 1); }
static limn_mesh *fan4_tris(limn_context *c) { return test_mesh_fan(c, 4, 1); }

static void run(const char *name, maker make, limn_scheme scheme, double alpha, int levels)
{
    limn_context *ctx = limn_context_create();
    limn_mesh *m = make(ctx);
    assert_non_null(m);
    test_perturb(m, 0.05, 7);
    check(name, m, scheme, alpha, levels);
    limn_mesh_destroy(m);
    limn_context_destroy(ctx);
}

/* A mesh and the levels it is checked at. */
typedef struct mask_case {
    const char *name;
    maker make;
    int levels;
} mask_case;

/* Catmull-Clark: valence 3 (cube), 4 with triangles (pyramid apex), regular
   interior / boundary / corner (grid), valence 5 and 3 interior with boundary. */
static const mask_case catmark_cases[] = {
    {"cube", test_mesh_cube, 9},
    {"pyramid", test_mesh_pyramid, 9},
    {"quad grid 4x3", grid_quads, 8},
    {"quad fan valence 5", fan5_quads, 8},
    {"quad fan valence 3", fan3_quads, 8},
};

static void run_cases(const mask_case *cases, size_t n, limn_scheme scheme, double alpha)
{
    for (size_t i = 0; i < n; i++)
        run(cases[i].name, cases[i].make, scheme, alpha, cases[i].levels);
}

static void catmark_alpha0(void **s)
{
    (void)s;
    run_cases(catmark_cases, sizeof catmark_cases / sizeof *catmark_cases, LIMN_SCHEME_CATMARK,
              0.0);
    run("triangles under CC", grid_tris, LIMN_SCHEME_CATMARK, 0.0, 8);
}

/* alpha applies at the first refinement step only (DESIGN.md §1). */
static void catmark_alpha_half(void **s)
{
    (void)s;
    run_cases(catmark_cases, sizeof catmark_cases / sizeof *catmark_cases, LIMN_SCHEME_CATMARK,
              0.5);
}

static void loop_masks(void **s)
{
    (void)s;
    static const mask_case cases[] = {
        {"icosahedron", test_mesh_icosahedron, 9},
        {"triangle grid 4x3", grid_tris, 8},
        {"triangle fan valence 7", fan7_tris, 9},
        {"triangle fan valence 4", fan4_tris, 9},
    };
    run_cases(cases, sizeof cases / sizeof *cases, LIMN_SCHEME_LOOP, 0.0);
}

/* The shared n-gon mesh with boundaries (OpenSubdiv's catmark_nonquads). */
static void shared_ngons(void **s)
{
    (void)s;
    if (!test_shared_meshes())
        skip();
    limn_context *ctx = limn_context_create();
    /* catmark_val2_interior: interior valence-2 vertices, where OpenSubdiv's
       limit mask differs */
    static const char *const names[] = {"catmark_nonquads", "catmark_val2_interior"};
    for (size_t i = 0; i < sizeof names / sizeof *names; i++) {
        char rel[64];
        snprintf(rel, sizeof rel, "opensubdiv/%s.obj", names[i]);
        limn_mesh *m = test_read_shared(ctx, rel);
        check(names[i], m, LIMN_SCHEME_CATMARK, 0.0, 8);
        check(names[i], m, LIMN_SCHEME_CATMARK, 0.5, 8);
        limn_mesh_destroy(m);
    }
    limn_context_destroy(ctx);
}

/* Every row of the stencil sums to 1 (affine invariance). */
static void rows_sum_to_one(const stencil_csr *a)
{
    for (size_t r = 0; r < a->rows; r++) {
        double sum = 0;
        for (uint32_t k = a->row_offsets[r]; k < a->row_offsets[r + 1]; k++)
            sum += a->weights[k];
        assert_true(fabs(sum - 1.0) < 1e-14);
    }
}

/* Closed forms of DESIGN.md §1 read straight off the CSR rows. */
static void closed_form_rows(void **s)
{
    assert_true(fabs(scheme_loop_limit_beta(3) - 0.4) < 1e-15);
    assert_true(fabs(scheme_loop_limit_beta(4) - 0.4364) < 1e-4);
    assert_true(fabs(scheme_loop_limit_beta(6) - 0.5) < 1e-15);
    /* the table of Loop's cos term is the formula's values: equal on glibc
       (whose cos rounds correctly), within one unit in the last place on any
       libm; past the table, the formula itself */
    for (uint32_t n = 1; n <= 40; n++) {
        double table = scheme_loop_cos_term(n), formula = scheme_loop_cos_term_formula(n);
        assert_true(table == formula || nextafter(formula, table) == table);
    }
    assert_true(scheme_loop_cos_term(6) == 0.5 && scheme_loop_cos_term(4) == 0.375);

    limn_context *ctx = *s;
    limn_mesh *g = test_mesh_grid(ctx, 4, 4, 0);
    topology t;
    stencil_csr a;
    assert_int_equal(topology_build(ctx, g, &t), LIMN_OK);
    assert_int_equal(stencil_limit_build(ctx, &t, LIMN_SCHEME_CATMARK, 0.0, &a), LIMN_OK);
    /* interior vertex (2,2) = 12: 16/36 itself, 4/36 edge neighbours, 1/36 diagonals */
    uint32_t v = 12;
    for (uint32_t k = a.row_offsets[v]; k < a.row_offsets[v + 1]; k++) {
        uint32_t c = a.columns[k];
        int dx = abs((int)(c % 5) - 2), dy = abs((int)(c / 5) - 2);
        double want = dx + dy == 0 ? 16.0 / 36 : dx + dy == 1 ? 4.0 / 36 : 1.0 / 36;
        assert_true(fabs(a.weights[k] - want) < 1e-15);
    }
    assert_int_equal(a.row_offsets[v + 1] - a.row_offsets[v], 9);
    /* boundary vertex 2 (bottom edge): (1, 4, 1) / 6 along the boundary */
    v = 2;
    assert_int_equal(a.row_offsets[v + 1] - a.row_offsets[v], 3);
    for (uint32_t k = a.row_offsets[v]; k < a.row_offsets[v + 1]; k++)
        assert_true(fabs(a.weights[k] - (a.columns[k] == v ? 4.0 / 6 : 1.0 / 6)) < 1e-15);
    /* corner vertex 0 is pinned */
    assert_int_equal(a.row_offsets[1] - a.row_offsets[0], 1);
    assert_true(a.weights[0] == 1.0);
    /* every row sums to 1 (affine invariance) */
    rows_sum_to_one(&a);
    stencil_free(&a);
    /* general alpha: rows of a valence-3 cube vertex with alpha = 0.5 sum to 1 */
    limn_mesh *cube = test_mesh_cube(ctx);
    topology tc;
    assert_int_equal(topology_build(ctx, cube, &tc), LIMN_OK);
    assert_int_equal(stencil_limit_build(ctx, &tc, LIMN_SCHEME_CATMARK, 0.5, &a), LIMN_OK);
    rows_sum_to_one(&a);
    stencil_free(&a);
    topology_free(&tc);
    topology_free(&t);
    limn_mesh_destroy(cube);
    limn_mesh_destroy(g);
}

TEST_MAIN(NULL, NULL, CONTEXT_TEST(closed_form_rows), cmocka_unit_test(catmark_alpha0),
          cmocka_unit_test(catmark_alpha_half), cmocka_unit_test(loop_masks),
          cmocka_unit_test(shared_ngons))
