/* SPDX-License-Identifier: MIT */
/*
 * The float path (issue 5): mixed-precision refinement, residuals in double,
 * corrections in float (host/solve/solve_mixed.c, kernels/mixed.cl).
 *  - Its kernels against their C twins (host/device/reference/device_ref_mixed.c): the same
 *    IEEE operations in the same order with contraction off, and the norms
 *    summed in double with sqrt in double (correctly rounded on both), so
 *    the agreement bound is zero: bit-identical floats and doubles, one
 *    operation at a time and over whole solves.
 *  - On every shared medium mesh, Loop and Catmull-Clark, tolerance 1e-6 and
 *    1e-8: the float solve meets the tolerance, measured by limn in double
 *    and by OpenSubdiv's limit of the P written; and it does so with at most
 *    two double products beyond the first (one float solve reaches 1e-8).
 *  - The choice: float with cg refused, auto by size, a singular operator
 *    still named as such, the OpenCL set-up and the loop's own time
 *    reported; the command line.
 */
#include "shell.h"
#include "support.h"
#include "device/device.h"
#include "solve/operator.h"
#include "osd_oracle.h"
#include "solve/solve_mixed.h"
#include "topology/topology.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

#include <cmocka.h>

/* One call of each float-path operation on both backends: same bits.
   ahead: whether the table's gathers are expected to be prefetched. */
static void ops_on(const char *name, const limn_mesh *mesh, limn_scheme scheme, int ahead)
{
    limn_context *ctx[2] = {limn_context_create(), limn_context_create()};
    assert_int_equal(limn_context_set_device(ctx[0], "opencl"), LIMN_OK);
    assert_int_equal(limn_context_set_device(ctx[1], "reference"), LIMN_OK);
    size_t n = limn_mesh_vertex_count(mesh);
    double *m4 = malloc(4 * n * sizeof *m4), *p4 = malloc(4 * n * sizeof *p4);
    float *b4 = malloc(4 * n * sizeof *b4);
    double *out_p[2] = {malloc(4 * n * sizeof(double)), malloc(4 * n * sizeof(double))};
    float *out_r[2] = {malloc(4 * n * sizeof(float)), malloc(4 * n * sizeof(float))};
    float *out_d[2] = {malloc(4 * n * sizeof(float)), malloc(4 * n * sizeof(float))};
    device_norms nr[2], ns[2];
    for (int k = 0; k < 2; k++) {
        stencil_operator op;
        if (operator_build(ctx[k], mesh, scheme, 0.0, &op) != LIMN_OK)
            fail_msg("%s: %s", name, limn_context_message(ctx[k]));
        struct device *dev = op.dev;
        assert_int_equal(op.device.gather_ahead, ahead);
        operator_pack(&op, limn_mesh_positions(mesh), m4);
        for (size_t i = 0; i < 4 * n; i++) {
            /* a P near M and a float right-hand side with mixed signs */
            p4[i] = (i & 3) == 3 ? 0.0 : m4[i] * (1.0 + 1e-3 * sin((double)i));
            b4[i] = (i & 3) == 3 ? 0.0f : (float)(1e-3 * cos(0.37 * (double)i));
        }
        device_buffer *m = NULL, *p = NULL, *r = NULL, *b = NULL, *d = NULL;
        assert_int_equal(device_csr_add_float(dev, &op.device), LIMN_OK);
        assert_int_equal(dev->ops->buffer_create(dev, 4 * n * sizeof(double), m4, &m), LIMN_OK);
        assert_int_equal(dev->ops->buffer_create(dev, 4 * n * sizeof(double), p4, &p), LIMN_OK);
        assert_int_equal(dev->ops->buffer_create(dev, 4 * n * sizeof(float), NULL, &r), LIMN_OK);
        assert_int_equal(dev->ops->buffer_create(dev, 4 * n * sizeof(float), b4, &b), LIMN_OK);
        assert_int_equal(dev->ops->buffer_create(dev, 4 * n * sizeof(float), b4, &d), LIMN_OK);
        assert_int_equal(dev->ops->mixed->residual_f(dev, &op.device, m, p, r, &nr[k]), LIMN_OK);
        /* a Chebyshev step from d = r towards b, the previous iterate (b) read
           and the next written in place */
        assert_int_equal(dev->ops->mixed->step_f(dev, &op.device, b, r, d, d, 0.7f, 1.3f, &ns[k]),
                         LIMN_OK);
        assert_int_equal(dev->ops->mixed->add_f(dev, n, p, d), LIMN_OK);
        assert_int_equal(dev->ops->buffer_read(dev, r, 4 * n * sizeof(float), out_r[k]), LIMN_OK);
        assert_int_equal(dev->ops->buffer_read(dev, d, 4 * n * sizeof(float), out_d[k]), LIMN_OK);
        assert_int_equal(dev->ops->buffer_read(dev, p, 4 * n * sizeof(double), out_p[k]),
                         LIMN_OK);
        device_buffer *all[] = {m, p, r, b, d};
        for (int i = 0; i < 5; i++)
            dev->ops->buffer_release(dev, all[i]);
        operator_free(&op);
    }
    assert_memory_equal(out_r[0], out_r[1], 4 * n * sizeof(float));
    assert_memory_equal(out_d[0], out_d[1], 4 * n * sizeof(float));
    assert_memory_equal(out_p[0], out_p[1], 4 * n * sizeof(double));
    assert_memory_equal(&nr[0], &nr[1], sizeof nr[0]);
    assert_memory_equal(&ns[0], &ns[1], sizeof ns[0]);
    assert_true(nr[0].max > 0 && ns[0].max > 0);
    printf("  %-30s %-7s: residual_f, step_f, add_f bit-identical (%zu rows%s)\n",
           name, limn_scheme_name(scheme), n, ahead ? ", gathers prefetched" : "");
    for (int k = 0; k < 2; k++) {
        free(out_p[k]);
        free(out_r[k]);
        free(out_d[k]);
        limn_context_destroy(ctx[k]);
    }
    free(m4);
    free(p4);
    free(b4);
}

