/* SPDX-License-Identifier: MIT */
/*
 * Interpolation end to end: after limn_interpolate, the limit of the control
 * mesh P, computed by an independent route, reproduces M to the tolerance.
 *  - alpha = 0 (Catmull-Clark) and Loop: OpenSubdiv's limit of P;
 *  - alpha = 0.5: one alpha-step of the brute-force refinement oracle, then
 *    OpenSubdiv's (standard) limit of that level-1 mesh (DESIGN.md §1).
 * On every small and medium shared mesh the scheme accepts, plus the embedded
 * Spot. Interior valence-2 vertices are left out of the OpenSubdiv route (its
 * limit mask differs there, see test_osd_limit.c).
 * Also: the singular alpha = 0 cube, the iteration cap, bad options; the
 * control mesh's faces and colours against the input's (its positions are the
 * solve's rows made positions in place: mesh_rows4_to_xyz against a plain
 * strided copy).
 */
#include "support.h"
#include "osd_oracle.h"
#include "refine_oracle.h"
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

/* Limit of P by the independent route; returns 0 if the oracle refuses. */
static int oracle_limit(const limn_mesh *p, limn_scheme scheme, double alpha, double *out)
{
    int n = (int)limn_mesh_vertex_count(p), nf = (int)limn_mesh_face_count(p);
    int *sizes, *idx;
    char err[512];
    test_oracle_faces(p, &sizes, &idx);
    int rc;
    if (alpha == 0.0) {
        rc = osd_oracle_limit(scheme == LIMN_SCHEME_LOOP ? 0 : 1, n, limn_mesh_positions(p), nf,
                              sizes, idx, out, err, sizeof err);
    } else {
        int n1, f1, *s1, *i1;
        double *p1;
        rc = refine_oracle(1, alpha, 1, n, limn_mesh_positions(p), nf, sizes, idx, &n1, &p1, &f1,
                           &s1, &i1, err, sizeof err);
        if (rc == 0) {
            double *lim1 = malloc(3 * (size_t)n1 * sizeof *lim1);
            rc = osd_oracle_limit(1, n1, p1, f1, s1, i1, lim1, err, sizeof err);
            memcpy(out, lim1, 3 * (size_t)n * sizeof *out); /* vertex i of level 1 is vertex i */
            free(lim1);
            free(p1);
            free(s1);
            free(i1);
        }
    }
    free(sizes);
    free(idx);
    return rc == 0;
}

static limn_method test_method = LIMN_METHOD_AUTO;
static double last_products;

static void check_mesh(limn_context *ctx, const char *name, const limn_mesh *m, limn_scheme scheme,
                       double alpha)
{
    limn_interpolate_options o;
    limn_interpolate_options_default(&o);
    o.method = test_method;
    o.scheme = scheme;
    o.alpha = alpha;
    limn_mesh *p = NULL;
    limn_report r = {.size = sizeof r};
    if (limn_interpolate(ctx, m, &o, &p, &r) != LIMN_OK)
        fail_msg("%s (%s, alpha %g): %s", name, limn_scheme_name(scheme), alpha,
                 limn_context_message(ctx));
    assert_true(r.max_rel_error <= o.tolerance);
    last_products = r.products;
    size_t n = limn_mesh_vertex_count(m);
    double *lim = malloc(3 * n * sizeof *lim);
    if (!oracle_limit(p, scheme, alpha, lim)) {
        printf("  %-36s %-7s alpha %.1f: oracle refuses this mesh (non-manifold)\n", name,
               limn_scheme_name(scheme), alpha);
        free(lim);
        limn_mesh_destroy(p);
        return;
    }
    topology t;
    assert_int_equal(topology_build(ctx, m, &t), LIMN_OK);
    double diag = test_bbox_diagonal(m), worst = 0, scale = 1;
    const double *mp = limn_mesh_positions(m), *pp = limn_mesh_positions(p);
    for (size_t i = 0; i < 3 * n; i++)
        scale = fmax(scale, fabs(pp[i]));
    size_t left_out = 0;
    for (uint32_t i = 0; i < n; i++) {
        if (scheme == LIMN_SCHEME_CATMARK && t.vertex_rule[i] == RULE_SMOOTH &&
            t.vertex_edge_offsets[i + 1] - t.vertex_edge_offsets[i] == 2) {
            left_out++;
            continue;
        }
        double d = sqrt(pow(lim[3 * i] - mp[3 * i], 2) + pow(lim[3 * i + 1] - mp[3 * i + 1], 2) +
                        pow(lim[3 * i + 2] - mp[3 * i + 2], 2));
        worst = fmax(worst, d);
    }
    /* limn's reported error plus the rounding of two different summation orders */
    if (worst > o.tolerance * diag + 1e-13 * scale)
        fail_msg("%s: the limit of P misses M by %.3g (relative %.3g), tolerance %g", name, worst,
                 worst / diag, o.tolerance);
    printf("  %-36s %-7s alpha %.1f: %6zu vertices, %4d iterations, limit of P misses M by "
           "%.2e diag (limn says %.2e)%s\n",
           name, limn_scheme_name(scheme), alpha, n, r.iterations, worst / diag, r.max_rel_error,
           left_out ? " [valence-2 left out]" : "");
    topology_free(&t);
    free(lim);
    limn_mesh_destroy(p);
}

