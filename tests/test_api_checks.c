/* SPDX-License-Identifier: MIT */
/*
 * Every public entry point checks its values (issue 18.4): non-finite
 * coordinates, from limn_mesh_create or written later through
 * limn_mesh_positions_mutable, are refused by each operation that uses them,
 * naming the vertex, with nothing written; unknown enum values, zero-length
 * and NULL buffers are refused with a message naming them; every failure
 * carries a message. Caps, formats and overflow: test_api_limits.c.
 */
#include "api_expect.h"
#include "shell.h"

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

/* ---------------------------------------------------- non-finite positions */

static void create_names_the_vertex(void **s)
{
    limn_context *ctx = *s;
    double p[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    uint32_t off[2] = {0, 3}, idx[3] = {0, 1, 2};
    limn_mesh *m = (limn_mesh *)&m;
    p[7] = NAN;
    REFUSED(ctx, limn_mesh_create(ctx, 4, p, 1, off, idx, &m), "limn_mesh_create",
            "vertex 2", "y = nan");
    assert_null(m);
    p[7] = 1.0;
    p[11] = -INFINITY;
    REFUSED(ctx, limn_mesh_create(ctx, 4, p, 1, off, idx, &m), "vertex 3", "z = -inf");
    p[11] = 1.0;
    p[0] = INFINITY;
    REFUSED(ctx, limn_mesh_create(ctx, 4, p, 0, off, idx, &m), "vertex 0", "x = inf");
    assert_null(m);
    /* the same check for new positions given in place */
    p[0] = 0.0;
    OK(ctx, limn_mesh_create(ctx, 4, p, 1, off, idx, &m));
    p[5] = NAN;
    REFUSED(ctx, limn_mesh_set_positions(ctx, m, p, 4), "limn_mesh_set_positions", "vertex 1",
            "z = nan");
    assert_true(limn_mesh_positions(m)[5] == 0.0);
    limn_mesh_destroy(m);
}

/* One NaN or Inf written through limn_mesh_positions_mutable: every
   operation that uses positions refuses, names vertex 4, writes nothing. */
static void mutable_edits_are_checked(void **s)
{
    (void)s;
    const double bad[3] = {NAN, INFINITY, -INFINITY};
    for (int b = 0; b < 3; b++) {
        limn_context *ctx = test_keep_context(api_reference_context());
        limn_mesh *m = test_keep_mesh(test_mesh_icosahedron(ctx));
        limn_mesh *good = test_keep_mesh(test_mesh_icosahedron(ctx));
        size_t n = limn_mesh_vertex_count(m);
        limn_mesh_positions_mutable(m)[3 * 4 + 1] = bad[b];
        const char *says = b == 0 ? "y = nan" : b == 1 ? "y = inf" : "y = -inf";
        limn_mesh *out = NULL;
        double *buf = test_keep(malloc(4 * 3 * n * sizeof *buf));
        for (size_t i = 0; i < 4 * 3 * n; i++)
            buf[i] = -7.0;
        double energy[4] = {-7, -7, -7, -7};
        uint8_t rgb[4 * 4 * 3] = {0};
        int frames = 0;

        REFUSED(ctx, limn_interpolate(ctx, m, NULL, &out, NULL), "limn_interpolate", "vertex 4",
                says);
        REFUSED(ctx, limn_subdivide(ctx, m, NULL, &out, NULL), "limn_subdivide", "vertex 4", says);
        REFUSED(ctx, limn_limit_positions(ctx, m, LIMN_SCHEME_AUTO, 0.0, buf),
                "limn_limit_positions", "vertex 4", says);
        REFUSED(ctx, limn_bands(ctx, m, NULL, 2, buf, energy, NULL), "limn_bands", "vertex 4",
                says);
        REFUSED(ctx, limn_smooth(ctx, m, NULL, 2, &out, NULL), "limn_smooth", "vertex 4", says);
        REFUSED(ctx, limn_denoise(ctx, m, NULL, 1, 1, 0, &out, NULL), "limn_denoise",
                "vertex 4", says);
        REFUSED(ctx, limn_sharpen(ctx, m, NULL, 0, 1, 1, &out, NULL), "limn_sharpen",
                "vertex 4", says);
        REFUSED(ctx, limn_denoise_features(ctx, m, NULL, &out, NULL), "limn_denoise_features",
                "vertex 4", says);
        REFUSED(ctx, limn_morph(ctx, m, good, NULL, api_count_frame, &frames, NULL), "limn_morph",
                "FROM", "vertex 4", says);
        REFUSED(ctx, limn_morph(ctx, good, m, NULL, api_count_frame, &frames, NULL), "limn_morph",
                "TO", "vertex 4", says);
        limn_morph_options mo;
        limn_morph_options_default(&mo);
        mo.linear = 1;
        REFUSED(ctx, limn_morph(ctx, good, m, &mo, api_count_frame, &frames, NULL), "vertex 4");
        limn_texture_options to;
        limn_texture_options_default(&to);
        to.levels = 1;
        to.colors = api_palette;
        to.color_count = 2;
        REFUSED(ctx, limn_texture(ctx, m, &to, &out, NULL), "limn_texture", "vertex 4", says);
        limn_render_options ro;
        limn_render_options_default(&ro);
        ro.width = ro.height = 4;
        ro.supersample = 1;
        REFUSED(ctx, limn_render(ctx, m, &ro, rgb), "limn_render", "vertex 4", says);
        limn_mesh_measures meas = {.size = sizeof meas};
        REFUSED(ctx, limn_mesh_measure(ctx, m, &meas), "limn_mesh_measure", "vertex 4", says);
        limn_mesh_comparison cmp = {.size = sizeof cmp};
        REFUSED(ctx, limn_mesh_compare(ctx, good, m, &cmp), "limn_mesh_compare", "vertex 4",
                says);
        limn_mesh_info info = {.size = sizeof info};
        REFUSED(ctx, limn_mesh_info_compute(ctx, m, &info), "limn_mesh_info_compute",
                "vertex 4", says);
        const char *formats[] = {"m.obj", "m.ply", "m.off", "m.stl"};
        for (int f = 0; f < 4; f++) {
            const char *path = api_scratch(formats[f]);
            REFUSED(ctx, limn_mesh_write(ctx, m, path, LIMN_FORMAT_AUTO), "limn_mesh_write",
                    "vertex 4", says);
            assert_false(test_file_exists(path));
        }
        /* nothing written anywhere */
        assert_null(out);
        assert_int_equal(frames, 0);
        for (size_t i = 0; i < 4 * 3 * n; i++)
            assert_true(buf[i] == -7.0);
        for (int i = 0; i < 4; i++)
            assert_true(energy[i] == -7.0);
        for (size_t i = 0; i < sizeof rgb; i++)
            assert_int_equal(rgb[i], 0);
        /* repaired positions are accepted again */
        limn_mesh_positions_mutable(m)[3 * 4 + 1] = limn_mesh_positions(good)[3 * 4 + 1];
        OK(ctx, limn_limit_positions(ctx, m, LIMN_SCHEME_AUTO, 0.0, buf));
    }
}

/* ------------------------------------------------------------------- enums */

/* The default interpolate options with the method or the precision (what)
   set to value: limn_interpolate refuses them naming both, and so does the
   estimate when asked to check it. */
static void refused_interpolate(limn_context *ctx, const limn_mesh *m, const char *what, int value,
                                int estimate)
{
    limn_interpolate_options io;
    limn_interpolate_options_default(&io);
    if (strcmp(what, "method") == 0)
        io.method = (limn_method)value;
    else
        io.precision = (limn_precision)value;
    char says[64];
    snprintf(says, sizeof says, "unknown %s %d", what, value);
    limn_mesh *out = NULL;
    size_t b;
    REFUSED(ctx, limn_interpolate(ctx, m, &io, &out, NULL), says);
    if (estimate)
        REFUSED(ctx, limn_interpolate_estimate(ctx, m, &io, 0, &b), says);
}

static void unknown_enums_are_refused(void **s)
{
    limn_context *ctx = *s;
    limn_mesh *m = test_mesh_icosahedron(ctx), *out = NULL;
    size_t n = limn_mesh_vertex_count(m), v, f, b;
    double *buf = calloc(3 * n, sizeof *buf);
    const int schemes[] = {99, -1, 3};
    for (int k = 0; k < 3; k++) {
        limn_scheme bad = (limn_scheme)schemes[k];
        char says[32];
        snprintf(says, sizeof says, "unknown scheme %d", schemes[k]);
        limn_interpolate_options io;
        limn_interpolate_options_default(&io);
        io.scheme = bad;
        REFUSED(ctx, limn_interpolate(ctx, m, &io, &out, NULL), "limn_interpolate", says);
        REFUSED(ctx, limn_interpolate_estimate(ctx, m, &io, 0, &b), says);
        limn_subdivide_options so;
        limn_subdivide_options_default(&so);
        so.scheme = bad;
        REFUSED(ctx, limn_subdivide(ctx, m, &so, &out, NULL), "limn_subdivide", says);
        REFUSED(ctx, limn_subdivide_estimate(ctx, m, &so, &v, &f, &b), "limn_subdivide_estimate",
                says);
        REFUSED(ctx, limn_limit_positions(ctx, m, bad, 0.0, buf), "limn_limit_positions", says);
        limn_series_options se;
        limn_series_options_default(&se);
        se.scheme = bad;
        REFUSED(ctx, limn_bands(ctx, m, &se, 1, NULL, NULL, NULL), "limn_bands", says);
        REFUSED(ctx, limn_smooth(ctx, m, &se, 1, &out, NULL), "limn_smooth", says);
        REFUSED(ctx, limn_denoise(ctx, m, &se, 1, 1, 0, &out, NULL), "limn_denoise", says);
        REFUSED(ctx, limn_sharpen(ctx, m, &se, 0, 1, 1, &out, NULL), "limn_sharpen", says);
        limn_morph_options mo;
        limn_morph_options_default(&mo);
        mo.series.scheme = bad;
        int frames = 0;
        REFUSED(ctx, limn_morph(ctx, m, m, &mo, api_count_frame, &frames, NULL), "limn_morph",
                says);
        assert_int_equal(frames, 0);
        limn_texture_options to;
        limn_texture_options_default(&to);
        to.series.scheme = bad;
        to.colors = api_palette;
        to.color_count = 2;
        REFUSED(ctx, limn_texture(ctx, m, &to, &out, NULL), "limn_texture", says);
        assert_string_equal(limn_scheme_name(bad), "unknown");
    }
    refused_interpolate(ctx, m, "method", 99, 1);
    refused_interpolate(ctx, m, "method", -1, 0);
    refused_interpolate(ctx, m, "precision", 99, 1);
    refused_interpolate(ctx, m, "precision", -1, 0);
    assert_string_equal(limn_method_name((limn_method)99), "unknown");
    assert_string_equal(limn_precision_name((limn_precision)99), "unknown");
    assert_string_equal(limn_status_name((limn_status)99), "LIMN_ERR_UNKNOWN");

    const char *path = api_scratch("e.ply");
    REFUSED(ctx, limn_mesh_write(ctx, m, path, (limn_format)99), "unknown format 99");
    REFUSED(ctx, limn_mesh_write(ctx, m, path, (limn_format)-1), "unknown format -1");
    assert_false(test_file_exists(path));
    OK(ctx, limn_mesh_write(ctx, m, path, LIMN_FORMAT_PLY));
    limn_mesh *back = NULL;
    REFUSED(ctx, limn_mesh_read(ctx, path, (limn_format)99, &back), "unknown format 99");
    assert_null(back);
    limn_format fmt = LIMN_FORMAT_OFF;
    assert_int_equal(limn_format_from_name("nope", &fmt), 0);
    assert_int_equal(fmt, LIMN_FORMAT_OFF);

    /* device kinds and the fallback: strings, checked the same way */
    REFUSED(ctx, limn_context_set_device(ctx, "gpu"), "unknown device 'gpu'");
    REFUSED(ctx, limn_context_set_fallback(ctx, "opencl"), "unknown fallback 'opencl'");
    REFUSED(ctx, limn_context_set_threads(ctx, -2), "-2 is not a thread count");
    assert_null(out);
    free(buf);
    limn_mesh_destroy(m);
}

/* ------------------------------------------------------- buffers and NULLs */

static void zero_length_and_null_buffers(void **s)
{
    limn_context *ctx = *s;
    char text[16] = "untouched";
    REFUSED(ctx, limn_list_devices(ctx, text, 0), "limn_list_devices", "buf_size is 0");
    assert_string_equal(text, "untouched");
    REFUSED(ctx, limn_list_devices(ctx, NULL, 100), "limn_list_devices", "buf is NULL");
    assert_null(strstr(limn_context_message(ctx), "buf_size"));
    int threads = -5;
    const char *source = NULL;
    REFUSED(ctx, limn_context_threads(ctx, NULL, NULL), "limn_context_threads",
            "threads is NULL");
    REFUSED(ctx, limn_context_threads(ctx, &threads, NULL), "source is NULL");
    REFUSED(ctx, limn_context_threads(ctx, NULL, &source), "threads is NULL");
    assert_int_equal(threads, -5);
    assert_null(source);

    limn_mesh *m = test_mesh_icosahedron(ctx);
    double d[3];
    uint32_t u[4];
    uint8_t c[3];
    REFUSED(ctx, limn_mesh_copy_positions(ctx, m, d, 0), "holds 0 vertices");
    REFUSED(ctx, limn_mesh_copy_faces(ctx, m, u, 0, u, 0), "hold 0 offsets and 0 indices");
    uint8_t rgb[36] = {0};
    OK(ctx, limn_mesh_set_colors(ctx, m, rgb));
    REFUSED(ctx, limn_mesh_copy_colors(ctx, m, c, 0), "holds 0 vertices");
    REFUSED(ctx, limn_png_write(ctx, api_scratch("x.png"), 0, 1, rgb), "picture size 0x1");
    REFUSED(ctx, limn_png_write(ctx, api_scratch("x.png"), 1, 1, NULL), "rgb is NULL");
    REFUSED(ctx, limn_png_write(ctx, "", 1, 1, rgb), "no file name");
    assert_false(test_file_exists(api_scratch("x.png")));
    /* staged: the same refusals, then nothing until the commit, which gives
       limn_png_write's bytes */
    limn_output_set *set = NULL;
    OK(ctx, limn_output_set_create(ctx, &set));
    REFUSED(ctx, limn_output_set_add_png(ctx, NULL, api_scratch("x.png"), 1, 1, rgb),
            "set is NULL");
    REFUSED(ctx, limn_output_set_add_png(ctx, set, api_scratch("x.png"), 0, 1, rgb),
            "limn_output_set_add_png", "picture size 0x1");
    OK(ctx, limn_output_set_add_png(ctx, set, api_scratch("x.png"), 2, 2, rgb));
    assert_false(test_file_exists(api_scratch("x.png")));
    OK(ctx, limn_output_set_commit(ctx, set));
    limn_output_set_destroy(set);
    OK(ctx, limn_png_write(ctx, api_scratch("y.png"), 2, 2, rgb));
    assert_true(test_same_bytes(api_scratch("x.png"), api_scratch("y.png")));
    limn_mesh_destroy(m);
}

/* Every error path reachable from the API carries a non-empty message. */
static void every_error_has_a_message(void **s)
{
    limn_context *ctx = *s;
    limn_mesh *m = test_mesh_icosahedron(ctx), *cube = test_mesh_cube(ctx), *out = NULL;
    size_t n = limn_mesh_vertex_count(m), v, f, b;
    double *d = calloc(3 * n, sizeof *d);
    uint8_t rgb[12];
    char text[8];
    int threads;
    limn_mesh_info info = {.size = sizeof info};
    limn_mesh_measures meas = {.size = sizeof meas};
    limn_mesh_comparison cmp = {.size = sizeof cmp};
    limn_interpolate_options io;
    limn_interpolate_options_default(&io);
    limn_subdivide_options so;
    limn_subdivide_options_default(&so);
    limn_texture_options to;
    limn_texture_options_default(&to);
    limn_morph_options mo;
    limn_morph_options_default(&mo);
    limn_render_options ro;
    limn_render_options_default(&ro);

    FAILS(ctx, limn_context_threads(ctx, &threads, NULL));
    FAILS(ctx, limn_list_devices(ctx, text, 0));
    FAILS(ctx, limn_list_devices(ctx, NULL, 8));
    FAILS(ctx, limn_context_set_device(ctx, "x"));
    FAILS(ctx, limn_context_set_fallback(ctx, "x"));
    FAILS(ctx, limn_context_set_threads(ctx, INT_MAX));
    FAILS(ctx, limn_mesh_create(ctx, 1, NULL, 0, NULL, NULL, &out));
    FAILS(ctx, limn_mesh_create(ctx, 0, NULL, 0, NULL, NULL, NULL));
    FAILS(ctx, limn_mesh_copy(ctx, NULL, &out));
    FAILS(ctx, limn_mesh_copy(ctx, m, NULL));
    FAILS(ctx, limn_mesh_set_colors(ctx, NULL, rgb));
    FAILS(ctx, limn_mesh_copy_positions(ctx, NULL, d, n));
    FAILS(ctx, limn_mesh_copy_faces(ctx, m, NULL, 0, NULL, 0));
    FAILS(ctx, limn_mesh_copy_colors(ctx, m, rgb, 4)); /* no colours */
    FAILS(ctx, limn_mesh_set_positions(ctx, m, d, n + 1));
    FAILS(ctx, limn_mesh_read(ctx, NULL, LIMN_FORMAT_AUTO, &out));
    FAILS(ctx, limn_mesh_read(ctx, "x.obj", LIMN_FORMAT_AUTO, NULL));
    FAILS(ctx, limn_mesh_read(ctx, api_scratch("missing.obj"), LIMN_FORMAT_AUTO, &out));
    FAILS(ctx, limn_mesh_read(ctx, api_scratch("noext"), LIMN_FORMAT_AUTO, &out));
    FAILS(ctx, limn_mesh_write(ctx, m, NULL, LIMN_FORMAT_AUTO));
    FAILS(ctx, limn_mesh_write(ctx, m, api_scratch("x.xyz"), LIMN_FORMAT_AUTO));
    FAILS(ctx, limn_mesh_write(ctx, m, "/nonexistent-dir/x.ply", LIMN_FORMAT_AUTO));
    FAILS(ctx, limn_mesh_repair(ctx, NULL, NULL, NULL));
    FAILS(ctx, limn_mesh_info_compute(ctx, m, NULL));
    FAILS(ctx, limn_mesh_measure(ctx, NULL, &meas));
    FAILS(ctx, limn_mesh_same_topology(ctx, m, cube));
    FAILS(ctx, limn_mesh_compare(ctx, m, cube, &cmp));
    FAILS(ctx, limn_interpolate(ctx, m, NULL, NULL, NULL));
    io.alpha = 2.0;
    FAILS(ctx, limn_interpolate(ctx, m, &io, &out, NULL));
    io.alpha = 0.0;
    io.tolerance = -1.0;
    FAILS(ctx, limn_interpolate(ctx, m, &io, &out, NULL));
    io.tolerance = 1e-6;
    io.max_iterations = 0;
    FAILS(ctx, limn_interpolate(ctx, m, &io, &out, NULL));
    io.max_iterations = 1000;
    io.method = LIMN_METHOD_CG;
    io.precision = LIMN_PRECISION_FLOAT;
    FAILS(ctx, limn_interpolate(ctx, m, &io, &out, NULL));
    FAILS(ctx, limn_interpolate_estimate(ctx, m, NULL, 1, &b)); /* over 1 byte */
    FAILS(ctx, limn_interpolate_estimate(ctx, NULL, NULL, 0, &b));
    io.method = LIMN_METHOD_PAPER;
    io.precision = LIMN_PRECISION_DOUBLE;
    io.max_iterations = 1;
    io.tolerance = 1e-12;
    FAILS(ctx, limn_interpolate(ctx, m, &io, &out, NULL)); /* the iteration cap */
    io.scheme = LIMN_SCHEME_LOOP;
    FAILS(ctx, limn_interpolate(ctx, cube, &io, &out, NULL)); /* quads */
    so.max_memory = 1;
    FAILS(ctx, limn_subdivide(ctx, m, &so, &out, NULL));
    FAILS(ctx, limn_subdivide_estimate(ctx, m, &so, &v, &f, &b));
    FAILS(ctx, limn_subdivide_estimate(ctx, m, NULL, &v, &f, &b));
    so.max_memory = 0;
    so.alpha = -1;
    FAILS(ctx, limn_subdivide(ctx, m, &so, &out, NULL));
    FAILS(ctx, limn_limit_positions(ctx, m, LIMN_SCHEME_AUTO, 2.0, d));
    FAILS(ctx, limn_limit_positions(ctx, cube, LIMN_SCHEME_LOOP, 0.0, d));
    FAILS(ctx, limn_bands(ctx, m, NULL, -1, NULL, NULL, NULL));
    FAILS(ctx, limn_smooth(ctx, m, NULL, 0, &out, NULL));
    FAILS(ctx, limn_denoise(ctx, m, NULL, -1, 1, 0, &out, NULL));
    FAILS(ctx, limn_denoise(ctx, m, NULL, 1, 0, 0, &out, NULL));
    FAILS(ctx, limn_sharpen(ctx, m, NULL, 2, 1, 1, &out, NULL));
    FAILS(ctx, limn_sharpen(ctx, m, NULL, 0, 1, 0, &out, NULL));
    mo.frames = 1;
    FAILS(ctx, limn_morph(ctx, m, m, &mo, api_count_frame, &threads, NULL));
    mo.frames = 3;
    mo.p = 1.5;
    FAILS(ctx, limn_morph(ctx, m, m, &mo, api_count_frame, &threads, NULL));
    mo.p = 0.5;
    FAILS(ctx, limn_morph(ctx, m, cube, &mo, api_count_frame, &threads, NULL));
    FAILS(ctx, limn_texture(ctx, m, &to, &out, NULL)); /* no colours */
    to.colors = api_palette;
    to.color_count = 2;
    to.frequency = 0;
    FAILS(ctx, limn_texture(ctx, m, &to, &out, NULL));
    to.frequency = 4;
    to.tolerance = 0;
    FAILS(ctx, limn_texture(ctx, m, &to, &out, NULL));
    ro.width = 0;
    FAILS(ctx, limn_render(ctx, m, &ro, rgb));
    ro.width = 4;
    ro.supersample = 9;
    FAILS(ctx, limn_render(ctx, m, &ro, rgb));
    ro.supersample = 1;
    ro.up_axis = 5;
    FAILS(ctx, limn_render(ctx, m, &ro, rgb));
    ro.up_axis = 1;
    ro.azimuth = NAN;
    FAILS(ctx, limn_render(ctx, m, &ro, rgb));
    FAILS(ctx, limn_png_write(ctx, NULL, 1, 1, rgb));
    assert_null(out);
    (void)info;
    free(d);
    limn_mesh_destroy(m);
    limn_mesh_destroy(cube);
}

TEST_MAIN(api_make_dir, api_remove_dir, CONTEXT_TEST(create_names_the_vertex),
          KEEP_TEST(mutable_edits_are_checked), REFERENCE_TEST(unknown_enums_are_refused),
          CONTEXT_TEST(zero_length_and_null_buffers), REFERENCE_TEST(every_error_has_a_message))
