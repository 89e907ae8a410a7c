/* SPDX-License-Identifier: MIT */
/*
 * STREAM triad a[i] = b[i] + s * c[i] on doubles (McCalpin's kernel), the
 * memory-bandwidth yardstick of the perf suite. Counts 24 bytes per element
 * (two loads, one store; write-allocate traffic not counted, as in STREAM).
 *   stream_triad [MiB per array, default 512] [repeats, default 10]
 * Threads: OMP_NUM_THREADS. Prints one JSON line with the best rate.
 */
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int main(int argc, char **argv)
{
    size_t mib = argc > 1 ? (size_t)atol(argv[1]) : 512;
    int repeats = argc > 2 ? atoi(argv[2]) : 10;
    size_t n = mib * (1 << 20) / sizeof(double);
    double *a = malloc(n * sizeof *a), *b = malloc(n * sizeof *b), *c = malloc(n * sizeof *c);
    if (!a || !b || !c)
        return 1;
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < n; i++) {
        a[i] = 0;
        b[i] = 1;
        c[i] = 2;
    }
    double best = 1e30, s = 3.0;
    for (int r = 0; r < repeats; r++) {
        double t = now();
#pragma omp parallel for schedule(static)
        for (size_t i = 0; i < n; i++)
            a[i] = b[i] + s * c[i];
        t = now() - t;
        if (t < best)
            best = t;
    }
    double check = a[n / 2];
    printf("{\"impl\": \"stream_triad\", \"threads\": %d, \"elements\": %zu, \"seconds\": %.6f, "
           "\"gb_per_s\": %.3f, \"check\": %g}\n",
           omp_get_max_threads(), n, best, 24.0 * (double)n / best / 1e9, check);
    free(a);
    free(b);
    free(c);
    return 0;
}
