/* SPDX-License-Identifier: MIT */
/*
 * Limits of the API (issue 18.4, 18.5, 11.4): counts over their caps are
 * refused at once with a message naming the argument, its value and the cap
 * (only statuses and messages are asserted, never times); a format that
 * cannot hold the mesh is not written and what a format drops is said;
 * overflow is named as such, not as divergence; subdivide says it drops
 * vertex colours.
 */
#include "api_expect.h"

#include <limits.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

/* ------------------------------------------------------------------- caps */

static void counts_over_their_caps(void **s)
{
    limn_context *ctx = *s;
    limn_mesh *m = test_keep_mesh(test_mesh_icosahedron(ctx)), *out = NULL;
    size_t v, f, b;
    int frames = 0;
    REFUSED(ctx, limn_smooth(ctx, m, NULL, INT_MAX, &out, NULL), "limn_smooth",
            "terms is 2147483647", "cap of 10000", "LIMN_MAX_TERMS");
    REFUSED(ctx, limn_bands(ctx, m, NULL, INT_MAX, NULL, NULL, NULL), "limn_bands",
            "count is 2147483647", "LIMN_MAX_TERMS");
    REFUSED(ctx, limn_denoise(ctx, m, NULL, INT_MAX, 1, 0, &out, NULL), "limn_denoise",
            "m is 2147483647", "LIMN_MAX_TERMS");
    REFUSED(ctx, limn_denoise(ctx, m, NULL, 1, INT_MAX, 0, &out, NULL), "limn_denoise",
            "steps is 2147483647", "LIMN_MAX_STEPS");
    REFUSED(ctx, limn_denoise(ctx, m, NULL, 9999, 9999, 0, &out, NULL),
            "(m + 1) * steps is 99990000", "cap of 10000000", "LIMN_MAX_PRODUCTS");
    REFUSED(ctx, limn_sharpen(ctx, m, NULL, 0, INT_MAX, 1, &out, NULL), "limn_sharpen",
            "to is 2147483647", "LIMN_MAX_TERMS");
    REFUSED(ctx, limn_sharpen(ctx, m, NULL, 0, 2, INT_MAX, &out, NULL), "steps is 2147483647",
            "LIMN_MAX_STEPS");
    REFUSED(ctx, limn_sharpen(ctx, m, NULL, 0, 5000, 5000, &out, NULL),
            "to * steps is 25000000", "LIMN_MAX_PRODUCTS");
    limn_morph_options mo;
    limn_morph_options_default(&mo);
    mo.frames = INT_MAX;
    REFUSED(ctx, limn_morph(ctx, m, m, &mo, api_count_frame, &frames, NULL), "limn_morph",
            "frames is 2147483647", "cap of 100000", "LIMN_MAX_FRAMES");
    mo.linear = 1;
    REFUSED(ctx, limn_morph(ctx, m, m, &mo, api_count_frame, &frames, NULL), "LIMN_MAX_FRAMES");
    mo.linear = 0;
    mo.frames = 30;
    mo.m = INT_MAX;
    REFUSED(ctx, limn_morph(ctx, m, m, &mo, api_count_frame, &frames, NULL), "m is 2147483647",
            "LIMN_MAX_TERMS");
    mo.frames = 100000;
    mo.m = 1000;
    REFUSED(ctx, limn_morph(ctx, m, m, &mo, api_count_frame, &frames, NULL),
            "(m + 1) * (frames - 1) is 100098999", "LIMN_MAX_PRODUCTS");
    assert_int_equal(frames, 0);
    limn_subdivide_options so;
    limn_subdivide_options_default(&so);
    so.levels = INT_MAX;
    REFUSED(ctx, limn_subdivide(ctx, m, &so, &out, NULL), "limn_subdivide",
            "levels is 2147483647", "cap of 16", "LIMN_MAX_SUBDIVIDE_LEVELS");
    REFUSED(ctx, limn_subdivide_estimate(ctx, m, &so, &v, &f, &b), "LIMN_MAX_SUBDIVIDE_LEVELS");
    so.levels = -1;
    REFUSED(ctx, limn_subdivide(ctx, m, &so, &out, NULL), "levels is -1", "at least 0");
    limn_texture_options to;
    limn_texture_options_default(&to);
    to.colors = api_palette;
    to.color_count = 2;
    to.levels = INT_MAX;
    REFUSED(ctx, limn_texture(ctx, m, &to, &out, NULL), "limn_texture", "levels is 2147483647",
            "LIMN_MAX_TEXTURE_LEVELS");
    to.levels = 1;
    to.color_count = SIZE_MAX; /* refused before a colour is read */
    REFUSED(ctx, limn_texture(ctx, m, &to, &out, NULL), "color_count is", "LIMN_MAX_COLORS");
    limn_interpolate_options io;
    limn_interpolate_options_default(&io);
    io.max_iterations = INT_MAX;
    REFUSED(ctx, limn_interpolate(ctx, m, &io, &out, NULL), "limn_interpolate",
            "max_iterations is 2147483647", "LIMN_MAX_ITERATIONS");
    REFUSED(ctx, limn_interpolate_estimate(ctx, m, &io, 0, &b), "LIMN_MAX_ITERATIONS");
    /* at the caps themselves the arguments are accepted */
    io.max_iterations = LIMN_MAX_ITERATIONS;
    OK(ctx, limn_interpolate(ctx, m, &io, &out, NULL));
    limn_mesh_destroy(out);
    out = NULL;
    OK(ctx, limn_denoise(ctx, m, NULL, 0, 2, 0, &out, NULL));
    limn_mesh_destroy(out);
}

