/* SPDX-License-Identifier: MIT */
/*
 * The OpenCL backend against the C reference backend (the oracle for every
 * kernel): limit positions and interpolated control meshes agree — both do
 * the same operations in the same order with contraction off, so they are
 * expected to be bit-identical, and are asserted to 1e-12 of the scale — and
 * the iteration counts are equal. Two runs of the CLI give identical bytes,
 * also with PoCL on 1 and on 2 threads; a solve whose scratch is large enough
 * to live in limn's own host memory, in float and double.
 */
#include "shell.h"
#include "support.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

static void compare_arrays(const char *what, const double *a, const double *b, size_t n,
                           size_t *identical)
{
    double scale = 1.0;
    for (size_t i = 0; i < n; i++)
        scale = fmax(scale, fabs(a[i]));
    for (size_t i = 0; i < n; i++) {
        if (fabs(a[i] - b[i]) > 1e-12 * scale)
            fail_msg("%s: entry %zu differs: opencl %.17g reference %.17g", what, i, a[i], b[i]);
        *identical += a[i] == b[i];
    }
}

static void agree_on(const char *name, limn_mesh *m, limn_scheme scheme, double alpha)
{
    limn_context *cl = limn_context_create(), *ref = limn_context_create();
    assert_int_equal(limn_context_set_device(cl, "opencl"), LIMN_OK);
    assert_int_equal(limn_context_set_device(ref, "reference"), LIMN_OK);
    size_t n = limn_mesh_vertex_count(m), same = 0;
    double *a = malloc(3 * n * sizeof *a), *b = malloc(3 * n * sizeof *b);
    if (limn_limit_positions(cl, m, scheme, alpha, a) != LIMN_OK)
        fail_msg("%s: %s", name, limn_context_message(cl));
    assert_int_equal(limn_limit_positions(ref, m, scheme, alpha, b), LIMN_OK);
    compare_arrays(name, a, b, 3 * n, &same);
    limn_interpolate_options o;
    limn_interpolate_options_default(&o);
    o.scheme = scheme;
    o.alpha = alpha;
    limn_mesh *pa = NULL, *pb = NULL;
    limn_report ra = {.size = sizeof ra}, rb = {.size = sizeof rb};
    assert_int_equal(limn_interpolate(cl, m, &o, &pa, &ra), LIMN_OK);
    assert_int_equal(limn_interpolate(ref, m, &o, &pb, &rb), LIMN_OK);
    assert_int_equal(ra.iterations, rb.iterations);
    compare_arrays(name, limn_mesh_positions(pa), limn_mesh_positions(pb), 3 * n, &same);
    printf("  %-34s %-7s: %zu of %zu values bit-identical, %d iterations each\n", name,
           limn_scheme_name(scheme), same, 6 * n, ra.iterations);
    /* every solver's kernels, too */
    limn_method others[] = {LIMN_METHOD_PAPER, LIMN_METHOD_WEIGHTED, LIMN_METHOD_CHEBYSHEV,
                            LIMN_METHOD_CG, LIMN_METHOD_SGS};
    for (int k = 0; k < 5; k++) {
        limn_mesh *qa = NULL, *qb = NULL;
        size_t same_k = 0;
        o.method = others[k];
        assert_int_equal(limn_interpolate(cl, m, &o, &qa, &ra), LIMN_OK);
        assert_int_equal(limn_interpolate(ref, m, &o, &qb, &rb), LIMN_OK);
        assert_int_equal(ra.iterations, rb.iterations);
        compare_arrays(name, limn_mesh_positions(qa), limn_mesh_positions(qb), 3 * n, &same_k);
        if (same_k != 3 * n)
            fail_msg("%s, method %s: %zu of %zu values bit-identical", name,
                     limn_method_name(others[k]), same_k, 3 * n);
        limn_mesh_destroy(qa);
        limn_mesh_destroy(qb);
    }
    o.method = LIMN_METHOD_AUTO;
    assert_true(strstr(limn_context_device_name(ref), "reference") != NULL);
    limn_mesh_destroy(pa);
    limn_mesh_destroy(pb);
    free(a);
    free(b);
    limn_context_destroy(cl);
    limn_context_destroy(ref);
}

