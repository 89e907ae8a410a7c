/* SPDX-License-Identifier: MIT */
/*
 * limn_mpi_mesh_denoise_features against limn_denoise_features, under
 * mpirun with 2, 3 and 5 ranks: the same bytes (the result written by both
 * routes and compared) on the generated meshes of mpi_meshes.c (several
 * components, boundaries, a non-manifold fin, isolated vertices, n-gons;
 * closed tori, icosahedron and prism, with keep_volume), with the default
 * options and with others (3 normal steps, 4 sweeps, 3 rounds, sigma_r 0.5,
 * a given sigma_s, no tangential pull); keep_volume on an open mesh refused
 * with the single process's message on every rank, nothing made; bad
 * options refused. The sanitizer build checks leaks here (the CLI runs
 * under mpirun do not).
 */
#include "mpi_check.h"
#include "mpi_meshes.h"
#include "shell.h"
#include "support.h"

#include "limn_mpi.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

MPI_CHECK_STATE;
static char dir[256];

/* The single process on rank 0: its status and message (broadcast). */
typedef struct single_out {
    int status;
    char message[1024];
} single_out;

static void single(limn_context *ctx, const char *in, const limn_feature_options *o,
                   const char *out, single_out *s)
{
    memset(s, 0, sizeof *s);
    limn_mesh *m = NULL, *f = NULL;
    limn_series_report r = {.size = sizeof r};
    s->status = (int)limn_mesh_read(ctx, in, LIMN_FORMAT_AUTO, &m);
    if (!s->status)
        s->status = (int)limn_mesh_repair(ctx, m, NULL, NULL);
    if (!s->status)
        s->status = (int)limn_denoise_features(ctx, m, o, &f, &r);
    if (!s->status)
        s->status = (int)limn_mesh_write(ctx, f, out, LIMN_FORMAT_AUTO);
    if (s->status)
        snprintf(s->message, sizeof s->message, "%s", limn_context_message(ctx));
    limn_mesh_destroy(m);
    limn_mesh_destroy(f);
}

/* Every rank: read in slices, repair, denoise, write; the status against s. */
/* W's products of the options: normal_steps in the first round, half of
   them (rounded up) in each later one with adaptive; with a crease angle
   the rounds again, the first with at most 3 (limn.h). */
static long long products_of(const limn_feature_options *o)
{
    int later = o->adaptive ? (o->normal_steps + 1) / 2 : o->normal_steps;
    long long pass = (long long)(o->outer_steps - 1) * later;
    int again = o->normal_steps < 3 ? o->normal_steps : 3;
    return o->normal_steps + pass + (o->crease_angle > 0.0 ? again + pass : 0);
}

static void distributed(limn_context *ctx, const char *name, const char *in,
                        const limn_feature_options *o, const char *out, const single_out *s)
{
    limn_mpi_mesh *m = NULL, *f = NULL;
    limn_series_report r = {.size = sizeof r};
    limn_status st = limn_mpi_mesh_read(ctx, MPI_COMM_WORLD, in, LIMN_FORMAT_AUTO, &m);
    if (!st)
        st = limn_mpi_mesh_repair(ctx, m, NULL, NULL);
    CHECK(st == LIMN_OK, "%s: reading: %s", name, limn_context_message(ctx));
    if (!st) {
        st = limn_mpi_mesh_denoise_features(ctx, m, o, &f, &r, NULL, NULL);
        CHECK((int)st == s->status && (st != LIMN_OK) == (f == NULL),
              "%s (%d ranks): status %d '%s', one process %d '%s'", name, size, (int)st,
              limn_context_message(ctx), s->status, s->message);
        if (st && s->status)
            CHECK(strcmp(limn_context_message(ctx), s->message) == 0,
                  "%s (%d ranks): '%s', one process '%s'", name, size,
                  limn_context_message(ctx), s->message);
    }
    if (!st) {
        CHECK(r.products == products_of(o),
              "%s: %lld products reported", name, r.products);
        st = limn_mpi_mesh_write(ctx, f, out, LIMN_FORMAT_AUTO, NULL, NULL);
        CHECK(st == LIMN_OK, "%s: writing %s: %s", name, out, limn_context_message(ctx));
    }
    limn_mpi_mesh_destroy(m);
    limn_mpi_mesh_destroy(f);
}