/* ---------------------------------------------------------------- formats */

static void formats_that_cannot_hold_the_mesh(void **s)
{
    limn_context *ctx = *s;
    double p[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    uint32_t off[1] = {0};
    limn_mesh *cloud = NULL, *empty = NULL, *back = NULL;
    OK(ctx, limn_mesh_create(ctx, 3, p, 0, off, NULL, &cloud));
    test_keep_mesh(cloud);
    OK(ctx, limn_mesh_create(ctx, 0, NULL, 0, off, NULL, &empty));
    test_keep_mesh(empty);
    const char *stl = api_scratch("cloud.stl");
    REFUSED(ctx, limn_mesh_write(ctx, cloud, stl, LIMN_FORMAT_AUTO), "limn_mesh_write",
            "STL holds triangles only", "3 vertices but no faces");
    assert_false(test_file_exists(stl));
    REFUSED(ctx, limn_mesh_write(ctx, cloud, api_scratch("cloud.bin"), LIMN_FORMAT_STL), "STL");
    /* the other formats hold a point cloud, and it reads back */
    const char *names[] = {"cloud.obj", "cloud.off", "cloud.ply", "cloud_a.ply"};
    const limn_format formats[] = {LIMN_FORMAT_OBJ, LIMN_FORMAT_OFF, LIMN_FORMAT_PLY,
                                   LIMN_FORMAT_PLY_ASCII};
    for (int k = 0; k < 4; k++) {
        const char *path = api_scratch(names[k]);
        OK(ctx, limn_mesh_write(ctx, cloud, path, formats[k]));
        OK(ctx, limn_mesh_read(ctx, path, LIMN_FORMAT_AUTO, &back));
        assert_int_equal(limn_mesh_vertex_count(back), 3);
        assert_int_equal(limn_mesh_face_count(back), 0);
        limn_mesh_destroy(back);
        back = NULL;
        /* no vertices at all: no format is read back, so none is written */
        const char *none = api_scratch(k == 0 ? "none.obj" : k == 1 ? "none.off" : "none.ply");
        REFUSED(ctx, limn_mesh_write(ctx, empty, none, formats[k]), "the mesh has no vertices");
        assert_false(test_file_exists(none));
    }
    REFUSED(ctx, limn_mesh_write(ctx, empty, api_scratch("none.stl"), LIMN_FORMAT_AUTO),
            "no vertices");
    /* what a format drops is said: colours but in PLY, STL's quads */
    limn_mesh *cube = test_keep_mesh(test_mesh_cube(ctx));
    uint8_t rgb[8 * 3] = {0};
    OK(ctx, limn_mesh_set_colors(ctx, cube, rgb));
    OK(ctx, limn_mesh_write(ctx, cube, api_scratch("cube.ply"), LIMN_FORMAT_AUTO));
    assert_string_equal(limn_context_warnings(ctx), "");
    OK(ctx, limn_mesh_write(ctx, cube, api_scratch("cube.obj"), LIMN_FORMAT_AUTO));
    assert_non_null(strstr(limn_context_warnings(ctx), "OBJ holds no vertex colours"));
    OK(ctx, limn_mesh_write(ctx, cube, api_scratch("cube.stl"), LIMN_FORMAT_AUTO));
    assert_non_null(strstr(limn_context_warnings(ctx), "STL holds no vertex colours"));
    assert_non_null(strstr(limn_context_warnings(ctx), "6 faces with more than 3 vertices"));
}

/* --------------------------------------------------------------- overflow */

static void huge_coordinates_are_named_as_overflow(void **s)
{
    limn_context *ctx = *s;
    limn_mesh *m = test_keep_mesh(test_mesh_icosahedron(ctx)), *out = NULL;
    size_t n = limn_mesh_vertex_count(m);
    double *p = limn_mesh_positions_mutable(m), *d = test_keep(malloc(3 * n * sizeof *d));
    for (size_t i = 0; i < 3 * n; i++)
        p[i] *= 1e300;
    /* Loop, where the old message blamed alpha */
    REFUSED(ctx, limn_interpolate(ctx, m, NULL, &out, NULL), "limn_interpolate",
            "coordinates too large (overflow)", "vertex");
    assert_null(strstr(limn_context_message(ctx), "alpha"));
    REFUSED(ctx, limn_smooth(ctx, m, NULL, 2, &out, NULL), "limn_smooth", "overflow");
    REFUSED(ctx, limn_subdivide(ctx, m, NULL, &out, NULL), "limn_subdivide", "overflow");
    REFUSED(ctx, limn_limit_positions(ctx, m, LIMN_SCHEME_AUTO, 0.0, d), "overflow");
    uint8_t rgb[4 * 4 * 3];
    limn_render_options ro;
    limn_render_options_default(&ro);
    ro.width = ro.height = 4;
    REFUSED(ctx, limn_render(ctx, m, &ro, rgb), "limn_render", "overflow");
    limn_interpolate_options io;
    limn_interpolate_options_default(&io);
    io.method = LIMN_METHOD_CG;
    REFUSED(ctx, limn_interpolate(ctx, m, &io, &out, NULL), "overflow");
    assert_null(out);
    /* large but inside double: the input passes, the float corrections
       overflow, and the message says so and what to do */
    for (size_t i = 0; i < 3 * n; i++)
        p[i] *= 1e-300 * 1e42;
    io.method = LIMN_METHOD_CHEBYSHEV;
    io.precision = LIMN_PRECISION_FLOAT;
    EXPECT(ctx, limn_interpolate(ctx, m, &io, &out, NULL), LIMN_ERR_NO_CONVERGENCE,
           "non-finite values in the iteration (overflow?)", "--precision double");
    assert_null(strstr(limn_context_message(ctx), "6/7"));
    assert_null(out);
    io.precision = LIMN_PRECISION_DOUBLE;
    OK(ctx, limn_interpolate(ctx, m, &io, &out, NULL));
    limn_mesh_destroy(out);
}

/* ---------------------------------------------------------------- colours */

static void subdivide_names_dropped_colours(void **s)
{
    limn_context *ctx = *s;
    limn_mesh *m = test_keep_mesh(test_mesh_icosahedron(ctx)), *out = NULL;
    uint8_t rgb[12 * 3];
    for (size_t i = 0; i < sizeof rgb; i++)
        rgb[i] = (uint8_t)(i * 7);
    OK(ctx, limn_mesh_set_colors(ctx, m, rgb));
    OK(ctx, limn_subdivide(ctx, m, NULL, &out, NULL));
    assert_null(limn_mesh_colors(out));
    assert_non_null(strstr(limn_context_warnings(ctx), "vertex colours were dropped"));
    limn_mesh_destroy(out);
    limn_subdivide_options so;
    limn_subdivide_options_default(&so);
    so.levels = 0; /* the mesh itself: its colours are kept, no warning */
    OK(ctx, limn_subdivide(ctx, m, &so, &out, NULL));
    assert_non_null(limn_mesh_colors(out));
    assert_null(strstr(limn_context_warnings(ctx), "colours"));
    limn_mesh_destroy(out);
    OK(ctx, limn_mesh_set_colors(ctx, m, NULL));
    OK(ctx, limn_subdivide(ctx, m, NULL, &out, NULL));
    assert_string_equal(limn_context_warnings(ctx), "");
    limn_mesh_destroy(out);
}

TEST_MAIN(api_make_dir, api_remove_dir, REFERENCE_TEST(counts_over_their_caps),
          CONTEXT_TEST(formats_that_cannot_hold_the_mesh),
          REFERENCE_TEST(huge_coordinates_are_named_as_overflow),
          REFERENCE_TEST(subdivide_names_dropped_colours))
