/* SPDX-License-Identifier: MIT */
/*
 * limn as an embedded library: every operation reached from the caller's own
 * arrays (a torus made here, no file) with its results copied into the
 * caller's own buffers, checked by properties that do not depend on how they
 * were computed (the limit of P is M; bands sum to M; one smoothing term is
 * the limit positions; frame 0 of a morph is FROM; a mesh given new
 * positions equals one made from them). Bad arguments are refused with a
 * message naming them, and a refused call writes nothing.
 */
#include "api_expect.h"
#include "support.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

enum { RING = 16, TUBE = 8, NV = RING * TUBE, NF = RING * TUBE };

/* A closed quad torus with a bumpy tube, in plain arrays. */
static void torus(double *pos, uint32_t *offsets, uint32_t *indices)
{
    const double pi = 3.14159265358979323846;
    for (int i = 0; i < RING; i++)
        for (int j = 0; j < TUBE; j++) {
            double u = 2 * pi * i / RING, v = 2 * pi * j / TUBE;
            double r = 0.3 + 0.05 * sin(3 * u) * cos(2 * v);
            double *p = pos + 3 * (i * TUBE + j);
            p[0] = (1 + r * cos(v)) * cos(u);
            p[1] = (1 + r * cos(v)) * sin(u);
            p[2] = r * sin(v);
        }
    for (int i = 0; i < RING; i++)
        for (int j = 0; j < TUBE; j++) {
            int f = i * TUBE + j, i1 = (i + 1) % RING, j1 = (j + 1) % TUBE;
            offsets[f] = (uint32_t)(4 * f);
            uint32_t *q = indices + 4 * f;
            q[0] = (uint32_t)(i * TUBE + j);
            q[1] = (uint32_t)(i1 * TUBE + j);
            q[2] = (uint32_t)(i1 * TUBE + j1);
            q[3] = (uint32_t)(i * TUBE + j1);
        }
    offsets[NF] = 4 * NF;
}

static double pos_m[3 * NV];
static uint32_t offsets_m[NF + 1], indices_m[4 * NF];

static limn_mesh *make(limn_context *ctx)
{
    limn_mesh *m = NULL;
    if (limn_mesh_create(ctx, NV, pos_m, NF, offsets_m, indices_m, &m) != LIMN_OK)
        fail_msg("limn_mesh_create: %s", limn_context_message(ctx));
    return m;
}

static double diagonal(const double *p, size_t n)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t i = 0; i < n; i++)
        for (int k = 0; k < 3; k++) {
            lo[k] = fmin(lo[k], p[3 * i + k]);
            hi[k] = fmax(hi[k], p[3 * i + k]);
        }
    return sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                (hi[2] - lo[2]) * (hi[2] - lo[2]));
}

static double max_distance(const double *a, const double *b, size_t n)
{
    double d = 0;
    for (size_t i = 0; i < n; i++)
        d = fmax(d, sqrt((a[3 * i] - b[3 * i]) * (a[3 * i] - b[3 * i]) +
                         (a[3 * i + 1] - b[3 * i + 1]) * (a[3 * i + 1] - b[3 * i + 1]) +
                         (a[3 * i + 2] - b[3 * i + 2]) * (a[3 * i + 2] - b[3 * i + 2])));
    return d;
}

static int setup(void **s)
{
    (void)s;
    torus(pos_m, offsets_m, indices_m);
    return 0;
}

static void interpolate_into_own_buffers(void **s)
{
    limn_context *ctx = *s;
    limn_mesh *m = test_keep_mesh(make(ctx)), *p = NULL;
    limn_interpolate_options o;
    limn_interpolate_options_default(&o);
    o.tolerance = 1e-9;
    limn_report r = {.size = sizeof r};
    OK(ctx, limn_interpolate(ctx, m, &o, &p, &r));
    test_keep_mesh(p);
    static double control[3 * NV], limit[3 * NV];
    OK(ctx, limn_mesh_copy_positions(ctx, p, control, NV));
    assert_memory_equal(control, limn_mesh_positions(p), sizeof control);
    /* the limit of P, from a mesh the caller makes of its own P and faces */
    limn_mesh *own = NULL;
    OK(ctx, limn_mesh_create(ctx, NV, control, NF, offsets_m, indices_m, &own));
    OK(ctx, limn_limit_positions(ctx, test_keep_mesh(own), r.scheme, r.alpha, limit));
    double err = max_distance(limit, pos_m, NV) / diagonal(pos_m, NV);
    print_message("limit of P against M: max relative error %.3g after %d iterations (%s)\n",
                  err, r.iterations, limn_context_device_name(ctx));
    assert_true(err <= o.tolerance);
    assert_true(max_distance(control, pos_m, NV) > 1e-3); /* P is not M */
}

