/* SPDX-License-Identifier: MIT */
/*
 * Uniform refinement (limn_subdivide) against OpenSubdiv's Far refinement
 * (test-only, tests/oracle): same vertex positions as point sets (1e-12 of the
 * scale; both evaluate the same masks in double) and the same faces once
 * vertices are matched by position, Catmull-Clark alpha = 0 and Loop, on meshes
 * with boundaries, n-gons, extraordinary and non-manifold vertices. Also: Euler
 * characteristic and boundary loops are preserved; alpha > 0 on the first step
 * equals the brute-force oracle; with --limit the surface vertex of input
 * vertex i lies within the tolerance of M_i after interpolation; both backends
 * agree; an oversize request is refused before any allocation.
 */
#include "support.h"
#include "osd_oracle.h"
#include "refine_oracle.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

typedef struct keyed {
    double key;
    uint32_t index;
} keyed;

static int cmp_keyed(const void *a, const void *b)
{
    double x = ((const keyed *)a)->key, y = ((const keyed *)b)->key;
    return x < y ? -1 : x > y;
}

static double project(const double *p) { return p[0] + 0.3719 * p[1] + 0.6113 * p[2]; }

/* map[i] = the nearest point of b within tol of a's point i that no earlier
   point claimed (coincident points exist, e.g. in catmark_val2_interior);
   returns 0 if some point has no partner. */
static int match_points(const double *a, const double *b, size_t n, size_t fixed, double tol,
                        uint32_t *map)
{
    keyed *kb = malloc(n * sizeof *kb);
    unsigned char *used = calloc(n, 1);
    /* the first `fixed` points must be the same points at the same index */
    for (size_t i = 0; i < fixed; i++) {
        for (int c = 0; c < 3; c++)
            if (fabs(a[3 * i + c] - b[3 * i + c]) > tol) {
                free(kb);
                free(used);
                return 0;
            }
        used[i] = 1;
        map[i] = (uint32_t)i;
    }
    for (size_t i = 0; i < n; i++) {
        kb[i].key = project(b + 3 * i);
        kb[i].index = (uint32_t)i;
    }
    qsort(kb, n, sizeof *kb, cmp_keyed);
    int ok = 1;
    for (size_t i = fixed; i < n && ok; i++) {
        double k = project(a + 3 * i), window = 2.0 * tol;
        size_t lo = 0, hi = n;
        while (lo < hi) {
            size_t mid = (lo + hi) / 2;
            if (kb[mid].key < k - window)
                lo = mid + 1;
            else
                hi = mid;
        }
        double best = INFINITY;
        uint32_t best_j = 0;
        for (size_t j = lo; j < n && kb[j].key <= k + window; j++) {
            const double *q = b + 3 * (size_t)kb[j].index;
            double d = fmax(fmax(fabs(q[0] - a[3 * i]), fabs(q[1] - a[3 * i + 1])),
                            fabs(q[2] - a[3 * i + 2]));
            if (d < best && !used[kb[j].index]) {
                best = d;
                best_j = kb[j].index;
            }
        }
        if (best > tol)
            ok = 0;
        else {
            used[best_j] = 1;
            map[i] = best_j;
        }
    }
    free(kb);
    free(used);
    return ok;
}

/* Faces as sorted tuples, each rotated to start at its smallest index. */
static uint32_t *canonical_faces(size_t nf, const int *sizes, const uint32_t *idx, const uint32_t *map,
                                 int width)
{
    uint32_t *out = malloc(nf * (size_t)width * sizeof *out);
    size_t k = 0;
    for (size_t f = 0; f < nf; f++) {
        int d = sizes[f];
        uint32_t tmp[8];
        int start = 0;
        for (int j = 0; j < d; j++) {
            tmp[j] = map ? map[idx[k + (size_t)j]] : idx[k + (size_t)j];
            if (tmp[j] < tmp[start])
                start = j;
        }
        for (int j = 0; j < width; j++)
            out[f * (size_t)width + (size_t)j] = j < d ? tmp[(start + j) % d] : UINT32_MAX;
        k += (size_t)d;
    }
    return out;
}

static int width_cmp;
static int cmp_tuple(const void *a, const void *b) { return memcmp(a, b, (size_t)width_cmp * 4); }

static void sort_tuples(uint32_t *t, size_t n, int width)
{
    /* memcmp on little-endian words is not numeric order, but any fixed total
       order works to compare two sets */
    width_cmp = width;
    qsort(t, n, (size_t)width * 4, cmp_tuple);
}