/* A grid whose vertex i moves to (i * 7919) mod n: its gathers scatter. */
static limn_mesh *shuffled_grid(limn_context *ctx, int nx, int ny)
{
    limn_mesh *g = test_mesh_grid(ctx, nx, ny, 0), *out = NULL;
    size_t n = limn_mesh_vertex_count(g), nf = limn_mesh_face_count(g);
    const uint32_t *off = limn_mesh_face_offsets(g), *idx = limn_mesh_face_indices(g);
    double *pos = malloc(3 * n * sizeof *pos);
    uint32_t *map = malloc(n * sizeof *map), *nidx = malloc(off[nf] * sizeof *nidx);
    for (size_t i = 0; i < n; i++) {
        map[i] = (uint32_t)(i * 7919 % n);
        memcpy(pos + 3 * map[i], limn_mesh_positions(g) + 3 * i, 3 * sizeof *pos);
    }
    for (size_t k = 0; k < off[nf]; k++)
        nidx[k] = map[idx[k]];
    assert_int_equal(limn_mesh_create(ctx, n, pos, nf, off, nidx, &out), LIMN_OK);
    free(pos);
    free(map);
    free(nidx);
    limn_mesh_destroy(g);
    return out;
}

static void kernels_match_reference(void **s)
{
    limn_context *ctx = *s;
    /* more rows than one chunk, and a ragged last chunk */
    limn_mesh *g = test_mesh_grid(ctx, 40, 37, 0), *gt = test_mesh_grid(ctx, 40, 37, 1);
    ops_on("quad grid 40x37", g, LIMN_SCHEME_CATMARK, 0);
    ops_on("triangle grid 40x37", gt, LIMN_SCHEME_LOOP, 0);
    limn_mesh_destroy(g);
    limn_mesh_destroy(gt);
    /* 40,401 vertices: 7919 is prime to 201^2, so this is a permutation */
    g = shuffled_grid(ctx, 200, 200);
    ops_on("shuffled quad grid 200x200", g, LIMN_SCHEME_CATMARK, 1);
    limn_mesh_destroy(g);
    if (test_shared_meshes()) {
        limn_mesh *m = test_read_shared(ctx, "medium/horse.ply");
        ops_on("medium/horse.ply", m, LIMN_SCHEME_LOOP, 0);
        ops_on("medium/horse.ply", m, LIMN_SCHEME_CATMARK, 0);
        limn_mesh_destroy(m);
    }
}

