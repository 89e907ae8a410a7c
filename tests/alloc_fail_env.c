/* SPDX-License-Identifier: MIT */
/*
 * alloc_fail.h armed from the environment, for a whole program (the CLI
 * built for tests/test_cli_oom.sh): LIMN_TEST_ALLOC_FAIL=K fails the K-th
 * allocation of limn's and the CLI's from the start (0: none, counting
 * only); LIMN_TEST_ALLOC_COUNT=FILE writes the count seen at exit there.
 * Under mpirun, LIMN_TEST_ALLOC_RANK=R limits both to rank R (Open MPI's
 * OMPI_COMM_WORLD_RANK): the other ranks allocate as usual.
 */
#include "alloc_fail.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void write_count(void)
{
    long n = alloc_fail_disarm();
    FILE *f = fopen(getenv("LIMN_TEST_ALLOC_COUNT"), "w");
    if (f) {
        fprintf(f, "%ld\n", n);
        fclose(f);
    }
}

__attribute__((constructor)) static void arm_from_environment(void)
{
    const char *k = getenv("LIMN_TEST_ALLOC_FAIL"), *only = getenv("LIMN_TEST_ALLOC_RANK");
    const char *mine = getenv("OMPI_COMM_WORLD_RANK");
    if (!k || (only && (!mine || strcmp(only, mine) != 0)))
        return;
    alloc_fail_arm(strtol(k, NULL, 10));
    if (getenv("LIMN_TEST_ALLOC_COUNT"))
        atexit(write_count);
}
