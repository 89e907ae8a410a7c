/* SPDX-License-Identifier: MIT */
/*
 * The local build's sort helpers (host/mpi/mpi_local_comm.c) against qsort
 * and a walk: mpi_local_distinct on ids narrower than 32 n (its bitmap) and
 * wider (its radix sort), each element's index pointing at its id, and
 * mpi_local_sort_uniform (one pass by the top bits, then each bucket) on
 * hash-like keys, a short list and keys all in one bucket. Run under mpirun
 * with 1 rank (tests/CMakeLists.txt): the helpers are rank-local.
 *
 * Not cmocka: the MPI tests' checks (mpi_check.h).
 */
#include "mpi_check.h"
#include "sort_check.h"

#include "mpi/mpi_local.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

MPI_CHECK_STATE;

/* mpi_local_distinct against qsort and a walk: ids in a range narrower
   than 32 n (the bitmap) and wider (the radix sort), the same answer. */
static void distinct_case(limn_context *ctx, const char *name, size_t n, uint32_t spread)
{
    uint32_t *ids = malloc(n * sizeof *ids), *ref = malloc(n * sizeof *ref);
    uint32_t *got = malloc(n * sizeof *got), *index = malloc(n * sizeof *index);
    uint64_t x = 14;
    for (size_t i = 0; i < n; i++)
        ref[i] = ids[i] = 1000 + (uint32_t)(sort_check_random(&x) % spread);
    qsort(ref, n, sizeof *ref, sort_check_cmp_u32);
    size_t nref = 0, nd = 0;
    for (size_t i = 0; i < n; i++)
        if (nref == 0 || ref[nref - 1] != ref[i])
            ref[nref++] = ref[i];
    CHECK(mpi_local_distinct(ctx, ids, n, got, &nd, index) == LIMN_OK, "%s: failed", name);
    CHECK(nd == nref && memcmp(got, ref, nd * sizeof *got) == 0, "%s: distinct ids differ",
          name);
    size_t bad = 0;
    for (size_t i = 0; i < n; i++)
        bad += index[i] >= nd || got[index[i]] != ids[i];
    CHECK(bad == 0, "%s: %zu elements point at the wrong id", name, bad);
    free(ids);
    free(ref);
    free(got);
    free(index);
}

/* mpi_local_sort_uniform against qsort: hash-like keys, and keys whose top
   bits are all the same (one bucket, the radix passes inside it). */
static void uniform_case(const char *name, size_t n, uint64_t mask)
{
    uint64_t *a = malloc(n * sizeof *a), *b = malloc(n * sizeof *b), x = 7;
    for (size_t i = 0; i < n; i++)
        a[i] = b[i] = sort_check_random(&x) & mask;
    mpi_local_sort_uniform(a, n);
    qsort(b, n, sizeof *b, sort_check_cmp_u64);
    CHECK(memcmp(a, b, n * sizeof *a) == 0, "%s: the sort differs from qsort", name);
    free(a);
    free(b);
}

static void sort_helpers(limn_context *ctx)
{
    distinct_case(ctx, "distinct, narrow range (bitmap)", 100000, 30000);
    distinct_case(ctx, "distinct, wide range (radix sort)", 5000, 4000000000u);
    distinct_case(ctx, "distinct, one id", 3, 1);
    uniform_case("sort by top bits, hash keys", 200000, ~(uint64_t)0);
    uniform_case("sort by top bits, short list", 100, ~(uint64_t)0);
    uniform_case("sort by top bits, one bucket", 50000, 0xffffffffULL);
}

int main(int argc, char **argv)
{
    MPI_Init(&argc, &argv);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    limn_context *ctx = limn_context_create();
    sort_helpers(ctx);
    limn_context_destroy(ctx);
    int total = 0;
    MPI_Allreduce(&failures, &total, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
    if (rank == 0)
        printf("test_mpi_sort: %d checks on rank 0, %d failures on all ranks\n", checks, total);
    MPI_Finalize();
    return total ? 1 : 0;
}
