/* SPDX-License-Identifier: MIT */
/* Work split into ranges over threads (ranges.h). */
#ifndef _GNU_SOURCE
#define _GNU_SOURCE /* sched_getaffinity, CPU_COUNT */
#endif
#include "mesh/io/ranges.h"
#include "base/context.h"

#include <pthread.h>
#include <sched.h>
#include <stdlib.h>

#define RANGES_MAX 64

typedef struct range_job {
    ranges_fn fn;
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

/* Where range i of parts starts: the first n % parts ranges are one longer. */
static size_t range_cut(size_t n, unsigned parts, unsigned i)
{
    size_t extra = n % parts;
    return n / parts * i + (i < extra ? i : extra);
}

int ranges_run(size_t n, unsigned parts, ranges_fn fn, void *arg)
{
    range_job jobs[RANGES_MAX];
    pthread_t tid[RANGES_MAX];
    int started[RANGES_MAX] = {0};
    if (parts < 1)
        parts = 1;
    if (parts > RANGES_MAX)
        parts = RANGES_MAX;
    if ((size_t)parts > n)
        parts = n ? (unsigned)n : 1;
    for (unsigned i = 0; i < parts; i++)
        jobs[i] = (range_job){fn, arg, range_cut(n, parts, i), range_cut(n, parts, i + 1), 0};
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

unsigned ranges_threads(const limn_context *ctx, uint64_t bytes)
{
    int cpus = ctx && ctx->threads_request > 0 ? ctx->threads_request : 0;
#ifdef CPU_COUNT
    cpu_set_t set;
    if (!cpus && sched_getaffinity(0, sizeof set, &set) == 0)
        cpus = CPU_COUNT(&set);
#endif
    uint64_t most = bytes / RANGES_GRAIN + 1;
    if (cpus < 1)
        cpus = 1;
    if ((uint64_t)cpus > most)
        cpus = (int)most;
    return cpus > RANGES_MAX ? RANGES_MAX : (unsigned)cpus;
}
