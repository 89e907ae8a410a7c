/* SPDX-License-Identifier: MIT */
/*
 * The commands that joined the MPI layer after interpolate, smooth, denoise
 * and morph, against the single process, run under mpirun with 2, 3 and 5
 * ranks (tests/CMakeLists.txt): limn_bands_mpi (every band, the remainder
 * and every energy bit for bit), limn_sharpen_mpi (bit for bit, and its
 * pieces), limn_interpolate_mpi with precision float (paper and Chebyshev
 * bit for bit with the single process's iteration count; weighted to 1e-12
 * of the scale, its omega coming from a reduced 2-norm) and with method sgs
 * (its CG reductions summed per rank first: to 1e-12 of the scale, the
 * single process's iteration count). The root computes the reference with
 * the same device. Meshes: the generated composites of test_mpi (several
 * components, boundaries, corners, a non-manifold fin, isolated vertices,
 * triangles and quads), tiny meshes (ranks without rows), and the shared
 * meshes with holes, non-manifold edges and n-gons when ../shared/meshes is
 * there.
 *
 * Not cmocka, as test_mpi: checks record failures and carry on; the ranks
 * agree on the outcome at the end.
 */
#include "mpi_meshes.h"
#include "mpi_check.h"
#include "support.h"

#include "limn_mpi.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

MPI_CHECK_STATE;

/* Root: b against the reference a (n values); exact: every bit. */
static void same_values(const char *what, const double *a, const double *b, size_t n, int exact)
{
    double scale = 0, worst = 0;
    size_t same = 0;
    for (size_t i = 0; i < n; i++) {
        scale = fmax(scale, fabs(a[i]));
        worst = fmax(worst, fabs(a[i] - b[i]));
        same += memcmp(a + i, b + i, sizeof *a) == 0;
    }
    CHECK(worst <= 1e-12 * scale, "%s: differs from the single process by %.3g (scale %.3g)",
          what, worst, scale);
    if (exact)
        CHECK(same == n, "%s: %zu of %zu values differ from the single process's bits", what,
              n - same, n);
    printf("  %-52s %zu/%zu bit-identical, max difference %.2g of the scale\n", what, same, n,
           scale > 0 ? worst / scale : worst);
}

static size_t vertices_of(const limn_mesh *mesh)
{
    unsigned long long n = rank == 0 ? limn_mesh_vertex_count(mesh) : 0;
    MPI_Bcast(&n, 1, MPI_UNSIGNED_LONG_LONG, 0, MPI_COMM_WORLD);
    return (size_t)n;
}

/* ------------------------------------------------------------------- bands */