static limn_mesh *solve(limn_context *ctx, const limn_mesh *m, limn_scheme scheme, double tol,
                        limn_method method, limn_precision precision, limn_report *r)
{
    limn_interpolate_options o;
    limn_interpolate_options_default(&o);
    o.scheme = scheme;
    o.tolerance = tol;
    o.method = method;
    o.precision = precision;
    limn_mesh *p = NULL;
    if (limn_interpolate(ctx, m, &o, &p, r) != LIMN_OK)
        fail_msg("%s, tolerance %g: %s", limn_scheme_name(scheme), tol,
                 limn_context_message(ctx));
    return p;
}

/* Whole float solves on both backends: same bits, same counts. */
static void solves_match_reference(void **s)
{
    (void)s;
    limn_context *cl = limn_context_create(), *ref = limn_context_create();
    assert_int_equal(limn_context_set_device(ref, "reference"), LIMN_OK);
    limn_mesh *g = test_mesh_grid(cl, 40, 37, 0);
    limn_mesh *spot = NULL;
    char path[4096];
    snprintf(path, sizeof path, "%s/spot_control_mesh.obj", getenv("LIMN_TEST_DATA"));
    assert_int_equal(limn_mesh_read(cl, path, LIMN_FORMAT_AUTO, &spot), LIMN_OK);
    const limn_mesh *meshes[] = {g, spot};
    limn_method methods[] = {LIMN_METHOD_PAPER, LIMN_METHOD_WEIGHTED, LIMN_METHOD_CHEBYSHEV};
    for (int i = 0; i < 2; i++)
        for (int k = 0; k < 3; k++) {
            limn_report ra = {.size = sizeof ra}, rb = {.size = sizeof rb};
            limn_mesh *a = solve(cl, meshes[i], LIMN_SCHEME_CATMARK, 1e-8, methods[k],
                                 LIMN_PRECISION_FLOAT, &ra);
            limn_mesh *b = solve(ref, meshes[i], LIMN_SCHEME_CATMARK, 1e-8, methods[k],
                                 LIMN_PRECISION_FLOAT, &rb);
            size_t n = limn_mesh_vertex_count(meshes[i]);
            assert_memory_equal(limn_mesh_positions(a), limn_mesh_positions(b),
                                3 * n * sizeof(double));
            assert_int_equal(ra.iterations, rb.iterations);
            assert_true(ra.products == rb.products && ra.products_float == rb.products_float);
            assert_true(ra.products_float > 0);
            limn_mesh_destroy(a);
            limn_mesh_destroy(b);
        }
    /* scattered gathers (prefetched), both precisions, vertex order kept */
    limn_mesh *sh = shuffled_grid(cl, 200, 200);
    for (int k = 0; k < 2; k++) {
        limn_interpolate_options o;
        limn_interpolate_options_default(&o);
        o.reorder = 0;
        o.precision = k ? LIMN_PRECISION_FLOAT : LIMN_PRECISION_DOUBLE;
        limn_mesh *a = NULL, *b = NULL;
        limn_report ra = {.size = sizeof ra}, rb = {.size = sizeof rb};
        assert_int_equal(limn_interpolate(cl, sh, &o, &a, &ra), LIMN_OK);
        assert_int_equal(limn_interpolate(ref, sh, &o, &b, &rb), LIMN_OK);
        assert_memory_equal(limn_mesh_positions(a), limn_mesh_positions(b),
                            3 * limn_mesh_vertex_count(sh) * sizeof(double));
        assert_true(ra.products == rb.products && ra.iterations == rb.iterations);
        limn_mesh_destroy(a);
        limn_mesh_destroy(b);
    }
    limn_mesh_destroy(sh);
    limn_mesh_destroy(g);
    limn_mesh_destroy(spot);
    limn_context_destroy(cl);
    limn_context_destroy(ref);
}

/* OpenSubdiv's limit of P misses M by at most tol * diag (plus the rounding
   of two summation orders); valence-2 interior vertices left out, as in
   test_interpolate.c. Returns the miss over the diagonal, or -1 when the
   oracle refuses the mesh. */