static limn_mesh *subdivide(limn_context *ctx, const limn_mesh *m, limn_scheme s, double alpha,
                            int levels, int limit)
{
    limn_subdivide_options o;
    limn_subdivide_options_default(&o);
    o.scheme = s;
    o.alpha = alpha;
    o.levels = levels;
    o.limit = limit;
    limn_mesh *out = NULL;
    if (limn_subdivide(ctx, m, &o, &out, NULL) != LIMN_OK)
        fail_msg("limn_subdivide: %s", limn_context_message(ctx));
    return out;
}

/* A mesh's faces in the oracles' form and an oracle's refined mesh, released together. */
typedef struct {
    int *sizes, *idx;
    int nv, nf, *fs, *fi;
    double *pos;
} oracle_refined;

static void oracle_refined_free(oracle_refined *o)
{
    void *owned[] = {o->sizes, o->idx, o->pos, o->fs, o->fi};
    for (size_t k = 0; k < sizeof owned / sizeof *owned; k++)
        free(owned[k]);
}

static void against_osd(limn_context *ctx, const char *name, const limn_mesh *m, limn_scheme s,
                        int levels)
{
    limn_mesh *ours = subdivide(ctx, m, s, 0.0, levels, 0);
    oracle_refined o;
    char err[512];
    test_oracle_faces(m, &o.sizes, &o.idx);
    if (osd_oracle_refine(s == LIMN_SCHEME_LOOP ? 0 : 1, (int)limn_mesh_vertex_count(m),
                          limn_mesh_positions(m), (int)limn_mesh_face_count(m), o.sizes, o.idx,
                          levels, &o.nv, &o.pos, &o.nf, &o.fs, &o.fi, err, sizeof err))
        fail_msg("%s: OpenSubdiv: %s", name, err);
    size_t n = limn_mesh_vertex_count(ours), nf = limn_mesh_face_count(ours);
    if (n != (size_t)o.nv || nf != (size_t)o.nf)
        fail_msg("%s level %d: limn %zu vertices %zu faces, OpenSubdiv %d and %d", name, levels, n,
                 nf, o.nv, o.nf);
    double scale = 1;
    for (size_t i = 0; i < 3 * n; i++)
        scale = fmax(scale, fabs(o.pos[i]));
    uint32_t *map = malloc(n * sizeof *map);
    /* input vertex i is vertex i, as in OpenSubdiv */
    if (!match_points(limn_mesh_positions(ours), o.pos, n, limn_mesh_vertex_count(m),
                      1e-12 * scale, map))
        fail_msg("%s (%s) level %d: vertex positions differ from OpenSubdiv's", name,
                 limn_scheme_name(s), levels);
    int width = s == LIMN_SCHEME_LOOP ? 3 : 4;
    int *our_sizes = calloc(nf ? nf : 1, sizeof *our_sizes);
    const uint32_t *off = limn_mesh_face_offsets(ours);
    for (size_t f = 0; f < nf; f++) {
        our_sizes[f] = (int)(off[f + 1] - off[f]);
        assert_int_equal(our_sizes[f], width);
        assert_int_equal(o.fs[f], width);
    }
    uint32_t *a = canonical_faces(nf, our_sizes, limn_mesh_face_indices(ours), map, width);
    uint32_t *b = canonical_faces(nf, o.fs, (const uint32_t *)o.fi, NULL, width);
    sort_tuples(a, nf, width);
    sort_tuples(b, nf, width);
    if (memcmp(a, b, nf * (size_t)width * 4) != 0)
        fail_msg("%s level %d: faces differ from OpenSubdiv's", name, levels);
    /* topology invariants */
    limn_mesh_info before = {.size = sizeof before}, after = {.size = sizeof after};
    assert_int_equal(limn_mesh_info_compute(ctx, m, &before), LIMN_OK);
    assert_int_equal(limn_mesh_info_compute(ctx, ours, &after), LIMN_OK);
    assert_int_equal(before.components, after.components);
    /* V - E + F with edges identified by their end vertices is a refinement
       invariant unless faces are duplicated (bun_zipper_res4: the inner child
       edges of two copies of a face then merge), so assert it where edges are
       manifold */
    if (before.nonmanifold_edges == 0) {
        assert_int_equal(before.euler_characteristic, after.euler_characteristic);
        assert_int_equal(before.boundary_loops, after.boundary_loops);
    }
    printf("  %-34s %-7s level %d: %7zu vertices %7zu faces = OpenSubdiv; euler %ld, %zu "
           "boundary loops kept\n",
           name, limn_scheme_name(s), levels, n, nf, after.euler_characteristic,
           after.boundary_loops);
    free(a);
    free(b);
    free(our_sizes);
    free(map);
    oracle_refined_free(&o);
    limn_mesh_destroy(ours);
}

