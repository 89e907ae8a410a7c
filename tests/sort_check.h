/* SPDX-License-Identifier: MIT */
/* What the sort tests (test_mpi_sort, test_topo_sort) compare against:
   qsort's comparators and a seeded splitmix64 for their keys. */
#ifndef LIMN_TEST_SORT_CHECK_H
#define LIMN_TEST_SORT_CHECK_H

#include <stdint.h>

static inline int sort_check_cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return x < y ? -1 : x > y;
}

static inline int sort_check_cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

static inline uint64_t sort_check_random(uint64_t *x) /* splitmix64 */
{
    uint64_t z = (*x += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

#endif
