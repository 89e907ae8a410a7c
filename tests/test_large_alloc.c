/* SPDX-License-Identifier: MIT */
/*
 * base/large_alloc.c: sizes that overflow are refused; zeroed arrays read
 * zero; blocks of LARGE_ALLOC_HUGE bytes or more start on a huge-page
 * boundary and carry the huge-page advice from their first byte (VmFlags
 * "hg" on their mapping in /proc/self/smaps, read back from the kernel);
 * smaller ones do not ask for it; every block is writable whole.
 */
#include "base/large_alloc.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

/* 1 when the mapping holding address a has VmFlags "hg" (MADV_HUGEPAGE),
   0 when not, -1 when smaps cannot tell. */
static int advised(uintptr_t a)
{
    FILE *f = fopen("/proc/self/smaps", "r");
    if (!f)
        return -1;
    char line[512];
    int inside = 0, found = -1;
    while (fgets(line, sizeof line, f)) {
        unsigned long lo, hi;
        if (sscanf(line, "%lx-%lx ", &lo, &hi) == 2 && strchr(line, '-') < strchr(line, ' ')) {
            inside = a >= lo && a < hi;
            continue;
        }
        if (inside && strncmp(line, "VmFlags:", 8) == 0) {
            found = strstr(line, " hg") != NULL;
            break;
        }
    }
    fclose(f);
    return found;
}

/* The kernel has transparent huge pages (madvise refuses the advice
   otherwise); whether they are on ("never" or not) does not matter. */
static int thp_built(void)
{
    FILE *f = fopen("/sys/kernel/mm/transparent_hugepage/enabled", "r");
    if (f)
        fclose(f);
    return f != NULL;
}

static void refuses_overflow(void **state)
{
    (void)state;
    assert_null(large_array(SIZE_MAX / 8 + 1, 16, 0));
    assert_null(large_array(SIZE_MAX / 8 + 1, 16, 1));
    void *empty = large_array(0, 8, 1); /* a valid block, never NULL for 0 */
    assert_non_null(empty);
    free(empty);
}

static void zeroed_and_whole(void **state)
{
    (void)state;
    size_t n = (size_t)3 << 20; /* 24 MiB of uint64 */
    uint64_t *z = large_array(n, sizeof *z, 1);
    assert_non_null(z);
    for (size_t i = 0; i < n; i += 4093)
        assert_int_equal(z[i], 0);
    assert_int_equal(z[n - 1], 0);
    memset(z, 0xab, n * sizeof *z);
    assert_int_equal(z[n - 1], 0xababababababababULL);
    free(z);
}

static void advice_on_large_blocks(void **state)
{
    (void)state;
    size_t bytes = (size_t)32 << 20;
    unsigned char *big = large_malloc(bytes);
    assert_non_null(big);
    memset(big, 1, bytes);
    /* from a huge-page boundary, so the advice holds from its first byte
       (an unaligned block's head, up to 2 MiB, would fault 4 KiB pages) */
    assert_int_equal((uintptr_t)big % ((uintptr_t)2 << 20), 0);
    int got = advised((uintptr_t)big), middle = advised((uintptr_t)big + bytes / 2);
    free(big);
    if (got < 0 || !thp_built())
        skip(); /* no smaps VmFlags or no THP in this kernel */
    assert_int_equal(got, 1);
    assert_int_equal(middle, 1);
    /* a block below the threshold is left as malloc gave it */
    size_t small = LARGE_ALLOC_HUGE / 2;
    unsigned char *s = large_malloc(small);
    assert_non_null(s);
    memset(s, 2, small);
    free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(refuses_overflow),
        cmocka_unit_test(zeroed_and_whole),
        cmocka_unit_test(advice_on_large_blocks),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