static void generated_vs_osd(void **s)
{
    limn_context *ctx = *s;
    limn_mesh *grid = test_keep_mesh(test_mesh_grid(ctx, 4, 3, 0));
    limn_mesh *tgrid = test_keep_mesh(test_mesh_grid(ctx, 4, 3, 1));
    limn_mesh *cube = test_keep_mesh(test_mesh_cube(ctx));
    limn_mesh *pyr = test_keep_mesh(test_mesh_pyramid(ctx));
    limn_mesh *ico = test_keep_mesh(test_mesh_icosahedron(ctx));
    limn_mesh *fan = test_keep_mesh(test_mesh_fan(ctx, 5, 0));
    test_perturb(grid, 0.05, 1);
    test_perturb(tgrid, 0.05, 2);
    for (int l = 1; l <= 3; l++) {
        against_osd(ctx, "quad grid", grid, LIMN_SCHEME_CATMARK, l);
        against_osd(ctx, "triangle grid", tgrid, LIMN_SCHEME_LOOP, l);
        against_osd(ctx, "cube", cube, LIMN_SCHEME_CATMARK, l);
        against_osd(ctx, "pyramid", pyr, LIMN_SCHEME_CATMARK, l);
        against_osd(ctx, "icosahedron", ico, LIMN_SCHEME_LOOP, l);
        against_osd(ctx, "quad fan valence 5", fan, LIMN_SCHEME_CATMARK, l);
    }
}

static void shared_vs_osd(void **s)
{
    if (!test_shared_meshes())
        skip();
    static const struct {
        const char *file;
        limn_scheme scheme;
        int levels;
    } cases[] = {
        {"opensubdiv/catmark_nonquads.obj", LIMN_SCHEME_CATMARK, 3},
        {"opensubdiv/catmark_helmet.obj", LIMN_SCHEME_CATMARK, 3},
        {"opensubdiv/catmark_fan.obj", LIMN_SCHEME_CATMARK, 3},
        {"opensubdiv/catmark_nonman_verts.obj", LIMN_SCHEME_CATMARK, 3},
        {"opensubdiv/catmark_val2_interior.obj", LIMN_SCHEME_CATMARK, 2},
        {"opensubdiv/catmark_pole64.obj", LIMN_SCHEME_CATMARK, 2},
        {"opensubdiv/catmark_car.obj", LIMN_SCHEME_CATMARK, 2},
        {"small/suzanne.obj", LIMN_SCHEME_CATMARK, 2},
        {"small/spot_control_mesh.obj", LIMN_SCHEME_CATMARK, 3},
        {"small/hand_lowres.obj", LIMN_SCHEME_LOOP, 2},
        {"small/hand_lowres.obj", LIMN_SCHEME_CATMARK, 2},
        /* 40 duplicate faces: from level 2 on OpenSubdiv keeps the inner child
           edges of the two copies apart, limn merges them (edges are vertex
           pairs at every level), so only level 1 is comparable */
        {"small/bun_zipper_res4.ply", LIMN_SCHEME_LOOP, 1},
        {"small/cow.obj", LIMN_SCHEME_LOOP, 1},
        {"opensubdiv/loop_xord_interior.obj", LIMN_SCHEME_LOOP, 3},
        {"opensubdiv/loop_pole64.obj", LIMN_SCHEME_LOOP, 2},
        {"medium/bob_quad.obj", LIMN_SCHEME_CATMARK, 1},
    };
    limn_context *ctx = *s;
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        limn_mesh *m = test_read_shared(ctx, cases[i].file);
        for (int l = 1; l <= cases[i].levels; l++)
            against_osd(ctx, cases[i].file, m, cases[i].scheme, l);
        limn_mesh_destroy(m);
    }
}

/* alpha on the first step: limn's level-k points equal the brute-force
   oracle's (which applies alpha at its first level only) as point sets. */
