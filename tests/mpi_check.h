/* SPDX-License-Identifier: MIT */
/*
 * The checks of the MPI tests. Not cmocka: an assertion that jumps out of a
 * test on one rank would leave the others waiting in a collective. A failed
 * CHECK is counted and printed with its rank, the test carries on, and the
 * ranks agree on the outcome at the end (an Allreduce of `failures`:
 * mpi_check_finish). A test file declares the counters with MPI_CHECK_STATE
 * at file scope. mpi_check.c: what the tests do alike around their cases.
 */
#ifndef LIMN_TEST_MPI_CHECK_H
#define LIMN_TEST_MPI_CHECK_H

#include "limn.h"

#include <stddef.h>
#include <stdio.h>

#define MPI_CHECK_STATE static int rank, size, failures, checks

#define CHECK(cond, ...)                                                                       \
    do {                                                                                       \
        checks++;                                                                              \
        if (!(cond)) {                                                                         \
            failures++;                                                                        \
            fprintf(stderr, "FAIL (rank %d, %s:%d): ", rank, __FILE__, __LINE__);              \
            fprintf(stderr, __VA_ARGS__);                                                      \
            fprintf(stderr, "\n");                                                             \
        }                                                                                      \
    } while (0)

/* A case on the shared mesh paths[k]: mesh the whole mesh on rank 0, NULL
   on the others (the case compares the ranks' result with one process's). */
typedef void (*mpi_shared_case)(limn_context *ctx, size_t k, const char *path, limn_mesh *mesh);
/* Collective: when ../shared/meshes is there, each of the n paths under it
   read on rank 0 and, when it could be, fn on every rank; then freed. */
void mpi_check_shared(limn_context *ctx, const char *const *paths, size_t n, mpi_shared_case fn);
/* Collective, the end of a test's main(): rank 0 removes dir (NULL: none),
   every rank's failures summed and said on rank 0 ("NAME: R ranks, C checks
   on rank 0, F failures on all ranks"), MPI_Finalize; the exit status (1
   when any rank failed a check). */
int mpi_check_finish(const char *name, const char *dir, int checks, int failures);

#endif
