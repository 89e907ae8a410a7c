/* SPDX-License-Identifier: MIT */
/*
 * The OpenCL runtime's thread count from the process's CPU binding
 * (threads.h). setenv is process wide and PoCL reads its variables once, at
 * the first platform query, so the decision is taken once per process under
 * a lock and remembered; that record is the only state shared by contexts.
 */
#include "device/threads.h"
#include "base/context.h"
#include "device/device.h"

#include <errno.h>
#include <limits.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define THREADS_MAX 65536

static pthread_mutex_t threads_lock = PTHREAD_MUTEX_INITIALIZER;
static int threads_decided;
static threads_plan threads_applied;
static int threads_applied_request;

static int is_set(const char *value) { return value && *value; }

/* A whole positive decimal integer, 1..THREADS_MAX. */
static int parse_count(const char *text, int *out)
{
    char *end;
    errno = 0;
    long v = strtol(text, &end, 10);
    if (end == text || *end || errno == ERANGE || v < 1 || v > THREADS_MAX)
        return 0;
    *out = (int)v;
    return 1;
}

void threads_plan_make(threads_plan *plan, const char *env_pthread, const char *env_cu,
                       int request, int binding_cores, const char *why)
{
    memset(plan, 0, sizeof *plan);
    if (is_set(env_pthread) || is_set(env_cu)) {
        /* the user's variable wins; PoCL 3.x reads the first name, 4.x the second */
        const char *name = is_set(env_pthread) ? THREADS_SOURCE_PTHREAD : THREADS_SOURCE_CU;
        const char *value = is_set(env_pthread) ? env_pthread : env_cu;
        snprintf(plan->source, sizeof plan->source, "%s", name);
        if (!parse_count(value, &plan->count)) {
            plan->count = 0;
            snprintf(plan->warning, sizeof plan->warning,
                     "%s='%.40s' is not a whole number from 1 to %d; left as it is, for the "
                     "OpenCL runtime to interpret",
                     name, value, THREADS_MAX);
            return;
        }
        plan->set_pthread = !is_set(env_pthread);
        plan->set_cu = !is_set(env_cu);
        if (is_set(env_pthread) && is_set(env_cu) && strcmp(env_pthread, env_cu) != 0)
            snprintf(plan->warning, sizeof plan->warning,
                     "POCL_MAX_PTHREAD_COUNT=%.20s and POCL_CPU_MAX_CU_COUNT=%.20s differ: PoCL "
                     "3.x uses the first, 4.x the second",
                     env_pthread, env_cu);
        else if (request != LIMN_THREADS_FROM_BINDING && request != LIMN_THREADS_RUNTIME_DEFAULT)
            snprintf(plan->warning, sizeof plan->warning,
                     "%s=%.20s from the environment takes precedence over "
                     "limn_context_set_threads(%d)",
                     name, value, request);
        return;
    }
    if (request == LIMN_THREADS_RUNTIME_DEFAULT) {
        snprintf(plan->source, sizeof plan->source, "%s", THREADS_SOURCE_RUNTIME);
        return;
    }
    if (request > 0 || binding_cores > 0) {
        plan->count = request > 0 ? request : binding_cores;
        snprintf(plan->source, sizeof plan->source, "%s",
                 request > 0 ? THREADS_SOURCE_API : THREADS_SOURCE_BINDING);
        plan->set_pthread = plan->set_cu = 1;
        return;
    }
    const char *reason = why && *why ? why : "no cores counted";
    snprintf(plan->source, sizeof plan->source, "%s (hwloc: %.100s)", THREADS_SOURCE_RUNTIME,
             reason);
    snprintf(plan->warning, sizeof plan->warning,
             "could not count the cores inside the CPU binding (%.100s): the OpenCL runtime "
             "picks its own thread count",
             reason);
}


void threads_apply(limn_context *ctx)
{
    int request = ctx ? ctx->threads_request : LIMN_THREADS_FROM_BINDING;
    pthread_mutex_lock(&threads_lock);
    if (!threads_decided) {
        const char *p = getenv(THREADS_SOURCE_PTHREAD), *c = getenv(THREADS_SOURCE_CU);
        char why[160] = "";
        int cores = -1;
        if (!is_set(p) && !is_set(c) && request == LIMN_THREADS_FROM_BINDING)
            cores = (int)cores_in_binding(why, sizeof why);
        threads_plan_make(&threads_applied, p, c, request, cores, why);
        char value[16];
        snprintf(value, sizeof value, "%d", threads_applied.count);
        /* overwrite = 0: a variable set meanwhile is the user's and stays */
        if (threads_applied.set_pthread)
            setenv(THREADS_SOURCE_PTHREAD, value, 0);
        if (threads_applied.set_cu)
            setenv(THREADS_SOURCE_CU, value, 0);
        threads_applied_request = request;
        threads_decided = 1;
        if (threads_applied.warning[0])
            ctx_warn(ctx, "%s", threads_applied.warning);
    } else if (request != threads_applied_request) {
        ctx_warn(ctx,
                  "the OpenCL runtime's thread count was fixed at %d (%s) by the first device "
                  "query in this process; this context's limn_context_set_threads(%d) has no "
                  "effect",
                  threads_applied.count, threads_applied.source, request);
    }
    pthread_mutex_unlock(&threads_lock);
}

limn_status limn_context_set_threads(limn_context *ctx, int threads)
{
    if (!ctx)
        return LIMN_ERR_ARGUMENT;
    ctx_clear(ctx);
    if (threads < LIMN_THREADS_RUNTIME_DEFAULT || threads > THREADS_MAX)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                         "limn_context_set_threads: %d is not a thread count (1..%d), "
                         "LIMN_THREADS_FROM_BINDING (0) or LIMN_THREADS_RUNTIME_DEFAULT (-1)",
                         threads, THREADS_MAX);
    ctx->threads_request = threads;
    return LIMN_OK;
}

limn_status limn_context_threads(const limn_context *ctx, int *threads, const char **source)
{
    if (!ctx)
        return LIMN_ERR_ARGUMENT;
    if (!threads || !source)
        /* the message is the one field a const context may change: the caller
           made ctx with limn_context_create, never const, so writing is defined */
        return ctx_fail((limn_context *)ctx, LIMN_ERR_ARGUMENT,
                         "limn_context_threads: %s is NULL", !threads ? "threads" : "source");
    if (ctx->device && strcmp(ctx->device->ops->kind, "reference") == 0) {
        *threads = 1;
        *source = THREADS_SOURCE_REFERENCE;
        return LIMN_OK;
    }
    pthread_mutex_lock(&threads_lock);
    *threads = threads_decided ? threads_applied.count : 0;
    /* the record never changes once decided, so the pointer stays valid */
    *source = threads_decided ? threads_applied.source
                              : "not decided yet: no OpenCL platform queried in this process";
    pthread_mutex_unlock(&threads_lock);
    return LIMN_OK;
}
