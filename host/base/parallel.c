/* SPDX-License-Identifier: MIT */
/* Work split into ranges over host threads (parallel.h). */
#ifndef _GNU_SOURCE
#define _GNU_SOURCE /* sched_getaffinity, CPU_COUNT */
#endif
#include "base/parallel.h"
#include "base/context.h"
#include "base/cores.h"

#include <pthread.h>
#include <sched.h>
#include <stdlib.h>
#include <string.h>

typedef struct range_job {
    parallel_fn fn;
    void *arg;
    size_t begin, end;
    int result;
} range_job;

static void *range_main(void *job)
{
    range_job *j = job;
    j->result = j->fn(j->arg, j->begin, j->end);
    return NULL;
}

size_t parallel_cut(size_t n, unsigned parts, unsigned i)
{
    /* the first n % parts ranges are one longer */
    size_t extra = n % parts;
    return n / parts * i + (i < extra ? i : extra);
}

/* parallel_run's number of ranges for n items. */
static unsigned clamp_parts(size_t n, unsigned parts)
{
    if (parts < 1)
        parts = 1;
    if (parts > PARALLEL_MAX)
        parts = PARALLEL_MAX;
    if ((size_t)parts > n)
        parts = n ? (unsigned)n : 1;
    return parts;
}

unsigned parallel_part(size_t n, unsigned parts, size_t begin)
{
    parts = clamp_parts(n, parts);
    unsigned i = 0;
    while (i + 1 < parts && parallel_cut(n, parts, i + 1) <= begin)
        i++;
    return i;
}

int parallel_run(size_t n, unsigned parts, parallel_fn fn, void *arg)
{
    range_job jobs[PARALLEL_MAX];
    pthread_t tid[PARALLEL_MAX];
    int started[PARALLEL_MAX] = {0};
    parts = clamp_parts(n, parts);
    for (unsigned i = 0; i < parts; i++)
        jobs[i] = (range_job){fn, arg, parallel_cut(n, parts, i), parallel_cut(n, parts, i + 1),
                              0};
    for (unsigned i = 1; i < parts; i++)
        started[i] = pthread_create(&tid[i], NULL, range_main, &jobs[i]) == 0;
    range_main(&jobs[0]);
    int bad = jobs[0].result != 0;
    for (unsigned i = 1; i < parts; i++) {
        if (started[i])
            pthread_join(tid[i], NULL);
        else
            range_main(&jobs[i]);
        bad |= jobs[i].result != 0;
    }
    return bad;
}

typedef struct prefix_job {
    uint32_t *a;
    size_t n;
    unsigned parts;
    uint32_t start[PARALLEL_MAX];
} prefix_job;

static int prefix_sum_range(void *arg, size_t begin, size_t end)
{
    prefix_job *j = arg;
    uint32_t sum = 0;
    for (size_t i = begin; i < end; i++)
        sum += j->a[i + 1];
    j->start[parallel_part(j->n, j->parts, begin)] = sum;
    return 0;
}

static int prefix_add_range(void *arg, size_t begin, size_t end)
{
    prefix_job *j = arg;
    uint32_t at = j->start[parallel_part(j->n, j->parts, begin)];
    for (size_t i = begin; i < end; i++) {
        at += j->a[i + 1];
        j->a[i + 1] = at;
    }
    return 0;
}

void parallel_prefix_u32(uint32_t *a, size_t n, unsigned parts)
{
    a[0] = 0;
    prefix_job j = {.a = a, .n = n, .parts = clamp_parts(n, parts)};
    if (j.parts > 1) {
        parallel_run(n, j.parts, prefix_sum_range, &j);
        uint32_t at = 0;
        for (unsigned i = 0; i < j.parts; i++) {
            uint32_t sum = j.start[i];
            j.start[i] = at;
            at += sum;
        }
    } else {
        j.start[0] = 0;
    }
    parallel_run(n, j.parts, prefix_add_range, &j);
}

typedef struct copy_job {
    char *to;
    const char *from;
} copy_job;

static int copy_bytes(void *arg, size_t begin, size_t end)
{
    copy_job *j = arg;
    memcpy(j->to + begin, j->from + begin, end - begin);
    return 0;
}

void parallel_copy(limn_context *ctx, void *to, const void *from, size_t bytes)
{
    copy_job j = {to, from};
    parallel_run(bytes, parallel_threads(ctx, bytes), copy_bytes, &j);
}

static int zero_bytes(void *arg, size_t begin, size_t end)
{
    memset((char *)arg + begin, 0, end - begin);
    return 0;
}

void parallel_zero(limn_context *ctx, void *to, size_t bytes)
{
    parallel_run(bytes, parallel_threads(ctx, bytes), zero_bytes, to);
}

/* The CPUs of the affinity mask, when hwloc cannot count cores. */
static int affinity_cpus(void)
{
#ifdef CPU_COUNT
    cpu_set_t set;
    if (sched_getaffinity(0, sizeof set, &set) == 0)
        return CPU_COUNT(&set);
#endif
    return 1;
}

unsigned parallel_host_threads(limn_context *ctx, const char **source)
{
    const char *from;
    int n;
    if (ctx && ctx->host_threads_request > 0) {
        n = ctx->host_threads_request;
        from = "API (host threads)";
    } else if (ctx && ctx->threads_request > 0) {
        n = ctx->threads_request;
        from = "API";
    } else {
        int counted = ctx ? ctx->host_threads_counted : 0;
        if (!counted) {
            char why[128];
            counted = (int)cores_in_binding(why, sizeof why);
            if (counted <= 0)
                counted = -affinity_cpus(); /* negative: from the mask */
            if (ctx)
                ctx->host_threads_counted = counted;
        }
        n = counted > 0 ? counted : -counted;
        from = counted > 0 ? "binding via hwloc" : "affinity mask";
    }
    if (n < 1)
        n = 1;
    if (source)
        *source = from;
    return n > PARALLEL_MAX ? PARALLEL_MAX : (unsigned)n;
}

unsigned parallel_threads(limn_context *ctx, uint64_t bytes)
{
    uint64_t most = bytes / PARALLEL_GRAIN + 1;
    if (most == 1)
        return 1; /* small work: no need to count the cores (hwloc, a few ms) */
    unsigned n = parallel_host_threads(ctx, NULL);
    return (uint64_t)n > most ? (unsigned)most : n;
}

limn_status limn_context_set_host_threads(limn_context *ctx, int threads)
{
    if (!ctx)
        return LIMN_ERR_ARGUMENT;
    ctx_clear(ctx);
    if (threads < 0 || threads > PARALLEL_MAX)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                        "limn_context_set_host_threads: %d is not a host thread count (1..%d, "
                        "or 0 for the default)",
                        threads, PARALLEL_MAX);
    ctx->host_threads_request = threads;
    return LIMN_OK;
}

limn_status limn_context_host_threads(limn_context *ctx, int *threads, const char **source)
{
    if (!ctx)
        return LIMN_ERR_ARGUMENT;
    ctx_clear(ctx);
    if (!threads)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "limn_context_host_threads: threads is NULL");
    *threads = (int)parallel_host_threads(ctx, source);
    return LIMN_OK;
}
