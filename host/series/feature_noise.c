/* SPDX-License-Identifier: MIT */
/*
 * The noise left in the face normals (features.h): the median of |n_f - n_j|
 * over the ring pairs, read off a histogram of fixed bins so that ranks can
 * add their counts (integers: the sum, and so the median, is the same in any
 * order) and find the single process's value.
 */
#include "series/features.h"

#include <math.h>
#include <string.h>

void feature_noise_count(const feature_mesh *fm, const double *n, size_t begin, size_t end,
                         uint64_t bins[FEATURE_NOISE_BINS])
{
    const stencil_csr *w = &fm->ring;
    for (size_t i = begin; i < end; i++)
        for (uint32_t k = w->row_offsets[i]; k < w->row_offsets[i + 1]; k++) {
            size_t j = w->columns[k];
            if (j == i)
                continue;
            const double *a = n + 3 * i, *b = n + 3 * j;
            double d0 = a[0] - b[0], d1 = a[1] - b[1], d2 = a[2] - b[2];
            /* |n_f - n_j| <= 2 for unit normals; a zero normal's too */
            double at = sqrt(d0 * d0 + d1 * d1 + d2 * d2) * (FEATURE_NOISE_BINS / 2.0);
            bins[at < FEATURE_NOISE_BINS ? (size_t)at : FEATURE_NOISE_BINS - 1]++;
        }
}

double feature_noise_median(const uint64_t bins[FEATURE_NOISE_BINS])
{
    uint64_t total = 0;
    for (size_t b = 0; b < FEATURE_NOISE_BINS; b++)
        total += bins[b];
    if (!total)
        return 0.0;
    /* the bin holding the middle pair, linear within it */
    double half = 0.5 * (double)total, below = 0.0;
    size_t b = 0;
    while (b + 1 < FEATURE_NOISE_BINS && below + (double)bins[b] < half)
        below += (double)bins[b++];
    double within = bins[b] ? (half - below) / (double)bins[b] : 0.0;
    return ((double)b + within) * (2.0 / FEATURE_NOISE_BINS);
}

double feature_adaptive_sigma(double median)
{
    return fmax(FEATURE_ADAPTIVE_GAIN * median, FEATURE_ADAPTIVE_FLOOR);
}