static double oracle_miss(limn_context *ctx, const limn_mesh *m, const limn_mesh *p,
                          limn_scheme scheme, double tol)
{
    size_t n = limn_mesh_vertex_count(m);
    int *sizes, *idx;
    char err[512];
    test_oracle_faces(p, &sizes, &idx);
    double *lim = malloc(3 * n * sizeof *lim);
    int rc = osd_oracle_limit(scheme == LIMN_SCHEME_LOOP ? 0 : 1, (int)n, limn_mesh_positions(p),
                              (int)limn_mesh_face_count(p), sizes, idx, lim, err, sizeof err);
    free(sizes);
    free(idx);
    if (rc != 0) {
        free(lim);
        return -1.0;
    }
    topology t;
    assert_int_equal(topology_build(ctx, m, &t), LIMN_OK);
    const double *mp = limn_mesh_positions(m), *pp = limn_mesh_positions(p);
    double diag = test_bbox_diagonal(m), worst = 0.0, scale = 1.0;
    for (size_t i = 0; i < 3 * n; i++)
        scale = fmax(scale, fabs(pp[i]));
    for (uint32_t i = 0; i < n; i++) {
        if (scheme == LIMN_SCHEME_CATMARK && t.vertex_rule[i] == RULE_SMOOTH &&
            t.vertex_edge_offsets[i + 1] - t.vertex_edge_offsets[i] == 2)
            continue;
        double d = sqrt(pow(lim[3 * i] - mp[3 * i], 2) + pow(lim[3 * i + 1] - mp[3 * i + 1], 2) +
                        pow(lim[3 * i + 2] - mp[3 * i + 2], 2));
        worst = fmax(worst, d);
    }
    topology_free(&t);
    free(lim);
    if (worst > tol * diag + 1e-13 * scale)
        fail_msg("the limit of P misses M by %.3g of the diagonal, tolerance %g", worst / diag,
                 tol);
    return worst / diag;
}

static void medium_meshes_meet_tolerance(void **s)
{
    if (!test_shared_meshes())
        skip();
    const char *names[64];
    size_t count = test_list_meshes("medium", names, 64);
    assert_true(count > 0);
    limn_context *ctx = *s;
    for (size_t i = 0; i < count; i++) {
        limn_mesh *m = test_read_shared(ctx, names[i]);
        limn_scheme schemes[2] = {LIMN_SCHEME_CATMARK, LIMN_SCHEME_LOOP};
        limn_method methods[2] = {LIMN_METHOD_AUTO, LIMN_METHOD_PAPER};
        for (int k = 0; k < (test_all_triangles(m) ? 4 : 2); k++)
            for (double tol = 1e-6; tol > 1e-9; tol *= 1e-2) {
                limn_report r = {.size = sizeof r};
                limn_mesh *p = solve(ctx, m, schemes[k / 2], tol, methods[k % 2],
                                     LIMN_PRECISION_FLOAT, &r);
                assert_string_equal(r.precision, "float");
                assert_true(r.max_rel_error <= tol);
                double doubles = r.products - r.products_float;
                /* the first residual, one float solve, the check; 1e-8 may take one more */
                assert_true(doubles >= 2 && doubles <= 3 && r.products_float > 0);
                double miss = oracle_miss(ctx, m, p, schemes[k / 2], tol);
                printf("  %-30s %-7s %-9s tol %g: %2.0f double + %3.0f float products, "
                       "error %.2e (OpenSubdiv's limit of P: %.2e)\n",
                       names[i], limn_scheme_name(schemes[k / 2]), r.method, tol, doubles,
                       r.products_float, r.max_rel_error, miss);
                limn_mesh_destroy(p);
            }
        limn_mesh_destroy(m);
    }
}

