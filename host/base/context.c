/* SPDX-License-Identifier: MIT */
/* Context settings, error messages and warnings (its life cycle, which closes
   the device, is in device/choice/choice.c). */
#include "base/context.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define LIMN_STR_(x) #x
#define LIMN_STR(x) LIMN_STR_(x)

const char *limn_version(void)
{
    return LIMN_STR(LIMN_VERSION_MAJOR) "." LIMN_STR(LIMN_VERSION_MINOR) "." LIMN_STR(
        LIMN_VERSION_PATCH);
}

const char *limn_context_message(const limn_context *ctx)
{
    if (!ctx)
        return "no context";
    return ctx->long_message && ctx->message[0] ? ctx->long_message : ctx->message;
}

const char *limn_context_warnings(const limn_context *ctx)
{
    return ctx && ctx->warnings ? ctx->warnings : "";
}

void limn_context_set_progress(limn_context *ctx, limn_progress_fn fn, void *user)
{
    if (!ctx)
        return;
    ctx->progress = fn;
    ctx->progress_user = user;
}

void limn_context_set_max_memory(limn_context *ctx, size_t bytes)
{
    if (ctx)
        ctx->max_memory = bytes;
}

size_t context_max_memory(const limn_context *ctx)
{
    if (ctx && ctx->max_memory)
        return ctx->max_memory;
    long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
    if (pages <= 0 || page <= 0)
        return SIZE_MAX;
    if ((unsigned long long)pages > SIZE_MAX / 3 / (unsigned long long)page)
        return SIZE_MAX;
    return (size_t)pages * (size_t)page / 4 * 3;
}

const char *limn_context_device_name(const limn_context *ctx)
{
    return ctx ? ctx->device_name : "";
}

limn_status ctx_fail(limn_context *ctx, limn_status status, const char *fmt, ...)
{
    if (!ctx)
        return status;
    free(ctx->long_message);
    ctx->long_message = NULL;
    va_list ap, again;
    va_start(ap, fmt);
    va_copy(again, ap);
    int n = vsnprintf(ctx->message, sizeof ctx->message, fmt, ap);
    va_end(ap);
    /* a message that does not fit (a compiler's whole build log) is kept
       whole on the heap; message[] keeps its start (MPI sends that) */
    if (n >= (int)sizeof ctx->message) {
        ctx->long_message = malloc((size_t)n + 1);
        if (ctx->long_message)
            vsnprintf(ctx->long_message, (size_t)n + 1, fmt, again);
    }
    va_end(again);
    return status;
}

void ctx_warn(limn_context *ctx, const char *fmt, ...)
{
    if (!ctx)
        return;
    char line[1024];
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    if (n < 0)
        return;
    size_t len = strlen(line);
    char *grown = realloc(ctx->warnings, ctx->warnings_len + len + 2);
    if (!grown)
        return; /* a lost warning is better than a failed operation */
    memcpy(grown + ctx->warnings_len, line, len);
    grown[ctx->warnings_len + len] = '\n';
    grown[ctx->warnings_len + len + 1] = '\0';
    ctx->warnings = grown;
    ctx->warnings_len += len + 1;
}

void ctx_clear(limn_context *ctx)
{
    if (!ctx)
        return;
    ctx->message[0] = '\0';
    free(ctx->long_message);
    ctx->long_message = NULL;
    ctx->device_failed = 0;
    free(ctx->warnings);
    ctx->warnings = NULL;
    ctx->warnings_len = 0;
}

void ctx_progress(limn_context *ctx, const char *stage, double fraction)
{
    if (ctx && ctx->progress)
        ctx->progress(ctx->progress_user, stage, fraction);
}

const char *limn_status_name(limn_status status)
{
    switch (status) {
    case LIMN_OK: return "LIMN_OK";
    case LIMN_ERR_ARGUMENT: return "LIMN_ERR_ARGUMENT";
    case LIMN_ERR_IO: return "LIMN_ERR_IO";
    case LIMN_ERR_FORMAT: return "LIMN_ERR_FORMAT";
    case LIMN_ERR_TOPOLOGY: return "LIMN_ERR_TOPOLOGY";
    case LIMN_ERR_MEMORY: return "LIMN_ERR_MEMORY";
    case LIMN_ERR_DEVICE: return "LIMN_ERR_DEVICE";
    case LIMN_ERR_NO_CONVERGENCE: return "LIMN_ERR_NO_CONVERGENCE";
    case LIMN_ERR_SINGULAR: return "LIMN_ERR_SINGULAR";
    }
    return "LIMN_ERR_UNKNOWN";
}
