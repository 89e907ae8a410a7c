/* SPDX-License-Identifier: MIT */
/* Helpers of the API checks' tests (api_expect.h). */
#include "api_expect.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

void api_expect(limn_context *ctx, const char *call, limn_status got, limn_status status, ...)
{
    const char *msg = limn_context_message(ctx);
    if (got != status)
        fail_msg("%s gave %s '%s', expected %s", call, limn_status_name(got), msg,
                 limn_status_name(status));
    if (!msg[0])
        fail_msg("%s failed with an empty message", call);
    va_list ap;
    va_start(ap, status);
    for (const char *s; (s = va_arg(ap, const char *));)
        if (!strstr(msg, s))
            fail_msg("%s: message '%s' does not say '%s'", call, msg, s);
    va_end(ap);
}

limn_context *api_reference_context(void)
{
    limn_context *ctx = limn_context_create();
    assert_non_null(ctx);
    OK(ctx, limn_context_set_device(ctx, "reference"));
    return ctx;
}

limn_status api_count_frame(void *user, const limn_morph_frame *frame)
{
    (void)frame;
    ++*(int *)user;
    return LIMN_OK;
}

const uint8_t api_palette[6] = {0, 0, 0, 255, 255, 255};

static char scratch_dir[64];

int api_make_dir(void **state)
{
    (void)state;
    strcpy(scratch_dir, "/tmp/limn_api_XXXXXX");
    return mkdtemp(scratch_dir) ? 0 : -1;
}

int api_remove_dir(void **state)
{
    (void)state;
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", scratch_dir);
    return system(cmd) == 0 ? 0 : -1;
}

const char *api_scratch(const char *name)
{
    static char path[2][128];
    static int k;
    k ^= 1;
    snprintf(path[k], sizeof path[k], "%s/%s", scratch_dir, name);
    return path[k];
}
