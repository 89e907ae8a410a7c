/* SPDX-License-Identifier: MIT */
/*
 * limn over MPI from an application (include/limn_mpi.h): rank 0 makes a
 * bumpy torus (quads), every rank calls limn_interpolate_mpi, rank 0 gets the
 * control mesh P whose Catmull-Clark limit passes through every vertex and
 * checks it against the single-process limn_interpolate: the Chebyshev
 * iteration gives the same bits on any number of ranks.
 *
 * Build against an installed limn (CMakeLists.txt: find_package(limn
 * COMPONENTS mpi); Makefile: pkg-config limn-mpi), run with
 *   mpirun -np 2 ./embed_mpi
 * Exit status 0 on every rank when the check passes.
 */
#include <limn_mpi.h>

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

enum { RING = 40, TUBE = 16, NV = RING * TUBE, NF = RING * TUBE };

static double torus_pos[3 * NV];
static uint32_t torus_offsets[NF + 1], torus_indices[4 * NF];

static void make_torus(void)
{
    const double pi = 3.14159265358979323846;
    for (int i = 0; i < RING; i++)
        for (int j = 0; j < TUBE; j++) {
            double u = 2 * pi * i / RING, v = 2 * pi * j / TUBE;
            double r = 0.3 + 0.05 * sin(5 * u) * cos(3 * v);
            int f = i * TUBE + j, i1 = (i + 1) % RING, j1 = (j + 1) % TUBE;
            double *p = torus_pos + 3 * f;
            p[0] = (1 + r * cos(v)) * cos(u);
            p[1] = (1 + r * cos(v)) * sin(u);
            p[2] = r * sin(v);
            torus_offsets[f] = (uint32_t)(4 * f);
            torus_indices[4 * f] = (uint32_t)(i * TUBE + j);
            torus_indices[4 * f + 1] = (uint32_t)(i1 * TUBE + j);
            torus_indices[4 * f + 2] = (uint32_t)(i1 * TUBE + j1);
            torus_indices[4 * f + 3] = (uint32_t)(i * TUBE + j1);
        }
    torus_offsets[NF] = 4 * NF;
}

static int failed(limn_context *ctx, const char *what, limn_status st)
{
    fprintf(stderr, "embed_mpi: %s failed: %s: %s\n", what, limn_status_name(st),
            limn_context_message(ctx));
    return 1;
}

/* Rank 0: the single process's control mesh, compared bit for bit. */
static int check_root(limn_context *ctx, const limn_mesh *torus, const limn_mesh *p_mpi,
                      const limn_interpolate_options *opt, const limn_report *report, int ranks)
{
    static double a[3 * NV], b[3 * NV];
    limn_mesh *p_one = NULL;
    limn_report one = {.size = sizeof one};
    limn_status st = limn_interpolate(ctx, torus, opt, &p_one, &one);
    if (!st)
        st = limn_mesh_copy_positions(ctx, p_one, a, NV);
    if (!st)
        st = limn_mesh_copy_positions(ctx, p_mpi, b, NV);
    limn_mesh_destroy(p_one);
    if (st)
        return failed(ctx, "single-process limn_interpolate", st);
    int same = memcmp(a, b, sizeof a) == 0 && one.iterations == report->iterations;
    printf("device: %s\n", limn_context_device_name(ctx));
    printf("interpolate over %d ranks: %d vertices, %s, %d iterations, max error %.3g\n",
           ranks, NV, limn_scheme_name(report->scheme), report->iterations,
           report->max_rel_error);
    printf("single process: %d iterations; control meshes %s\n", one.iterations,
           same ? "bit for bit equal" : "DIFFER");
    int ok = same && report->max_rel_error <= opt->tolerance;
    printf("check: %s\n", ok ? "OK" : "FAILED");
    return ok ? 0 : 1;
}

int main(int argc, char **argv)
{
    MPI_Init(&argc, &argv);
    int rank, ranks;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &ranks);
    limn_context *ctx = limn_context_create();
    int rc = ctx ? 0 : 1;
    limn_mesh *torus = NULL, *p = NULL;
    limn_status st = LIMN_OK;
    if (!rc && rank == 0) {
        make_torus();
        st = limn_mesh_create(ctx, NV, torus_pos, NF, torus_offsets, torus_indices, &torus);
        if (st)
            rc = failed(ctx, "limn_mesh_create", st);
    }
    limn_interpolate_options opt;
    limn_interpolate_options_default(&opt);
    opt.method = LIMN_METHOD_CHEBYSHEV;
    opt.tolerance = 1e-8;
    limn_report report = {.size = sizeof report};
    /* collective: every rank calls it; a failure on one is returned on all */
    if (ctx && (st = limn_interpolate_mpi(ctx, MPI_COMM_WORLD, torus, &opt, &p, &report, NULL,
                                          NULL)))
        rc = failed(ctx, "limn_interpolate_mpi", st);
    if (!rc && rank == 0)
        rc = check_root(ctx, torus, p, &opt, &report, ranks);
    MPI_Bcast(&rc, 1, MPI_INT, 0, MPI_COMM_WORLD);
    limn_mesh_destroy(p);
    limn_mesh_destroy(torus);
    limn_context_destroy(ctx);
    MPI_Finalize();
    return rc;
}