static void choice_and_refusals(void **s)
{
    limn_context *ctx = *s;
    limn_mesh *g = test_mesh_grid(ctx, 6, 5, 0), *p = NULL;
    limn_interpolate_options o;
    limn_report r = {.size = sizeof r};
    limn_interpolate_options_default(&o);
    assert_int_equal(o.precision, LIMN_PRECISION_AUTO);
    o.precision = LIMN_PRECISION_FLOAT;
    o.method = LIMN_METHOD_CG;
    assert_int_equal(limn_interpolate(ctx, g, &o, &p, NULL), LIMN_ERR_ARGUMENT);
    assert_non_null(strstr(limn_context_message(ctx), "runs in double"));
    assert_null(p);
    o.precision = (limn_precision)7;
    o.method = LIMN_METHOD_PAPER;
    assert_int_equal(limn_interpolate(ctx, g, &o, &p, NULL), LIMN_ERR_ARGUMENT);
    assert_non_null(strstr(limn_context_message(ctx), "precision"));
    /* auto: double on small meshes and with cg */
    limn_interpolate_options_default(&o);
    p = solve(ctx, g, LIMN_SCHEME_CATMARK, 1e-6, LIMN_METHOD_PAPER, LIMN_PRECISION_AUTO, &r);
    assert_string_equal(r.precision, "double");
    assert_true(r.products_float == 0 && strstr(r.precision_reason, "auto") != NULL);
    limn_mesh_destroy(p);
    p = solve(ctx, g, LIMN_SCHEME_CATMARK, 1e-6, LIMN_METHOD_CG, LIMN_PRECISION_AUTO, &r);
    assert_string_equal(r.precision, "double");
    limn_mesh_destroy(p);
    /* auto: float from SOLVE_FLOAT_MIN_VERTICES on */
    limn_mesh *big = test_mesh_grid(ctx, 450, 450, 0);
    assert_true(limn_mesh_vertex_count(big) >= SOLVE_FLOAT_MIN_VERTICES);
    p = solve(ctx, big, LIMN_SCHEME_CATMARK, 1e-6, LIMN_METHOD_AUTO, LIMN_PRECISION_AUTO, &r);
    assert_string_equal(r.precision, "float");
    assert_true(r.max_rel_error <= 1e-6 && r.products_float > 0);
    limn_mesh_destroy(p);
    limn_mesh_destroy(big);
    limn_mesh_destroy(g);
}

/* The alpha = 0 perturbed cube is singular: the float corrections stop
   gaining, the double iteration takes over and names the cause. */
static void singular_cube_in_float(void **s)
{
    limn_context *ctx = *s;
    limn_mesh *cube = test_mesh_cube(ctx), *p = NULL;
    test_perturb(cube, 0.1, 3);
    limn_interpolate_options o;
    limn_interpolate_options_default(&o);
    o.precision = LIMN_PRECISION_FLOAT;
    assert_int_equal(limn_interpolate(ctx, cube, &o, &p, NULL), LIMN_ERR_SINGULAR);
    assert_null(p);
    assert_non_null(strstr(limn_context_message(ctx), "--alpha 0.5"));
    o.alpha = 0.5;
    limn_report r = {.size = sizeof r};
    assert_int_equal(limn_interpolate(ctx, cube, &o, &p, &r), LIMN_OK);
    assert_true(r.max_rel_error <= o.tolerance && r.products_float > 0);
    limn_mesh_destroy(p);
    limn_mesh_destroy(cube);
}

/* Far from the origin float keeps fewer digits of the diagonal: this grid
   moved by 200 diagonals has a pure-float floor of 2.5e-5 of it (measured
   with perf/float_floor; bunny_closed moved by 10: 2.4e-6), yet the mixed
   path, whose float vectors hold only corrections, still meets 1e-8. */
static void far_from_origin(void **s)
{
    limn_context *ctx = *s;
    limn_mesh *g = test_mesh_grid(ctx, 40, 37, 1);
    double *pos = limn_mesh_positions_mutable(g), shift = 200.0 * test_bbox_diagonal(g);
    for (size_t i = 0; i < 3 * limn_mesh_vertex_count(g); i++)
        pos[i] += shift;
    limn_report r = {.size = sizeof r};
    limn_mesh *p = solve(ctx, g, LIMN_SCHEME_LOOP, 1e-8, LIMN_METHOD_PAPER,
                         LIMN_PRECISION_FLOAT, &r);
    assert_true(r.max_rel_error <= 1e-8 && r.products_float > 0);
    assert_true(r.seconds_iterations > 0 && r.seconds_iterations <= r.seconds_solve);
    printf("  grid moved by 200 diagonals, float: %.0f double + %.0f float products, error "
           "%.2e\n",
           r.products - r.products_float, r.products_float, r.max_rel_error);
    limn_mesh_destroy(p);
    limn_mesh_destroy(g);
}

/* The first solve on a fresh context opens OpenCL and says what it cost;
   the second finds everything ready. The reference backend has none. */