static void subdivide_faces_into_own_buffers(void **s)
{
    limn_context *ctx = *s;
    limn_mesh *m = test_keep_mesh(make(ctx)), *sub = NULL;
    limn_subdivide_options o;
    limn_subdivide_options_default(&o);
    o.levels = 1;
    OK(ctx, limn_subdivide(ctx, m, &o, &sub, NULL));
    test_keep_mesh(sub);
    size_t nv = limn_mesh_vertex_count(sub), nf = limn_mesh_face_count(sub);
    size_t ni = limn_mesh_index_count(sub);
    /* Catmull-Clark, one step: V + F + E vertices (E = 2F on a quad torus), 4 quads a face */
    assert_int_equal(nv, NV + NF + 2 * NF);
    assert_int_equal(nf, 4 * NF);
    assert_int_equal(ni, 4 * nf);
    uint32_t *off = test_keep(malloc((nf + 1) * sizeof *off));
    uint32_t *idx = test_keep(malloc(ni * sizeof *idx));
    double *pos = test_keep(malloc(3 * nv * sizeof *pos));
    OK(ctx, limn_mesh_copy_faces(ctx, sub, off, nf + 1, idx, ni));
    OK(ctx, limn_mesh_copy_positions(ctx, sub, pos, nv));
    for (size_t f = 0; f <= nf; f++)
        assert_int_equal(off[f], 4 * f);
    for (size_t i = 0; i < ni; i++)
        assert_true(idx[i] < nv);
    assert_memory_equal(idx, limn_mesh_face_indices(sub), ni * sizeof *idx);
    /* the caller's copy makes the same mesh again */
    limn_mesh *again = NULL;
    OK(ctx, limn_mesh_create(ctx, nv, pos, nf, off, idx, &again));
    OK(ctx, limn_mesh_same_topology(ctx, sub, test_keep_mesh(again)));
}

typedef struct frames {
    double first[3 * NV], last[3 * NV];
    int count;
} frames;

static limn_status keep_frame(void *user, const limn_morph_frame *fr)
{
    frames *f = user;
    memcpy(fr->index == 0 ? f->first : f->last, fr->positions, sizeof f->first);
    f->count++;
    return LIMN_OK;
}

