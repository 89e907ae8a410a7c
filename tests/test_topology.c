/* SPDX-License-Identifier: MIT */
/*
 * Topology counts against stats.jsonl of the shared meshes, which a separate
 * numpy/scipy script computed (see ../shared/meshes/README.md), and against
 * closed forms on generated meshes; the parallel topology_build against the
 * previous sequential one (tests/oracle/topology_previous.c), array by array,
 * for 1, 2 and 4 host threads; one topology per run (the mesh's cache).
 */
#include "support.h"
#include "mesh/mesh.h"
#include "topology_previous.h"

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

/* ------------------------------------------- against the previous build */

#define SAME_ARRAY(field, count)                                                               \
    do {                                                                                       \
        if ((count) > 0 && memcmp(a->field, b->field, (count) * sizeof *a->field) != 0)        \
            fail_msg("%s: %s differs from the previous build", what, #field);                  \
    } while (0)
#define SAME_COUNT(field)                                                                      \
    do {                                                                                       \
        if (a->field != b->field)                                                              \
            fail_msg("%s: %s is %zu, the previous build says %zu", what, #field,               \
                     (size_t)a->field, (size_t)b->field);                                      \
    } while (0)

/* Every array and statistic of a equal to b's. */
static void assert_same_topology(const topology *a, const topology *b, const char *what)
{
    SAME_COUNT(vertex_count);
    SAME_COUNT(face_count);
    SAME_COUNT(edge_count);
    SAME_COUNT(corner_count);
    SAME_COUNT(boundary_edges);
    SAME_COUNT(nonmanifold_edges);
    SAME_COUNT(inconsistent_edges);
    SAME_COUNT(nonmanifold_vertices);
    SAME_COUNT(referenced_vertices);
    SAME_COUNT(components);
    SAME_COUNT(boundary_loops);
    SAME_COUNT(max_face_size);
    SAME_COUNT(max_valence);
    SAME_COUNT(triangles);
    SAME_COUNT(quads);
    SAME_COUNT(other_faces);
    size_t nv = a->vertex_count, nc = a->corner_count, ne = a->edge_count;
    SAME_ARRAY(corner_face, nc);
    SAME_ARRAY(corner_edge, nc);
    SAME_ARRAY(edge_vertices, 2 * ne);
    SAME_ARRAY(edge_corner_offsets, ne + 1);
    SAME_ARRAY(edge_corners, nc);
    SAME_ARRAY(vertex_corner_offsets, nv + 1);
    SAME_ARRAY(vertex_corners, nc);
    SAME_ARRAY(vertex_edge_offsets, nv + 1);
    SAME_ARRAY(vertex_edges, 2 * ne);
    SAME_ARRAY(edge_flags, ne);
    SAME_ARRAY(vertex_flags, nv);
    SAME_ARRAY(vertex_rule, nv);
    SAME_ARRAY(crease_neighbors, 2 * nv);
}

/* Referenced vertices of fewer than 3 neighbours, from t's arrays. */
static size_t thin_vertices(const topology *t)
{
    size_t n = 0;
    for (size_t v = 0; v < t->vertex_count; v++)
        n += t->vertex_corner_offsets[v + 1] > t->vertex_corner_offsets[v] &&
             t->vertex_edge_offsets[v + 1] - t->vertex_edge_offsets[v] < 3;
    return n;
}

/* The census's counts equal to the statistics of b (the previous build). */
static void assert_counts_of(const topology_counts *k, const topology *b, const char *what)
{
    topology_counts want;
    topology_counts_of(b, &want);
    want.thin_vertices = thin_vertices(b); /* the previous build did not count them */
#define SAME_CENSUS(field)                                                                     \
    if (k->field != want.field)                                                                \
        fail_msg("%s: the census's %s is %zu, the previous build says %zu", what, #field,      \
                 k->field, want.field);
    SAME_CENSUS(edges);
    SAME_CENSUS(boundary_edges);
    SAME_CENSUS(nonmanifold_edges);
    SAME_CENSUS(inconsistent_edges);
    SAME_CENSUS(nonmanifold_vertices);
    SAME_CENSUS(referenced_vertices);
    SAME_CENSUS(components);
    SAME_CENSUS(boundary_loops);
    SAME_CENSUS(max_face_size);
    SAME_CENSUS(max_valence);
    SAME_CENSUS(triangles);
    SAME_CENSUS(quads);
    SAME_CENSUS(other_faces);
#undef SAME_CENSUS
}

/* topology_build equal to the previous build for 1, 2 and 4 host threads,
   or refused with the same message, and the census's counts its statistics;
   returns 1 when built. */
static int check_against_previous(limn_context *ctx, const limn_mesh *m, const char *what)
{
    topology old;
    limn_status want = topology_previous_build(ctx, m, &old);
    char message[512];
    snprintf(message, sizeof message, "%s", limn_context_message(ctx));
    static const int threads[] = {1, 2, 4};
    for (int i = 0; i < 3; i++) {
        assert_int_equal(limn_context_set_host_threads(ctx, threads[i]), LIMN_OK);
        topology_counts k;
        limn_status counted = topology_census(ctx, m, &k);
        if (counted != want)
            fail_msg("%s (%d threads): census status %d, the previous build %d (%s)", what,
                     threads[i], counted, want, limn_context_message(ctx));
        if (counted)
            assert_string_equal(limn_context_message(ctx), message);
        else
            assert_counts_of(&k, &old, what);
        topology t;
        limn_status got = topology_build(ctx, m, &t);
        if (got != want)
            fail_msg("%s (%d threads): status %d, the previous build %d (%s)", what, threads[i],
                     got, want, limn_context_message(ctx));
        if (got) {
            assert_string_equal(limn_context_message(ctx), message);
            continue;
        }
        /* the build leaves corner_edge to refinement's request */
        assert_null(t.corner_edge);
        assert_int_equal(topology_corner_edges(ctx, &t), LIMN_OK);
        assert_same_topology(&t, &old, what);
        if (t.thin_vertices != thin_vertices(&old))
            fail_msg("%s: %zu thin vertices, the previous build's arrays say %zu", what,
                     t.thin_vertices, thin_vertices(&old));
        topology_free(&t);
    }
    assert_int_equal(limn_context_set_host_threads(ctx, 0), LIMN_OK);
    if (!want)
        topology_previous_free(&old);
    return want == LIMN_OK;
}

static void shared_meshes_as_before(void **state)
{
    limn_context *ctx = *state;
    if (!test_shared_meshes())
        skip();
    static const char *subs[] = {"small", "medium", "opensubdiv", "large"};
    int built = 0, refused = 0;
    for (int s = 0; s < 4; s++) {
        const char *names[64];
        size_t n = test_list_meshes(subs[s], names, 64);
        for (size_t i = 0; i < n; i++) {
            limn_mesh *m = test_read_shared(ctx, names[i]);
            if (check_against_previous(ctx, m, names[i]))
                built++;
            else
                refused++;
            limn_mesh_destroy(m);
        }
    }
    printf("  %d shared meshes as before, %d refused as before\n", built, refused);
    assert_true(built >= 30);
}

/* n copies of the faces of (nf faces, off, idx over nv vertices), vertex v
   of copy k at (v * n + k) * 2 + 1: copies interleave across the thread
   ranges, and the even vertices stay isolated. */
static limn_mesh *tiled(limn_context *ctx, size_t nv, size_t nf, const uint32_t *off,
                        const uint32_t *idx, size_t n)
{
    size_t nc = off[nf], total_v = 2 * nv * n + 1;
    uint32_t *o = malloc((nf * n + 1) * sizeof *o), *x = malloc(nc * n * sizeof *x);
    double *p = calloc(3 * total_v, sizeof *p);
    assert_true(o && x && p);
    o[0] = 0;
    for (size_t k = 0; k < n; k++)
        for (size_t f = 0; f < nf; f++) {
            size_t at = o[k * nf + f];
            for (uint32_t c = off[f]; c < off[f + 1]; c++)
                x[at++] = (uint32_t)((idx[c] * n + k) * 2 + 1);
            o[k * nf + f + 1] = (uint32_t)at;
        }
    for (size_t v = 0; v < total_v; v++)
        p[3 * v] = (double)v;
    limn_mesh *m = NULL;
    assert_int_equal(limn_mesh_create(ctx, total_v, p, nf * n, o, x, &m), LIMN_OK);
    free(o);
    free(x);
    free(p);
    return m;
}

typedef struct hand_mesh {
    const char *name;
    size_t nv, nf;
    const uint32_t *off, *idx;
} hand_mesh;

/* Bow ties (several fans), fins, flipped pairs, boundaries, a 40-face fan and
   a 300-gon (the long paths of the sorts), mixed face sizes, faces repeating a
   vertex (refused, naming the face): once, and tiled large enough for 4
   threads. */
static void hand_built_as_before(void **state)
{
    limn_context *ctx = *state;
    static const uint32_t bow_off[] = {0, 3, 6}, bow_idx[] = {0, 1, 2, 0, 3, 4};
    static const uint32_t fin_off[] = {0, 3, 6, 9}, fin_idx[] = {0, 1, 2, 1, 0, 3, 0, 1, 4};
    static const uint32_t flip_off[] = {0, 3, 6}, flip_idx[] = {0, 1, 2, 0, 1, 3};
    /* a quad, a pentagon and a triangle around vertex 0, one boundary */
    static const uint32_t mix_off[] = {0, 4, 9, 12},
                          mix_idx[] = {0, 1, 2, 3, 0, 3, 4, 5, 6, 0, 6, 1};
    /* two closed fans at vertex 0 (two tetrahedra sharing a vertex) */
    static const uint32_t two_off[] = {0, 3, 6, 9, 12, 15, 18, 21, 24},
                          two_idx[] = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3,
                                       0, 5, 4, 0, 4, 6, 0, 6, 5, 4, 5, 6};
    static const uint32_t deg_off[] = {0, 3, 7}, deg_idx[] = {0, 1, 2, 0, 1, 0, 3};
    /* GON > 256: the previous corner of the first is looked up (wrap 255) */
    enum { FAN = 40, GON = 300 };
    uint32_t fan_off[FAN + 1], fan_idx[3 * FAN], gon_off[3], gon_idx[GON + 3];
    uint32_t bad_off[3], bad_idx[GON + 3];
    fan_off[0] = 0;
    for (uint32_t f = 0; f < FAN; f++) {
        fan_idx[3 * f] = 0, fan_idx[3 * f + 1] = 1 + f, fan_idx[3 * f + 2] = 1 + (f + 1) % FAN;
        fan_off[f + 1] = 3 * (f + 1);
    }
    /* a 300-gon and a triangle on one of its edges; then the same with the
       300-gon visiting vertex 7 twice */
    gon_off[0] = 0, gon_off[1] = GON, gon_off[2] = GON + 3;
    for (uint32_t c = 0; c < GON; c++)
        gon_idx[c] = c;
    gon_idx[GON] = 1, gon_idx[GON + 1] = 0, gon_idx[GON + 2] = GON;
    memcpy(bad_off, gon_off, sizeof bad_off);
    memcpy(bad_idx, gon_idx, sizeof bad_idx);
    bad_idx[30] = 7;
    const hand_mesh meshes[] = {
        {"bow tie", 5, 2, bow_off, bow_idx},        {"fin", 5, 3, fin_off, fin_idx},
        {"flipped", 4, 2, flip_off, flip_idx},      {"mixed sizes", 8, 3, mix_off, mix_idx},
        {"two fans", 7, 8, two_off, two_idx},       {"fan of 40", FAN + 2, FAN, fan_off, fan_idx},
        {"300-gon", GON + 1, 2, gon_off, gon_idx},  {"repeat", 5, 2, deg_off, deg_idx},
        {"300-gon repeat", GON + 1, 2, bad_off, bad_idx},
    };
    for (size_t i = 0; i < sizeof meshes / sizeof *meshes; i++) {
        const hand_mesh *h = &meshes[i];
        /* 1 copy (with isolated vertices), then enough corners for 4 ranges */
        size_t copies[] = {1, (20u << 20) / (60 * h->off[h->nf]) + 1};
        for (int c = 0; c < 2; c++) {
            limn_mesh *m = tiled(ctx, h->nv, h->nf, h->off, h->idx, copies[c]);
            int built = check_against_previous(ctx, m, h->name);
            assert_int_equal(built, strstr(h->name, "repeat") == NULL);
            limn_mesh_destroy(m);
        }
    }
    /* the refusal names the first face in face order */
    limn_mesh *m = tiled(ctx, 5, 2, deg_off, deg_idx, 1);
    topology t;
    assert_int_equal(topology_build(ctx, m, &t), LIMN_ERR_TOPOLOGY);
    assert_non_null(strstr(limn_context_message(ctx), "face 1 uses vertex 1 twice"));
    limn_mesh_destroy(m);
}

