/* SPDX-License-Identifier: MIT */
/*
 * limn denoise's default form (limn_denoise_sure) over MPI against the
 * single process, under mpirun with 2, 3 and 5 ranks, on both paths:
 * limn_mpi_mesh_denoise_sure (a distributed mesh: no rank gathers a vector,
 * the noise estimate's and the fit's inner products summed rank to rank)
 * and limn_denoise_sure_mpi (the root holds the mesh and fits after a
 * gather) write limn_denoise_sure's bytes and give its noise estimate to the
 * bit, with keep_volume on closed meshes (volume kept as limn_denoise does)
 * and without; an open mesh with keep_volume is refused on every rank with
 * limn_denoise_sure's message, nothing made. Meshes: the generated
 * composites and closed meshes of test_mpi (several components, boundaries,
 * a non-manifold fin, isolated vertices, n-gons), with seeded noise, tiny
 * meshes (one triangle, a pyramid: ranks without vertices), and shared
 * meshes when ../shared/meshes is there. Rank 0 runs the single
 * process on the same file.
 */
#include "mpi_check.h"
#include "mpi_meshes.h"
#include "noise.h"
#include "shell.h"
#include "support.h"

#include "limn_mpi.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

MPI_CHECK_STATE;
static char dir[256];

/* The single process's outcome on rank 0 (broadcast to all). */
typedef struct single_out {
    int ok, status;
    double sigma;
    char message[1024];
} single_out;

/* One case: the file, the options, the degree, keep_volume. */
typedef struct sure_case {
    const char *name, *in, *ref, *out;
    const limn_series_options *o;
    int products, keep_volume;
} sure_case;

/* Reads and repairs c->in on this process (rank 0 only on the root path). */
static limn_mesh *read_whole(limn_context *ctx, const char *in)
{
    limn_mesh *m = NULL;
    if (limn_mesh_read(ctx, in, LIMN_FORMAT_AUTO, &m) || limn_mesh_repair(ctx, m, NULL, NULL)) {
        limn_mesh_destroy(m);
        return NULL;
    }
    return m;
}

static void single(limn_context *ctx, const sure_case *c, single_out *s)
{
    memset(s, 0, sizeof *s);
    limn_mesh *m = read_whole(ctx, c->in), *f = NULL;
    CHECK(m != NULL, "single process on %s: %s", c->in, limn_context_message(ctx));
    s->ok = m != NULL;
    if (m)
        s->status =
            (int)limn_denoise_sure(ctx, m, c->o, c->products, c->keep_volume, &f, &s->sigma, NULL);
    if (m && s->status)
        snprintf(s->message, sizeof s->message, "%s", limn_context_message(ctx));
    else if (m)
        s->ok = limn_mesh_write(ctx, f, c->ref, LIMN_FORMAT_AUTO) == LIMN_OK;
    limn_mesh_destroy(m);
    limn_mesh_destroy(f);
}

/* The outcome st (sigma, message) of a distributed call against the single's. */
static int same_outcome(limn_context *ctx, const char *path, const sure_case *c,
                        const single_out *s, limn_status st, double sigma)
{
    if (s->status) {
        CHECK(st == (limn_status)s->status && strcmp(limn_context_message(ctx), s->message) == 0,
              "%s %s (%d ranks): refusal %d '%s', one process %d '%s'", c->name, path, size,
              (int)st, limn_context_message(ctx), s->status, s->message);
        return 0;
    }
    CHECK(st == LIMN_OK, "%s %s (%d ranks): %s", c->name, path, size, limn_context_message(ctx));
    CHECK(st || memcmp(&sigma, &s->sigma, sizeof sigma) == 0,
          "%s %s (%d ranks): sigma %.17g, one process %.17g", c->name, path, size, sigma,
          s->sigma);
    return st == LIMN_OK;
}

/* Every rank: read the slices, repair, denoise (limn_mpi_mesh_denoise_sure), write. */
static void sliced(limn_context *ctx, const sure_case *c, const single_out *s)
{
    limn_mpi_mesh *m = NULL, *f = NULL;
    limn_status st = limn_mpi_mesh_read(ctx, MPI_COMM_WORLD, c->in, LIMN_FORMAT_AUTO, &m);
    if (!st)
        st = limn_mpi_mesh_repair(ctx, m, NULL, NULL);
    CHECK(st == LIMN_OK, "%s: reading slices: %s", c->name, limn_context_message(ctx));
    double sigma = -1.0;
    if (!st)
        st = limn_mpi_mesh_denoise_sure(ctx, m, c->o, c->products, c->keep_volume, &f, &sigma,
                                        NULL, NULL, NULL);
    if (same_outcome(ctx, "slices", c, s, st, sigma))
        CHECK(limn_mpi_mesh_write(ctx, f, c->out, LIMN_FORMAT_AUTO, NULL, NULL) == LIMN_OK,
              "%s: writing %s: %s", c->name, c->out, limn_context_message(ctx));
    CHECK(!s->status || f == NULL, "%s: a refused call made a mesh", c->name);
    limn_mpi_mesh_destroy(m);
    limn_mpi_mesh_destroy(f);
}