static void alpha_first_step(void **s)
{
    limn_context *ctx = *s;
    limn_mesh *meshes[] = {test_mesh_cube(ctx), test_mesh_pyramid(ctx), test_mesh_fan(ctx, 5, 0),
                           test_mesh_grid(ctx, 3, 3, 0)};
    for (size_t i = 0; i < 4; i++) {
        test_perturb(meshes[i], 0.05, (unsigned)i);
        for (int l = 1; l <= 3; l++) {
            limn_mesh *ours = subdivide(ctx, meshes[i], LIMN_SCHEME_CATMARK, 0.5, l, 0);
            oracle_refined o;
            char err[256];
            test_oracle_faces(meshes[i], &o.sizes, &o.idx);
            assert_int_equal(refine_oracle(1, 0.5, l, (int)limn_mesh_vertex_count(meshes[i]),
                                           limn_mesh_positions(meshes[i]),
                                           (int)limn_mesh_face_count(meshes[i]), o.sizes, o.idx,
                                           &o.nv, &o.pos, &o.nf, &o.fs, &o.fi, err, sizeof err),
                             0);
            size_t n = limn_mesh_vertex_count(ours);
            assert_int_equal(n, (size_t)o.nv);
            uint32_t *map = malloc(n * sizeof *map);
            assert_true(match_points(limn_mesh_positions(ours), o.pos, n,
                                     limn_mesh_vertex_count(meshes[i]), 1e-12 * 4, map));
            free(map);
            oracle_refined_free(&o);
            limn_mesh_destroy(ours);
        }
        limn_mesh_destroy(meshes[i]);
    }
}

/* interpolate, then refine with --limit: the surface passes through M. */
static void surface_passes_through_input(void **s)
{
    limn_context *ctx = *s;
    char spot[4096];
    snprintf(spot, sizeof spot, "%.4000s/spot_control_mesh.obj", getenv("LIMN_TEST_DATA"));
    limn_mesh *spot_mesh = NULL;
    assert_int_equal(limn_mesh_read(ctx, spot, LIMN_FORMAT_AUTO, &spot_mesh), LIMN_OK);
    test_keep_mesh(spot_mesh);
    limn_mesh *tri = test_keep_mesh(test_mesh_icosahedron(ctx));
    limn_mesh *tgrid = test_keep_mesh(test_mesh_grid(ctx, 5, 4, 1));
    test_perturb(tri, 0.1, 9);
    struct {
        const char *name;
        limn_mesh *m;
        limn_scheme scheme;
        double alpha;
    } cases[] = {
        {"spot", spot_mesh, LIMN_SCHEME_CATMARK, 0.0},
        {"spot", spot_mesh, LIMN_SCHEME_CATMARK, 0.5},
        {"icosahedron", tri, LIMN_SCHEME_LOOP, 0.0},
        {"triangle grid", tgrid, LIMN_SCHEME_LOOP, 0.0},
        {"triangle grid", tgrid, LIMN_SCHEME_CATMARK, 0.5},
    };
    for (size_t c = 0; c < sizeof cases / sizeof *cases; c++) {
        limn_interpolate_options o;
        limn_interpolate_options_default(&o);
        o.scheme = cases[c].scheme;
        o.alpha = cases[c].alpha;
        limn_mesh *p = NULL;
        assert_int_equal(limn_interpolate(ctx, cases[c].m, &o, &p, NULL), LIMN_OK);
        double diag = test_bbox_diagonal(cases[c].m);
        for (int levels = 1; levels <= 3; levels++) {
            limn_mesh *surf = subdivide(ctx, p, cases[c].scheme, cases[c].alpha, levels, 1);
            const double *sp = limn_mesh_positions(surf), *mp = limn_mesh_positions(cases[c].m);
            double worst = 0;
            for (size_t i = 0; i < limn_mesh_vertex_count(cases[c].m); i++)
                worst = fmax(worst, sqrt(pow(sp[3 * i] - mp[3 * i], 2) +
                                         pow(sp[3 * i + 1] - mp[3 * i + 1], 2) +
                                         pow(sp[3 * i + 2] - mp[3 * i + 2], 2)));
            if (worst > o.tolerance * diag * (1 + 1e-6))
                fail_msg("%s alpha %g level %d: surface misses M by %.3g diag", cases[c].name,
                         cases[c].alpha, levels, worst / diag);
            printf("  %-14s %-7s alpha %.1f level %d --limit: surface vertex i within %.2e diag "
                   "of M_i\n",
                   cases[c].name, limn_scheme_name(cases[c].scheme), cases[c].alpha, levels,
                   worst / diag);
            limn_mesh_destroy(surf);
        }
        limn_mesh_destroy(p);
    }
}

