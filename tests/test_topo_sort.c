/* SPDX-License-Identifier: MIT */
/*
 * The topology passes' sorts (host/topology/topology_sort.c): the sorting
 * networks for 6, 8, 10 and 12 entries sort every 0/1 input of their length
 * (by the 0-1 principle a comparator network that sorts those sorts every
 * input), and every length 0..40, networks, insertion and qsort alike, gives
 * qsort's order on random keys with many repeats and on distinct ones, in
 * both widths.
 */
#include "topology/topology_build.h"
#include "sort_check.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

/* Every 0/1 input of the networks' lengths, both widths: sorted. */
static void zero_one_inputs(void **state)
{
    (void)state;
    static const size_t lengths[] = {6, 8, 10, 12};
    for (size_t l = 0; l < sizeof lengths / sizeof *lengths; l++) {
        size_t n = lengths[l];
        for (uint32_t bits = 0; bits < (1u << n); bits++) {
            uint32_t a[12];
            uint64_t b[12];
            for (size_t i = 0; i < n; i++) {
                a[i] = bits >> i & 1;
                /* the high word too: the 64-bit compare must see it */
                b[i] = (uint64_t)(bits >> i & 1) << 40;
            }
            topo_sort_u32(a, n);
            topo_sort_u64(b, n);
            for (size_t i = 1; i < n; i++) {
                assert_true(a[i - 1] <= a[i]);
                assert_true(b[i - 1] <= b[i]);
            }
        }
    }
}

/* Random keys of every length up to 40 (past the insertion sort's 24):
   qsort's order exactly. */
static void random_lists(void **state)
{
    (void)state;
    uint64_t seed = 1;
    for (size_t n = 0; n <= 40; n++)
        for (int round = 0; round < 200; round++) {
            uint32_t a[40], ea[40];
            uint64_t b[40], eb[40];
            /* half the rounds from a few values (a vertex's neighbours come in pairs) */
            uint64_t range = round % 2 ? 5 : UINT64_MAX;
            for (size_t i = 0; i < n; i++) {
                uint64_t r = sort_check_random(&seed);
                ea[i] = a[i] = (uint32_t)(range == UINT64_MAX ? r : r % range);
                eb[i] = b[i] = range == UINT64_MAX ? r : (r % range) << 33 | (r >> 60);
            }
            qsort(ea, n, sizeof *ea, sort_check_cmp_u32);
            qsort(eb, n, sizeof *eb, sort_check_cmp_u64);
            topo_sort_u32(a, n);
            topo_sort_u64(b, n);
            for (size_t i = 0; i < n; i++) {
                assert_int_equal(a[i], ea[i]);
                assert_true(b[i] == eb[i]);
            }
        }
}

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(zero_one_inputs),
                                       cmocka_unit_test(random_lists)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