/* limn_mesh_repair leaves its topology on the mesh, and what follows (info,
   measure, interpolate) uses it: one build for the whole run. The operator
   keeps it (slimmed after its stencils), so the next call builds its own.
   Copies do not carry it; a repair that changes the faces builds it afresh;
   while it is lent, a second reader builds its own. */
static void one_topology_per_run(void **state)
{
    limn_context *ctx = *state;
    limn_mesh *m = test_mesh_icosahedron(ctx);
    limn_repair_report rep = {.size = sizeof rep};
    size_t before = topology_build_count();
    assert_int_equal(limn_mesh_repair(ctx, m, NULL, &rep), LIMN_OK);
    assert_non_null(m->topology);
    limn_mesh_info in = {.size = sizeof in};
    assert_int_equal(limn_mesh_info_compute(ctx, m, &in), LIMN_OK);
    limn_mesh_measures me = {.size = sizeof me};
    assert_int_equal(limn_mesh_measure(ctx, m, &me), LIMN_OK);
    limn_mesh *control = NULL;
    assert_non_null(m->topology);
    assert_int_equal(limn_interpolate(ctx, m, NULL, &control, NULL), LIMN_OK);
    assert_int_equal(topology_build_count() - before, 1);
    assert_null(m->topology); /* handed to the operator, freed with it */
    assert_int_equal(limn_mesh_repair(ctx, m, NULL, &rep), LIMN_OK);
    assert_int_equal(topology_build_count() - before, 2);
    assert_null(control->topology);
    topology t, second, fresh;
    const topology *cached = m->topology;
    assert_int_equal(topology_get(ctx, m, &t), LIMN_OK);
    assert_true(t.lent == cached && t.vertex_rule == cached->vertex_rule);
    assert_null(m->topology); /* out on loan: another reader builds its own */
    assert_int_equal(topology_get(ctx, m, &second), LIMN_OK);
    assert_null(second.lent);
    assert_int_equal(topology_build_count() - before, 3);
    assert_int_equal(topology_previous_build(ctx, m, &fresh), LIMN_OK);
    /* corner_edge made on request, on the loan too: the mesh's one keeps it */
    assert_int_equal(topology_corner_edges(ctx, &t), LIMN_OK);
    assert_int_equal(topology_corner_edges(ctx, &second), LIMN_OK);
    assert_same_topology(&t, &fresh, "cached");
    assert_same_topology(&second, &fresh, "built while the cache was lent");
    topology_free(&second);
    topology_free(&t);
    assert_ptr_equal(m->topology, cached); /* given back */
    assert_non_null(cached->corner_edge);
    topology_previous_free(&fresh);
    limn_mesh_destroy(control);
    limn_mesh_destroy(m);

    /* keep_topology = 0 (limn info): counts by a census, no topology built;
       info reads the counts kept; a later operator builds its own */
    m = test_mesh_icosahedron(ctx);
    limn_repair_options census = {.size = sizeof census};
    limn_repair_options_default(&census);
    assert_int_equal(census.keep_topology, 1);
    census.keep_topology = 0;
    before = topology_build_count();
    limn_repair_report counted = {.size = sizeof counted};
    assert_int_equal(limn_mesh_repair(ctx, m, &census, &counted), LIMN_OK);
    assert_null(m->topology);
    assert_non_null(m->counts);
    limn_mesh_info from_census = {.size = sizeof from_census};
    assert_int_equal(limn_mesh_info_compute(ctx, m, &from_census), LIMN_OK);
    assert_int_equal(topology_build_count() - before, 0);
    /* the full repair's report */
    assert_int_equal(counted.nonmanifold_edges, rep.nonmanifold_edges);
    assert_int_equal(counted.nonmanifold_vertices, rep.nonmanifold_vertices);
    assert_int_equal(counted.unreferenced_vertices, rep.unreferenced_vertices);
    assert_int_equal(counted.components, rep.components);
    assert_int_equal(counted.boundary_loops, rep.boundary_loops);
    assert_memory_equal(&from_census, &in, sizeof in);
    assert_int_equal(limn_interpolate(ctx, m, NULL, &control, NULL), LIMN_OK);
    assert_int_equal(topology_build_count() - before, 1);
    limn_mesh_destroy(control);
    limn_mesh_destroy(m);

    /* a duplicate face, removed: the repair drops the cache and builds anew */
    static const double pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    static const uint32_t off[] = {0, 3, 6, 9}, idx[] = {0, 1, 2, 2, 1, 0, 0, 1, 3};
    assert_int_equal(limn_mesh_create(ctx, 4, pos, 3, off, idx, &m), LIMN_OK);
    limn_repair_options keep = {.size = sizeof keep}, drop = {.size = sizeof drop};
    limn_repair_options_default(&keep);
    limn_repair_options_default(&drop);
    drop.duplicate_faces = 1;
    assert_int_equal(limn_mesh_repair(ctx, m, &keep, &rep), LIMN_OK);
    assert_int_equal(m->topology->face_count, 3);
    assert_int_equal(limn_mesh_repair(ctx, m, &drop, &rep), LIMN_OK);
    assert_int_equal(m->face_count, 2);
    assert_int_equal(topology_get(ctx, m, &t), LIMN_OK);
    assert_int_equal(topology_previous_build(ctx, m, &fresh), LIMN_OK);
    assert_int_equal(topology_corner_edges(ctx, &t), LIMN_OK);
    assert_same_topology(&t, &fresh, "after the repair");
    topology_free(&t);
    topology_previous_free(&fresh);
    limn_mesh_destroy(m);
}