static void folder(const char *sub)
{
    if (!test_shared_meshes())
        skip();
    const char *names[128];
    size_t count = test_list_meshes(sub, names, 128);
    limn_context *ctx = limn_context_create();
    for (size_t i = 0; i < count; i++) {
        limn_mesh_info info;
        limn_mesh *m = test_read_shared_info(ctx, names[i], 36, &info);
        if (!m)
            continue;
        check_mesh(ctx, names[i], m, LIMN_SCHEME_CATMARK, 0.0);
        if (test_all_triangles(m))
            check_mesh(ctx, names[i], m, LIMN_SCHEME_LOOP, 0.0);
        if (info.nonmanifold_edges == 0 && info.nonmanifold_vertices == 0 &&
            info.referenced_vertices == info.vertices && info.vertices < 10000)
            check_mesh(ctx, names[i], m, LIMN_SCHEME_CATMARK, 0.5);
        limn_mesh_destroy(m);
    }
    limn_context_destroy(ctx);
}

/* The folder with every method, the automatic choice first. */
static void folder_every_method(const char *sub)
{
    static const limn_method methods[] = {LIMN_METHOD_AUTO, LIMN_METHOD_CG,
                                          LIMN_METHOD_CHEBYSHEV, LIMN_METHOD_SGS};
    for (size_t i = 0; i < sizeof methods / sizeof *methods; i++) {
        test_method = methods[i];
        folder(sub);
    }
    test_method = LIMN_METHOD_AUTO;
}

static void small_meshes(void **s)
{
    (void)s;
    folder_every_method("small");
}

static void medium_meshes(void **s)
{
    (void)s;
    folder_every_method("medium");
}

static void embedded_spot(void **s)
{
    (void)s;
    char path[4096];
    snprintf(path, sizeof path, "%s/spot_control_mesh.obj", getenv("LIMN_TEST_DATA"));
    limn_context *ctx = limn_context_create();
    limn_mesh *m = NULL;
    assert_int_equal(limn_mesh_read(ctx, path, LIMN_FORMAT_AUTO, &m), LIMN_OK);
    check_mesh(ctx, "data/spot_control_mesh.obj", m, LIMN_SCHEME_CATMARK, 0.0);
    check_mesh(ctx, "data/spot_control_mesh.obj", m, LIMN_SCHEME_CATMARK, 0.5);
    limn_mesh_destroy(m);
    limn_context_destroy(ctx);
}

/* Device rows to positions in place, against a strided copy, at sizes
   around the first rows whose source and target overlap. */
static void rows4_to_xyz(void **s)
{
    (void)s;
    for (size_t n = 0; n < 1030; n = n < 8 ? n + 1 : n * 2 + 7) {
        double *rows = malloc((4 * n + 1) * sizeof *rows);
        double *want = malloc((3 * n + 1) * sizeof *want);
        assert_non_null(rows);
        assert_non_null(want);
        for (size_t i = 0; i < 4 * n; i++)
            rows[i] = (double)i + 0.25;
        for (size_t k = 0; k < n; k++)
            for (int c = 0; c < 3; c++)
                want[3 * k + (size_t)c] = rows[4 * k + (size_t)c];
        double *got = mesh_rows4_to_xyz(rows, n);
        if (n)
            assert_memory_equal(got, want, 3 * n * sizeof *got);
        free(got);
        free(want);
    }
}

/* The control mesh keeps the input's faces and colours, whatever the route
   its positions took (in place, or through a renumbering: --method paper
   renumbers a scattered order). */
