/* SPDX-License-Identifier: MIT */
/*
 * The ABI rule of limn.h's options and report structs (issue 12.5): every
 * one begins with `size_t size`; the library refuses a size of 0, options
 * smaller than the first released layout and larger ones whose extra bytes
 * are set, accepts larger ones whose extra bytes are zero, reads older
 * (shorter) options over its defaults, and never writes a report past the
 * caller's size (a canary after a truncated struct stays intact, also under
 * ASan: scripts/sanitize.sh).
 */
#include "base/abi.h"
#include "api_expect.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

/* Room for a struct and what a newer caller might add after it. */
#define EXTRA 64
#define CANARY 0xA5

/* A caller's struct of `size` bytes at the start of a bigger buffer whose
   other bytes are the canary. */
typedef struct big {
    _Alignas(max_align_t) unsigned char b[1024 + EXTRA];
} big;

static void set_size(void *p, size_t n)
{
    memcpy(p, &n, sizeof n);
}

static int canary_intact(const big *g, size_t from)
{
    for (size_t i = from; i < sizeof g->b; i++)
        if (g->b[i] != CANARY)
            return 0;
    return 1;
}

/* ------------------------------------------------------------- options */

/*
 * The checks every options struct takes, through one entry point: `call`
 * runs it on the caller bytes `p` (the struct filled by its defaults
 * function, then resized). lib: the library's sizeof; last: offsetof its
 * last field (a size there cuts the first released layout short).
 */
typedef limn_status (*options_call)(limn_context *ctx, const limn_mesh *mesh, const void *p);

static void options_checks(const char *fn, const char *type, const char *init, size_t lib,
                           size_t last, void (*fill)(void *), options_call call)
{
    limn_context *ctx = api_reference_context();
    limn_mesh *mesh = test_mesh_cube(ctx);
    assert_non_null(mesh);
    big g;
    memset(&g, 0, sizeof g);
    fill(g.b);
    size_t n;
    memcpy(&n, g.b, sizeof n);
    assert_int_equal(n, lib); /* the defaults function sets the size */
    OK(ctx, call(ctx, mesh, g.b));

    char msg[160];
    snprintf(msg, sizeof msg, "%s: options->size is 0: initialise options with %s", fn, init);
    set_size(g.b, 0);
    REFUSED(ctx, call(ctx, mesh, g.b), msg);

    set_size(g.b, last);
    REFUSED(ctx, call(ctx, mesh, g.b), fn, "smaller than the first released", type, init);
    set_size(g.b, (size_t)1 << 20);
    REFUSED(ctx, call(ctx, mesh, g.b), fn, "no size of a", type);

    /* a newer caller asking nothing new: extra bytes zero */
    set_size(g.b, lib + EXTRA);
    OK(ctx, call(ctx, mesh, g.b));
    /* ... and one asking for an option this library lacks */
    g.b[lib + 5] = 1;
    char byte[64];
    snprintf(byte, sizeof byte, "byte %zu of the caller's is set", lib + 5);
    REFUSED(ctx, call(ctx, mesh, g.b), fn, type, byte, "newer limn.h");
    limn_mesh_destroy(mesh);
    limn_context_destroy(ctx);
}

static void fill_repair(void *p)
{
    limn_repair_options_default(p);
}
static limn_status call_repair(limn_context *ctx, const limn_mesh *mesh, const void *p)
{
    limn_mesh *m = NULL;
    limn_status st = limn_mesh_copy(ctx, mesh, &m);
    if (!st)
        st = limn_mesh_repair(ctx, m, p, NULL);
    limn_mesh_destroy(m);
    return st;
}

static void fill_interpolate(void *p)
{
    limn_interpolate_options_default(p);
}
static limn_status call_interpolate(limn_context *ctx, const limn_mesh *mesh, const void *p)
{
    size_t peak;
    limn_status st = limn_interpolate_estimate(ctx, mesh, p, 0, &peak);
    if (st)
        return st;
    limn_mesh *control = NULL;
    st = limn_interpolate(ctx, mesh, p, &control, NULL);
    limn_mesh_destroy(control);
    return st;
}