static void generated(void **s)
{
    limn_context *ctx = *s;
    /* 40 x 40 grids: more rows than one work-item's chunk, and a ragged last chunk */
    limn_mesh *g = test_keep_mesh(test_mesh_grid(ctx, 40, 37, 0));
    limn_mesh *gt = test_keep_mesh(test_mesh_grid(ctx, 40, 37, 1));
    limn_mesh *cube = test_keep_mesh(test_mesh_cube(ctx));
    agree_on("quad grid 40x37", g, LIMN_SCHEME_CATMARK, 0.0);
    agree_on("quad grid 40x37", g, LIMN_SCHEME_CATMARK, 0.5);
    agree_on("triangle grid 40x37", gt, LIMN_SCHEME_LOOP, 0.0);
    agree_on("cube", cube, LIMN_SCHEME_CATMARK, 0.5);
}

/* A mesh whose solve scratch passes LARGE_ALLOC_HUGE (4 MiB: 262,144 float4
   rows): on a device sharing host memory that scratch lives in limn's own
   advised host memory (device_opencl.c cl_buffer_scratch), in float and in
   double; the same bytes as the reference backend either way. */
static void large_scratch(void **s)
{
    limn_context *ctx = *s;
    limn_mesh *g = test_keep_mesh(test_mesh_grid(ctx, 560, 520, 1));
    assert_true(limn_mesh_vertex_count(g) > 262144);
    limn_context *cl = limn_context_create(), *ref = limn_context_create();
    assert_int_equal(limn_context_set_device(cl, "opencl"), LIMN_OK);
    assert_int_equal(limn_context_set_device(ref, "reference"), LIMN_OK);
    size_t n = limn_mesh_vertex_count(g);
    static const limn_precision precisions[] = {LIMN_PRECISION_FLOAT, LIMN_PRECISION_DOUBLE};
    for (int k = 0; k < 2; k++) {
        limn_interpolate_options o;
        limn_interpolate_options_default(&o);
        o.scheme = LIMN_SCHEME_LOOP;
        o.precision = precisions[k];
        limn_mesh *pa = NULL, *pb = NULL;
        limn_report ra = {.size = sizeof ra}, rb = {.size = sizeof rb};
        if (limn_interpolate(cl, g, &o, &pa, &ra) != LIMN_OK)
            fail_msg("opencl: %s", limn_context_message(cl));
        assert_int_equal(limn_interpolate(ref, g, &o, &pb, &rb), LIMN_OK);
        assert_int_equal(ra.iterations, rb.iterations);
        assert_memory_equal(limn_mesh_positions(pa), limn_mesh_positions(pb),
                            3 * n * sizeof(double));
        printf("  %zu-vertex grid, %s: bit-identical, %d iterations\n", n,
               k == 0 ? "float" : "double", ra.iterations);
        limn_mesh_destroy(pa);
        limn_mesh_destroy(pb);
    }
    limn_context_destroy(cl);
    limn_context_destroy(ref);
}

static void shared(void **s)
{
    if (!test_shared_meshes())
        skip();
    static const char *files[] = {"medium/bob_quad.obj", "medium/horse.ply", "small/cow.obj",
                                  "medium/beast.obj", "opensubdiv/catmark_car.obj"};
    limn_context *ctx = *s;
    for (size_t i = 0; i < sizeof files / sizeof *files; i++) {
        limn_mesh *m = test_read_shared(ctx, files[i]);
        agree_on(files[i], m, LIMN_SCHEME_CATMARK, 0.0);
        if (test_all_triangles(m))
            agree_on(files[i], m, LIMN_SCHEME_LOOP, 0.0);
        limn_mesh_destroy(m);
    }
}

static int run_cli(const char *env, const char *input, const char *output)
{
    char cmd[16384];
    snprintf(cmd, sizeof cmd, "%s '%s' interpolate '%s' -o '%s' -q", env, getenv("LIMN_BIN"),
             input, output);
    return system(cmd);
}