/* The repair's face checks run over ranges of faces (topology/face_keys.c):
   a grid of 240k triangles with duplicates (same set, other order or
   orientation) and repeated vertices planted at known faces, among them a
   60-corner face (the sorted path), gives the same report and faces for 1,
   2 and 4 host threads, and the counts the planting implies. */
static limn_mesh *planted_mesh(limn_context *ctx, int with_repeats)
{
    enum { N = 347 }; /* vertices a side */
    size_t nv = (size_t)N * N, cells = (size_t)(N - 1) * (N - 1);
    size_t nf = 2 * cells + 4 + (with_repeats ? 2 : 0);
    double *pos = malloc(3 * nv * sizeof *pos);
    uint32_t *off = malloc((nf + 1) * sizeof *off), *idx = malloc((6 * cells + 200) * sizeof *idx);
    assert_non_null(pos);
    assert_non_null(off);
    assert_non_null(idx);
    for (size_t v = 0; v < nv; v++) {
        pos[3 * v] = (double)(v % N);
        pos[3 * v + 1] = (double)(v / N);
        pos[3 * v + 2] = 0.0;
    }
    size_t f = 0, c = 0;
    off[0] = 0;
#define FACE(...)                                                                              \
    do {                                                                                       \
        uint32_t face_[] = {__VA_ARGS__};                                                      \
        for (size_t i_ = 0; i_ < sizeof face_ / sizeof *face_; i_++)                           \
            idx[c++] = face_[i_];                                                              \
        off[++f] = (uint32_t)c;                                                                \
    } while (0)
    for (uint32_t y = 0; y + 1 < N; y++)
        for (uint32_t x = 0; x + 1 < N; x++) {
            uint32_t a = y * N + x, b = a + 1, d = a + N, e = d + 1;
            FACE(a, b, e);
            FACE(a, e, d);
            if (with_repeats && y == 200 && x == 100)
                FACE(a, b, b, e); /* a repeat in the second half */
            if (with_repeats && y == 300 && x == 7) {
                uint32_t big[60];
                for (int i = 0; i < 60; i++)
                    big[i] = (uint32_t)(i < 59 ? 5000 + i : 5000 + 31); /* back to corner 31 */
                for (int i = 0; i < 60; i++)
                    idx[c++] = big[i];
                off[++f] = (uint32_t)c;
            }
        }
    FACE(1, N + 1, 0);          /* face 1 again, rotated */
    FACE(N + 1, 1, 0);          /* and reversed */
    FACE(3 * N + 5, 3 * N + 6, 4 * N + 6); /* a copy of a face deep in the grid */
    FACE(7, 8, N + 8);
#undef FACE
    assert_int_equal(f, nf);
    limn_mesh *m = NULL;
    assert_int_equal(limn_mesh_create(ctx, nv, pos, nf, off, idx, &m), LIMN_OK);
    free(pos);
    free(off);
    free(idx);
    return m;
}