static void fill_subdivide(void *p)
{
    limn_subdivide_options_default(p);
}
static limn_status call_subdivide(limn_context *ctx, const limn_mesh *mesh, const void *p)
{
    size_t v, f, peak;
    limn_status st = limn_subdivide_estimate(ctx, mesh, p, &v, &f, &peak);
    if (st)
        return st;
    limn_mesh *out = NULL;
    st = limn_subdivide(ctx, mesh, p, &out, NULL);
    limn_mesh_destroy(out);
    return st;
}

static void fill_series(void *p)
{
    limn_series_options_default(p);
}
static limn_status call_series(limn_context *ctx, const limn_mesh *mesh, const void *p)
{
    limn_mesh *out = NULL;
    double energy[3];
    limn_status st = limn_bands(ctx, mesh, p, 2, NULL, energy, NULL);
    if (!st)
        st = limn_smooth(ctx, mesh, p, 2, &out, NULL);
    limn_mesh_destroy(out);
    out = NULL;
    if (!st)
        st = limn_denoise(ctx, mesh, p, 1, 1, 0, &out, NULL);
    limn_mesh_destroy(out);
    out = NULL;
    if (!st)
        st = limn_sharpen(ctx, mesh, p, 0, 1, 1, &out, NULL);
    limn_mesh_destroy(out);
    return st;
}

static void fill_morph(void *p)
{
    limn_morph_options *o = p;
    limn_morph_options_default(o);
    o->frames = 3;
}
static limn_status call_morph(limn_context *ctx, const limn_mesh *mesh, const void *p)
{
    int frames = 0;
    return limn_morph(ctx, mesh, mesh, p, api_count_frame, &frames, NULL);
}

static void fill_texture(void *p)
{
    limn_texture_options *o = p;
    limn_texture_options_default(o);
    o->series.alpha = 0.5; /* the cube's operator is singular at alpha 0 */
    o->levels = 1;
    o->colors = api_palette;
    o->color_count = 2;
}
static limn_status call_texture(limn_context *ctx, const limn_mesh *mesh, const void *p)
{
    limn_mesh *out = NULL;
    limn_status st = limn_texture(ctx, mesh, p, &out, NULL);
    limn_mesh_destroy(out);
    return st;
}

static void fill_feature(void *p)
{
    limn_feature_options *o = p;
    limn_feature_options_default(o);
    o->normal_steps = 2;
    o->vertex_steps = 2;
}
static limn_status call_feature(limn_context *ctx, const limn_mesh *mesh, const void *p)
{
    limn_mesh *out = NULL;
    limn_status st = limn_denoise_features(ctx, mesh, p, &out, NULL);
    limn_mesh_destroy(out);
    return st;
}

static void fill_render(void *p)
{
    limn_render_options *o = p;
    limn_render_options_default(o);
    o->width = 16;
    o->height = 12;
}
static limn_status call_render(limn_context *ctx, const limn_mesh *mesh, const void *p)
{
    uint8_t rgb[16 * 12 * 3];
    return limn_render(ctx, mesh, p, rgb);
}