static void setup_reported(void **s)
{
    (void)s;
    limn_context *ctx = limn_context_create(), *ref = limn_context_create();
    assert_int_equal(limn_context_set_device(ctx, "opencl"), LIMN_OK);
    assert_int_equal(limn_context_set_device(ref, "reference"), LIMN_OK);
    limn_mesh *g = test_mesh_grid(ctx, 6, 5, 0);
    limn_report r = {.size = sizeof r};
    limn_mesh *p = solve(ctx, g, LIMN_SCHEME_CATMARK, 1e-6, LIMN_METHOD_PAPER,
                         LIMN_PRECISION_DOUBLE, &r);
    limn_mesh_destroy(p);
    printf("  set-up: platform %.3f s, context %.3f s, build %.3f s, first launches %.3f s\n",
           r.seconds_opencl_platform, r.seconds_opencl_context, r.seconds_opencl_build,
           r.seconds_opencl_kernels);
    assert_true(r.seconds_opencl_platform > 0 && r.seconds_opencl_build > 0 &&
                r.seconds_opencl_kernels > 0);
    /* the loop alone, without the first launches' compiles */
    assert_true(r.seconds_iterations > 0 && r.seconds_iterations <= r.seconds_solve);
    p = solve(ctx, g, LIMN_SCHEME_CATMARK, 1e-6, LIMN_METHOD_PAPER, LIMN_PRECISION_DOUBLE, &r);
    limn_mesh_destroy(p);
    assert_true(r.seconds_opencl_platform == 0 && r.seconds_opencl_build == 0 &&
                r.seconds_opencl_kernels == 0);
    p = solve(ref, g, LIMN_SCHEME_CATMARK, 1e-6, LIMN_METHOD_PAPER, LIMN_PRECISION_DOUBLE, &r);
    limn_mesh_destroy(p);
    assert_true(r.seconds_opencl_platform + r.seconds_opencl_context + r.seconds_opencl_build +
                    r.seconds_opencl_kernels ==
                0);
    limn_mesh_destroy(g);
    limn_context_destroy(ctx);
    limn_context_destroy(ref);
}

/* Runs `limn ARGS`, output into text; returns the exit status. */
static int limn_cli(const char *args, char *text, size_t size)
{
    return test_limn(text, size, NULL, "%s", args);
}

static void command_line(void **s)
{
    (void)s;
    char dir[64], args[4096], text[8192];
    assert_int_equal(test_make_dir(dir, sizeof dir, "precision"), 0);
    const char *spot = getenv("LIMN_TEST_DATA");
    snprintf(args, sizeof args, "interpolate '%s/spot_control_mesh.obj' -o '%s/p.ply' "
                                "--precision half", spot, dir);
    assert_int_equal(limn_cli(args, text, sizeof text), 2);
    assert_non_null(strstr(text, "--precision 'half' is not one of auto, double, float"));
    snprintf(args, sizeof args, "interpolate '%s/spot_control_mesh.obj' -o '%s/p.ply' "
                                "--precision float --method cg", spot, dir);
    assert_int_equal(limn_cli(args, text, sizeof text), 2);
    assert_non_null(strstr(text, "cg and sgs run in double"));
    snprintf(args, sizeof args, "interpolate '%s/spot_control_mesh.obj' -o '%s/p.ply' "
                                "--precision float --report '%s/r.json' -q && cat '%s/r.json'",
             spot, dir, dir, dir);
    assert_int_equal(limn_cli(args, text, sizeof text), 0);
    const char *keys[] = {"\"precision\": \"float\"", "\"precision_reason\": \"chosen by the caller\"",
                          "\"products_float\": ", "\"opencl_setup\": ", "\"kernels\": "};
    for (size_t i = 0; i < sizeof keys / sizeof *keys; i++)
        if (!strstr(text, keys[i]))
            fail_msg("the report lacks %s:\n%s", keys[i], text);
    assert_int_equal(test_remove_dir(dir), 0);
}

TEST_MAIN(NULL, NULL, CONTEXT_TEST(kernels_match_reference),
          cmocka_unit_test(solves_match_reference), CONTEXT_TEST(choice_and_refusals),
          CONTEXT_TEST(singular_cube_in_float), CONTEXT_TEST(far_from_origin),
          cmocka_unit_test(setup_reported), cmocka_unit_test(command_line),
          CONTEXT_TEST(medium_meshes_meet_tolerance))
