/* SPDX-License-Identifier: MIT */
/*
 * Topology counts against stats.jsonl of the shared meshes, which a separate
 * numpy/scipy script computed (see ../shared/meshes/README.md), and against
 * closed forms on generated meshes.
 */
#include "support.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

static int json_number(const char *line, const char *key, double *out)
{
    char pat[96];
    snprintf(pat, sizeof pat, "\"%s\": ", key);
    const char *p = strstr(line, pat);
    if (!p)
        return 0;
    p += strlen(pat);
    if (*p == 't' || *p == 'f') {
        *out = *p == 't';
        return 1;
    }
    char *end;
    *out = strtod(p, &end);
    return end != p;
}

static void check_field(const char *file, const char *line, const char *key, double got)
{
    double want;
    if (!json_number(line, key, &want))
        return;
    if (want != got)
        fail_msg("%s: %s is %.0f, stats.jsonl says %.0f", file, key, got, want);
}

static void shared_meshes_match_stats(void **state)
{
    (void)state;
    if (!test_shared_meshes())
        skip();
    FILE *f = fopen(test_shared_path("stats.jsonl"), "r");
    assert_non_null(f);
    char line[16384];
    int checked = 0;
    limn_context *ctx = limn_context_create();
    while (fgets(line, sizeof line, f)) {
        const char *p = strstr(line, "\"file\": \"");
        assert_non_null(p);
        char file[256];
        sscanf(p + 9, "%255[^\"]", file);
        limn_mesh *m = test_read_shared(ctx, file);
        double degenerate = 0, manifold = 0;
        json_number(line, "degenerate_faces", &degenerate);
        json_number(line, "manifold", &manifold);
        limn_mesh_info in = {.size = sizeof in};
        limn_status st = limn_mesh_info_compute(ctx, m, &in);
        if (degenerate > 0) {
            /* Faces that repeat a vertex are refused, naming the face. */
            assert_int_equal(st, LIMN_ERR_TOPOLOGY);
            assert_non_null(strstr(limn_context_message(ctx), "twice"));
            limn_mesh_destroy(m);
            checked++;
            continue;
        }
        if (st)
            fail_msg("%s: %s", file, limn_context_message(ctx));
        check_field(file, line, "vertices", (double)in.vertices);
        check_field(file, line, "faces", (double)in.faces);
        check_field(file, line, "edges", (double)in.edges);
        check_field(file, line, "referenced_vertices", (double)in.referenced_vertices);
        check_field(file, line, "boundary_edges", (double)in.boundary_edges);
        check_field(file, line, "components", (double)in.components);
        check_field(file, line, "nonmanifold_edges", (double)in.nonmanifold_edges);
        check_field(file, line, "nonmanifold_vertices", (double)in.nonmanifold_vertices);
        check_field(file, line, "inconsistent_orientation_edges", (double)in.inconsistent_edges);
        check_field(file, line, "euler_characteristic", (double)in.euler_characteristic);
        if (manifold)
            check_field(file, line, "boundary_loops", (double)in.boundary_loops);
        limn_mesh_destroy(m);
        checked++;
    }
    fclose(f);
    limn_context_destroy(ctx);
    assert_true(checked >= 40);
}

/* Closed forms of the generated meshes' info; -1 where a field is not asserted. */
static const struct {
    long vertices, edges, boundary_edges, boundary_loops, euler, nonmanifold, max_valence;
} generated_info[] = {
    /* 4 x 3 quad grid: V = 20, E = 4*4 + 5*3 = 31, F = 12, boundary 14, one loop. */
    {20, 31, 14, 1, 1, 0, -1},
    /* cube: closed, genus 0, all valence 3 */
    {-1, 12, 0, -1, 2, -1, 3},
    /* icosahedron: E = 30, valence 5 */
    {-1, 30, -1, -1, 2, -1, 5},
};

static void expect_info_field(long want, size_t got)
{
    if (want >= 0)
        assert_int_equal(got, (size_t)want);
}