static void series_into_own_buffers(void **s)
{
    limn_context *ctx = *s;
    limn_mesh *m = test_keep_mesh(make(ctx)), *out = NULL;
    double diag = diagonal(pos_m, NV);
    static double buf[3 * NV], limit[3 * NV], bands[4 * 3 * NV];
    double energy[4];

    /* bands 0..2 and the remainder sum back to M */
    OK(ctx, limn_bands(ctx, m, NULL, 3, bands, energy, NULL));
    for (size_t i = 0; i < 3 * NV; i++) {
        double sum = 0;
        for (int b = 0; b < 4; b++)
            sum += bands[(size_t)b * 3 * NV + i];
        assert_true(fabs(sum - pos_m[i]) <= 1e-12 * diag);
    }
    assert_true(energy[1] < energy[0]);

    /* one smoothing term is A M: the limit positions */
    OK(ctx, limn_smooth(ctx, m, NULL, 1, &out, NULL));
    OK(ctx, limn_mesh_copy_positions(ctx, out, buf, NV));
    OK(ctx, limn_limit_positions(ctx, m, LIMN_SCHEME_AUTO, 0.0, limit));
    assert_true(max_distance(buf, limit, NV) <= 1e-12 * diag);
    limn_mesh_destroy(out);

    /* denoise and sharpen move the vertices by less than the mesh's size */
    OK(ctx, limn_denoise(ctx, m, NULL, 2, 2, 0, &out, NULL));
    OK(ctx, limn_mesh_copy_positions(ctx, out, buf, NV));
    double moved = max_distance(buf, pos_m, NV);
    assert_true(moved > 0 && moved < 0.1 * diag);
    limn_mesh_destroy(out);
    OK(ctx, limn_sharpen(ctx, m, NULL, 1, 2, 1, &out, NULL));
    OK(ctx, limn_mesh_copy_positions(ctx, out, buf, NV));
    moved = max_distance(buf, pos_m, NV);
    assert_true(moved > 0 && moved < 0.1 * diag);
    limn_mesh_destroy(out);

    /* morph to the torus scaled by 1.5 (new positions on a copy): frame 0 is FROM */
    limn_mesh *to = NULL;
    OK(ctx, limn_mesh_copy(ctx, m, &to));
    for (size_t i = 0; i < 3 * NV; i++)
        buf[i] = 1.5 * pos_m[i];
    OK(ctx, limn_mesh_set_positions(ctx, to, buf, NV));
    limn_morph_options mo;
    limn_morph_options_default(&mo);
    mo.frames = 5;
    static frames fr;
    OK(ctx, limn_morph(ctx, m, to, &mo, keep_frame, &fr, NULL));
    assert_int_equal(fr.count, 5);
    assert_memory_equal(fr.first, pos_m, sizeof pos_m);
    assert_true(max_distance(fr.last, buf, NV) < max_distance(pos_m, buf, NV));
    limn_mesh_destroy(to);

    /* texture: colours from the caller's array, into the caller's buffer */
    const uint8_t colors[] = {255, 0, 0, 0, 0, 255};
    limn_texture_options to_opt;
    limn_texture_options_default(&to_opt);
    to_opt.colors = colors;
    to_opt.color_count = 2;
    to_opt.levels = 1;
    OK(ctx, limn_texture(ctx, m, &to_opt, &out, NULL));
    size_t nv = limn_mesh_vertex_count(out);
    uint8_t *rgb = test_keep(malloc(3 * nv));
    OK(ctx, limn_mesh_copy_colors(ctx, out, rgb, nv));
    assert_memory_equal(rgb, limn_mesh_colors(out), 3 * nv);
    for (size_t i = 0; i < nv; i++)
        assert_int_equal(rgb[3 * i + 1], 0); /* between red and blue: no green */
    limn_mesh_destroy(out);
}

static void new_positions_in_place(void **s)
{
    limn_context *ctx = *s;
    limn_mesh *m = make(ctx);
    const double *before = limn_mesh_positions(m);
    static double moved[3 * NV], a[3 * NV], b[3 * NV];
    for (size_t i = 0; i < 3 * NV; i++)
        moved[i] = pos_m[i] + 0.01 * sin((double)i);
    OK(ctx, limn_mesh_set_positions(ctx, m, moved, NV));
    assert_ptr_equal(limn_mesh_positions(m), before); /* accessors stay valid */
    limn_mesh *fresh = NULL;
    OK(ctx, limn_mesh_create(ctx, NV, moved, NF, offsets_m, indices_m, &fresh));
    OK(ctx, limn_limit_positions(ctx, m, LIMN_SCHEME_AUTO, 0.0, a));
    OK(ctx, limn_limit_positions(ctx, fresh, LIMN_SCHEME_AUTO, 0.0, b));
    assert_memory_equal(a, b, sizeof a);
    limn_mesh_destroy(fresh);
    limn_mesh_destroy(m);
}

