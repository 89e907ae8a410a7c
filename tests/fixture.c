/* SPDX-License-Identifier: MIT */
#include "fixture.h"
#include "support.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include <cmocka.h>

/* cmocka runs one test at a time, so one list serves the running test. */
static struct {
    void (*release)(void *);
    void *p;
} kept[256];
static size_t kept_count;

void *test_defer(void (*release)(void *), void *p)
{
    if (kept_count == sizeof kept / sizeof kept[0])
        fail_msg("test_defer: more than %zu objects kept", kept_count);
    kept[kept_count].release = release;
    kept[kept_count].p = p;
    kept_count++;
    return p;
}

static void release_mesh(void *p)
{
    limn_mesh_destroy(p);
}

static void release_context(void *p)
{
    limn_context_destroy(p);
}

limn_mesh *test_keep_mesh(limn_mesh *m)
{
    return test_defer(release_mesh, m);
}

limn_context *test_keep_context(limn_context *ctx)
{
    return test_defer(release_context, ctx);
}

void *test_keep(void *p)
{
    return test_defer(free, p);
}

int test_release_teardown(void **state)
{
    (void)state;
    while (kept_count > 0) {
        kept_count--;
        kept[kept_count].release(kept[kept_count].p);
    }
    return 0;
}

int test_context_setup(void **state)
{
    *state = limn_context_create();
    assert_non_null(*state);
    return 0;
}

static int context_on(void **state, const char *device)
{
    test_context_setup(state);
    limn_context *ctx = *state;
    limn_status st = limn_context_set_device(ctx, device);
    if (st != LIMN_OK)
        fail_msg("limn_context_set_device(%s): %s: %s", device, limn_status_name(st),
                 limn_context_message(ctx));
    return 0;
}

int test_reference_setup(void **state)
{
    return context_on(state, "reference");
}

int test_opencl_setup(void **state)
{
    return context_on(state, "opencl");
}

int test_context_teardown(void **state)
{
    test_release_teardown(state);
    limn_context_destroy(*state);
    return 0;
}

limn_mesh *test_read_shared(limn_context *ctx, const char *rel)
{
    limn_mesh *m = NULL;
    if (limn_mesh_read(ctx, test_shared_path(rel), LIMN_FORMAT_AUTO, &m) != LIMN_OK)
        fail_msg("%s: %s", rel, limn_context_message(ctx));
    return m;
}

limn_mesh *test_read_shared_info(limn_context *ctx, const char *rel, int width,
                                 limn_mesh_info *info)
{
    limn_mesh *m = test_read_shared(ctx, rel);
    *info = (limn_mesh_info){.size = sizeof *info};
    if (limn_mesh_info_compute(ctx, m, info) == LIMN_OK)
        return m;
    printf("  %-*s refused: %s\n", width, rel, limn_context_message(ctx));
    limn_mesh_destroy(m);
    return NULL;
}