static void repair_same_for_any_thread_count(void **state)
{
    static const int thread_counts[] = {1, 2, 4};
    limn_context *ctx = *state;
    for (int repeats = 0; repeats < 2; repeats++) {
        limn_repair_report first = {.size = sizeof first};
        limn_mesh *first_mesh = NULL;
        for (size_t k = 0; k < sizeof thread_counts / sizeof *thread_counts; k++) {
            assert_int_equal(limn_context_set_host_threads(ctx, thread_counts[k]), LIMN_OK);
            limn_mesh *m = planted_mesh(ctx, repeats);
            limn_repair_options o = {.size = sizeof o};
            limn_repair_options_default(&o);
            o.duplicate_faces = 1;
            limn_repair_report r = {.size = sizeof r};
            assert_int_equal(limn_mesh_repair(ctx, m, &o, &r), LIMN_OK);
            /* the planted repeat (a b b e) becomes a copy of the face before it */
            size_t cells = 346 * 346, planted = 2 * (200 * 346 + 100) + 2;
            assert_int_equal(r.duplicate_faces, repeats ? 5 : 4);
            assert_int_equal(r.first_duplicate_face, repeats ? planted : 2 * cells);
            assert_int_equal(r.repeat_faces, repeats ? 2 : 0);
            if (repeats) {
                assert_int_equal(r.first_repeat_face, planted);
                assert_int_equal(r.first_repeat_vertex, 200 * 347 + 100 + 1);
                assert_int_equal(r.faces_split, 1); /* the 60-corner face, in two */
            }
            if (k == 0) {
                first = r;
                first_mesh = m;
                continue;
            }
            assert_memory_equal(&r, &first, sizeof r);
            assert_int_equal(m->face_count, first_mesh->face_count);
            assert_memory_equal(m->face_offsets, first_mesh->face_offsets,
                                (m->face_count + 1) * sizeof *m->face_offsets);
            assert_memory_equal(m->face_indices, first_mesh->face_indices,
                                m->face_offsets[m->face_count] * sizeof *m->face_indices);
            limn_mesh_destroy(m);
        }
        limn_mesh_destroy(first_mesh);
    }
    assert_int_equal(limn_context_set_host_threads(ctx, 0), LIMN_OK);
}

TEST_MAIN(NULL, NULL, CONTEXT_TEST(generated_meshes_closed_forms),
          CONTEXT_TEST(nonmanifold_classes), cmocka_unit_test(shared_meshes_match_stats),
          CONTEXT_TEST(shared_meshes_as_before), CONTEXT_TEST(hand_built_as_before),
          CONTEXT_TEST(one_topology_per_run),
          CONTEXT_TEST(repair_same_for_any_thread_count))