static void refusals_write_nothing(void **s)
{
    limn_context *ctx = *s;
    limn_mesh *m = make(ctx), *out = (limn_mesh *)&out;
    static double buf[3 * NV], sentinel[3 * NV];
    for (size_t i = 0; i < 3 * NV; i++)
        buf[i] = sentinel[i] = -7.0;
    REFUSED(ctx, limn_mesh_copy_positions(ctx, m, buf, NV - 1),
            "holds 127 vertices but the mesh has 128");
    REFUSED(ctx, limn_mesh_copy_positions(ctx, NULL, buf, NV), "mesh is NULL");
    REFUSED(ctx, limn_mesh_copy_positions(ctx, m, NULL, NV), "dst is NULL");
    assert_memory_equal(buf, sentinel, sizeof buf);
    uint32_t off[NF + 1], idx[4 * NF];
    memset(off, 0xab, sizeof off);
    memset(idx, 0xab, sizeof idx);
    REFUSED(ctx, limn_mesh_copy_faces(ctx, m, off, NF + 1, idx, 4 * NF - 1),
            "nothing was copied");
    REFUSED(ctx, limn_mesh_copy_faces(ctx, m, off, NF, idx, 4 * NF), "needs 129 (face_count + 1)");
    REFUSED(ctx, limn_mesh_copy_faces(ctx, m, off, NF + 1, NULL, 4 * NF), "indices is NULL");
    assert_int_equal(off[0], 0xabababab);
    assert_int_equal(idx[0], 0xabababab);
    uint8_t rgb[3 * NV];
    REFUSED(ctx, limn_mesh_copy_colors(ctx, m, rgb, NV), "has no colours");
    /* new positions: wrong count, non-finite, NULL; the mesh keeps its own */
    buf[5] = NAN;
    REFUSED(ctx, limn_mesh_set_positions(ctx, m, buf, NV), "vertex 1 has a non-finite");
    REFUSED(ctx, limn_mesh_set_positions(ctx, m, pos_m, NV + 1), "129 vertices given");
    REFUSED(ctx, limn_mesh_set_positions(ctx, m, NULL, NV), "positions is NULL");
    assert_memory_equal(limn_mesh_positions(m), pos_m, sizeof pos_m);
    /* making a mesh: every bad array named, *out cleared */
    uint32_t bad[4 * NF];
    memcpy(bad, indices_m, sizeof bad);
    bad[9] = NV;
    REFUSED(ctx, limn_mesh_create(ctx, NV, pos_m, NF, offsets_m, bad, &out),
            "face index 9 is 128 but there are 128 vertices");
    assert_null(out);
    uint32_t offs[3] = {0, 2, 6};
    REFUSED(ctx, limn_mesh_create(ctx, NV, pos_m, 2, offs, indices_m, &out),
            "face 0 has 2 vertices");
    /* offsets near the top: offset + 3 must not wrap around (checked before any index is read) */
    uint32_t wrap[3] = {0, UINT32_MAX - 1, UINT32_MAX};
    REFUSED(ctx, limn_mesh_create(ctx, NV, pos_m, 2, wrap, indices_m, &out),
            "face 1 has 1 vertices");
    offs[0] = 1;
    REFUSED(ctx, limn_mesh_create(ctx, NV, pos_m, 1, offs, indices_m, &out),
            "face_offsets[0] is 1");
    REFUSED(ctx, limn_mesh_create(ctx, NV, NULL, NF, offsets_m, indices_m, &out),
            "positions is NULL");
    REFUSED(ctx, limn_mesh_create(ctx, NV, pos_m, NF, offsets_m, indices_m, NULL), "out is NULL");
    limn_mesh_destroy(m);
}

static limn_status no_frame(void *user, const limn_morph_frame *fr)
{
    (void)user;
    (void)fr;
    return LIMN_OK;
}