/* Collective: limn_bands both ways; also energies alone and bands alone. */
static void bands_case(limn_context *ctx, const char *name, const limn_mesh *mesh, int count)
{
    limn_series_options o;
    limn_series_options_default(&o);
    size_t n3 = 3 * vertices_of(mesh), total = ((size_t)count + 1) * n3;
    double *b1 = NULL, *b2 = NULL, *b3 = NULL, e1[16], e2[16], e3[16];
    limn_series_report r1 = {.size = sizeof r1}, r2 = {.size = sizeof r2};
    if (rank == 0) {
        b1 = malloc(total * sizeof *b1);
        b2 = malloc(total * sizeof *b2);
        b3 = malloc(total * sizeof *b3);
        CHECK(limn_bands(ctx, mesh, &o, count, b1, e1, &r1) == LIMN_OK, "%s bands: %s", name,
              limn_context_message(ctx));
    }
    limn_mpi_result res = {.size = sizeof res, .stats.size = sizeof res.stats};
    limn_status st = limn_bands_mpi(ctx, MPI_COMM_WORLD, rank == 0 ? mesh : NULL, &o, count, b2,
                                    e2, &r2, NULL, &res);
    CHECK(st == LIMN_OK, "%s bands (MPI): %s", name, limn_context_message(ctx));
    CHECK(st != LIMN_OK || res.stats.ranks == size, "%s bands: stats.ranks", name);
    /* energies alone, then bands alone: the same values */
    limn_status s2 = limn_bands_mpi(ctx, MPI_COMM_WORLD, rank == 0 ? mesh : NULL, &o, count,
                                    NULL, e3, NULL, NULL, NULL);
    limn_status s3 = limn_bands_mpi(ctx, MPI_COMM_WORLD, rank == 0 ? mesh : NULL, &o, count, b3,
                                    NULL, NULL, NULL, NULL);
    CHECK(s2 == LIMN_OK && s3 == LIMN_OK, "%s bands (MPI, energy or bands alone): %s", name,
          limn_context_message(ctx));
    if (rank == 0 && st == LIMN_OK && s2 == LIMN_OK && s3 == LIMN_OK) {
        char what[200];
        snprintf(what, sizeof what, "%s bands 0..%d + remainder", name, count - 1);
        same_values(what, b1, b2, total, 1);
        snprintf(what, sizeof what, "%s band energies", name);
        same_values(what, e1, e2, (size_t)count + 1, 1);
        CHECK(memcmp(e2, e3, ((size_t)count + 1) * sizeof *e2) == 0 &&
                  memcmp(b2, b3, total * sizeof *b2) == 0,
              "%s: bands or energies alone differ", name);
        CHECK(r1.products == r2.products && r1.stencil_nonzeros == r2.stencil_nonzeros &&
                  r1.vertices == r2.vertices,
              "%s bands: report differs (products %lld vs %lld)", name, r1.products,
              r2.products);
    }
    free(b1);
    free(b2);
    free(b3);
}

/* ----------------------------------------------------------------- sharpen */

/* Collective: limn_sharpen both ways; every rank's piece against the result. */
static void sharpen_case(limn_context *ctx, const char *name, const limn_mesh *mesh, int from,
                         int to, int steps)
{
    limn_series_options o;
    limn_series_options_default(&o);
    limn_mpi_options mo;
    limn_mpi_options_default(&mo);
    mo.keep_piece = 1;
    limn_mesh *s1 = NULL, *s2 = NULL;
    if (rank == 0)
        CHECK(limn_sharpen(ctx, mesh, &o, from, to, steps, &s1, NULL) == LIMN_OK,
              "%s sharpen: %s", name, limn_context_message(ctx));
    limn_mpi_result res = {.size = sizeof res, .stats.size = sizeof res.stats};
    limn_status st = limn_sharpen_mpi(ctx, MPI_COMM_WORLD, rank == 0 ? mesh : NULL, &o, from, to,
                                      steps, rank == 0 ? &s2 : NULL, NULL, &mo, &res);
    CHECK(st == LIMN_OK, "%s sharpen (MPI): %s", name, limn_context_message(ctx));
    size_t n3 = 3 * vertices_of(mesh);
    double *all = malloc((n3 ? n3 : 1) * sizeof *all);
    if (rank == 0 && s2)
        memcpy(all, limn_mesh_positions(s2), n3 * sizeof *all);
    MPI_Bcast(all, (int)n3, MPI_DOUBLE, 0, MPI_COMM_WORLD);
    if (st == LIMN_OK) {
        size_t bad = 0;
        for (size_t i = 0; res.piece && i < limn_mesh_vertex_count(res.piece); i++)
            bad += memcmp(limn_mesh_positions(res.piece) + 3 * i,
                          all + 3 * (size_t)res.piece_vertices[i], 3 * sizeof(double)) != 0;
        CHECK(res.piece && res.piece_owned == res.stats.owned && bad == 0,
              "%s sharpen: piece of %zu owned vertices, %zu differ from the result", name,
              res.piece_owned, bad);
    }
    if (rank == 0 && s1 && s2) {
        char what[200];
        snprintf(what, sizeof what, "%s sharpen %d..%d x%d", name, from, to, steps);
        same_values(what, limn_mesh_positions(s1), limn_mesh_positions(s2), n3, 1);
    }
    limn_mpi_result_free(&res);
    free(all);
    limn_mesh_destroy(s1);
    limn_mesh_destroy(s2);
}

