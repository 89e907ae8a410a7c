/* SPDX-License-Identifier: MIT */
/*
 * Measures and volume-keeping denoise on distributed meshes against the
 * single process, under mpirun with 2, 3 and 5 ranks: limn_mpi_mesh_measure
 * and limn_mpi_mesh_volume_area give limn_mesh_measure's and
 * limn_mesh_volume_area's bits (closed, volume, area, centroid) on closed
 * meshes (tori, an icosahedron, a hexagonal prism: n-gons), the same with a
 * face turned over (inconsistent edges), and open ones (boundaries, a
 * non-manifold fin, isolated vertices, several components); and
 * limn_mpi_mesh_denoise with keep_volume writes limn_denoise's bytes, or
 * refuses an open mesh with limn_denoise's message (its edge counts) on
 * every rank, nothing made. Rank 0 runs the single process on the same file.
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

/* What the single process gives on rank 0 (broadcast to all). */
typedef struct single_out {
    int ok, status;
    limn_mesh_measures measures;
    double volume, area;
    char message[1024];
} single_out;

static void single(limn_context *ctx, const char *in, const limn_series_options *o,
                   const char *out, single_out *s)
{
    memset(s, 0, sizeof *s);
    limn_mesh *m = NULL, *f = NULL;
    s->measures.size = sizeof s->measures;
    limn_series_report r = {.size = sizeof r};
    s->ok = limn_mesh_read(ctx, in, LIMN_FORMAT_AUTO, &m) == LIMN_OK &&
            limn_mesh_repair(ctx, m, NULL, NULL) == LIMN_OK &&
            limn_mesh_measure(ctx, m, &s->measures) == LIMN_OK;
    CHECK(s->ok, "single process on %s: %s", in, limn_context_message(ctx));
    if (s->ok) {
        limn_mesh_volume_area(m, &s->volume, &s->area);
        s->status = (int)limn_denoise(ctx, m, o, 2, 3, 1, &f, &r);
        if (s->status)
            snprintf(s->message, sizeof s->message, "%s", limn_context_message(ctx));
        else
            s->ok = limn_mesh_write(ctx, f, out, LIMN_FORMAT_AUTO) == LIMN_OK;
    }
    limn_mesh_destroy(m);
    limn_mesh_destroy(f);
}

/* Every rank: read, repair, measure, denoise with keep_volume, write. */
static void distributed(limn_context *ctx, const char *name, const char *in,
                        const limn_series_options *o, const char *out, const single_out *s)
{
    limn_mpi_mesh *m = NULL, *f = NULL;
    limn_mesh_measures me = {.size = sizeof me};
    double v = 0.0, a = 0.0;
    limn_status st = limn_mpi_mesh_read(ctx, MPI_COMM_WORLD, in, LIMN_FORMAT_AUTO, &m);
    if (!st)
        st = limn_mpi_mesh_repair(ctx, m, NULL, NULL);
    if (!st)
        st = limn_mpi_mesh_measure(ctx, m, &me);
    if (!st)
        st = limn_mpi_mesh_volume_area(ctx, m, &v, &a);
    CHECK(st == LIMN_OK, "%s: measuring: %s", name, limn_context_message(ctx));
    if (st)
        goto done;
    CHECK(me.closed == s->measures.closed, "%s (%d ranks): closed %d, one process %d", name, size,
          me.closed, s->measures.closed);
    CHECK(memcmp(&me.volume, &s->measures.volume, sizeof me.volume) == 0 &&
              memcmp(&me.area, &s->measures.area, sizeof me.area) == 0 &&
              memcmp(me.centroid, s->measures.centroid, sizeof me.centroid) == 0,
          "%s (%d ranks): volume %.17g area %.17g centroid %.17g, one process %.17g %.17g %.17g",
          name, size, me.volume, me.area, me.centroid[0], s->measures.volume, s->measures.area,
          s->measures.centroid[0]);
    CHECK(memcmp(&v, &s->volume, sizeof v) == 0 && memcmp(&a, &s->area, sizeof a) == 0,
          "%s (%d ranks): volume_area %.17g %.17g, one process %.17g %.17g", name, size, v, a,
          s->volume, s->area);
    st = limn_mpi_mesh_denoise(ctx, m, o, 2, 3, 1, &f, NULL, NULL, NULL);
    if (s->status) {
        CHECK(st == (limn_status)s->status && f == NULL &&
                  strcmp(limn_context_message(ctx), s->message) == 0,
              "%s (%d ranks): keep_volume refusal %d '%s', one process %d '%s'", name, size,
              (int)st, limn_context_message(ctx), s->status, s->message);
        goto done;
    }
    CHECK(st == LIMN_OK, "%s: denoise keep_volume: %s", name, limn_context_message(ctx));
    if (!st)
        st = limn_mpi_mesh_write(ctx, f, out, LIMN_FORMAT_AUTO, NULL, NULL);
    CHECK(st == LIMN_OK, "%s: writing %s: %s", name, out, limn_context_message(ctx));
done:
    limn_mpi_mesh_destroy(m);
    limn_mpi_mesh_destroy(f);
}

