/* SPDX-License-Identifier: MIT */
#include "fixture.h"

#include "limn.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

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
    limn_context_destroy(*state);
    return 0;
}