static void control_keeps_faces(void **s)
{
    limn_context *ctx = *s;
    limn_mesh *g = test_mesh_grid(ctx, 9, 7, 1);
    size_t n = limn_mesh_vertex_count(g);
    uint8_t *rgb = malloc(3 * n);
    assert_non_null(rgb);
    for (size_t i = 0; i < 3 * n; i++)
        rgb[i] = (uint8_t)(i * 7);
    assert_int_equal(limn_mesh_set_colors(ctx, g, rgb), LIMN_OK);
    limn_method methods[] = {LIMN_METHOD_AUTO, LIMN_METHOD_PAPER};
    for (int k = 0; k < 2; k++) {
        limn_interpolate_options o;
        limn_interpolate_options_default(&o);
        o.method = methods[k];
        limn_mesh *p = NULL;
        assert_int_equal(limn_interpolate(ctx, g, &o, &p, NULL), LIMN_OK);
        assert_int_equal(limn_mesh_vertex_count(p), n);
        assert_int_equal(limn_mesh_face_count(p), limn_mesh_face_count(g));
        assert_int_equal(limn_mesh_index_count(p), limn_mesh_index_count(g));
        assert_memory_equal(limn_mesh_face_offsets(p), limn_mesh_face_offsets(g),
                            (limn_mesh_face_count(g) + 1) * sizeof(uint32_t));
        assert_memory_equal(limn_mesh_face_indices(p), limn_mesh_face_indices(g),
                            limn_mesh_index_count(g) * sizeof(uint32_t));
        assert_memory_equal(limn_mesh_colors(p), rgb, 3 * n);
        limn_mesh_destroy(p);
    }
    free(rgb);
    limn_mesh_destroy(g);
}

/* Generated meshes: closed, open, all vertex kinds, both schemes. */
static void generated_meshes(void **s)
{
    limn_context *ctx = *s;
    limn_mesh *g = test_mesh_grid(ctx, 6, 5, 0), *gt = test_mesh_grid(ctx, 6, 5, 1);
    limn_mesh *ico = test_mesh_icosahedron(ctx), *pyr = test_mesh_pyramid(ctx);
    check_mesh(ctx, "quad grid", g, LIMN_SCHEME_CATMARK, 0.0);
    check_mesh(ctx, "quad grid", g, LIMN_SCHEME_CATMARK, 0.5);
    check_mesh(ctx, "triangle grid", gt, LIMN_SCHEME_LOOP, 0.0);
    check_mesh(ctx, "icosahedron", ico, LIMN_SCHEME_LOOP, 0.0);
    check_mesh(ctx, "pyramid", pyr, LIMN_SCHEME_CATMARK, 0.0);
    check_mesh(ctx, "pyramid", pyr, LIMN_SCHEME_CATMARK, 0.5);
    limn_mesh_destroy(g);
    limn_mesh_destroy(gt);
    limn_mesh_destroy(ico);
    limn_mesh_destroy(pyr);
}

/* alpha = 0 on a perturbed cube: the operator has a zero eigenvalue; limn
   must stop with LIMN_ERR_SINGULAR and say to use alpha, not loop to the cap.
   The exactly affine cube lies in A's range and converges; alpha 0.5 cures
   the perturbed one. */
static void singular_cube(void **s)
{
    limn_context *ctx = *s;
    limn_mesh *cube = test_keep_mesh(test_mesh_cube(ctx)), *p = NULL;
    limn_interpolate_options o;
    limn_interpolate_options_default(&o);
    assert_int_equal(limn_interpolate(ctx, cube, &o, &p, NULL), LIMN_OK);
    limn_mesh_destroy(p);
    p = NULL;
    test_perturb(cube, 0.1, 3);
    assert_int_equal(limn_interpolate(ctx, cube, &o, &p, NULL), LIMN_ERR_SINGULAR);
    assert_null(p);
    assert_non_null(strstr(limn_context_message(ctx), "--alpha 0.5"));
    /* chebyshev: the restart rule must not hide the stall; cg and sgs: their
       own stall and breakdown guards */
    limn_method ms[] = {LIMN_METHOD_CHEBYSHEV, LIMN_METHOD_CG, LIMN_METHOD_SGS};
    for (int k = 0; k < 3; k++) {
        o.method = ms[k];
        assert_int_equal(limn_interpolate(ctx, cube, &o, &p, NULL), LIMN_ERR_SINGULAR);
        assert_null(p);
        if (!strstr(limn_context_message(ctx), "--alpha 0.5"))
            fail_msg("%s: %s", limn_method_name(ms[k]), limn_context_message(ctx));
    }
    o.method = LIMN_METHOD_AUTO;
    o.alpha = 0.5;
    limn_report r = {.size = sizeof r};
    assert_int_equal(limn_interpolate(ctx, cube, &o, &p, &r), LIMN_OK);
    limn_mesh_destroy(p);
    check_mesh(ctx, "perturbed cube", cube, LIMN_SCHEME_CATMARK, 0.5);
}

