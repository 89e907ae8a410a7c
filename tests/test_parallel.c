/* SPDX-License-Identifier: MIT */
/*
 * base/parallel.c's prefix sum against the sequential loop it replaced in
 * the topology (a[0] = 0, a[i + 1] += a[i]): every length from 0 to 300 and
 * a long one, 1 to 64 ranges (more ranges than items too), counts that make
 * the sums wrap past 2^32 as uint32 arithmetic does; and parallel_run's
 * ranges covering [0, n) once, in order, for the same counts; parallel_copy
 * against memcpy and parallel_zero against memset for lengths around their
 * range cuts, 1 to 8 host threads.
 */
#include "base/parallel.h"
#include "limn.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

static uint32_t lcg(uint64_t *s)
{
    *s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
    return (uint32_t)(*s >> 33);
}

static void check_prefix(size_t n, unsigned parts, uint64_t *seed, int huge)
{
    uint32_t *a = malloc((n + 1) * sizeof *a), *want = malloc((n + 1) * sizeof *want);
    assert_non_null(a);
    assert_non_null(want);
    a[0] = 12345; /* overwritten with 0 */
    for (size_t i = 1; i <= n; i++)
        a[i] = huge ? lcg(seed) | 0x80000000u : lcg(seed) % 17;
    memcpy(want, a, (n + 1) * sizeof *a);
    want[0] = 0;
    for (size_t i = 0; i < n; i++)
        want[i + 1] += want[i];
    parallel_prefix_u32(a, n, parts);
    if (memcmp(a, want, (n + 1) * sizeof *a) != 0)
        fail_msg("prefix of %zu counts over %u ranges differs from the sequential loop", n,
                 parts);
    free(a);
    free(want);
}

static void prefix_as_sequential(void **state)
{
    (void)state;
    uint64_t seed = 42;
    static const unsigned parts[] = {1, 2, 3, 4, 7, 16, 64, 65};
    for (size_t p = 0; p < sizeof parts / sizeof *parts; p++) {
        for (size_t n = 0; n <= 300; n++)
            check_prefix(n, parts[p], &seed, 0);
        check_prefix(1000003, parts[p], &seed, 0);
        check_prefix(5000, parts[p], &seed, 1);
    }
}

typedef struct cover {
    unsigned char *seen;
    int overlap;
} cover;

static int mark(void *arg, size_t begin, size_t end)
{
    cover *c = arg;
    for (size_t i = begin; i < end; i++)
        c->overlap |= c->seen[i]++ != 0;
    return 0;
}

static void ranges_cover_once(void **state)
{
    (void)state;
    static const size_t sizes[] = {0, 1, 2, 5, 64, 65, 1000};
    for (size_t s = 0; s < sizeof sizes / sizeof *sizes; s++)
        for (unsigned parts = 1; parts <= 70; parts++) {
            size_t n = sizes[s];
            cover c = {calloc(n ? n : 1, 1), 0};
            assert_non_null(c.seen);
            assert_int_equal(parallel_run(n, parts, mark, &c), 0);
            assert_false(c.overlap);
            for (size_t i = 0; i < n; i++)
                assert_int_equal(c.seen[i], 1);
            free(c.seen);
        }
}

static void copy_as_memcpy(void **state)
{
    (void)state;
    limn_context *ctx = limn_context_create();
    assert_non_null(ctx);
    size_t big = ((size_t)9 << 20) + 7; /* past PARALLEL_GRAIN: several ranges */
    unsigned char *from = malloc(big), *to = malloc(big);
    assert_non_null(from);
    assert_non_null(to);
    uint64_t seed = 7;
    for (size_t i = 0; i < big; i++)
        from[i] = (unsigned char)lcg(&seed);
    static const size_t sizes[] = {0, 1, 4095, (size_t)4 << 20, ((size_t)8 << 20) + 1, 0};
    for (int threads = 1; threads <= 8; threads *= 2) {
        assert_int_equal(limn_context_set_host_threads(ctx, threads), LIMN_OK);
        for (size_t s = 0; s < sizeof sizes / sizeof *sizes; s++) {
            size_t n = s + 1 < sizeof sizes / sizeof *sizes ? sizes[s] : big;
            memset(to, 0xA5, big);
            parallel_copy(ctx, to, from, n);
            assert_memory_equal(to, from, n);
            for (size_t i = n; i < big && i < n + 64; i++)
                assert_int_equal(to[i], 0xA5); /* nothing past the end */
            /* parallel_zero: zeros over the same ranges, nothing past them */
            parallel_zero(ctx, to, n);
            for (size_t i = 0; i < n; i++)
                if (to[i])
                    fail_msg("byte %zu of %zu not zeroed (%d threads)", i, n, threads);
            for (size_t i = n; i < big && i < n + 64; i++)
                assert_int_equal(to[i], 0xA5);
        }
    }
    free(from);
    free(to);
    limn_context_destroy(ctx);
}

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(prefix_as_sequential),
                                       cmocka_unit_test(ranges_cover_once),
                                       cmocka_unit_test(copy_as_memcpy)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
