/* SPDX-License-Identifier: MIT */
/* Large allocations advised for transparent huge pages (large_alloc.h). */
#define _DEFAULT_SOURCE /* madvise */
#include "base/large_alloc.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>

#define HUGE_PAGE ((uintptr_t)2 << 20)

void large_advise(void *p, size_t bytes)
{
#ifdef MADV_HUGEPAGE
    if (!p || bytes < LARGE_ALLOC_HUGE)
        return;
    /* only whole huge pages inside the block: the advice splits the mapping
       there and nothing outside the block changes */
    uintptr_t begin = ((uintptr_t)p + HUGE_PAGE - 1) & ~(HUGE_PAGE - 1);
    uintptr_t end = ((uintptr_t)p + bytes) & ~(HUGE_PAGE - 1);
    if (end > begin)
        (void)madvise((void *)begin, end - begin, MADV_HUGEPAGE); /* advice: may fail */
#else
    (void)p;
    (void)bytes;
#endif
}

void *large_malloc(size_t bytes)
{
    if (bytes < LARGE_ALLOC_HUGE)
        return malloc(bytes ? bytes : 1);
    /* from a huge-page boundary, so the advice holds from the first byte (an
       unaligned block's head, up to 2 MiB, faults 4 KiB pages: measured,
       ~40% of a rank's faults); the size rounded up as C11's aligned_alloc
       asks, the rounding never touched and not advised (no memory taken) */
    size_t rounded = (bytes + HUGE_PAGE - 1) & ~(size_t)(HUGE_PAGE - 1);
    void *p = rounded >= bytes ? aligned_alloc(HUGE_PAGE, rounded) : NULL;
    large_advise(p, bytes);
    return p;
}

void *large_array(size_t n, size_t size, int zero)
{
    if (size && n > SIZE_MAX / size)
        return NULL;
    size_t bytes = n * size;
    if (!zero)
        return large_malloc(bytes);
    /* calloc's fresh pages need no clearing; advised before their first touch */
    void *p = calloc(bytes ? bytes : 1, 1);
    large_advise(p, bytes);
    return p;
}