static void backends_agree(void **s)
{
    limn_context *cl = *s, *ref = test_keep_context(limn_context_create());
    assert_int_equal(limn_context_set_device(ref, "reference"), LIMN_OK);
    limn_mesh *g = test_keep_mesh(test_mesh_grid(cl, 30, 20, 0));
    limn_mesh *t = test_keep_mesh(test_mesh_grid(cl, 30, 20, 1));
    limn_mesh *meshes[] = {g, t};
    for (int i = 0; i < 2; i++)
        for (int limit = 0; limit <= 1; limit++) {
            limn_mesh *a = subdivide(cl, meshes[i], LIMN_SCHEME_AUTO, 0.5, 3, limit);
            limn_mesh *b = subdivide(ref, meshes[i], LIMN_SCHEME_AUTO, 0.5, 3, limit);
            size_t n = limn_mesh_vertex_count(a);
            assert_int_equal(n, limn_mesh_vertex_count(b));
            assert_memory_equal(limn_mesh_positions(a), limn_mesh_positions(b),
                                3 * n * sizeof(double));
            limn_mesh_destroy(a);
            limn_mesh_destroy(b);
        }
}

static void memory_refusal(void **s)
{
    limn_context *ctx = *s;
    limn_mesh *g = test_mesh_grid(ctx, 10, 10, 0), *out = NULL;
    limn_subdivide_options o;
    limn_subdivide_options_default(&o);
    o.levels = 6;
    o.max_memory = 1 << 20;
    assert_int_equal(limn_subdivide(ctx, g, &o, &out, NULL), LIMN_ERR_MEMORY);
    assert_null(out);
    assert_non_null(strstr(limn_context_message(ctx), "--max-memory"));
    assert_non_null(strstr(limn_context_message(ctx), "409600 faces"));
    o.levels = 17;
    assert_int_equal(limn_subdivide(ctx, g, &o, &out, NULL), LIMN_ERR_ARGUMENT);
    limn_mesh_destroy(g);
}

/* The child faces are written over ranges of faces (refine.c child_range):
   grids large enough for several ranges give the same mesh, positions and
   faces, for 1, 2 and 4 host threads, in both schemes. */
static void same_for_any_thread_count(void **state)
{
    limn_context *ctx = *state;
    static const int threads[] = {1, 2, 4};
    for (int quads = 0; quads < 2; quads++) {
        limn_mesh *g = test_keep_mesh(quads ? test_mesh_grid(ctx, 400, 400, 0)
                                            : test_mesh_grid(ctx, 300, 300, 1));
        limn_scheme s = quads ? LIMN_SCHEME_CATMARK : LIMN_SCHEME_LOOP;
        limn_mesh *first = NULL;
        for (size_t k = 0; k < sizeof threads / sizeof *threads; k++) {
            assert_int_equal(limn_context_set_host_threads(ctx, threads[k]), LIMN_OK);
            limn_mesh *out = subdivide(ctx, g, s, 0.0, 1, 0);
            if (!first) {
                first = out;
                continue;
            }
            size_t nf = limn_mesh_face_count(out), ni = limn_mesh_index_count(out);
            assert_int_equal(nf, limn_mesh_face_count(first));
            assert_int_equal(ni, limn_mesh_index_count(first));
            assert_memory_equal(limn_mesh_face_offsets(out), limn_mesh_face_offsets(first),
                                (nf + 1) * sizeof(uint32_t));
            assert_memory_equal(limn_mesh_face_indices(out), limn_mesh_face_indices(first),
                                ni * sizeof(uint32_t));
            assert_memory_equal(limn_mesh_positions(out), limn_mesh_positions(first),
                                3 * limn_mesh_vertex_count(out) * sizeof(double));
            limn_mesh_destroy(out);
        }
        limn_mesh_destroy(first);
    }
    assert_int_equal(limn_context_set_host_threads(ctx, 0), LIMN_OK);
}

TEST_MAIN(NULL, NULL, CONTEXT_TEST(generated_vs_osd), CONTEXT_TEST(shared_vs_osd),
          CONTEXT_TEST(alpha_first_step), CONTEXT_TEST(surface_passes_through_input),
          CONTEXT_TEST(backends_agree), CONTEXT_TEST(memory_refusal),
          CONTEXT_TEST(same_for_any_thread_count))