static void generated_meshes_closed_forms(void **state)
{
    limn_context *ctx = *state;
    limn_mesh *meshes[] = {test_mesh_grid(ctx, 4, 3, 0), test_mesh_cube(ctx),
                           test_mesh_icosahedron(ctx)};
    for (size_t i = 0; i < sizeof meshes / sizeof *meshes; i++) {
        limn_mesh_info in = {.size = sizeof in};
        assert_int_equal(limn_mesh_info_compute(ctx, meshes[i], &in), LIMN_OK);
        expect_info_field(generated_info[i].vertices, in.vertices);
        expect_info_field(generated_info[i].edges, in.edges);
        expect_info_field(generated_info[i].boundary_edges, in.boundary_edges);
        expect_info_field(generated_info[i].boundary_loops, in.boundary_loops);
        assert_int_equal(in.euler_characteristic, generated_info[i].euler);
        expect_info_field(generated_info[i].nonmanifold,
                          in.nonmanifold_edges + in.nonmanifold_vertices);
        expect_info_field(generated_info[i].max_valence, in.max_valence);
        limn_mesh_destroy(meshes[i]);
    }
}

/* Two triangles sharing only a vertex (a bow tie) and a fin of three faces on
   one edge: the classes of non-manifold input. */
static void nonmanifold_classes(void **state)
{
    limn_context *ctx = *state;
    static const double pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, -1, 0, 0, 0, -1, 0};
    static const uint32_t bow_idx[] = {0, 1, 2, 0, 3, 4};
    static const uint32_t bow_off[] = {0, 3, 6};
    limn_mesh *bow = NULL;
    limn_mesh_info in = {.size = sizeof in};
    assert_int_equal(limn_mesh_create(ctx, 5, pos, 2, bow_off, bow_idx, &bow), LIMN_OK);
    assert_int_equal(limn_mesh_info_compute(ctx, bow, &in), LIMN_OK);
    assert_int_equal(in.nonmanifold_vertices, 1);
    assert_int_equal(in.nonmanifold_edges, 0);
    assert_int_equal(in.components, 1);
    limn_mesh_destroy(bow);

    static const double fpos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1};
    static const uint32_t fin_idx[] = {0, 1, 2, 1, 0, 3, 0, 1, 4};
    static const uint32_t fin_off[] = {0, 3, 6, 9};
    limn_mesh *fin = NULL;
    assert_int_equal(limn_mesh_create(ctx, 5, fpos, 3, fin_off, fin_idx, &fin), LIMN_OK);
    assert_int_equal(limn_mesh_info_compute(ctx, fin, &in), LIMN_OK);
    assert_int_equal(in.nonmanifold_edges, 1);
    assert_int_equal(in.nonmanifold_vertices, 2);
    /* faces 0 and 2 both run 0 -> 1: counted as inconsistent? no: 3 faces make
       it non-manifold by count; orientation is only judged on 2-face edges. */
    assert_int_equal(in.inconsistent_edges, 0);
    limn_mesh_destroy(fin);

    /* Two triangles sharing an edge in the same direction. */
    static const uint32_t flip_idx[] = {0, 1, 2, 0, 1, 3};
    static const uint32_t flip_off[] = {0, 3, 6};
    limn_mesh *flip = NULL;
    assert_int_equal(limn_mesh_create(ctx, 5, fpos, 2, flip_off, flip_idx, &flip), LIMN_OK);
    assert_int_equal(limn_mesh_info_compute(ctx, flip, &in), LIMN_OK);
    assert_int_equal(in.inconsistent_edges, 1);
    assert_int_equal(in.nonmanifold_edges, 1);
    limn_mesh_destroy(flip);

    /* A face using a vertex twice is refused, naming the face. */
    static const uint32_t deg_idx[] = {0, 1, 2, 0, 1, 0, 3};
    static const uint32_t deg_off[] = {0, 3, 7};
    limn_mesh *deg = NULL;
    assert_int_equal(limn_mesh_create(ctx, 5, fpos, 2, deg_off, deg_idx, &deg), LIMN_OK);
    assert_int_equal(limn_mesh_info_compute(ctx, deg, &in), LIMN_ERR_TOPOLOGY);
    assert_non_null(strstr(limn_context_message(ctx), "face 1 uses vertex 0 twice"));
    limn_mesh_destroy(deg);
}

TEST_MAIN(NULL, NULL, CONTEXT_TEST(generated_meshes_closed_forms),
          CONTEXT_TEST(nonmanifold_classes), cmocka_unit_test(shared_meshes_match_stats))
