/* SPDX-License-Identifier: MIT */
/*
 * Strong scaling of limn_interpolate_mpi (driven by perf/mpi_scaling.py).
 *
 *   mpirun -np R mpi_bench MESH [--tol T] [--method M] [--repeat K] [--device D]
 *       interpolates MESH K times on R ranks; rank 0 prints one JSON line per
 *       rank (its figures in the best run: the least wall time per iteration)
 *       and one summary line.
 *   mpi_bench MESH --parts P
 *       no solve: METIS splits MESH into P parts as the MPI layer would, and
 *       the ghost, halo and neighbour counts of every part are summarised (the
 *       input of the projection to P ranks).
 */
#include "limn_mpi.h"

#include "mpi/mpi_part.h"
#include "solve/operator.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void print_stats(const limn_mpi_stats *s, int iterations)
{
    double it = iterations > 0 ? (double)iterations : 1.0;
    double ex = s->exchanges > 0 ? (double)s->exchanges : 1.0;
    printf("{\"rank\": %d, \"ranks\": %d, \"owned\": %zu, \"ghosts\": %zu, \"interior_rows\": %zu, "
           "\"neighbours\": %d, \"halo_bytes_sent\": %zu, \"halo_bytes_received\": %zu, "
           "\"exchanges\": %lld, \"seconds_per_iteration\": %.6g, \"compute_per_exchange\": "
           "%.6g, \"halo_per_exchange\": %.6g, \"wait_per_exchange\": %.6g, "
           "\"reduce_per_exchange\": %.6g, "
           "\"seconds_partition\": %.4g, \"seconds_distribute\": %.4g, \"device\": \"%s\"}\n",
           s->rank, s->ranks, s->owned, s->ghosts, s->interior_rows, s->neighbours,
           s->halo_bytes_sent, s->halo_bytes_received, s->exchanges, s->seconds_solve / it,
           s->seconds_compute / ex, s->seconds_halo / ex, s->seconds_wait / ex,
           s->seconds_reduce / ex,
           s->seconds_partition, s->seconds_distribute, s->device);
}

/* The partition into `parts` and each part's halo, from the stencil rows. */
static int partition_only(limn_context *ctx, const limn_mesh *mesh, int parts)
{
    stencil_operator op;
    if (operator_build_ex(ctx, mesh, LIMN_SCHEME_AUTO, 0.0, OPERATOR_HOST_ONLY, &op)) {
        fprintf(stderr, "mpi_bench: %s\n", limn_context_message(ctx));
        return 1;
    }
    size_t n = op.vertex_count, cut = 0;
    uint32_t *part = malloc(n * sizeof *part), *stamp = calloc(n, sizeof *stamp);
    size_t *owned = calloc((size_t)parts, sizeof *owned), *ghosts = calloc((size_t)parts, sizeof *ghosts);
    char *pair = calloc((size_t)parts * (size_t)parts, 1);
    if (mpi_partition(ctx, mesh, parts, part, &cut)) {
        fprintf(stderr, "mpi_bench: %s\n", limn_context_message(ctx));
        return 1;
    }
    /* ghosts of part p: distinct columns of p's rows owned elsewhere (rows
       visited part by part, so a stamp per part counts each ghost once) */
    size_t *start = calloc((size_t)parts + 1, sizeof *start);
    uint32_t *rows = malloc(n * sizeof *rows);
    for (size_t v = 0; v < n; v++)
        owned[part[v]]++;
    for (int p = 0; p < parts; p++)
        start[p + 1] = start[p] + owned[p];
    for (size_t v = 0; v < n; v++) /* counting sort: rows grouped by part */
        rows[start[part[v]]++] = (uint32_t)v;
    for (size_t k = 0; k < n; k++) {
        uint32_t v = rows[k];
        for (uint32_t e = op.host.row_offsets[v]; e < op.host.row_offsets[v + 1]; e++) {
            uint32_t u = op.host.columns[e];
            if (part[u] == part[v])
                continue;
            pair[(size_t)part[v] * (size_t)parts + part[u]] = 1;
            if (stamp[u] != part[v] + 1) {
                stamp[u] = part[v] + 1;
                ghosts[part[v]]++;
            }
        }
    }
    free(start);
    free(rows);
    size_t omax = 0, gmax = 0, gsum = 0, nmax = 0;
    for (int p = 0; p < parts; p++) {
        size_t nb = 0;
        for (int q = 0; q < parts; q++)
            nb += pair[(size_t)p * (size_t)parts + (size_t)q];
        omax = owned[p] > omax ? owned[p] : omax;
        gmax = ghosts[p] > gmax ? ghosts[p] : gmax;
        nmax = nb > nmax ? nb : nmax;
        gsum += ghosts[p];
    }
    printf("{\"parts\": %d, \"vertices\": %zu, \"nonzeros\": %zu, \"edge_cut\": %zu, "
           "\"owned_max\": %zu, \"owned_mean\": %.1f, \"ghosts_max\": %zu, \"ghosts_mean\": %.1f, "
           "\"neighbours_max\": %zu}\n",
           parts, n, (size_t)op.host.row_offsets[n], cut, omax, (double)n / parts, gmax,
           (double)gsum / parts, nmax);
    free(part);
    free(stamp);
    free(owned);
    free(ghosts);
    free(pair);
    operator_free(&op);
    return 0;
}

