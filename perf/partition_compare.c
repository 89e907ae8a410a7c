/* SPDX-License-Identifier: MIT */
/*
 * Partition quality and time: serial METIS (mpi_partition.c, the root
 * path) against the distributed PT-Scotch partition (mpi_dgraph.c) and the
 * space-filling curve (mpi_sfc.c, the distributed pipeline's default), all
 * into as many parts as ranks (driven by perf/partition_compare.py).
 *
 *   mpirun -np R partition_compare [--strategy quality|default|speed] MESH [MESH ...]
 *
 * Every rank reads the mesh (a benchmark shortcut: the pipeline gives each
 * rank only its slice), keeps an even block of the vertices and of the
 * faces; METIS runs on rank 0 alone on the whole mesh. Rank 0 prints one
 * JSON line per mesh: vertices, edges, and per partitioner the edge cut, the
 * imbalance (largest part / mean), the wall seconds (METIS: the graph and
 * METIS on rank 0; PT-Scotch and the curve: the whole collective call,
 * slowest rank) and the CPU seconds of the process (the distributed ones:
 * the busiest rank's), which a shared machine inflates less than the wall
 * time. The curve's cut is counted on rank 0 from the gathered parts. Also
 * the face-slice partition's cut and imbalance (slices_run; no timing).
 */
#include "limn.h"