/* One mesh: both routes on the same file. */
static void measure_case(limn_context *ctx, const char *name, const limn_mesh *mesh,
                         limn_scheme scheme, double alpha, int closed)
{
    char in[320], ref[320], out[320];
    snprintf(in, sizeof in, "%s/in.ply", dir);
    snprintf(ref, sizeof ref, "%s/ref.ply", dir);
    snprintf(out, sizeof out, "%s/out.ply", dir);
    limn_series_options o;
    limn_series_options_default(&o);
    o.scheme = scheme;
    o.alpha = alpha;
    single_out s = {0};
    if (rank == 0) {
        s.ok = limn_mesh_write(ctx, mesh, in, LIMN_FORMAT_AUTO) == LIMN_OK;
        CHECK(s.ok, "%s: writing %s: %s", name, in, limn_context_message(ctx));
        if (s.ok)
            single(ctx, in, &o, ref, &s);
    }
    MPI_Bcast(&s, (int)sizeof s, MPI_BYTE, 0, MPI_COMM_WORLD);
    if (closed >= 0) /* the case is what it is meant to be: kept, or refused */
        CHECK(s.measures.closed == closed && (s.status == 0) == closed,
              "%s: closed %d, denoise status %d (%s)", name, s.measures.closed, s.status,
              s.message);
    if (s.ok)
        distributed(ctx, name, in, &o, out, &s);
    if (rank == 0 && s.ok && !s.status)
        CHECK(test_same_bytes(ref, out), "%s (%d ranks): denoise keep_volume differs from one "
                                    "process's",
              name, size);
    MPI_Barrier(MPI_COMM_WORLD);
    if (rank == 0) {
        unlink(in);
        unlink(ref);
        unlink(out);
    }
}

/* A shared mesh (mpi_check_shared): closed or not, as it is. */
static void shared_case(limn_context *ctx, size_t k, const char *path, limn_mesh *m)
{
    (void)k;
    measure_case(ctx, path, m, LIMN_SCHEME_AUTO, 0.0, -1);
}

int main(int argc, char **argv)
{
    MPI_Init(&argc, &argv);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    mpi_test_scratch_dir(dir, sizeof dir, "test_mpi_measure");
    limn_context *ctx = limn_context_create();
    limn_mesh *ctri = mpi_test_closed(ctx, 1), *cquad = mpi_test_closed(ctx, 0);
    limn_mesh *otri = mpi_test_composite(ctx, 1), *oquad = mpi_test_composite(ctx, 0);
    /* its first face turned over: two inconsistent edges and more, so not closed */
    limn_mesh *flip = mpi_test_turned(ctx, cquad, 0);
    measure_case(ctx, "closed tri", ctri, LIMN_SCHEME_LOOP, 0.0, 1);
    measure_case(ctx, "closed quad", cquad, LIMN_SCHEME_CATMARK, 0.5, 1);
    measure_case(ctx, "closed quad a0", cquad, LIMN_SCHEME_AUTO, 0.0, 1);
    measure_case(ctx, "turned face", flip, LIMN_SCHEME_CATMARK, 0.0, 0);
    measure_case(ctx, "composite tri", otri, LIMN_SCHEME_LOOP, 0.0, 0);
    measure_case(ctx, "composite quad", oquad, LIMN_SCHEME_CATMARK, 0.0, 0);
    static const char *const real[] = {"small/suzanne.obj", "small/cow.obj",
                                       "medium/bob_quad.obj"};
    mpi_check_shared(ctx, real, sizeof real / sizeof *real, shared_case);
    limn_mesh_destroy(ctri);
    limn_mesh_destroy(cquad);
    limn_mesh_destroy(otri);
    limn_mesh_destroy(oquad);
    limn_mesh_destroy(flip);
    limn_context_destroy(ctx);
    return mpi_check_finish("test_mpi_measure", dir, checks, failures);
}
