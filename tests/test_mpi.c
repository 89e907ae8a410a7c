/* SPDX-License-Identifier: MIT */
/*
 * The MPI layer against the single process, run under mpirun with 2 and 3
 * ranks (tests/CMakeLists.txt). On every mesh and method the distributed
 * result must equal limn_interpolate's to 1e-12 of the coordinates' scale with
 * the same iteration count; the paper iteration, Chebyshev (its coefficients
 * follow the reduced maximum) and the series filters must give the very same bits (each row is summed in the single process's order,
 * mpi_part.h). The root computes the single-process reference with the same
 * device. Meshes: a generated one with several components (open grids with
 * boundaries and corners, a closed icosahedron, a pyramid, a non-manifold fin,
 * isolated vertices, a shuffled grid so that RCM runs), and shared real
 * meshes with holes, non-manifold edges, unreferenced vertices and several
 * components when ../shared/meshes is there.
 *
 * Not cmocka: an assertion that jumps out of a test on one rank would leave
 * the others waiting in a collective. Checks here record failures and carry
 * on; the ranks agree on the outcome at the end.
 */
#include "mpi_meshes.h"
#include "mpi_check.h"
#include "support.h"

#include "limn_mpi.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

MPI_CHECK_STATE;

/* ------------------------------------------------------------- comparisons */

/* Root: b against the reference a (3 per vertex); returns the identical count. */
static size_t compare(const char *what, const double *a, const double *b, size_t n3,
                      int exact)
{
    double scale = 0, worst = 0;
    size_t same = 0;
    for (size_t i = 0; i < n3; i++)
        scale = fmax(scale, fabs(a[i]));
    for (size_t i = 0; i < n3; i++) {
        worst = fmax(worst, fabs(a[i] - b[i]));
        same += a[i] == b[i];
    }
    CHECK(worst <= 1e-12 * scale, "%s: differs from the single process by %.3g (scale %.3g)",
          what, worst, scale);
    if (exact)
        CHECK(same == n3, "%s: %zu of %zu values differ from the single process's bits", what,
              n3 - same, n3);
    printf("  %-44s %zu/%zu values bit-identical, max difference %.2g of the scale\n", what, same,
           n3, scale > 0 ? worst / scale : worst);
    return same;
}

