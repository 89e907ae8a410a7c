/* SPDX-License-Identifier: MIT */
/*
 * The claim under the MPI layer's data layout (DESIGN.md §2, README "MPI"):
 * the limit-stencil row of a vertex depends only on the faces incident to it
 * (its rule, smooth / crease / corner / non-manifold, included). Checked by
 * building the operator of a sub-mesh, the faces incident to a set of
 * vertices (vertices renumbered in increasing order, faces in input order),
 * and comparing each of those vertices' rows with the global operator's:
 * the same columns (mapped back) in the same order and the same weights bit
 * for bit, for Loop and Catmull-Clark (alpha 0 and 0.5), on meshes with
 * boundaries, corners, non-manifold edges and vertices, several components
 * and isolated vertices. So ranks can build their own rows from their faces
 * (mpi_local.c; test_mpi_local). And the RCM permutation keeps each row's
 * entries in order, so a reordered solve gives the input order's bits.
 */
#include "support.h"

#include "solve/operator.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

/* Face f has an owned vertex. */
static int touches_owned(const uint32_t *off, const uint32_t *idx, const uint8_t *owned, size_t f)
{
    int incident = 0;
    for (uint32_t c = off[f]; c < off[f + 1]; c++)
        incident |= owned[idx[c]];
    return incident;
}

/* Rows of `owned` (a mask) from the sub-mesh against the global rows;
   returns the number of rows compared. */
static size_t compare_rows(const char *name, const limn_mesh *mesh, const uint8_t *owned,
                           limn_scheme scheme, double alpha)
{
    limn_context *ctx = limn_context_create();
    size_t n = limn_mesh_vertex_count(mesh), nf = limn_mesh_face_count(mesh);
    const uint32_t *off = limn_mesh_face_offsets(mesh), *idx = limn_mesh_face_indices(mesh);
    /* the faces incident to an owned vertex, and their vertices */
    uint8_t *keep = calloc(n, 1);
    uint32_t *local = malloc(n * sizeof *local), *global = malloc(n * sizeof *global);
    uint32_t *off2 = malloc((nf + 1) * sizeof *off2), *idx2 = malloc(off[nf] * sizeof *idx2);
    size_t nf2 = 0, k2 = 0, nv2 = 0;
    off2[0] = 0;
    for (size_t f = 0; f < nf; f++) {
        if (!touches_owned(off, idx, owned, f))
            continue;
        for (uint32_t c = off[f]; c < off[f + 1]; c++)
            keep[idx[c]] = 1;
        nf2++;
    }
    for (size_t v = 0; v < n; v++)
        if (keep[v] || owned[v]) { /* increasing order: sorted rows stay sorted */
            local[v] = (uint32_t)nv2;
            global[nv2++] = (uint32_t)v;
        }
    for (size_t f = 0, g = 0; f < nf; f++) {
        if (!touches_owned(off, idx, owned, f))
            continue;
        for (uint32_t c = off[f]; c < off[f + 1]; c++)
            idx2[k2++] = local[idx[c]];
        off2[++g] = (uint32_t)k2;
    }
    double *pos = malloc((nv2 ? 3 * nv2 : 3) * sizeof *pos);
    for (size_t i = 0; i < nv2; i++)
        memcpy(pos + 3 * i, limn_mesh_positions(mesh) + 3 * (size_t)global[i], 3 * sizeof *pos);
    limn_mesh *sub = NULL;
    assert_int_equal(limn_mesh_create(ctx, nv2, pos, nf2, off2, idx2, &sub), LIMN_OK);
    assert_int_equal(limn_context_set_device(ctx, "reference"), LIMN_OK);
    stencil_operator a, b;
    if (operator_build(ctx, mesh, scheme, alpha, &a) || operator_build(ctx, sub, scheme, alpha, &b))
        fail_msg("%s: %s", name, limn_context_message(ctx));
    size_t rows = 0;
    for (size_t v = 0; v < n; v++) {
        if (!owned[v])
            continue;
        uint32_t l = local[v];
        uint32_t ga = a.host.row_offsets[v], na = a.host.row_offsets[v + 1] - ga;
        uint32_t gb = b.host.row_offsets[l], nb = b.host.row_offsets[l + 1] - gb;
        if (na != nb)
            fail_msg("%s: vertex %zu: %u entries globally, %u from its faces", name, v, na, nb);
        for (uint32_t e = 0; e < na; e++) {
            if (a.host.columns[ga + e] != global[b.host.columns[gb + e]] ||
                a.host.weights[ga + e] != b.host.weights[gb + e])
                fail_msg("%s: vertex %zu entry %u: (%u, %.17g) globally, (%u, %.17g) from its "
                         "faces",
                         name, v, e, a.host.columns[ga + e], a.host.weights[ga + e],
                         global[b.host.columns[gb + e]], b.host.weights[gb + e]);
        }
        rows++;
    }
    operator_free(&a);
    operator_free(&b);
    limn_mesh_destroy(sub);
    free(keep);
    free(local);
    free(global);
    free(off2);
    free(idx2);
    free(pos);
    limn_context_destroy(ctx);
    return rows;
}