#include "mpi/mpi_dgraph.h"
#include "mpi/mpi_part.h"
#include "mpi/mpi_sfc.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double cpu_seconds(void)
{
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static double imbalance_of(const uint32_t *part, size_t n, int parts)
{
    size_t *count = calloc((size_t)parts, sizeof *count), mx = 0;
    for (size_t v = 0; v < n; v++)
        count[part[v]]++;
    for (int p = 0; p < parts; p++)
        mx = count[p] > mx ? count[p] : mx;
    free(count);
    return n ? (double)mx * parts / (double)n : 1.0;
}

/* METIS on rank 0: cut, imbalance, seconds. */
static int metis_run(limn_context *ctx, const limn_mesh *m, int parts, size_t *cut, double *imb,
                     double sec[2])
{
    size_t n = limn_mesh_vertex_count(m);
    uint32_t *part = malloc((n + 1) * sizeof *part);
    double t0 = MPI_Wtime(), c0 = cpu_seconds();
    int ok = mpi_partition(ctx, m, parts, part, cut) == LIMN_OK;
    sec[0] = MPI_Wtime() - t0;
    sec[1] = cpu_seconds() - c0;
    if (ok)
        *imb = imbalance_of(part, n, parts);
    else
        fprintf(stderr, "partition_compare: METIS: %s\n", limn_context_message(ctx));
    free(part);
    return ok;
}

/* PT-Scotch over all ranks, faces in even contiguous blocks. */
static int scotch_run(limn_context *ctx, const limn_mesh *m, int rank, int size,
                      mpi_dgraph_strategy strategy, mpi_dgraph_stats *st, double *cpu)
{
    size_t n = limn_mesh_vertex_count(m), nf = limn_mesh_face_count(m);
    const uint32_t *off = limn_mesh_face_offsets(m), *idx = limn_mesh_face_indices(m);
    size_t *vtxdist = malloc(((size_t)size + 1) * sizeof *vtxdist);
    for (int r = 0; r <= size; r++)
        vtxdist[r] = n * (size_t)r / (size_t)size;
    size_t f0 = nf * (size_t)rank / (size_t)size, f1 = nf * (size_t)(rank + 1) / (size_t)size;
    uint32_t *loff = malloc((f1 - f0 + 1) * sizeof *loff), *part = NULL;
    for (size_t f = f0; f <= f1; f++)
        loff[f - f0] = off[f] - off[f0];
    double c0 = cpu_seconds();
    limn_status s = mpi_dgraph_partition_with(ctx, MPI_COMM_WORLD, vtxdist, f1 - f0, loff,
                                              idx + off[f0], size, strategy, &part, st);
    double c = cpu_seconds() - c0;
    MPI_Allreduce(&c, cpu, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
    if (s != LIMN_OK && rank == 0)
        fprintf(stderr, "partition_compare: PT-Scotch: %s\n", limn_context_message(ctx));
    free(part);
    free(loff);
    free(vtxdist);
    return s == LIMN_OK;
}

/* The curve over all ranks, vertices in even blocks; its cut and
   imbalance from the parts gathered on rank 0. */
typedef struct sfc_figures {
    size_t cut;
    double imbalance, seconds, cpu, travel;
} sfc_figures;

/* The rank that reads face f of nf: even blocks in the file's order, as the
   slice reader splits them. */
static uint32_t file_block(size_t f, size_t nf, int parts)
{
    return (uint32_t)(f * (size_t)parts / nf);
}

/* The share of the faces that leave the rank reading them: each rank reads
   an even block of the faces in the file's order (as the slice reader does)
   and sends a face on when a corner's part is not the rank's. */
static double faces_travelling(const limn_mesh *m, const uint32_t *part, int parts)
{
    size_t nf = limn_mesh_face_count(m), moved = 0;
    const uint32_t *off = limn_mesh_face_offsets(m), *idx = limn_mesh_face_indices(m);
    for (size_t f = 0; f < nf; f++) {
        uint32_t block = file_block(f, nf, parts);
        int leaves = 0;
        for (uint32_t c = off[f]; c < off[f + 1]; c++)
            leaves |= part[idx[c]] != block;
        moved += (size_t)leaves;
    }
    return nf ? (double)moved / (double)nf : 0.0;
}

static int sfc_run(limn_context *ctx, const limn_mesh *m, int rank, int size, sfc_figures *f)
{
    size_t n = limn_mesh_vertex_count(m);
    size_t *vtxdist = malloc(((size_t)size + 1) * sizeof *vtxdist);
    int *cnt = malloc(2 * (size_t)size * sizeof *cnt), *disp = cnt + size;
    for (int r = 0; r <= size; r++)
        vtxdist[r] = n * (size_t)r / (size_t)size;
    for (int r = 0; r < size; r++) {
        cnt[r] = (int)(vtxdist[r + 1] - vtxdist[r]);
        disp[r] = (int)vtxdist[r];
    }
    mpi_part p;
    uint32_t *part = NULL, *all = rank == 0 ? malloc((n + 1) * sizeof *all) : NULL;
    mpi_sfc_stats st;
    double c0 = cpu_seconds();
    limn_status s = mpi_part_begin(ctx, MPI_COMM_WORLD, NULL, &p);
    if (!s)
        s = mpi_sfc_partition(&p, vtxdist, limn_mesh_positions(m) + 3 * vtxdist[rank], size,
                              &part, &st);
    double c = cpu_seconds() - c0;
    MPI_Allreduce(&c, &f->cpu, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
    if (!s) {
        MPI_Gatherv(part, cnt[rank], MPI_UINT32_T, all, cnt, disp, MPI_UINT32_T, 0,
                    MPI_COMM_WORLD);
        f->imbalance = st.imbalance;
        f->seconds = st.seconds;
        if (rank == 0 && mpi_edge_cut(ctx, m, size, all, &f->cut))
            s = LIMN_ERR_MEMORY;
        if (rank == 0 && !s)
            f->travel = faces_travelling(m, all, size);
    }
    if (s != LIMN_OK && rank == 0)
        fprintf(stderr, "partition_compare: curve: %s\n", limn_context_message(ctx));
    if (p.comm != MPI_COMM_NULL)
        mpi_part_end(&p);
    free(part);
    free(all);
    free(cnt);
    free(vtxdist);
    return s == LIMN_OK;
}

/* The partition that moves no face (not built: docs/mpi.md "Set-up,
   2026-12-06 (session 26)"): the faces in even contiguous blocks of the
   file's order, as the ranks read them, and each vertex to the lowest block
   among its faces (a vertex in no face to the last); its cut and imbalance,
   on rank 0. Good only where the file's face order is spatial. */
static int slices_run(limn_context *ctx, const limn_mesh *m, int parts, size_t *cut, double *imb)
{
    size_t n = limn_mesh_vertex_count(m), nf = limn_mesh_face_count(m);
    const uint32_t *off = limn_mesh_face_offsets(m), *idx = limn_mesh_face_indices(m);
    uint32_t *part = malloc((n + 1) * sizeof *part);
    if (!part)
        return 0;
    for (size_t v = 0; v < n; v++)
        part[v] = (uint32_t)parts - 1;
    for (size_t f = 0; f < nf; f++) {
        uint32_t block = file_block(f, nf, parts);
        for (uint32_t c = off[f]; c < off[f + 1]; c++)
            part[idx[c]] = block < part[idx[c]] ? block : part[idx[c]];
    }
    int ok = mpi_edge_cut(ctx, m, parts, part, cut) == LIMN_OK;
    *imb = imbalance_of(part, n, parts);
    free(part);
    return ok;
}

static int one_mesh(limn_context *ctx, const char *path, int rank, int size,
                    mpi_dgraph_strategy strategy)
{
    limn_mesh *m = NULL;
    int ok = limn_mesh_read(ctx, path, LIMN_FORMAT_AUTO, &m) == LIMN_OK;
    if (!ok)
        fprintf(stderr, "partition_compare: %s: %s\n", path, limn_context_message(ctx));
    MPI_Allreduce(MPI_IN_PLACE, &ok, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    if (!ok) {
        limn_mesh_destroy(m);
        return 0;
    }
    size_t mcut = 0;
    double mimb = 0, msec[2] = {0, 0}, scpu = 0;
    size_t slices_cut = 0;
    double slices_imb = 0;
    if (rank == 0)
        ok = metis_run(ctx, m, size, &mcut, &mimb, msec) &&
             slices_run(ctx, m, size, &slices_cut, &slices_imb);
    mpi_dgraph_stats st;
    MPI_Barrier(MPI_COMM_WORLD);
    ok = scotch_run(ctx, m, rank, size, strategy, &st, &scpu) && ok;
    sfc_figures sf = {0, 0, 0, 0, 0};
    MPI_Barrier(MPI_COMM_WORLD);
    ok = sfc_run(ctx, m, rank, size, &sf) && ok;
    if (ok && rank == 0)
        printf("{\"mesh\": \"%s\", \"parts\": %d, \"strategy\": %d, \"vertices\": %zu, "
               "\"edges\": %zu, \"metis_cut\": %zu, \"metis_imbalance\": %.4f, "
               "\"metis_seconds\": %.4f, \"metis_cpu\": %.4f, \"scotch_cut\": %zu, "
               "\"scotch_imbalance\": %.4f, \"scotch_seconds\": %.4f, \"scotch_cpu\": %.4f, "
               "\"graph_seconds\": %.4f, \"sfc_cut\": %zu, \"sfc_imbalance\": %.4f, "
               "\"sfc_seconds\": %.4f, \"sfc_cpu\": %.4f, \"sfc_faces_travel\": %.4f, "
               "\"slices_cut\": %zu, \"slices_imbalance\": %.4f}\n",
               path, size, (int)strategy, st.vertices, st.edges, mcut, mimb, msec[0], msec[1],
               st.edge_cut, st.imbalance, st.seconds, scpu, st.seconds_graph, sf.cut,
               sf.imbalance, sf.seconds, sf.cpu, sf.travel, slices_cut, slices_imb);
    fflush(stdout);
    limn_mesh_destroy(m);
    return ok;
}

int main(int argc, char **argv)
{
    MPI_Init(&argc, &argv);
    int rank, size, ok = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    int first = 1;
    mpi_dgraph_strategy strategy = MPI_DGRAPH_QUALITY;
    if (argc > 2 && !strcmp(argv[1], "--strategy")) {
        strategy = !strcmp(argv[2], "speed")     ? MPI_DGRAPH_SPEED
                   : !strcmp(argv[2], "default") ? MPI_DGRAPH_DEFAULT
                                                 : MPI_DGRAPH_QUALITY;
        first = 3;
    }
    if (argc <= first && rank == 0)
        fprintf(stderr, "usage: mpirun -np R partition_compare [--strategy quality|default|speed] "
                        "MESH [MESH ...]\n");
    limn_context *ctx = limn_context_create();
    for (int k = first; k < argc; k++)
        ok = one_mesh(ctx, argv[k], rank, size, strategy) && ok;
    limn_context_destroy(ctx);
    MPI_Finalize();
    return argc <= first || !ok;
}