/* The root path: rank 0 reads, every rank computes (limn_denoise_sure_mpi). */
static void root_path(limn_context *ctx, const sure_case *c, const single_out *s)
{
    limn_mesh *m = rank == 0 ? read_whole(ctx, c->in) : NULL, *f = NULL;
    double sigma = -1.0;
    limn_status st = limn_denoise_sure_mpi(ctx, MPI_COMM_WORLD, m, c->o, c->products,
                                           c->keep_volume, rank == 0 ? &f : NULL, &sigma, NULL,
                                           NULL, NULL);
    if (same_outcome(ctx, "root path", c, s, st, sigma) && rank == 0)
        CHECK(limn_mesh_write(ctx, f, c->out, LIMN_FORMAT_AUTO) == LIMN_OK &&
                  test_same_bytes(c->ref, c->out),
              "%s (%d ranks): the root path's mesh differs from one process's", c->name, size);
    limn_mesh_destroy(m);
    limn_mesh_destroy(f);
}

static void run_case(limn_context *ctx, const sure_case *c)
{
    single_out s = {0};
    if (rank == 0)
        single(ctx, c, &s);
    MPI_Bcast(&s, (int)sizeof s, MPI_BYTE, 0, MPI_COMM_WORLD);
    if (!s.ok)
        return;
    sliced(ctx, c, &s);
    if (rank == 0 && !s.status)
        CHECK(test_same_bytes(c->ref, c->out),
              "%s (%d ranks, products %d, keep_volume %d): slices differ from one process's",
              c->name, size, c->products, c->keep_volume);
    MPI_Barrier(MPI_COMM_WORLD);
    root_path(ctx, c, &s);
    MPI_Barrier(MPI_COMM_WORLD);
}

/* One mesh (noisy when noise > 0): degrees 12 and 3, keep_volume 0 and 1
   (1 on an open mesh: the refusal). */
static void mesh_case(limn_context *ctx, const char *name, limn_mesh *mesh, limn_scheme scheme,
                      double noise)
{
    char in[320], ref[320], out[320];
    snprintf(in, sizeof in, "%s/in.ply", dir);
    snprintf(ref, sizeof ref, "%s/ref.ply", dir);
    snprintf(out, sizeof out, "%s/out.ply", dir);
    limn_series_options o;
    limn_series_options_default(&o);
    o.scheme = scheme;
    int ok = 1;
    if (rank == 0) {
        if (noise > 0)
            test_gaussian_noise(mesh, noise * test_mean_edge(mesh), 16);
        ok = limn_mesh_write(ctx, mesh, in, LIMN_FORMAT_AUTO) == LIMN_OK;
        CHECK(ok, "%s: writing %s: %s", name, in, limn_context_message(ctx));
    }
    MPI_Bcast(&ok, 1, MPI_INT, 0, MPI_COMM_WORLD);
    static const int degrees[] = {12, 3};
    for (int k = 0; ok && k < 4; k++) {
        sure_case c = {name, in, ref, out, &o, degrees[k / 2], k % 2};
        run_case(ctx, &c);
    }
    if (rank == 0) {
        printf("  %-28s 2 degrees x keep_volume 0/1: both paths checked on %d ranks\n", name,
               size);
        unlink(in);
        unlink(ref);
        unlink(out);
    }
}

/* A shared mesh (holes, non-manifold edges, n-gons: mpi_check_shared), noisy. */
static void shared_case(limn_context *ctx, size_t k, const char *path, limn_mesh *m)
{
    (void)k;
    mesh_case(ctx, path, m, LIMN_SCHEME_AUTO, 0.3);
}

int main(int argc, char **argv)
{
    MPI_Init(&argc, &argv);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    mpi_test_scratch_dir(dir, sizeof dir, "test_mpi_denoise");
    limn_context *ctx = limn_context_create();
    limn_mesh *ctri = mpi_test_closed(ctx, 1), *cquad = mpi_test_closed(ctx, 0);
    limn_mesh *otri = mpi_test_composite(ctx, 1), *oquad = mpi_test_composite(ctx, 0);
    mesh_case(ctx, "closed tri, noisy", ctri, LIMN_SCHEME_LOOP, 0.3);
    mesh_case(ctx, "closed quad, noisy", cquad, LIMN_SCHEME_CATMARK, 0.3);
    mesh_case(ctx, "composite tri", otri, LIMN_SCHEME_LOOP, 0.0);
    mesh_case(ctx, "composite quad, noisy", oquad, LIMN_SCHEME_CATMARK, 0.2);
    /* tiny meshes: at 5 ranks some without vertices or rows */
    static const double one_pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0.2};
    static const uint32_t one_off[] = {0, 3}, one_idx[] = {0, 1, 2};
    limn_mesh *one = NULL, *pyramid = test_mesh_pyramid(ctx);
    limn_mesh_create(ctx, 3, one_pos, 1, one_off, one_idx, &one);
    mesh_case(ctx, "one triangle", one, LIMN_SCHEME_LOOP, 0.0);
    mesh_case(ctx, "pyramid, noisy", pyramid, LIMN_SCHEME_CATMARK, 0.1);
    limn_mesh_destroy(one);
    limn_mesh_destroy(pyramid);
    static const char *const real[] = {"small/suzanne.obj", "small/fandisk_quads.off",
                                       "small/cow.obj"};
    mpi_check_shared(ctx, real, sizeof real / sizeof *real, shared_case);
    limn_mesh_destroy(ctri);
    limn_mesh_destroy(cquad);
    limn_mesh_destroy(otri);
    limn_mesh_destroy(oquad);
    limn_context_destroy(ctx);
    return mpi_check_finish("test_mpi_denoise", dir, checks, failures);
}