/* Three vertex sets: a block of indices, every third vertex, a random half. */
static void all_sets(const char *name, const limn_mesh *mesh, limn_scheme scheme, double alpha)
{
    size_t n = limn_mesh_vertex_count(mesh), rows = 0;
    uint8_t *owned = malloc(n);
    unsigned long long s = 12345;
    for (int set = 0; set < 3; set++) {
        for (size_t v = 0; v < n; v++) {
            s = s * 6364136223846793005ULL + 1442695040888963407ULL;
            owned[v] = set == 0 ? v < n / 3 : set == 1 ? v % 3 == 0 : (s >> 40) & 1;
        }
        rows += compare_rows(name, mesh, owned, scheme, alpha);
    }
    printf("  %-40s %-7s alpha %.1f: %zu rows equal bit for bit\n", name, limn_scheme_name(scheme),
           alpha, rows);
    free(owned);
}

static void generated(void **st)
{
    limn_context *ctx = *st;
    limn_mesh *tri = test_keep_mesh(test_mesh_grid(ctx, 25, 17, 1));
    limn_mesh *quad = test_keep_mesh(test_mesh_grid(ctx, 25, 17, 0));
    limn_mesh *fan = test_keep_mesh(test_mesh_fan(ctx, 7, 0));
    limn_mesh *pyr = test_keep_mesh(test_mesh_pyramid(ctx));
    all_sets("triangle grid (boundary, corners)", tri, LIMN_SCHEME_LOOP, 0.0);
    all_sets("quad grid (boundary, corners)", quad, LIMN_SCHEME_CATMARK, 0.0);
    all_sets("quad grid (boundary, corners)", quad, LIMN_SCHEME_CATMARK, 0.5);
    all_sets("quad fan (valence 7)", fan, LIMN_SCHEME_CATMARK, 0.5);
    all_sets("pyramid (mixed faces)", pyr, LIMN_SCHEME_CATMARK, 0.0);
}

static void shared(void **st)
{
    if (!test_shared_meshes())
        skip();
    static const struct {
        const char *path;
        limn_scheme scheme;
        double alpha;
    } real[] = {{"small/bun_zipper_res4.ply", LIMN_SCHEME_LOOP, 0.0},     /* non-manifold, holes */
                {"small/bun_zipper_res4.ply", LIMN_SCHEME_CATMARK, 0.5},
                {"small/suzanne.obj", LIMN_SCHEME_CATMARK, 0.0},         /* 3 components, tri+quad */
                {"small/cow.obj", LIMN_SCHEME_LOOP, 0.0},                /* pinch vertex */
                {"opensubdiv/catmark_nonman_edges.obj", LIMN_SCHEME_CATMARK, 0.5},
                {"opensubdiv/catmark_nonman_verts.obj", LIMN_SCHEME_CATMARK, 0.0},
                {"opensubdiv/loop_nonman_edges.obj", LIMN_SCHEME_LOOP, 0.0},
                {"medium/bun_zipper.ply", LIMN_SCHEME_LOOP, 0.0}};       /* unreferenced vertices */
    limn_context *ctx = *st;
    for (size_t k = 0; k < sizeof real / sizeof *real; k++) {
        limn_mesh *m = NULL;
        if (limn_mesh_read(ctx, test_shared_path(real[k].path), LIMN_FORMAT_AUTO, &m) != LIMN_OK)
            continue; /* a mesh the shared set may not have */
        assert_int_equal(limn_mesh_repair(ctx, m, NULL, NULL), LIMN_OK);
        all_sets(real[k].path, m, real[k].scheme, real[k].alpha);
        limn_mesh_destroy(m);
    }
}

/* The RCM permutation keeps each row's entries in their order (columns
   renamed, stencil_permute), so a reordered solve sums every row as the
   input-order one does: the paper and weighted iterations give the same
   bits with and without reordering, and so do rows built per rank. */
static void reordered(void **st)
{
    limn_context *ctx = *st;
    assert_int_equal(limn_context_set_device(ctx, "reference"), LIMN_OK);
    limn_mesh *tri = test_keep_mesh(test_mesh_shuffle(ctx, test_mesh_grid(ctx, 90, 60, 1), 7));
    limn_mesh *quad = test_keep_mesh(test_mesh_shuffle(ctx, test_mesh_grid(ctx, 90, 60, 0), 7));
    static const limn_method methods[] = {LIMN_METHOD_PAPER, LIMN_METHOD_WEIGHTED};
    for (int k = 0; k < 4; k++) {
        limn_interpolate_options o;
        limn_interpolate_options_default(&o);
        o.method = methods[k % 2];
        o.alpha = k < 2 ? 0.0 : 0.5;
        const limn_mesh *m = k < 2 ? tri : quad;
        limn_mesh *a = NULL, *b = NULL;
        limn_report ra = {.size = sizeof ra}, rb = {.size = sizeof rb};
        assert_int_equal(limn_interpolate(ctx, m, &o, &a, &ra), LIMN_OK);
        o.reorder = 0;
        assert_int_equal(limn_interpolate(ctx, m, &o, &b, &rb), LIMN_OK);
        assert_int_equal(ra.reordered, 1);
        assert_int_equal(rb.reordered, 0);
        assert_int_equal(ra.iterations, rb.iterations);
        size_t n3 = 3 * limn_mesh_vertex_count(m);
        assert_memory_equal(limn_mesh_positions(a), limn_mesh_positions(b), n3 * sizeof(double));
        printf("  shuffled %s grid, %-8s: RCM and input order, %d iterations, same bits\n",
               k < 2 ? "triangle" : "quad", ra.method, ra.iterations);
        limn_mesh_destroy(a);
        limn_mesh_destroy(b);
    }
}

TEST_MAIN(NULL, NULL, CONTEXT_TEST(generated), CONTEXT_TEST(shared), CONTEXT_TEST(reordered))
