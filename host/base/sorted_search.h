/* SPDX-License-Identifier: MIT */
/* Binary search in a non-decreasing array: the position of the last value
   at or below a key, the question of "which block, row or face holds this
   index" over an offsets array (repeated values are empty blocks, passed
   over to the one that holds the key). */
#ifndef LIMN_SORTED_SEARCH_H
#define LIMN_SORTED_SEARCH_H

#include <stddef.h>
#include <stdint.h>

/* The largest i < n with a[i] <= key. Preconditions: n >= 1, a[0 .. n)
   non-decreasing, a[0] <= key (the answer exists; 0 is returned otherwise). */
size_t sorted_last_at_most_u32(const uint32_t *a, size_t n, uint32_t key);
size_t sorted_last_at_most_size(const size_t *a, size_t n, size_t key);

#endif