/* ------------------------------------------------------------- interpolate */

/* Collective: limn_interpolate both ways with method and precision. */
static void solve_case(limn_context *ctx, const char *name, const limn_mesh *mesh,
                       limn_scheme scheme, double alpha, limn_method method,
                       limn_precision precision)
{
    limn_interpolate_options o;
    limn_interpolate_options_default(&o);
    o.scheme = scheme;
    o.alpha = alpha;
    o.method = method;
    o.precision = precision;
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
    limn_status st = limn_interpolate_mpi(ctx, MPI_COMM_WORLD, rank == 0 ? mesh : NULL, &o,
                                          rank == 0 ? &dist : NULL, &rd, NULL, NULL);
    CHECK(st == LIMN_OK, "%s: distributed: %s", name, limn_context_message(ctx));
    if (rank == 0 && st == LIMN_OK) {
        char what[200];
        snprintf(what, sizeof what, "%s %s a=%g %s %s", name, limn_scheme_name(rd.scheme), alpha,
                 rd.method, rd.precision);
        CHECK(strcmp(rd.method, rs.method) == 0 && strcmp(rd.precision, rs.precision) == 0,
              "%s: method %s / %s, single %s / %s", what, rd.method, rd.precision, rs.method,
              rs.precision);
        CHECK(rd.iterations == rs.iterations, "%s: %d iterations, single process %d", what,
              rd.iterations, rs.iterations);
        CHECK(rd.products_float == rs.products_float, "%s: %g float products, single %g", what,
              rd.products_float, rs.products_float);
        int exact = method != LIMN_METHOD_WEIGHTED && strcmp(rd.method, "sgs") != 0;
        same_values(what, limn_mesh_positions(single), limn_mesh_positions(dist),
                    3 * limn_mesh_vertex_count(mesh), exact);
    }
    limn_mesh_destroy(single);
    limn_mesh_destroy(dist);
}

/* ------------------------------------------------------------------ errors */

/* Refusals every rank returns alike, with the message everywhere. */
static void errors(limn_context *ctx, const limn_mesh *mesh)
{
    limn_series_options o;
    limn_series_options_default(&o);
    limn_mesh *out = NULL;
    limn_status st = limn_sharpen_mpi(ctx, MPI_COMM_WORLD, rank == 0 ? mesh : NULL, &o, 3, 1, 1,
                                      rank == 0 ? &out : NULL, NULL, NULL, NULL);
    CHECK(st == LIMN_ERR_ARGUMENT && strstr(limn_context_message(ctx), "from 3 to 1") && !out,
          "sharpen 3..1: status %d, '%s'", (int)st, limn_context_message(ctx));
    st = limn_bands_mpi(ctx, MPI_COMM_WORLD, rank == 0 ? mesh : NULL, &o, -1, NULL, NULL, NULL,
                        NULL, NULL);
    CHECK(st == LIMN_ERR_ARGUMENT, "bands -1: status %d, '%s'", (int)st,
          limn_context_message(ctx));
    /* no mesh on the root */
    st = limn_bands_mpi(ctx, MPI_COMM_WORLD, NULL, &o, 2, NULL, NULL, NULL, NULL, NULL);
    CHECK(st == LIMN_ERR_ARGUMENT && strstr(limn_context_message(ctx), "root"),
          "bands without a mesh: status %d, '%s'", (int)st, limn_context_message(ctx));
    limn_interpolate_options io;
    limn_interpolate_options_default(&io);
    io.method = LIMN_METHOD_CG;
    io.precision = LIMN_PRECISION_FLOAT;
    st = limn_interpolate_mpi(ctx, MPI_COMM_WORLD, rank == 0 ? mesh : NULL, &io,
                              rank == 0 ? &out : NULL, NULL, NULL, NULL);
    CHECK(st == LIMN_ERR_ARGUMENT && strstr(limn_context_message(ctx), "precision float") &&
              !out,
          "cg in float: status %d, '%s'", (int)st, limn_context_message(ctx));
}

