/* SPDX-License-Identifier: MIT */
/* The context's life cycle and its device: which backend runs (the choice,
   the fallback to the reference backend), opened on first use, closed with
   the context. Above both backends, the one place that knows them both. */
#include "device/choice/choice.h"
#include "base/context.h"
#include "device/device.h"
#include "device/opencl/opencl_open.h"
#include "device/reference/ref_open.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

limn_context *limn_context_create(void)
{
    limn_context *ctx = calloc(1, sizeof *ctx);
    return ctx;
}

void limn_context_destroy(limn_context *ctx)
{
    if (!ctx)
        return;
    device_close(ctx->device);
    free(ctx->long_message);
    free(ctx->warnings);
    free(ctx);
}

limn_status limn_context_set_device(limn_context *ctx, const char *spec)
{
    if (!ctx)
        return LIMN_ERR_ARGUMENT;
    ctx_clear(ctx);
    if (!spec)
        spec = "";
    if (strlen(spec) >= sizeof ctx->device_spec)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "device spec is too long (%zu characters)",
                         strlen(spec));
    if (spec[0] && strcmp(spec, "reference") != 0 && strcmp(spec, "ref") != 0 &&
        strcmp(spec, "opencl") != 0 && strncmp(spec, "opencl:", 7) != 0)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                         "unknown device '%s': use 'reference', 'opencl', 'opencl:P.D' or "
                         "'opencl:NAME' (see 'limn devices')",
                         spec);
    device_close(ctx->device);
    ctx->device = NULL;
    ctx->device_name[0] = '\0';
    strcpy(ctx->device_spec, spec);
    return LIMN_OK;
}

limn_status device_open(limn_context *ctx, struct device **out)
{
    const char *spec = ctx->device_spec;
    const char *env = getenv("LIMN_DEVICE");
    if (!spec[0] && env && (strcmp(env, "reference") == 0 || strcmp(env, "ref") == 0))
        spec = "reference";
    if (strcmp(spec, "reference") == 0 || strcmp(spec, "ref") == 0)
        return device_open_reference(ctx, out);
    if (strncmp(spec, "opencl:", 7) == 0)
        return device_open_opencl(ctx, spec + 7, out);
    return device_open_opencl(ctx, NULL, out);
}

limn_status limn_context_set_fallback(limn_context *ctx, const char *backend)
{
    if (!ctx)
        return LIMN_ERR_ARGUMENT;
    ctx_clear(ctx);
    if (!backend || strcmp(backend, "none") == 0)
        ctx->fallback = 1;
    else if (strcmp(backend, "reference") == 0 || strcmp(backend, "ref") == 0)
        ctx->fallback = 2;
    else
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                         "unknown fallback '%s': use 'reference' or 'none'", backend);
    return LIMN_OK;
}

limn_status limn_context_fall_back(limn_context *ctx, limn_status status)
{
    if (!ctx || !device_fallback_allowed(ctx) || !ctx->device ||
        strcmp(ctx->device->ops->kind, "reference") == 0 ||
        !(status == LIMN_ERR_DEVICE || (status == LIMN_ERR_MEMORY && ctx->device_failed)))
        return status;
    char why[sizeof ctx->message];
    snprintf(why, sizeof why, "%s", ctx->message);
    device_close(ctx->device);
    ctx->device = NULL;
    strcpy(ctx->device_spec, "reference");
    ctx->device_name[0] = '\0';
    ctx->device_failed = 0;
    ctx_warn(ctx, "the OpenCL device failed (%.900s); running again on the reference backend "
                   "(the fallback was allowed)",
              why);
    return LIMN_OK;
}

limn_status device_get(limn_context *ctx, struct device **out)
{
    if (!ctx->device) {
        limn_status st = device_open(ctx, &ctx->device);
        if (st == LIMN_ERR_DEVICE && device_fallback_allowed(ctx)) {
            ctx_warn(ctx, "%.900s; using the reference backend instead (the fallback was "
                           "allowed)",
                      ctx->message);
            ctx->message[0] = '\0';
            st = device_open_reference(ctx, &ctx->device);
        }
        if (st)
            return st;
        snprintf(ctx->device_name, sizeof ctx->device_name, "%s", ctx->device->name);
    }
    *out = ctx->device;
    return LIMN_OK;
}
