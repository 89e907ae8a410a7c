/* SPDX-License-Identifier: MIT */
/*
 * base/sorted_search.c (the block, row or face holding an index) against a
 * linear scan from the end: every length 1..300 of random non-decreasing
 * arrays, dense with repeats (empty blocks) and sparse, every key from a[0]
 * to one past the last value, and values at the top of each type's range.
 */
#include "support.h"
#include "base/sorted_search.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include <cmocka.h>

static uint64_t next(uint64_t *s)
{
    uint64_t z = (*s += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

static size_t scan_u32(const uint32_t *a, size_t n, uint32_t key)
{
    size_t i = n - 1;
    while (i > 0 && a[i] > key)
        i--;
    return i;
}

static size_t scan_size(const size_t *a, size_t n, size_t key)
{
    size_t i = n - 1;
    while (i > 0 && a[i] > key)
        i--;
    return i;
}

/* Non-decreasing steps of 0..step-1 from base. */
static void fill(uint32_t *a32, size_t *az, size_t n, uint64_t base, unsigned step, uint64_t *s)
{
    uint64_t v = base;
    for (size_t i = 0; i < n; i++) {
        a32[i] = (uint32_t)v;
        az[i] = (size_t)v;
        v += next(s) % step;
    }
}

static void against_scan(void **state)
{
    (void)state;
    uint64_t seed = 16;
    uint32_t a32[300];
    size_t az[300];
    const unsigned steps[] = {1, 2, 5, 40};
    for (size_t n = 1; n <= 300; n++)
        for (size_t t = 0; t < sizeof steps / sizeof *steps; t++) {
            fill(a32, az, n, next(&seed) % 1000, steps[t], &seed);
            for (uint32_t key = a32[0]; key <= a32[n - 1] + 1; key++) {
                assert_int_equal(sorted_last_at_most_u32(a32, n, key), scan_u32(a32, n, key));
                assert_int_equal(sorted_last_at_most_size(az, n, key), scan_size(az, n, key));
            }
        }
}

/* Values at the top of the range: no overflow in the search's midpoints. */
static void top_of_range(void **state)
{
    (void)state;
    uint64_t seed = 17;
    uint32_t a32[64];
    size_t az[64];
    for (size_t n = 1; n <= 64; n++) {
        fill(a32, az, n, UINT32_MAX - 200, 3, &seed);
        for (uint32_t k = a32[0];; k++) {
            assert_int_equal(sorted_last_at_most_u32(a32, n, k), scan_u32(a32, n, k));
            if (k == UINT32_MAX)
                break;
        }
        for (size_t i = 0; i < n; i++)
            az[i] = SIZE_MAX - 2 * (n - 1 - i);
        for (size_t k = az[0];; k++) {
            assert_int_equal(sorted_last_at_most_size(az, n, k), scan_size(az, n, k));
            if (k == SIZE_MAX)
                break;
        }
    }
}

TEST_MAIN(NULL, NULL, cmocka_unit_test(against_scan), cmocka_unit_test(top_of_range))