/* Collective: interpolate mesh (root's) both ways and compare. */
static void interpolate_case(limn_context *ctx, const char *name, const limn_mesh *mesh,
                             limn_scheme scheme, double alpha, limn_method method)
{
    limn_interpolate_options o;
    limn_interpolate_options_default(&o);
    o.scheme = scheme;
    o.alpha = alpha;
    o.method = method;
    limn_mesh *single = NULL, *dist = NULL;
    limn_report rs = {.size = sizeof rs}, rd = {.size = sizeof rd};
    limn_status ss = LIMN_OK;
    if (rank == 0) {
        ss = limn_interpolate(ctx, mesh, &o, &single, &rs);
        CHECK(ss == LIMN_OK, "%s: single process: %s", name, limn_context_message(ctx));
    }
    MPI_Bcast(&ss, 1, MPI_INT, 0, MPI_COMM_WORLD);
    if (ss != LIMN_OK)
        return;
    limn_mpi_result res = {.size = sizeof res, .stats.size = sizeof res.stats};
    limn_status st = limn_interpolate_mpi(ctx, MPI_COMM_WORLD, rank == 0 ? mesh : NULL, &o,
                                          rank == 0 ? &dist : NULL, &rd, NULL, &res);
    CHECK(st == LIMN_OK, "%s: distributed: %s", name, limn_context_message(ctx));
    if (rank == 0 && st == LIMN_OK) {
        char what[160];
        snprintf(what, sizeof what, "%s %s a=%g %s", name, limn_scheme_name(rd.scheme), alpha,
                 rd.method);
        CHECK(rd.iterations == rs.iterations, "%s: %d iterations, single process %d", what,
              rd.iterations, rs.iterations);
        CHECK(strcmp(rd.method, rs.method) == 0, "%s: method %s, single %s", what, rd.method,
              rs.method);
        CHECK(fabs(rd.products - rs.products) <= 1e-9 * rs.products, "%s: products %g vs %g",
              what, rd.products, rs.products);
        CHECK(rd.reordered == rs.reordered, "%s: vertex order differs", what);
        CHECK(fabs(rd.max_abs_error - rs.max_abs_error) <= 1e-12 * rs.bbox_diagonal,
              "%s: max error %.17g vs %.17g", what, rd.max_abs_error, rs.max_abs_error);
        compare(what, limn_mesh_positions(single), limn_mesh_positions(dist),
                3 * limn_mesh_vertex_count(mesh), method != LIMN_METHOD_WEIGHTED &&
                                                      strcmp(rd.method, "cg") != 0);
    }
    /* every rank's figures add up: each vertex is owned once */
    unsigned long long owned = res.stats.owned, total = 0;
    MPI_Allreduce(&owned, &total, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
    unsigned long long n = rank == 0 ? limn_mesh_vertex_count(mesh) : 0;
    MPI_Bcast(&n, 1, MPI_UNSIGNED_LONG_LONG, 0, MPI_COMM_WORLD);
    CHECK(st != LIMN_OK || total == n, "%s: ranks own %llu vertices of %llu", name, total, n);
    CHECK(st != LIMN_OK || res.stats.ranks == size, "%s: stats.ranks", name);
    limn_mesh_destroy(single);
    limn_mesh_destroy(dist);
}

/* Collective: smooth and denoise both ways; the pieces checked on every rank. */
static void series_case(limn_context *ctx, const char *name, const limn_mesh *mesh)
{
    limn_series_options o;
    limn_series_options_default(&o);
    limn_mpi_options mo;
    limn_mpi_options_default(&mo);
    mo.keep_piece = 1;
    limn_mesh *s1 = NULL, *s2 = NULL, *d1 = NULL, *d2 = NULL;
    if (rank == 0) {
        CHECK(limn_smooth(ctx, mesh, &o, 3, &s1, NULL) == LIMN_OK, "%s smooth: %s", name,
              limn_context_message(ctx));
        CHECK(limn_denoise(ctx, mesh, &o, 2, 3, 0, &d1, NULL) == LIMN_OK, "%s denoise: %s",
              name, limn_context_message(ctx));
    }
    limn_mpi_result res = {.size = sizeof res, .stats.size = sizeof res.stats};
    limn_status st = limn_smooth_mpi(ctx, MPI_COMM_WORLD, rank == 0 ? mesh : NULL, &o, 3,
                                     rank == 0 ? &s2 : NULL, NULL, &mo, &res);
    CHECK(st == LIMN_OK, "%s smooth (MPI): %s", name, limn_context_message(ctx));
    /* the piece: owned vertices first, positions of the result */
    size_t n3 = rank == 0 ? 3 * limn_mesh_vertex_count(mesh) : 0;
    unsigned long long n3b = n3;
    MPI_Bcast(&n3b, 1, MPI_UNSIGNED_LONG_LONG, 0, MPI_COMM_WORLD);
    double *all = malloc(n3b * sizeof *all);
    if (rank == 0 && s2)
        memcpy(all, limn_mesh_positions(s2), n3b * sizeof *all);
    MPI_Bcast(all, (int)n3b, MPI_DOUBLE, 0, MPI_COMM_WORLD);
    if (st == LIMN_OK) {
        CHECK(res.piece && res.piece_owned == res.stats.owned, "%s: piece of %zu owned vertices",
              name, res.piece_owned);
        size_t bad = 0;
        for (size_t i = 0; res.piece && i < limn_mesh_vertex_count(res.piece); i++)
            bad += memcmp(limn_mesh_positions(res.piece) + 3 * i,
                          all + 3 * (size_t)res.piece_vertices[i], 3 * sizeof(double)) != 0;
        CHECK(bad == 0, "%s: %zu piece vertices differ from the result", name, bad);
    }
    limn_mpi_result_free(&res);
    free(all);
    st = limn_denoise_mpi(ctx, MPI_COMM_WORLD, rank == 0 ? mesh : NULL, &o, 2, 3, 0,
                          rank == 0 ? &d2 : NULL, NULL, NULL, NULL);
    CHECK(st == LIMN_OK, "%s denoise (MPI): %s", name, limn_context_message(ctx));
    if (rank == 0 && s1 && s2 && d1 && d2) {
        char what[160];
        snprintf(what, sizeof what, "%s smooth 3 terms", name);
        compare(what, limn_mesh_positions(s1), limn_mesh_positions(s2), n3, 1);
        snprintf(what, sizeof what, "%s denoise m=2 K=3", name);
        compare(what, limn_mesh_positions(d1), limn_mesh_positions(d2), n3, 1);
    }
    limn_mesh_destroy(s1);
    limn_mesh_destroy(s2);
    limn_mesh_destroy(d1);
    limn_mesh_destroy(d2);
}

/* Collective: morph both ways, frames compared on root. */
typedef struct frames {
    size_t n3;
    int count;
    double *pos;
} frames;

static limn_status keep_frame(void *user, const limn_morph_frame *f)
{
    frames *fr = user;
    memcpy(fr->pos + (size_t)f->index * fr->n3, f->positions, fr->n3 * sizeof(double));
    fr->count++;
    return LIMN_OK;
}

static void morph_case(limn_context *ctx, const char *name, const limn_mesh *mesh)
{
    limn_morph_options o;
    limn_morph_options_default(&o);
    o.frames = 4;
    limn_mesh *to = NULL;
    frames a = {0, 0, NULL}, b = {0, 0, NULL};
    if (rank == 0) {
        limn_mesh_copy(ctx, mesh, &to);
        test_perturb(to, 0.2, 11);
        a.n3 = b.n3 = 3 * limn_mesh_vertex_count(mesh);
        a.pos = malloc((size_t)o.frames * a.n3 * sizeof(double));
        b.pos = malloc((size_t)o.frames * b.n3 * sizeof(double));
        CHECK(limn_morph(ctx, mesh, to, &o, keep_frame, &a, NULL) == LIMN_OK, "%s morph: %s",
              name, limn_context_message(ctx));
    }
    limn_status st = limn_morph_mpi(ctx, MPI_COMM_WORLD, rank == 0 ? mesh : NULL, to, &o,
                                    keep_frame, &b, NULL, NULL, NULL);
    CHECK(st == LIMN_OK, "%s morph (MPI): %s", name, limn_context_message(ctx));
    if (rank == 0 && st == LIMN_OK) {
        CHECK(a.count == o.frames && b.count == o.frames, "%s: %d and %d frames", name, a.count,
              b.count);
        char what[160];
        snprintf(what, sizeof what, "%s morph, %d frames", name, o.frames);
        compare(what, a.pos, b.pos, (size_t)o.frames * a.n3, 1);
    }
    free(a.pos);
    free(b.pos);
    limn_mesh_destroy(to);
}

/* ------------------------------------------------------------------ errors */

/* A failure on the root only (Loop on quads) and on one other rank only (a
   device that does not exist there): every rank returns it, with the
   failing rank's message, and nothing hangs. */
static void errors(limn_context *ctx, const limn_mesh *quads)
{
    limn_interpolate_options o;
    limn_interpolate_options_default(&o);
    o.scheme = LIMN_SCHEME_LOOP;
    limn_mesh *out = NULL;
    limn_status st = limn_interpolate_mpi(ctx, MPI_COMM_WORLD, rank == 0 ? quads : NULL, &o,
                                          rank == 0 ? &out : NULL, NULL, NULL, NULL);
    CHECK(st == LIMN_ERR_TOPOLOGY && strstr(limn_context_message(ctx), "Loop"),
          "Loop on quads: status %d, message '%s'", (int)st, limn_context_message(ctx));
    CHECK(out == NULL, "no mesh after a failure");

    limn_context *odd = limn_context_create();
    limn_context_set_device(odd, rank == size - 1 ? "opencl:no-such-device" : "opencl");
    o.scheme = LIMN_SCHEME_AUTO;
    st = limn_interpolate_mpi(odd, MPI_COMM_WORLD, rank == 0 ? quads : NULL, &o,
                              rank == 0 ? &out : NULL, NULL, NULL, NULL);
    CHECK(st == LIMN_ERR_DEVICE && strstr(limn_context_message(odd), "no-such-device"),
          "one rank's device: status %d, message '%s'", (int)st, limn_context_message(odd));
    CHECK(out == NULL, "no mesh after a failure");
    limn_context_destroy(odd);

    limn_mpi_options mo;
    limn_mpi_options_default(&mo);
    mo.root = size;
    st = limn_interpolate_mpi(ctx, MPI_COMM_WORLD, quads, &o, &out, NULL, &mo, NULL);
    CHECK(st == LIMN_ERR_ARGUMENT, "bad root: status %d", (int)st);

    /* a NaN written on the root (issue 18.4) and counts over their caps:
       every rank is refused with the root's message naming them */
    limn_mesh *bad = NULL;
    limn_mesh_copy(ctx, quads, &bad);
    if (rank == 0)
        limn_mesh_positions_mutable(bad)[3 * 2 + 1] = NAN;
    st = limn_interpolate_mpi(ctx, MPI_COMM_WORLD, rank == 0 ? bad : NULL, &o,
                              rank == 0 ? &out : NULL, NULL, NULL, NULL);
    CHECK(st == LIMN_ERR_ARGUMENT && strstr(limn_context_message(ctx), "vertex 2"),
          "NaN on the root: status %d, message '%s'", (int)st, limn_context_message(ctx));
    st = limn_smooth_mpi(ctx, MPI_COMM_WORLD, rank == 0 ? bad : NULL, NULL, 2,
                         rank == 0 ? &out : NULL, NULL, NULL, NULL);
    CHECK(st == LIMN_ERR_ARGUMENT && strstr(limn_context_message(ctx), "vertex 2"),
          "NaN on the root (smooth): status %d, message '%s'", (int)st,
          limn_context_message(ctx));
    st = limn_smooth_mpi(ctx, MPI_COMM_WORLD, rank == 0 ? quads : NULL, NULL, INT_MAX,
                         rank == 0 ? &out : NULL, NULL, NULL, NULL);
    CHECK(st == LIMN_ERR_ARGUMENT && strstr(limn_context_message(ctx), "LIMN_MAX_TERMS"),
          "terms over the cap: status %d, message '%s'", (int)st, limn_context_message(ctx));
    st = limn_denoise_mpi(ctx, MPI_COMM_WORLD, rank == 0 ? quads : NULL, NULL, 1, INT_MAX, 0,
                          rank == 0 ? &out : NULL, NULL, NULL, NULL);
    CHECK(st == LIMN_ERR_ARGUMENT && strstr(limn_context_message(ctx), "LIMN_MAX_STEPS"),
          "steps over the cap: status %d, message '%s'", (int)st, limn_context_message(ctx));
    CHECK(out == NULL, "no mesh after a failure");
    limn_mesh_destroy(bad);
}

/* The size fields (limn.h's ABI rule) under MPI: a refusal on one rank only
   is returned on every rank (none waits); a result too short for the piece
   fields gets the stats and no piece (nothing leaks); the canary after it
   stays intact. */
static void abi_sizes(limn_context *ctx, const limn_mesh *mesh)
{
    limn_interpolate_options o;
    limn_interpolate_options_default(&o);
    limn_mpi_options mo;
    limn_mpi_options_default(&mo);
    CHECK(mo.size == sizeof mo, "limn_mpi_options_default sets size");
    if (rank == size - 1)
        mo.size = 0;
    limn_mesh *out = NULL;
    limn_status st = limn_interpolate_mpi(ctx, MPI_COMM_WORLD, rank == 0 ? mesh : NULL, &o,
                                          rank == 0 ? &out : NULL, NULL, &mo, NULL);
    const char *msg = limn_context_message(ctx);
    CHECK(st == LIMN_ERR_ARGUMENT &&
              strstr(msg, rank == size - 1 ? "mpi->size is 0: initialise mpi with "
                                             "limn_mpi_options_default()"
                                           : (size > 1 ? "another rank refused" : "mpi->size")),
          "mpi->size 0 on the last rank: status %d, message '%s'", (int)st, msg);
    CHECK(out == NULL, "no mesh after a refusal");

    limn_mpi_options_default(&mo);
    mo.keep_piece = 1;
    struct {
        limn_mpi_result r;
        unsigned char canary[64];
    } g;
    memset(&g, 0xA5, sizeof g);
    g.r.size = offsetof(limn_mpi_result, piece);
    g.r.stats.size = sizeof g.r.stats;
    st = limn_smooth_mpi(ctx, MPI_COMM_WORLD, rank == 0 ? mesh : NULL, NULL, 2,
                         rank == 0 ? &out : NULL, NULL, &mo, &g.r);
    CHECK(st == LIMN_OK, "short result: %s", limn_context_message(ctx));
    CHECK(g.r.stats.ranks == size, "short result: stats.ranks %d", g.r.stats.ranks);
    const unsigned char *tail = (const unsigned char *)&g.r + offsetof(limn_mpi_result, piece);
    size_t spoilt = 0;
    for (size_t i = 0; i < sizeof g - offsetof(limn_mpi_result, piece); i++)
        spoilt += tail[i] != 0xA5;
    CHECK(spoilt == 0, "short result: %zu bytes written past its size", spoilt);
    limn_mpi_result_free(&g.r); /* too short for a piece: touches nothing */
    limn_mesh_destroy(out);
}

/* The device of each rank: the node's ranks take the matching devices in
   turn (local rank % count); PoCL has one CPU device: 0.0 for everyone. */
static void devices(limn_context *ctx, const limn_mesh *mesh)
{
    limn_mpi_result res = {.size = sizeof res, .stats.size = sizeof res.stats};
    limn_interpolate_options o;
    limn_interpolate_options_default(&o);
    limn_mesh *out = NULL;
    limn_context *fresh = limn_context_create();
    limn_status st = limn_interpolate_mpi(fresh, MPI_COMM_WORLD, rank == 0 ? mesh : NULL, &o,
                                          rank == 0 ? &out : NULL, NULL, NULL, &res);
    CHECK(st == LIMN_OK, "devices: %s", limn_context_message(fresh));
    CHECK(res.stats.local_rank == rank, "one node: local rank %d = rank %d", res.stats.local_rank,
          rank);
    if (strstr(res.stats.device, "reference") == NULL)
        CHECK(strstr(res.stats.device, "device 0.0") != NULL, "rank %d device '%s'", rank,
              res.stats.device);
    (void)ctx;
    limn_mesh_destroy(out);
    limn_context_destroy(fresh);
}

int main(int argc, char **argv)
{
    MPI_Init(&argc, &argv);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    limn_context *ctx = limn_context_create();
    if (rank == 0)
        printf("test_mpi: %d ranks\n", size);

    limn_mesh *tri = mpi_test_composite(ctx, 1), *quad = mpi_test_composite(ctx, 0);
    interpolate_case(ctx, "composite", tri, LIMN_SCHEME_LOOP, 0.0, LIMN_METHOD_PAPER);
    interpolate_case(ctx, "composite", tri, LIMN_SCHEME_LOOP, 0.0, LIMN_METHOD_WEIGHTED);
    interpolate_case(ctx, "composite", tri, LIMN_SCHEME_LOOP, 0.0, LIMN_METHOD_CG);
    interpolate_case(ctx, "composite", tri, LIMN_SCHEME_LOOP, 0.0, LIMN_METHOD_CHEBYSHEV);
    interpolate_case(ctx, "composite", quad, LIMN_SCHEME_CATMARK, 0.0, LIMN_METHOD_PAPER);
    interpolate_case(ctx, "composite", quad, LIMN_SCHEME_CATMARK, 0.5, LIMN_METHOD_PAPER);
    interpolate_case(ctx, "composite", quad, LIMN_SCHEME_CATMARK, 0.5, LIMN_METHOD_WEIGHTED);
    interpolate_case(ctx, "composite", quad, LIMN_SCHEME_CATMARK, 0.0, LIMN_METHOD_CG);
    interpolate_case(ctx, "composite", quad, LIMN_SCHEME_CATMARK, 0.5, LIMN_METHOD_CHEBYSHEV);
    series_case(ctx, "composite tri", tri);
    series_case(ctx, "composite quad", quad);
    morph_case(ctx, "composite quad", quad);
    errors(ctx, quad);
    abi_sizes(ctx, quad);
    devices(ctx, tri);

    /* tiny meshes: no more vertices than ranks (ranks without rows), and a
       few more (METIS on a handful of vertices) */
    static const double one_pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0.2};
    static const uint32_t one_off[] = {0, 3}, one_idx[] = {0, 1, 2};
    limn_mesh *one = NULL, *pyramid = test_mesh_pyramid(ctx);
    limn_mesh_create(ctx, 3, one_pos, 1, one_off, one_idx, &one);
    interpolate_case(ctx, "one triangle", one, LIMN_SCHEME_LOOP, 0.0, LIMN_METHOD_PAPER);
    interpolate_case(ctx, "pyramid", pyramid, LIMN_SCHEME_CATMARK, 0.5, LIMN_METHOD_PAPER);
    interpolate_case(ctx, "pyramid", pyramid, LIMN_SCHEME_CATMARK, 0.5, LIMN_METHOD_CG);
    series_case(ctx, "one triangle", one);
    series_case(ctx, "pyramid", pyramid);
    limn_mesh_destroy(one);
    limn_mesh_destroy(pyramid);

    /* the reference backend on every rank */
    limn_context *ref = limn_context_create();
    limn_context_set_device(ref, "reference");
    interpolate_case(ref, "composite (reference)", quad, LIMN_SCHEME_CATMARK, 0.5,
                     LIMN_METHOD_PAPER);
    limn_context_destroy(ref);

    /* shared real meshes: holes, non-manifold, components, unreferenced vertices */
    int shared = rank == 0 ? test_shared_meshes() != NULL : 0;
    MPI_Bcast(&shared, 1, MPI_INT, 0, MPI_COMM_WORLD);
    static const struct {
        const char *path;
        limn_scheme scheme;
        double alpha;
    } real[] = {{"small/suzanne.obj", LIMN_SCHEME_CATMARK, 0.0},
                {"small/bun_zipper_res4.ply", LIMN_SCHEME_LOOP, 0.0},
                {"small/bun_zipper_res4.ply", LIMN_SCHEME_CATMARK, 0.5},
                {"small/cow.obj", LIMN_SCHEME_LOOP, 0.0},
                {"small/hand_lowres.obj", LIMN_SCHEME_LOOP, 0.0},
                {"medium/bun_zipper.ply", LIMN_SCHEME_LOOP, 0.0},
                {"medium/bob_quad.obj", LIMN_SCHEME_CATMARK, 0.0},
                {"opensubdiv/catmark_nonman_edges.obj", LIMN_SCHEME_CATMARK, 0.5}};
    for (size_t k = 0; shared && k < sizeof real / sizeof *real; k++) {
        limn_mesh *m = NULL;
        int ok = 1;
        if (rank == 0) {
            ok = limn_mesh_read(ctx, test_shared_path(real[k].path), LIMN_FORMAT_AUTO, &m) ==
                     LIMN_OK &&
                 limn_mesh_repair(ctx, m, NULL, NULL) == LIMN_OK;
            CHECK(ok, "%s: %s", real[k].path, limn_context_message(ctx));
        }
        MPI_Bcast(&ok, 1, MPI_INT, 0, MPI_COMM_WORLD);
        if (!ok)
            continue;
        interpolate_case(ctx, real[k].path, m, real[k].scheme, real[k].alpha, LIMN_METHOD_PAPER);
        interpolate_case(ctx, real[k].path, m, real[k].scheme, real[k].alpha,
                         LIMN_METHOD_WEIGHTED);
        interpolate_case(ctx, real[k].path, m, real[k].scheme, real[k].alpha, LIMN_METHOD_CG);
        interpolate_case(ctx, real[k].path, m, real[k].scheme, real[k].alpha,
                         LIMN_METHOD_CHEBYSHEV);
        if (k < 2)
            series_case(ctx, real[k].path, m);
        limn_mesh_destroy(m);
    }
    if (!shared && rank == 0)
        printf("  (shared meshes not found: generated meshes only)\n");

    limn_mesh_destroy(tri);
    limn_mesh_destroy(quad);
    limn_context_destroy(ctx);
    return mpi_check_finish("test_mpi", NULL, checks, failures);
}
