/* SPDX-License-Identifier: MIT */
/*
 * Set-up of the distributed operator: the root path (mpi_distribute: rank 0
 * builds the whole operator and ships rows) against local rows
 * (mpi_local_build: every rank builds its own from a vertex block and a face
 * range), on the same METIS partition (issue 14.3, docs/mpi.md "Local rows").
 * Both include the repair (the root path's of the whole mesh on rank 0);
 * neither includes METIS (computed once before, given to both).
 *
 *   mpirun -np R mpi_local_bench MESH [--repeat K]
 *
 * Every rank reads the whole mesh here (this program measures the set-up,
 * not the reading: the slice readers of issue 14.1 replace that), so
 * process memory says nothing; the per-vertex arrays and sub-mesh sizes the
 * local build reports do. Prints one JSON line per rank (best of K): the
 * root path's seconds on that rank, the local path's, its sub-mesh, the
 * largest per-vertex array it allocated, owned rows and ghosts.
 */
#include "limn_mpi.h"

#include "mpi/mpi_local.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct figures {
    double root_s, local_s;
    mpi_local_stats st;
    size_t owned, ghosts;
} figures;

/* One run of each path; their seconds on this rank into f. */
static int run_once(limn_context *ctx, const limn_mesh *raw, const uint32_t *part, int rank,
                    int size, figures *f)
{
    size_t n = limn_mesh_vertex_count(raw), nf = limn_mesh_face_count(raw);
    size_t *vtx = malloc(((size_t)size + 1) * sizeof *vtx);
    for (int r = 0; r <= size; r++)
        vtx[r] = n * (size_t)r / (size_t)size;
    size_t fb = nf * (size_t)rank / (size_t)size, fe = nf * (size_t)(rank + 1) / (size_t)size;
    const uint32_t *off = limn_mesh_face_offsets(raw), *idx = limn_mesh_face_indices(raw);
    uint32_t *off2 = malloc((fe - fb + 1) * sizeof *off2);
    for (size_t k = 0; k <= fe - fb; k++)
        off2[k] = off[fb + k] - off[fb];
    mpi_part a, b;
    limn_mesh *whole = NULL;
    MPI_Barrier(MPI_COMM_WORLD);
    double t0 = MPI_Wtime();
    limn_status sa = LIMN_OK;
    if (rank == 0) /* the root path repairs the whole mesh first */
        sa = limn_mesh_copy(ctx, raw, &whole) || limn_mesh_repair(ctx, whole, NULL, NULL);
    if (!sa)
        sa = mpi_part_begin(ctx, MPI_COMM_WORLD, NULL, &a);
    if (!sa)
        sa = mpi_distribute_part(&a, rank == 0 ? whole : NULL, LIMN_SCHEME_AUTO, 0.0, 0,
                                 rank == 0 ? part : NULL);
    double t1 = MPI_Wtime();
    limn_mesh_destroy(whole);
    MPI_Barrier(MPI_COMM_WORLD);
    double t2 = MPI_Wtime();
    limn_status sb = mpi_part_begin(ctx, MPI_COMM_WORLD, NULL, &b);
    mpi_local_stats st;
    if (!sb)
        sb = mpi_local_build(&b, vtx, limn_mesh_positions(raw) + 3 * vtx[rank], part + vtx[rank],
                             fb, fe - fb, off2, idx + off[fb], LIMN_SCHEME_AUTO, 0.0, NULL,
                             NULL, &st);
    double t3 = MPI_Wtime();
    if (!sa && !sb) {
        f->root_s = t1 - t0;
        f->local_s = t3 - t2;
        f->st = st;
        f->owned = b.n_owned;
        f->ghosts = b.n_ghost;
    }
    if (sa || sb)
        fprintf(stderr, "mpi_local_bench: %s\n", limn_context_message(ctx));
    mpi_part_end(&a);
    mpi_part_end(&b);
    free(off2);
    free(vtx);
    return sa || sb;
}

int main(int argc, char **argv)
{
    MPI_Init(&argc, &argv);
    int rank, size, repeat = 3;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    if (argc < 2) {
        if (rank == 0)
            fprintf(stderr, "usage: mpirun -np R mpi_local_bench MESH [--repeat K]\n");
        MPI_Finalize();
        return 2;
    }
    if (argc >= 4 && !strcmp(argv[2], "--repeat"))
        repeat = atoi(argv[3]);
    limn_context *ctx = limn_context_create();
    limn_context_set_device(ctx, "reference");
    limn_mesh *raw = NULL, *rep = NULL;
    if (limn_mesh_read(ctx, argv[1], LIMN_FORMAT_AUTO, &raw) ||
        limn_mesh_copy(ctx, raw, &rep) || limn_mesh_repair(ctx, rep, NULL, NULL)) {
        fprintf(stderr, "mpi_local_bench: %s\n", limn_context_message(ctx));
        MPI_Abort(MPI_COMM_WORLD, 1);
    }
    size_t n = limn_mesh_vertex_count(raw), cut = 0;
    uint32_t *part = malloc(n * sizeof *part);
    if (rank == 0 && mpi_partition(ctx, rep, size, part, &cut))
        MPI_Abort(MPI_COMM_WORLD, 1);
    MPI_Bcast(part, (int)n, MPI_UINT32_T, 0, MPI_COMM_WORLD);
    figures best = {1e300, 1e300, {0}, 0, 0}, f;
    int bad = 0;
    for (int k = 0; k < repeat && !bad; k++) {
        bad = run_once(ctx, raw, part, rank, size, &f);
        if (!bad && f.local_s < best.local_s)
            best.local_s = f.local_s, best.st = f.st, best.owned = f.owned, best.ghosts = f.ghosts;
        if (!bad && f.root_s < best.root_s)
            best.root_s = f.root_s;
    }
    for (int r = 0; r < size && !bad; r++) {
        if (r == rank)
            printf("{\"rank\": %d, \"ranks\": %d, \"vertices\": %zu, \"root_path_s\": %.4f, "
                   "\"local_s\": %.4f, \"sub_vertices\": %zu, \"sub_faces\": %zu, "
                   "\"largest_vertex_array\": %zu, \"owned\": %zu, \"ghosts\": %zu}\n",
                   rank, size, n, best.root_s, best.local_s, best.st.sub_vertices,
                   best.st.sub_faces, best.st.largest_vertex_array, best.owned, best.ghosts);
        fflush(stdout);
        MPI_Barrier(MPI_COMM_WORLD);
    }
    free(part);
    limn_mesh_destroy(raw);
    limn_mesh_destroy(rep);
    limn_context_destroy(ctx);
    MPI_Finalize();
    return bad;
}