/* One mesh and options: both routes on the same file, the same bytes. */
static void features_case(limn_context *ctx, const char *name, const limn_mesh *mesh,
                          const limn_feature_options *o)
{
    char in[320], ref[320], out[320];
    snprintf(in, sizeof in, "%s/in.ply", dir);
    snprintf(ref, sizeof ref, "%s/ref.ply", dir);
    snprintf(out, sizeof out, "%s/out.ply", dir);
    single_out s = {0};
    if (rank == 0) {
        int ok = limn_mesh_write(ctx, mesh, in, LIMN_FORMAT_AUTO) == LIMN_OK;
        CHECK(ok, "%s: writing %s: %s", name, in, limn_context_message(ctx));
        single(ctx, in, o, ref, &s);
    }
    MPI_Bcast(&s, (int)sizeof s, MPI_BYTE, 0, MPI_COMM_WORLD);
    distributed(ctx, name, in, o, out, &s);
    if (rank == 0 && !s.status)
        CHECK(test_same_bytes(ref, out), "%s (%d ranks): not one process's bytes", name, size);
    MPI_Barrier(MPI_COMM_WORLD);
    if (rank == 0) {
        unlink(in);
        unlink(ref);
        unlink(out);
    }
}

/* Bad options and arguments: refused on every rank, nothing made. */
static void refusals(limn_context *ctx, const limn_mesh *mesh)
{
    char in[320];
    snprintf(in, sizeof in, "%s/in.ply", dir);
    if (rank == 0)
        CHECK(limn_mesh_write(ctx, mesh, in, LIMN_FORMAT_AUTO) == LIMN_OK, "writing %s", in);
    MPI_Barrier(MPI_COMM_WORLD);
    limn_mpi_mesh *m = NULL, *f = NULL;
    CHECK(limn_mpi_mesh_read(ctx, MPI_COMM_WORLD, in, LIMN_FORMAT_AUTO, &m) == LIMN_OK,
          "reading: %s", limn_context_message(ctx));
    limn_feature_options o;
    limn_feature_options_default(&o);
    o.sigma_r = -1.0;
    limn_status st = limn_mpi_mesh_denoise_features(ctx, m, &o, &f, NULL, NULL, NULL);
    CHECK(st == LIMN_ERR_ARGUMENT && f == NULL && strstr(limn_context_message(ctx), "sigma_r"),
          "sigma_r -1: %d '%s'", (int)st, limn_context_message(ctx));
    limn_feature_options_default(&o);
    o.normal_steps = 0;
    st = limn_mpi_mesh_denoise_features(ctx, m, &o, &f, NULL, NULL, NULL);
    CHECK(st == LIMN_ERR_ARGUMENT && f == NULL &&
              strstr(limn_context_message(ctx), "normal_steps"),
          "normal_steps 0: %d '%s'", (int)st, limn_context_message(ctx));
    st = limn_mpi_mesh_denoise_features(ctx, m, NULL, NULL, NULL, NULL, NULL);
    CHECK(st == LIMN_ERR_ARGUMENT, "out NULL: %d", (int)st);
    st = limn_mpi_mesh_denoise_features(ctx, NULL, NULL, &f, NULL, NULL, NULL);
    CHECK(st == LIMN_ERR_ARGUMENT && f == NULL, "mesh NULL: %d", (int)st);
    limn_mpi_mesh_destroy(m);
    MPI_Barrier(MPI_COMM_WORLD);
    if (rank == 0)
        unlink(in);
}

int main(int argc, char **argv)
{
    MPI_Init(&argc, &argv);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    mpi_test_scratch_dir(dir, sizeof dir, "test_mpi_features");
    limn_context *ctx = limn_context_create();
    limn_mesh *meshes[4] = {mpi_test_composite(ctx, 1), mpi_test_composite(ctx, 0),
                            mpi_test_closed(ctx, 1), mpi_test_closed(ctx, 0)};
    static const char *const names[4] = {"composite tri", "composite quad", "closed tri",
                                         "closed quad"};
    limn_feature_options o;
    for (int k = 0; k < 4; k++) {
        limn_feature_options_default(&o);
        features_case(ctx, names[k], meshes[k], &o);
        o.keep_volume = 1; /* kept on the closed ones, refused on the open ones */
        features_case(ctx, names[k], meshes[k], &o);
        limn_feature_options_default(&o);
        o.normal_steps = 3;
        o.vertex_steps = 4;
        o.outer_steps = 3;
        o.sigma_r = 0.5;
        o.sigma_s = 0.3;
        o.tangential = 0.0;
        o.adaptive = 0; /* the fixed rounds; the defaults above are the adaptive ones */
        features_case(ctx, names[k], meshes[k], &o);
    }
    refusals(ctx, meshes[0]);
    for (int k = 0; k < 4; k++)
        limn_mesh_destroy(meshes[k]);
    limn_context_destroy(ctx);
    return mpi_check_finish("test_mpi_features", dir, checks, failures);
}
