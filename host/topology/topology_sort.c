/* SPDX-License-Identifier: MIT */
/*
 * The sorts of the topology passes (topology_build.h): a vertex's 2n ring
 * entries and a face's or an edge's few corners. Nearly every list is 2n
 * long for a vertex of 3 to 6 faces, and an insertion sort of 12 entries is
 * a chain of mispredicted branches (15% of a warm `limn info`), so those
 * lengths go through branch-free sorting networks (optimal ones: 12, 19, 29
 * and 39 comparators for 6, 8, 10 and 12 entries; test_topo_sort checks them
 * by the 0-1 principle); other short lists by insertion, long ones by qsort.
 * Every list sorts to the one increasing order, so the topology is the same.
 */
#include "topology/topology_build.h"

#include <stdlib.h>

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

static int cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return x < y ? -1 : x > y;
}

/* a[i], a[j] in order, without a branch (the compiler's min and max) */
static inline void cx_u32(uint32_t *a, int i, int j)
{
    uint32_t x = a[i], y = a[j];
    a[i] = x < y ? x : y;
    a[j] = x < y ? y : x;
}

static inline void cx_u64(uint64_t *a, int i, int j)
{
    uint64_t x = a[i], y = a[j];
    a[i] = x < y ? x : y;
    a[j] = x < y ? y : x;
}

/* The networks (test_topo_sort: the 0-1 principle), one sequence of
   comparators a length for both widths: cx is cx_u32 or cx_u64. */
#define NET6(cx, a)                                                                       \
    cx(a, 0, 5); cx(a, 1, 3); cx(a, 2, 4); cx(a, 1, 2); cx(a, 3, 4); cx(a, 0, 3);         \
    cx(a, 2, 5); cx(a, 0, 1); cx(a, 2, 3); cx(a, 4, 5); cx(a, 1, 2); cx(a, 3, 4);

#define NET8(cx, a)                                                                       \
    cx(a, 0, 2); cx(a, 1, 3); cx(a, 4, 6); cx(a, 5, 7); cx(a, 0, 4); cx(a, 1, 5);         \
    cx(a, 2, 6); cx(a, 3, 7); cx(a, 0, 1); cx(a, 2, 3); cx(a, 4, 5); cx(a, 6, 7);         \
    cx(a, 2, 4); cx(a, 3, 5); cx(a, 1, 4); cx(a, 3, 6); cx(a, 1, 2); cx(a, 3, 4);         \
    cx(a, 5, 6);

#define NET10(cx, a)                                                                      \
    cx(a, 0, 8); cx(a, 1, 9); cx(a, 2, 7); cx(a, 3, 5); cx(a, 4, 6); cx(a, 0, 2);         \
    cx(a, 1, 4); cx(a, 5, 8); cx(a, 7, 9); cx(a, 0, 3); cx(a, 2, 4); cx(a, 5, 7);         \
    cx(a, 6, 9); cx(a, 0, 1); cx(a, 3, 6); cx(a, 8, 9); cx(a, 1, 5); cx(a, 2, 3);         \
    cx(a, 4, 8); cx(a, 6, 7); cx(a, 1, 2); cx(a, 3, 5); cx(a, 4, 6); cx(a, 7, 8);         \
    cx(a, 2, 3); cx(a, 4, 5); cx(a, 6, 7); cx(a, 3, 4); cx(a, 5, 6);

#define NET12(cx, a)                                                                      \
    cx(a, 0, 8); cx(a, 1, 7); cx(a, 2, 6); cx(a, 3, 11); cx(a, 4, 10); cx(a, 5, 9);       \
    cx(a, 0, 1); cx(a, 2, 5); cx(a, 3, 4); cx(a, 6, 9); cx(a, 7, 8); cx(a, 10, 11);       \
    cx(a, 0, 2); cx(a, 1, 6); cx(a, 5, 10); cx(a, 9, 11); cx(a, 0, 3); cx(a, 1, 2);       \
    cx(a, 4, 6); cx(a, 5, 7); cx(a, 8, 11); cx(a, 9, 10); cx(a, 1, 4); cx(a, 3, 5);       \
    cx(a, 6, 8); cx(a, 7, 10); cx(a, 1, 3); cx(a, 2, 5); cx(a, 6, 9); cx(a, 8, 10);       \
    cx(a, 2, 3); cx(a, 4, 5); cx(a, 6, 7); cx(a, 8, 9); cx(a, 4, 6); cx(a, 5, 7);         \
    cx(a, 3, 4); cx(a, 5, 6); cx(a, 7, 8);

static void net6_u32(uint32_t *a)
{
    NET6(cx_u32, a);
}

static void net8_u32(uint32_t *a)
{
    NET8(cx_u32, a);
}

static void net10_u32(uint32_t *a)
{
    NET10(cx_u32, a);
}

static void net12_u32(uint32_t *a)
{
    NET12(cx_u32, a);
}

static void net6_u64(uint64_t *a)
{
    NET6(cx_u64, a);
}

static void net8_u64(uint64_t *a)
{
    NET8(cx_u64, a);
}

static void net10_u64(uint64_t *a)
{
    NET10(cx_u64, a);
}

static void net12_u64(uint64_t *a)
{
    NET12(cx_u64, a);
}

/* Networks for 6, 8, 10 and 12 entries, insertion for other short lists,
   qsort past 24 (one body for both widths). */
#define SORT_SMALL(T, suf, a, n, cmp)                                                         \
    do {                                                                                      \
        switch (n) {                                                                          \
        case 6: net6_##suf(a); return;                                                        \
        case 8: net8_##suf(a); return;                                                        \
        case 10: net10_##suf(a); return;                                                      \
        case 12: net12_##suf(a); return;                                                      \
        default: break;                                                                       \
        }                                                                                     \
        if ((n) > 24) {                                                                       \
            qsort((a), (n), sizeof *(a), cmp);                                                \
            return;                                                                           \
        }                                                                                     \
        for (size_t i_ = 1; i_ < (n); i_++) {                                                 \
            T v_ = (a)[i_];                                                                   \
            size_t j_ = i_;                                                                   \
            for (; j_ > 0 && (a)[j_ - 1] > v_; j_--)                                          \
                (a)[j_] = (a)[j_ - 1];                                                        \
            (a)[j_] = v_;                                                                     \
        }                                                                                     \
    } while (0)

void topo_sort_u64(uint64_t *a, size_t n)
{
    SORT_SMALL(uint64_t, u64, a, n, cmp_u64);
}

void topo_sort_u32(uint32_t *a, size_t n)
{
    SORT_SMALL(uint32_t, u32, a, n, cmp_u32);
}
