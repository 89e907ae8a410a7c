/* SPDX-License-Identifier: MIT */
/* Helpers of the API checks' tests (test_api_checks.c, test_api_limits.c,
   test_abi.c, test_embed.c):
   assertions on a refused call's status and message, a context on the
   reference backend, a scratch directory. */
#ifndef LIMN_API_EXPECT_H
#define LIMN_API_EXPECT_H

#include "limn.h"
#include "support.h"

/* The call failed with `status` and a non-empty message containing every
   one of the NULL-terminated strings after it; else the test fails. */
void api_expect(limn_context *ctx, const char *call, limn_status got, limn_status status, ...);
#define EXPECT(ctx, call, status, ...) api_expect(ctx, #call, (call), status, __VA_ARGS__, NULL)
#define REFUSED(ctx, call, ...) EXPECT(ctx, call, LIMN_ERR_ARGUMENT, __VA_ARGS__)

/* Any failure at all, with a non-empty message. */
#define FAILS(ctx, call)                                                                       \
    do {                                                                                       \
        limn_status st_ = (call);                                                              \
        if (st_ == LIMN_OK)                                                                    \
            fail_msg("%s succeeded", #call);                                                   \
        if (!limn_context_message(ctx)[0])                                                     \
            fail_msg("%s failed (%s) with an empty message", #call, limn_status_name(st_));    \
    } while (0)

#define OK(ctx, call)                                                                          \
    do {                                                                                       \
        limn_status st_ = (call);                                                              \
        if (st_ != LIMN_OK)                                                                    \
            fail_msg("%s: %s: %s", #call, limn_status_name(st_), limn_context_message(ctx));    \
    } while (0)

/* A new context on the reference backend (refusals do not need a device). */
limn_context *api_reference_context(void);
/* A morph callback counting the frames in *(int *)user. */
limn_status api_count_frame(void *user, const limn_morph_frame *frame);
/* Two colours, black and white, for limn_texture. */
extern const uint8_t api_palette[6];

/* cmocka group set-up and tear-down of a scratch directory, and a path in
   it (two alternating static buffers). */
int api_make_dir(void **state);
int api_remove_dir(void **state);
const char *api_scratch(const char *name);

#endif
