/* SPDX-License-Identifier: MIT */
/*
 * The checks of the MPI tests. Not cmocka: an assertion that jumps out of a
 * test on one rank would leave the others waiting in a collective. A failed
 * CHECK is counted and printed with its rank, the test carries on, and the
 * ranks agree on the outcome at the end (an Allreduce of `failures`). A test
 * file declares the counters with MPI_CHECK_STATE at file scope.
 */
#ifndef LIMN_TEST_MPI_CHECK_H
#define LIMN_TEST_MPI_CHECK_H

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

#endif