#define OPTIONS_TEST(name, T, fn, last)                                                            \
    static void name(void **s)                                                                     \
    {                                                                                              \
        (void)s;                                                                                   \
        options_checks(fn, #T, #T "_default()", sizeof(T), offsetof(T, last), fill_##name,         \
                       call_##name);                                                               \
    }
OPTIONS_TEST(repair, limn_repair_options, "limn_mesh_repair", duplicate_faces)
OPTIONS_TEST(interpolate, limn_interpolate_options, "limn_interpolate_estimate", precision)
OPTIONS_TEST(subdivide, limn_subdivide_options, "limn_subdivide_estimate", max_memory)
OPTIONS_TEST(series, limn_series_options, "limn_bands", alpha)
OPTIONS_TEST(morph, limn_morph_options, "limn_morph", linear)
OPTIONS_TEST(texture, limn_texture_options, "limn_texture", max_memory)
OPTIONS_TEST(render, limn_render_options, "limn_render", color)
OPTIONS_TEST(feature, limn_feature_options, "limn_denoise_features", keep_volume)

/* Every defaults function sets size to the struct as compiled (also the
   embedded series of morph and texture). */
static void defaults_set_size(void **s)
{
    (void)s;
    limn_repair_options a;
    limn_interpolate_options b;
    limn_subdivide_options c;
    limn_series_options d;
    limn_morph_options e;
    limn_texture_options f;
    limn_render_options g;
    limn_feature_options h;
    limn_feature_options_default(&h);
    assert_int_equal(h.size, sizeof h);
    limn_repair_options_default(&a);
    limn_interpolate_options_default(&b);
    limn_subdivide_options_default(&c);
    limn_series_options_default(&d);
    limn_morph_options_default(&e);
    limn_texture_options_default(&f);
    limn_render_options_default(&g);
    assert_int_equal(a.size, sizeof a);
    assert_int_equal(b.size, sizeof b);
    assert_int_equal(c.size, sizeof c);
    assert_int_equal(d.size, sizeof d);
    assert_int_equal(e.size, sizeof e);
    assert_int_equal(e.series.size, sizeof e.series);
    assert_int_equal(f.size, sizeof f);
    assert_int_equal(f.series.size, sizeof f.series);
    assert_int_equal(g.size, sizeof g);
}

/* The embedded series struct is checked by its own size. */
static void embedded_series_size(void **s)
{
    limn_context *ctx = *s;
    limn_mesh *mesh = test_mesh_cube(ctx);
    limn_morph_options mo;
    fill_morph(&mo);
    mo.series.size = 0;
    REFUSED(ctx, call_morph(ctx, mesh, &mo),
            "limn_morph: options->series.size is 0: initialise options->series with "
            "limn_series_options_default()");
    limn_texture_options to;
    fill_texture(&to);
    to.series.size = 3;
    REFUSED(ctx, call_texture(ctx, mesh, &to), "limn_texture", "options->series.size is 3",
            "smaller than the first released limn_series_options");
    limn_mesh_destroy(mesh);
}

/*
 * A caller built against a newer limn.h whose series options grew by 16
 * bytes: its morph fields sit 16 bytes further on, and the library still
 * finds them (the frame count it asked for is the one run); a set byte in
 * the series' extra room is refused naming options->series.
 */
static void embedded_series_newer(void **s)
{
    limn_context *ctx = *s;
    limn_mesh *mesh = test_mesh_cube(ctx);
    limn_morph_options mo;
    fill_morph(&mo);
    mo.frames = 4;
    big g;
    memset(&g, 0, sizeof g);
    const size_t grow = 16, at = sizeof(size_t), series = sizeof mo.series;
    memcpy(g.b, &mo, at + series);
    memcpy(g.b + at + series + grow, (unsigned char *)&mo + at + series, sizeof mo - at - series);
    set_size(g.b, sizeof mo + grow);
    set_size(g.b + at, series + grow);
    int frames = 0;
    OK(ctx, limn_morph(ctx, mesh, mesh, (const limn_morph_options *)g.b, api_count_frame, &frames,
                       NULL));
    assert_int_equal(frames, 4);
    g.b[at + series + 3] = 7;
    REFUSED(ctx,
            limn_morph(ctx, mesh, mesh, (const limn_morph_options *)g.b, api_count_frame, &frames,
                       NULL),
            "limn_morph: options->series.size is", "limn_series_options", "is set");
    limn_mesh_destroy(mesh);
}

/*
 * The mechanism for older options (the next release will take this
 * release's layout so): a caller's struct cut short before its last field
 * is read over the library's defaults, which the missing field keeps. The
 * public entry points refuse such a size today (it is below the first
 * released layout), so this drives abi_options_in with a layout whose first
 * release ended one field earlier.
 */
static void older_options_get_defaults(void **s)
{
    (void)s;
    limn_context *ctx = api_reference_context();
    abi_layout older = abi_interpolate_options;
    older.min_size = offsetof(limn_interpolate_options, precision);
    limn_interpolate_options caller, lib;
    limn_interpolate_options_default(&caller);
    caller.size = offsetof(limn_interpolate_options, precision);
    caller.tolerance = 1e-9;
    caller.max_iterations = 77;
    caller.precision = LIMN_PRECISION_FLOAT; /* beyond its size: not read */
    limn_interpolate_options_default(&lib);
    lib.precision = LIMN_PRECISION_DOUBLE; /* the library's default here */
    OK(ctx, abi_options_in(ctx, "t", "options", &older, &caller, &lib));
    assert_int_equal(lib.size, sizeof lib);
    assert_true(lib.tolerance == 1e-9);
    assert_int_equal(lib.max_iterations, 77);
    assert_int_equal(lib.precision, LIMN_PRECISION_DOUBLE);

    /* and an older morph whose tail lacks `linear` */
    abi_layout older_morph = abi_morph_options;
    older_morph.min_size = offsetof(limn_morph_options, linear);
    limn_morph_options cm, lm;
    limn_morph_options_default(&cm);
    cm.size = offsetof(limn_morph_options, linear);
    cm.series.alpha = 0.25;
    cm.frames = 9;
    cm.linear = 1;
    limn_morph_options_default(&lm);
    OK(ctx, abi_options_in(ctx, "t", "options", &older_morph, &cm, &lm));
    assert_true(lm.series.alpha == 0.25);
    assert_int_equal(lm.frames, 9);
    assert_int_equal(lm.linear, 0);
    assert_int_equal(lm.size, sizeof lm);
    assert_int_equal(lm.series.size, sizeof lm.series);
    limn_context_destroy(ctx);
}

/* -------------------------------------------------------------- reports */

/*
 * The checks of every report: size 0 refused before any work; a caller size
 * cut before the last field gets the fields before it and nothing after (the
 * canary beyond is intact); a larger size gets the extra bytes zeroed and
 * its size kept. `first` is a size_t field right after `size` the call
 * fills with a non-zero count (vertices, faces_before, ...).
 */
typedef limn_status (*report_call)(limn_context *ctx, const limn_mesh *mesh, void *report);

static void report_checks(const char *fn, const char *what, size_t lib, size_t last,
                          report_call call)
{
    limn_context *ctx = api_reference_context();
    limn_mesh *mesh = test_mesh_cube(ctx);
    big g;
    memset(&g, 0, sizeof g);
    char msg[160];
    snprintf(msg, sizeof msg, "%s: %s->size is 0: set it to sizeof(", fn, what);
    REFUSED(ctx, call(ctx, mesh, g.b), msg);
    set_size(g.b, 3);
    REFUSED(ctx, call(ctx, mesh, g.b), fn, "is 3, smaller than its size field");

    /* the whole struct */
    memset(&g, CANARY, sizeof g);
    memset(g.b, 0, lib);
    set_size(g.b, lib);
    OK(ctx, call(ctx, mesh, g.b));
    size_t first;
    memcpy(&first, g.b + sizeof(size_t), sizeof first);
    assert_true(first > 0);
    assert_true(canary_intact(&g, lib));

    /* an older caller's, without the last field */
    memset(&g, CANARY, sizeof g);
    set_size(g.b, last);
    OK(ctx, call(ctx, mesh, g.b));
    memcpy(&first, g.b + sizeof(size_t), sizeof first);
    assert_true(first > 0);
    assert_true(canary_intact(&g, last));
    size_t n;
    memcpy(&n, g.b, sizeof n);
    assert_int_equal(n, last);

    /* a newer caller's: what this library does not know reads as zero */
    memset(&g, CANARY, sizeof g);
    set_size(g.b, lib + EXTRA);
    OK(ctx, call(ctx, mesh, g.b));
    for (size_t i = lib; i < lib + EXTRA; i++)
        assert_int_equal(g.b[i], 0);
    assert_true(canary_intact(&g, lib + EXTRA));
    memcpy(&n, g.b, sizeof n);
    assert_int_equal(n, lib + EXTRA);
    limn_mesh_destroy(mesh);
    limn_context_destroy(ctx);
}

static limn_status rep_repair(limn_context *ctx, const limn_mesh *mesh, void *r)
{
    limn_mesh *m = NULL;
    limn_status st = limn_mesh_copy(ctx, mesh, &m);
    if (!st)
        st = limn_mesh_repair(ctx, m, NULL, r);
    limn_mesh_destroy(m);
    return st;
}
static limn_status rep_info(limn_context *ctx, const limn_mesh *mesh, void *r)
{
    return limn_mesh_info_compute(ctx, mesh, r);
}
static limn_status rep_interpolate(limn_context *ctx, const limn_mesh *mesh, void *r)
{
    limn_mesh *control = NULL;
    limn_status st = limn_interpolate(ctx, mesh, NULL, &control, r);
    limn_mesh_destroy(control);
    return st;
}
static limn_status rep_subdivide(limn_context *ctx, const limn_mesh *mesh, void *r)
{
    limn_mesh *out = NULL;
    limn_status st = limn_subdivide(ctx, mesh, NULL, &out, r);
    limn_mesh_destroy(out);
    return st;
}
static limn_status rep_series(limn_context *ctx, const limn_mesh *mesh, void *r)
{
    limn_mesh *out = NULL;
    limn_status st = limn_smooth(ctx, mesh, NULL, 2, &out, r);
    limn_mesh_destroy(out);
    return st;
}
static limn_status rep_texture(limn_context *ctx, const limn_mesh *mesh, void *r)
{
    limn_texture_options o;
    fill_texture(&o);
    limn_mesh *out = NULL;
    limn_status st = limn_texture(ctx, mesh, &o, &out, r);
    limn_mesh_destroy(out);
    return st;
}
static limn_status rep_morph(limn_context *ctx, const limn_mesh *mesh, void *r)
{
    int frames = 0;
    return limn_morph(ctx, mesh, mesh, NULL, api_count_frame, &frames, r);
}
static limn_status rep_measures(limn_context *ctx, const limn_mesh *mesh, void *r)
{
    return limn_mesh_measure(ctx, mesh, r);
}
static limn_status rep_comparison(limn_context *ctx, const limn_mesh *mesh, void *r)
{
    limn_mesh *moved = NULL;
    limn_status st = limn_mesh_copy(ctx, mesh, &moved);
    if (!st) {
        test_perturb(moved, 0.1, 3);
        st = limn_mesh_compare(ctx, mesh, moved, r);
    }
    limn_mesh_destroy(moved);
    return st;
}

/* limn_mesh_measures and limn_mesh_comparison begin with other fields than
   a size_t count: their checks look at fields of their own below. */
#define REPORT_TEST(name, T, fn, what, last)                                                       \
    static void report_##name(void **s)                                                            \
    {                                                                                              \
        (void)s;                                                                                   \
        report_checks(fn, what, sizeof(T), offsetof(T, last), rep_##name);                         \
    }
REPORT_TEST(repair, limn_repair_report, "limn_mesh_repair", "report", boundary_loops)
REPORT_TEST(info, limn_mesh_info, "limn_mesh_info_compute", "info", bbox_diagonal)
REPORT_TEST(interpolate, limn_report, "limn_interpolate", "report", seconds_opencl_kernels)
REPORT_TEST(subdivide, limn_subdivide_report, "limn_subdivide", "report", seconds_limit)
REPORT_TEST(series, limn_series_report, "limn_smooth", "report", seconds_compute)
REPORT_TEST(texture, limn_series_report, "limn_texture", "report", seconds_compute)
REPORT_TEST(morph, limn_series_report, "limn_morph", "report", seconds_compute)

/* measures and comparison: no count after size, so their own checks. */
static void report_measures_comparison(void **s)
{
    (void)s;
    limn_context *ctx = api_reference_context();
    limn_mesh *mesh = test_mesh_cube(ctx);
    big g;
    memset(&g, 0, sizeof g);
    REFUSED(ctx, rep_measures(ctx, mesh, g.b), "limn_mesh_measure: out->size is 0");
    REFUSED(ctx, rep_comparison(ctx, mesh, g.b), "limn_mesh_compare: out->size is 0");

    /* measures without the centroid: closed, volume and area, no more */
    memset(&g, CANARY, sizeof g);
    size_t cut = offsetof(limn_mesh_measures, centroid);
    set_size(g.b, cut);
    OK(ctx, rep_measures(ctx, mesh, g.b));
    limn_mesh_measures m;
    memcpy(&m, g.b, cut);
    assert_int_equal(m.closed, 1);
    assert_true(m.area > 0);
    assert_true(canary_intact(&g, cut));

    /* comparison without flipped_faces */
    memset(&g, CANARY, sizeof g);
    cut = offsetof(limn_mesh_comparison, flipped_faces);
    set_size(g.b, cut);
    OK(ctx, rep_comparison(ctx, mesh, g.b));
    limn_mesh_comparison c;
    memcpy(&c, g.b, cut);
    assert_true(c.max_distance > 0);
    assert_true(canary_intact(&g, cut));

    /* a newer caller's measures: extra bytes zeroed */
    memset(&g, CANARY, sizeof g);
    set_size(g.b, sizeof m + EXTRA);
    OK(ctx, rep_measures(ctx, mesh, g.b));
    for (size_t i = sizeof m; i < sizeof m + EXTRA; i++)
        assert_int_equal(g.b[i], 0);
    assert_true(canary_intact(&g, sizeof m + EXTRA));
    limn_mesh_destroy(mesh);
    limn_context_destroy(ctx);
}

/* A refused report size costs nothing: no mesh is made, *out stays NULL. */
static void report_refused_before_work(void **s)
{
    limn_context *ctx = *s;
    limn_mesh *mesh = test_mesh_cube(ctx);
    limn_report r;
    memset(&r, 0, sizeof r);
    limn_mesh *control = (limn_mesh *)&control;
    REFUSED(ctx, limn_interpolate(ctx, mesh, NULL, &control, &r),
            "limn_interpolate: report->size is 0: set it to sizeof(limn_report)");
    assert_null(control);
    assert_int_equal(r.vertices, 0);
    limn_mesh_destroy(mesh);
}

TEST_MAIN(NULL, NULL, cmocka_unit_test(defaults_set_size), cmocka_unit_test(repair),
          cmocka_unit_test(interpolate), cmocka_unit_test(subdivide), cmocka_unit_test(series),
          cmocka_unit_test(morph), cmocka_unit_test(texture), cmocka_unit_test(render), cmocka_unit_test(feature),
          REFERENCE_TEST(embedded_series_size), REFERENCE_TEST(embedded_series_newer),
          cmocka_unit_test(older_options_get_defaults), cmocka_unit_test(report_repair),
          cmocka_unit_test(report_info), cmocka_unit_test(report_interpolate),
          cmocka_unit_test(report_subdivide), cmocka_unit_test(report_series),
          cmocka_unit_test(report_texture), cmocka_unit_test(report_morph),
          cmocka_unit_test(report_measures_comparison), REFERENCE_TEST(report_refused_before_work))
