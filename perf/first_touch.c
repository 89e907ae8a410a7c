/* SPDX-License-Identifier: MIT */
/*
 * The rate at which this machine hands out fresh memory: a memset of newly
 * mapped pages (each page faulted in and cleared by the kernel first) against
 * a memset of the same pages once touched. The floor of every stage that
 * fills memory it has just allocated (perf/end_to_end.py): bytes it must
 * write to fresh memory / the first-touch rate.
 *   first_touch [MiB, default 256] [repeats, default 5]
 * One thread (the stages that fill fresh memory mostly run on one). Prints
 * one JSON line with the best rate of each, and the first-touch rate of a
 * mapping advised for transparent huge pages (limn's large blocks are).
 */
#define _DEFAULT_SOURCE
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <time.h>

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Best seconds of a memset of fresh pages (*first) and of the same pages
   once touched (*touched); huge: the mapping advised for transparent huge
   pages first, as limn's large blocks are (host/base/large_alloc.c). */
static int rates(size_t bytes, int repeats, int huge, double *first, double *touched,
                 unsigned *check)
{
    *first = *touched = 1e30;
    for (int r = 0; r < repeats; r++) {
        /* a mapping of its own, as malloc makes for blocks this size */
        unsigned char *p =
            mmap(NULL, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        if (p == MAP_FAILED)
            return 1;
#ifdef MADV_HUGEPAGE
        if (huge)
            (void)madvise(p, bytes, MADV_HUGEPAGE);
#endif
        double t = now();
        memset(p, 1 + r, bytes);
        double t1 = now();
        memset(p, 2 + r, bytes);
        double t2 = now();
        *check += p[bytes / 2];
        if (t1 - t < *first)
            *first = t1 - t;
        if (t2 - t1 < *touched)
            *touched = t2 - t1;
        munmap(p, bytes);
    }
    return 0;
}

int main(int argc, char **argv)
{
    size_t mib = argc > 1 ? (size_t)atol(argv[1]) : 256;
    int repeats = argc > 2 ? atoi(argv[2]) : 5;
    size_t bytes = mib << 20;
    double first, touched, huge_first, huge_touched;
    unsigned check = 0;
    if (rates(bytes, repeats, 0, &first, &touched, &check) ||
        rates(bytes, repeats, 1, &huge_first, &huge_touched, &check))
        return 1;
    printf("{\"impl\": \"first_touch\", \"bytes\": %zu, \"first_touch_gb_per_s\": %.3f, "
           "\"touched_gb_per_s\": %.3f, \"huge_first_touch_gb_per_s\": %.3f, \"check\": %u}\n",
           bytes, (double)bytes / first / 1e9, (double)bytes / touched / 1e9,
           (double)bytes / huge_first / 1e9, check);
    return 0;
}