/* Every entry point given NULL in each handle or buffer: refused, named, no crash. */
static void null_arguments_everywhere(void **s)
{
    limn_context *ctx = *s;
    limn_mesh *m = make(ctx), *out = NULL;
    double d[3 * NV];
    uint8_t rgb[12];
    limn_mesh_info info = {.size = sizeof info};
    limn_mesh_measures meas = {.size = sizeof meas};
    limn_mesh_comparison cmp = {.size = sizeof cmp};
    size_t v, f, b;
    limn_subdivide_options so;
    limn_subdivide_options_default(&so);
    limn_texture_options to;
    limn_texture_options_default(&to);

    REFUSED(ctx, limn_interpolate(ctx, NULL, NULL, &out, NULL), "NULL");
    REFUSED(ctx, limn_interpolate(ctx, m, NULL, NULL, NULL), "NULL");
    REFUSED(ctx, limn_interpolate_estimate(ctx, NULL, NULL, 0, NULL), "NULL");
    REFUSED(ctx, limn_subdivide(ctx, NULL, NULL, &out, NULL), "NULL");
    REFUSED(ctx, limn_subdivide(ctx, m, NULL, NULL, NULL), "NULL");
    REFUSED(ctx, limn_subdivide_estimate(ctx, m, &so, NULL, &f, &b), "NULL");
    REFUSED(ctx, limn_limit_positions(ctx, NULL, LIMN_SCHEME_AUTO, 0, d), "NULL");
    REFUSED(ctx, limn_limit_positions(ctx, m, LIMN_SCHEME_AUTO, 0, NULL), "NULL");
    REFUSED(ctx, limn_bands(ctx, NULL, NULL, 2, d, NULL, NULL), "NULL");
    REFUSED(ctx, limn_smooth(ctx, NULL, NULL, 2, &out, NULL), "NULL");
    REFUSED(ctx, limn_smooth(ctx, m, NULL, 2, NULL, NULL), "NULL");
    REFUSED(ctx, limn_denoise(ctx, NULL, NULL, 2, 1, 0, &out, NULL), "NULL");
    REFUSED(ctx, limn_denoise(ctx, m, NULL, 2, 1, 0, NULL, NULL), "NULL");
    REFUSED(ctx, limn_sharpen(ctx, NULL, NULL, 1, 2, 1, &out, NULL), "NULL");
    REFUSED(ctx, limn_sharpen(ctx, m, NULL, 1, 2, 1, NULL, NULL), "NULL");
    REFUSED(ctx, limn_morph(ctx, m, NULL, NULL, no_frame, NULL, NULL), "NULL");
    REFUSED(ctx, limn_morph(ctx, m, m, NULL, NULL, NULL, NULL), "NULL");
    REFUSED(ctx, limn_texture(ctx, NULL, &to, &out, NULL), "NULL");
    REFUSED(ctx, limn_texture(ctx, m, NULL, &out, NULL), "NULL");
    REFUSED(ctx, limn_mesh_info_compute(ctx, NULL, &info), "NULL");
    REFUSED(ctx, limn_mesh_measure(ctx, m, NULL), "NULL");
    REFUSED(ctx, limn_mesh_compare(ctx, m, NULL, &cmp), "NULL");
    REFUSED(ctx, limn_mesh_same_topology(ctx, NULL, m), "NULL");
    REFUSED(ctx, limn_mesh_repair(ctx, NULL, NULL, NULL), "NULL");
    REFUSED(ctx, limn_mesh_copy(ctx, NULL, &out), "mesh is NULL");
    REFUSED(ctx, limn_mesh_set_colors(ctx, NULL, rgb), "NULL");
    REFUSED(ctx, limn_render(ctx, NULL, NULL, rgb), "NULL");
    REFUSED(ctx, limn_mesh_write(ctx, NULL, "x.ply", LIMN_FORMAT_AUTO), "NULL");
    REFUSED(ctx, limn_mesh_read(ctx, NULL, LIMN_FORMAT_AUTO, &out), "no file name");
    REFUSED(ctx, limn_list_devices(ctx, NULL, 0), "NULL");
    assert_null(out);
    /* no context: the status alone, no crash */
    assert_int_equal(limn_interpolate(NULL, m, NULL, &out, NULL), LIMN_ERR_ARGUMENT);
    assert_int_equal(limn_smooth(NULL, m, NULL, 1, &out, NULL), LIMN_ERR_ARGUMENT);
    assert_int_equal(limn_mesh_copy_positions(NULL, m, NULL, NV), LIMN_ERR_ARGUMENT);
    assert_int_equal(limn_context_set_device(NULL, "reference"), LIMN_ERR_ARGUMENT);
    assert_int_equal(limn_mesh_info_compute(NULL, m, &info), LIMN_ERR_ARGUMENT);
    assert_int_equal(limn_mesh_measure(NULL, m, &meas), LIMN_ERR_ARGUMENT);
    (void)v;
    /* functions without a context tolerate NULL */
    limn_interpolate_options_default(NULL);
    limn_subdivide_options_default(NULL);
    limn_series_options_default(NULL);
    limn_morph_options_default(NULL);
    limn_texture_options_default(NULL);
    limn_render_options_default(NULL);
    limn_repair_options_default(NULL);
    limn_noise_init(NULL, 1);
    assert_true(limn_noise_eval(NULL, 0.5, 0.5, 0.5) == 0.0);
    double vol = 0, area = 0;
    limn_mesh_volume_area(NULL, &vol, &area);
    assert_true(isnan(vol) && isnan(area));
    limn_mesh_volume_area(m, NULL, NULL);
    assert_int_equal(limn_mesh_vertex_count(NULL), 0);
    assert_int_equal(limn_mesh_index_count(NULL), 0);
    assert_null(limn_mesh_positions(NULL));
    limn_mesh_destroy(NULL);
    limn_context_destroy(NULL);
    limn_mesh_destroy(m);
}

TEST_MAIN(setup, NULL, CONTEXT_TEST(interpolate_into_own_buffers),
          CONTEXT_TEST(subdivide_faces_into_own_buffers),
          CONTEXT_TEST(series_into_own_buffers), CONTEXT_TEST(new_positions_in_place),
          CONTEXT_TEST(refusals_write_nothing), CONTEXT_TEST(null_arguments_everywhere))