/* --------------------------------------------------------------- the cases */

/* Every command of this file on one mesh. */
static void all_cases(limn_context *ctx, const char *name, const limn_mesh *mesh,
                      limn_scheme scheme, double alpha)
{
    bands_case(ctx, name, mesh, 3);
    sharpen_case(ctx, name, mesh, 1, 3, 2);
    static const limn_method floats[] = {LIMN_METHOD_PAPER, LIMN_METHOD_CHEBYSHEV,
                                         LIMN_METHOD_WEIGHTED};
    for (size_t k = 0; k < sizeof floats / sizeof *floats; k++)
        solve_case(ctx, name, mesh, scheme, alpha, floats[k], LIMN_PRECISION_FLOAT);
    solve_case(ctx, name, mesh, scheme, alpha, LIMN_METHOD_SGS, LIMN_PRECISION_DOUBLE);
}

static void shared_cases(limn_context *ctx)
{
    int shared = rank == 0 ? test_shared_meshes() != NULL : 0;
    MPI_Bcast(&shared, 1, MPI_INT, 0, MPI_COMM_WORLD);
    static const struct {
        const char *path;
        limn_scheme scheme;
        double alpha;
    } real[] = {{"small/suzanne.obj", LIMN_SCHEME_CATMARK, 0.0},
                {"small/bun_zipper_res4.ply", LIMN_SCHEME_LOOP, 0.0},
                {"small/cow.obj", LIMN_SCHEME_LOOP, 0.0},
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
        if (ok)
            all_cases(ctx, real[k].path, m, real[k].scheme, real[k].alpha);
        limn_mesh_destroy(m);
    }
    if (!shared && rank == 0)
        printf("  (shared meshes not found: generated meshes only)\n");
}

int main(int argc, char **argv)
{
    MPI_Init(&argc, &argv);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    limn_context *ctx = limn_context_create();
    if (rank == 0)
        printf("test_mpi_cmds: %d ranks\n", size);

    limn_mesh *tri = mpi_test_composite(ctx, 1), *quad = mpi_test_composite(ctx, 0);
    all_cases(ctx, "composite tri", tri, LIMN_SCHEME_LOOP, 0.0);
    all_cases(ctx, "composite quad", quad, LIMN_SCHEME_CATMARK, 0.5);
    solve_case(ctx, "composite quad", quad, LIMN_SCHEME_CATMARK, 0.0, LIMN_METHOD_CHEBYSHEV,
               LIMN_PRECISION_FLOAT);
    errors(ctx, quad);

    /* a small open grid: ranks without rows of a tier (pinned corners, creases,
       smooth rows) */
    limn_mesh *grid = test_mesh_grid(ctx, 3, 3, 0);
    all_cases(ctx, "grid 3x3", grid, LIMN_SCHEME_CATMARK, 0.5);
    limn_mesh_destroy(grid);

    /* tiny meshes: ranks without rows */
    static const double one_pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0.2};
    static const uint32_t one_off[] = {0, 3}, one_idx[] = {0, 1, 2};
    limn_mesh *one = NULL, *pyramid = test_mesh_pyramid(ctx);
    limn_mesh_create(ctx, 3, one_pos, 1, one_off, one_idx, &one);
    all_cases(ctx, "one triangle", one, LIMN_SCHEME_LOOP, 0.0);
    all_cases(ctx, "pyramid", pyramid, LIMN_SCHEME_CATMARK, 0.5);
    limn_mesh_destroy(one);
    limn_mesh_destroy(pyramid);

    /* the reference backend on every rank */
    limn_context *ref = limn_context_create();
    limn_context_set_device(ref, "reference");
    all_cases(ref, "composite quad (reference)", quad, LIMN_SCHEME_CATMARK, 0.5);
    limn_context_destroy(ref);

    shared_cases(ctx);
    limn_mesh_destroy(tri);
    limn_mesh_destroy(quad);
    limn_context_destroy(ctx);
    return mpi_check_finish("test_mpi_cmds", NULL, checks, failures);
}