/* Same input, same bytes: two runs, 1 and 2 PoCL threads, both backends. */
static void deterministic_output(void **s)
{
    (void)s;
    char dir[64];
    assert_int_equal(test_make_dir(dir, sizeof dir, "det"), 0);
    char in[4096], o1[4096], o2[4096], o3[4096], o4[4096];
    if (test_shared_meshes())
        snprintf(in, sizeof in, "%.4000s", test_shared_path("medium/bunny_closed.off"));
    else
        snprintf(in, sizeof in, "%.4000s/spot_control_mesh.obj", getenv("LIMN_TEST_DATA"));
    snprintf(o1, sizeof o1, "%.4000s/a.ply", dir);
    snprintf(o2, sizeof o2, "%.4000s/b.ply", dir);
    snprintf(o3, sizeof o3, "%.4000s/c.ply", dir);
    snprintf(o4, sizeof o4, "%.4000s/d.ply", dir);
    assert_int_equal(run_cli("POCL_MAX_PTHREAD_COUNT=2", in, o1), 0);
    assert_int_equal(run_cli("POCL_MAX_PTHREAD_COUNT=2", in, o2), 0);
    assert_int_equal(run_cli("POCL_MAX_PTHREAD_COUNT=1", in, o3), 0);
    assert_int_equal(run_cli("LIMN_DEVICE=reference", in, o4), 0);
    assert_true(test_same_bytes(o1, o2));
    assert_true(test_same_bytes(o1, o3));
    char cmd[16384];
    snprintf(cmd, sizeof cmd, "'%s' interpolate '%s' -o '%s' -q --device reference",
             getenv("LIMN_BIN"), in, o4);
    assert_int_equal(system(cmd), 0);
    assert_true(test_same_bytes(o1, o4));
    assert_int_equal(test_remove_dir(dir), 0);
}

/* Every mesh output of the CLI is the same bytes for PoCL on 1 and 2 threads,
   on two runs, and on the reference backend: subdivide (with --limit), and
   interpolate with its surface, on a mesh with n-gons and one with
   non-manifold parts and repaired faces; STL and OFF outputs too. */
static void deterministic_cli(void **s)
{
    (void)s;
    char dir[64];
    assert_int_equal(test_make_dir(dir, sizeof dir, "det2"), 0);
    char inputs[2][4096];
    int count = 1;
    snprintf(inputs[0], sizeof inputs[0], "%.4000s/spot_control_mesh.obj", getenv("LIMN_TEST_DATA"));
    if (test_shared_meshes()) {
        snprintf(inputs[1], sizeof inputs[1], "%.4000s",
                 test_shared_path("opensubdiv/catmark_nonman_edges.obj"));
        count = 2;
    }
    static const char *const envs[] = {"POCL_MAX_PTHREAD_COUNT=2", "POCL_MAX_PTHREAD_COUNT=2",
                                       "POCL_MAX_PTHREAD_COUNT=1", "LIMN_DEVICE=reference"};
    static const char *const commands[] = {
        "subdivide '%s' -o '%s/%d.ply' --levels 2 --limit -q",
        "subdivide '%s' -o '%s/%d.off' --levels 1 --alpha 0.5 -q",
        "interpolate '%s' -o '%s/%d.ply' --surface '%s/%d_surface.stl' --levels 2 --limit -q",
    };
    for (int in = 0; in < count; in++)
        for (size_t c = 0; c < sizeof commands / sizeof *commands; c++) {
            for (int e = 0; e < 4; e++) {
                char args[8192], cmd[16384];
                snprintf(args, sizeof args, commands[c], inputs[in], dir, e, dir, e);
                snprintf(cmd, sizeof cmd, "%s '%s' %s", envs[e], getenv("LIMN_BIN"), args);
                if (system(cmd) != 0)
                    fail_msg("failed: %s", cmd);
            }
            const char *ext = c == 1 ? "off" : "ply";
            for (int e = 1; e < 4; e++) {
                char a[4200], b[4200];
                snprintf(a, sizeof a, "%s/0.%s", dir, ext);
                snprintf(b, sizeof b, "%s/%d.%s", dir, e, ext);
                if (!test_same_bytes(a, b))
                    fail_msg("%s: command %zu, run %d (%s) differs", inputs[in], c, e, envs[e]);
                if (c == 2) {
                    snprintf(a, sizeof a, "%s/0_surface.stl", dir);
                    snprintf(b, sizeof b, "%s/%d_surface.stl", dir, e);
                    if (!test_same_bytes(a, b))
                        fail_msg("%s: surface of run %d (%s) differs", inputs[in], e, envs[e]);
                }
            }
        }
    assert_int_equal(test_remove_dir(dir), 0);
}

TEST_MAIN(NULL, NULL, CONTEXT_TEST(generated), CONTEXT_TEST(shared),
          cmocka_unit_test(deterministic_output), cmocka_unit_test(deterministic_cli),
          CONTEXT_TEST(large_scratch))
