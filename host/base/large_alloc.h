/* SPDX-License-Identifier: MIT */
/*
 * Allocations for the large arrays of a mesh (positions, faces, topology,
 * stencil tables, the solve's blocks): malloc, with blocks of
 * LARGE_ALLOC_HUGE bytes or more aligned to 2 MiB (large_malloc) and
 * advised to the kernel for transparent huge pages (Linux MADV_HUGEPAGE, on
 * the whole 2 MiB pages inside the block: all but the tail when aligned).
 * Their first touch then takes one fault per 2 MiB instead of 512 and the
 * kernel clears the page in one go: docs/performance.md "First touch".
 * Where THP is off ("never"), or on other systems, they are plain malloc.
 * Free them with free(); realloc keeps the advice on what stays.
 */
#ifndef LIMN_LARGE_ALLOC_H
#define LIMN_LARGE_ALLOC_H

#include <stddef.h>

#define LARGE_ALLOC_HUGE ((size_t)4 << 20)

/* malloc(bytes), advised as above; NULL when out of memory. */
void *large_malloc(size_t bytes);
/* n * size bytes (NULL on overflow or out of memory), advised as above;
   zeroed when zero is set. */
void *large_array(size_t n, size_t size, int zero);
/* The advice alone, for a block the caller already holds (bytes long). */
void large_advise(void *p, size_t bytes);

#endif