int main(int argc, char **argv)
{
    MPI_Init(&argc, &argv);
    int rank, size, parts = 0, repeat = 3;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    limn_interpolate_options o;
    limn_interpolate_options_default(&o);
    /* double unless asked: auto picks float from 200,000 vertices, under MPI
       too, and the figures of docs/mpi.md were measured in double */
    o.precision = LIMN_PRECISION_DOUBLE;
    const char *path = NULL, *device = NULL;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--tol") == 0 && i + 1 < argc)
            o.tolerance = atof(argv[++i]);
        else if (strcmp(argv[i], "--method") == 0 && i + 1 < argc)
            o.method = strcmp(argv[++i], "weighted") == 0    ? LIMN_METHOD_WEIGHTED
                       : strcmp(argv[i], "cg") == 0          ? LIMN_METHOD_CG
                       : strcmp(argv[i], "chebyshev") == 0   ? LIMN_METHOD_CHEBYSHEV
                       : strcmp(argv[i], "paper") == 0       ? LIMN_METHOD_PAPER
                                                             : LIMN_METHOD_AUTO;
        else if (strcmp(argv[i], "--precision") == 0 && i + 1 < argc)
            o.precision = strcmp(argv[++i], "float") == 0  ? LIMN_PRECISION_FLOAT
                          : strcmp(argv[i], "auto") == 0   ? LIMN_PRECISION_AUTO
                                                           : LIMN_PRECISION_DOUBLE;
        else if (strcmp(argv[i], "--repeat") == 0 && i + 1 < argc)
            repeat = atoi(argv[++i]);
        else if (strcmp(argv[i], "--parts") == 0 && i + 1 < argc)
            parts = atoi(argv[++i]);
        else if (strcmp(argv[i], "--device") == 0 && i + 1 < argc)
            device = argv[++i];
        else
            path = argv[i];
    }
    limn_context *ctx = limn_context_create();
    limn_context_set_device(ctx, device);
    limn_mesh *mesh = NULL;
    int rc = 0;
    if (rank == 0 && (!path || limn_mesh_read(ctx, path, LIMN_FORMAT_AUTO, &mesh) != LIMN_OK)) {
        fprintf(stderr, "mpi_bench: %s\n", path ? limn_context_message(ctx) : "no mesh given");
        rc = 1;
    }
    MPI_Bcast(&rc, 1, MPI_INT, 0, MPI_COMM_WORLD);
    if (!rc && parts > 0) {
        rc = rank == 0 ? partition_only(ctx, mesh, parts) : 0;
    } else if (!rc) {
        limn_mpi_stats best, *all = rank == 0 ? calloc((size_t)size, sizeof *all) : NULL;
        double best_time = 1e300;
        int iterations = 0;
        for (int k = 0; k < repeat && !rc; k++) {
            limn_mesh *control = NULL;
            limn_report r = {.size = sizeof r};
            limn_mpi_result res = {.size = sizeof res, .stats.size = sizeof res.stats};
            limn_status st = limn_interpolate_mpi(ctx, MPI_COMM_WORLD, mesh, &o,
                                                  rank == 0 ? &control : NULL, &r, NULL, &res);
            if (st) {
                if (rank == 0)
                    fprintf(stderr, "mpi_bench: %s\n", limn_context_message(ctx));
                rc = 1;
                break;
            }
            /* the slowest rank sets the pace */
            double mine = res.stats.seconds_solve, slowest;
            MPI_Allreduce(&mine, &slowest, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
            if (slowest < best_time) {
                best_time = slowest;
                best = res.stats;
                iterations = r.iterations + 1; /* steps run: the last measures */
            }
            limn_mesh_destroy(control);
        }
        if (!rc) {
            MPI_Gather(&best, (int)sizeof best, MPI_BYTE, all, (int)sizeof best, MPI_BYTE, 0,
                       MPI_COMM_WORLD);
            for (int r = 0; rank == 0 && r < size; r++)
                print_stats(&all[r], iterations);
            if (rank == 0)
                printf("{\"summary\": true, \"ranks\": %d, \"vertices\": %zu, \"iterations\": %d, "
                       "\"seconds_per_iteration\": %.6g}\n",
                       size, limn_mesh_vertex_count(mesh), iterations, best_time / iterations);
        }
        free(all);
    }
    limn_mesh_destroy(mesh);
    limn_context_destroy(ctx);
    MPI_Finalize();
    return rc;
}
