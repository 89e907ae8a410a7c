/* SPDX-License-Identifier: MIT */
#include "mpi_check.h"
#include "support.h"

#include <mpi.h>
#include <stdio.h>
#include <unistd.h>

void mpi_check_shared(limn_context *ctx, const char *const *paths, size_t n, mpi_shared_case fn)
{
    int rank = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    int shared = rank == 0 ? test_shared_meshes() != NULL : 0;
    MPI_Bcast(&shared, 1, MPI_INT, 0, MPI_COMM_WORLD);
    for (size_t k = 0; shared && k < n; k++) {
        limn_mesh *m = NULL;
        int ok = 1;
        if (rank == 0)
            ok = limn_mesh_read(ctx, test_shared_path(paths[k]), LIMN_FORMAT_AUTO, &m) == LIMN_OK;
        MPI_Bcast(&ok, 1, MPI_INT, 0, MPI_COMM_WORLD);
        if (ok)
            fn(ctx, k, paths[k], m);
        limn_mesh_destroy(m);
    }
}

int mpi_check_finish(const char *name, const char *dir, int checks, int failures)
{
    int rank = 0, size = 1, all = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    if (rank == 0 && dir)
        rmdir(dir);
    MPI_Allreduce(&failures, &all, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
    if (rank == 0)
        printf("%s: %d ranks, %d checks on rank 0, %d failures on all ranks\n", name, size, checks,
               all);
    MPI_Finalize();
    return all ? 1 : 0;
}