static void iteration_cap_and_options(void **s)
{
    limn_context *ctx = *s;
    limn_mesh *g = test_mesh_grid(ctx, 6, 5, 0), *p = NULL;
    limn_interpolate_options o;
    limn_interpolate_options_default(&o);
    o.max_iterations = 5;
    assert_int_equal(limn_interpolate(ctx, g, &o, &p, NULL), LIMN_ERR_NO_CONVERGENCE);
    assert_null(p);
    assert_non_null(strstr(limn_context_message(ctx), "raise --max-iter"));
    limn_interpolate_options_default(&o);
    o.alpha = 1.5;
    assert_int_equal(limn_interpolate(ctx, g, &o, &p, NULL), LIMN_ERR_ARGUMENT);
    assert_non_null(strstr(limn_context_message(ctx), "alpha"));
    limn_interpolate_options_default(&o);
    o.tolerance = -1;
    assert_int_equal(limn_interpolate(ctx, g, &o, &p, NULL), LIMN_ERR_ARGUMENT);
    limn_interpolate_options_default(&o);
    o.scheme = LIMN_SCHEME_LOOP;
    assert_int_equal(limn_interpolate(ctx, g, &o, &p, NULL), LIMN_ERR_TOPOLOGY);
    assert_non_null(strstr(limn_context_message(ctx), "face 0 has 4 vertices"));
    assert_null(p);
    limn_mesh_destroy(g);
}

/* Every method reaches the tolerance (checked through OpenSubdiv's limit of
   P), and conjugate gradients need far fewer stencil products. */
static void methods(void **s)
{
    (void)s;
    char path[4096];
    snprintf(path, sizeof path, "%s/spot_control_mesh.obj", getenv("LIMN_TEST_DATA"));
    limn_context *ctx = limn_context_create();
    limn_mesh *spot = NULL, *ico = test_mesh_icosahedron(ctx), *grid = test_mesh_grid(ctx, 8, 7, 0);
    assert_int_equal(limn_mesh_read(ctx, path, LIMN_FORMAT_AUTO, &spot), LIMN_OK);
    test_perturb(ico, 0.2, 4);
    limn_method ms[] = {LIMN_METHOD_PAPER, LIMN_METHOD_WEIGHTED, LIMN_METHOD_CG,
                        LIMN_METHOD_CHEBYSHEV, LIMN_METHOD_SGS};
    double products[5][3];
    for (int k = 0; k < 5; k++) {
        test_method = ms[k];
        check_mesh(ctx, limn_method_name(ms[k]), spot, LIMN_SCHEME_CATMARK, 0.0);
        products[k][0] = last_products;
        check_mesh(ctx, limn_method_name(ms[k]), ico, LIMN_SCHEME_LOOP, 0.0);
        products[k][1] = last_products;
        /* open grid: boundary and corner tiers before the smooth block */
        check_mesh(ctx, limn_method_name(ms[k]), grid, LIMN_SCHEME_CATMARK, 0.5);
        products[k][2] = last_products;
    }
    test_method = LIMN_METHOD_AUTO;
    printf("  products paper / weighted / cg / chebyshev / sgs: spot %.0f / %.0f / %.1f / %.0f / "
           "%.1f, perturbed icosahedron %.0f / %.0f / %.1f / %.0f / %.1f, open grid %.0f / %.0f "
           "/ %.1f / %.0f / %.1f\n",
           products[0][0], products[1][0], products[2][0], products[3][0], products[4][0],
           products[0][1], products[1][1], products[2][1], products[3][1], products[4][1],
           products[0][2], products[1][2], products[2][2], products[3][2], products[4][2]);
    /* the preconditioner must pay: fewer products than cg and chebyshev (not on
       the 12-vertex icosahedron, whose few distinct eigenvalues cg resolves in
       5 products) */
    for (int m = 0; m < 3; m += 2)
        assert_true(products[4][m] < products[3][m] && products[4][m] < products[2][m]);
    assert_true(products[2][0] * 4 < products[0][0]);
    assert_true(products[3][0] * 4 < products[0][0]);
    assert_true(products[1][0] < products[0][0]);
    assert_true(products[3][1] < products[0][1]);
    limn_mesh_destroy(spot);
    limn_mesh_destroy(ico);
    limn_mesh_destroy(grid);
    limn_context_destroy(ctx);
}

TEST_MAIN(NULL, NULL, CONTEXT_TEST(generated_meshes), CONTEXT_TEST(singular_cube),
          cmocka_unit_test(methods), CONTEXT_TEST(iteration_cap_and_options),
          cmocka_unit_test(embedded_spot), cmocka_unit_test(small_meshes),
          cmocka_unit_test(medium_meshes), cmocka_unit_test(rows4_to_xyz),
          CONTEXT_TEST(control_keeps_faces))
