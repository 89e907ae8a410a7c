/* SPDX-License-Identifier: MIT */
/*
 * alloc_fail.h and cl_fail.h armed from the environment, for a whole
 * program (the CLI built for tests/test_cli_oom.sh): LIMN_TEST_ALLOC_FAIL=K
 * fails the K-th allocation of limn's and the CLI's from the start (0: none,
 * counting only); LIMN_TEST_ALLOC_COUNT=FILE writes the count seen at exit
 * there. LIMN_TEST_CL_FAIL=K and LIMN_TEST_CL_COUNT=FILE do the same for
 * limn's OpenCL calls (cl_fail.h's list). Under mpirun,
 * LIMN_TEST_ALLOC_RANK=R limits all of them to rank R (Open MPI's
 * OMPI_COMM_WORLD_RANK): the other ranks run as usual.
 */
#include "alloc_fail.h"
#include "cl_fail.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void write_number(const char *var, long n)
{
    FILE *f = fopen(getenv(var), "w");
    if (f) {
        fprintf(f, "%ld\n", n);
        fclose(f);
    }
}

static void write_alloc_count(void) { write_number("LIMN_TEST_ALLOC_COUNT", alloc_fail_disarm()); }
static void write_cl_count(void) { write_number("LIMN_TEST_CL_COUNT", cl_fail_disarm()); }

__attribute__((constructor)) static void arm_from_environment(void)
{
    const char *k = getenv("LIMN_TEST_ALLOC_FAIL"), *cl = getenv("LIMN_TEST_CL_FAIL");
    const char *only = getenv("LIMN_TEST_ALLOC_RANK"), *mine = getenv("OMPI_COMM_WORLD_RANK");
    if (only && (!mine || strcmp(only, mine) != 0))
        return;
    if (k) {
        alloc_fail_arm(strtol(k, NULL, 10));
        if (getenv("LIMN_TEST_ALLOC_COUNT"))
            atexit(write_alloc_count);
    }
    if (cl) {
        cl_fail_arm(strtol(cl, NULL, 10));
        if (getenv("LIMN_TEST_CL_COUNT"))
            atexit(write_cl_count);
    }
}
