/* SPDX-License-Identifier: MIT */
/* Binary search for the last value at or below a key (sorted_search.h). */
#include "base/sorted_search.h"

/* One body for each element type; the invariant: a[lo] <= key < a[hi], a[n]
   standing for a value past every key. */
#define DEFINE_LAST_AT_MOST(name, type)                                                          \
    size_t name(const type *a, size_t n, type key)                                               \
    {                                                                                            \
        size_t lo = 0, hi = n;                                                                   \
        while (hi - lo > 1) {                                                                    \
            size_t mid = lo + (hi - lo) / 2;                                                     \
            if (a[mid] <= key)                                                                   \
                lo = mid;                                                                        \
            else                                                                                 \
                hi = mid;                                                                        \
        }                                                                                        \
        return lo;                                                                               \
    }

DEFINE_LAST_AT_MOST(sorted_last_at_most_u32, uint32_t)
DEFINE_LAST_AT_MOST(sorted_last_at_most_size, size_t)
