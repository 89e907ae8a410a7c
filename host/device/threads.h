/* SPDX-License-Identifier: MIT */
/*
 * The OpenCL runtime's thread count (DESIGN.md §4): PoCL sizes its thread
 * pool from the whole machine and ignores the process's CPU binding, so
 * under MPI (one rank per core or socket) every rank would start one thread
 * per core of the node. Before the first platform query limn counts the
 * cores inside the binding with hwloc and passes that count on through
 * POCL_MAX_PTHREAD_COUNT (PoCL 3.x) and POCL_CPU_MAX_CU_COUNT (PoCL 4.x),
 * unless the user set either variable or the context asked otherwise.
 */
#ifndef LIMN_THREADS_H
#define LIMN_THREADS_H

#include "limn.h"

#include "base/cores.h"

/* Where the count came from (the report's threads_source). */
#define THREADS_SOURCE_BINDING "binding via hwloc"
#define THREADS_SOURCE_API "API"
#define THREADS_SOURCE_PTHREAD "POCL_MAX_PTHREAD_COUNT"
#define THREADS_SOURCE_CU "POCL_CPU_MAX_CU_COUNT"
#define THREADS_SOURCE_RUNTIME "OpenCL runtime default"
#define THREADS_SOURCE_REFERENCE "reference backend"

/* What to do with the environment, decided before touching it. */
typedef struct threads_plan {
    int count;               /* threads the runtime will use; 0 = its own choice */
    char source[160];        /* a THREADS_SOURCE_*, with a reason for RUNTIME */
    int set_pthread, set_cu; /* which variables to set to `count` */
    char warning[256];       /* "" or why the plan is not what was asked */
} threads_plan;

/*
 * The decision, without side effects. env_pthread, env_cu: the variables'
 * values (NULL or "" when unset); request: limn_context_set_threads's value;
 * binding_cores: cores inside the binding (> 0), or <= 0 when not counted,
 * with why saying why (may be NULL). Precedence: a variable the user set
 * (copied into the other, never overwritten), then the API's count, then
 * the binding; LIMN_THREADS_RUNTIME_DEFAULT sets nothing.
 */
void threads_plan_make(threads_plan *plan, const char *env_pthread, const char *env_cu,
                       int request, int binding_cores, const char *why);

/*
 * Once per process, before the first clGetPlatformIDs: decides from ctx's
 * request and the environment and sets the variables (setenv is process
 * wide: later calls only compare, and warn on ctx when its request can no
 * longer take effect). Records the outcome for limn_context_threads.
 */
void threads_apply(limn_context *ctx);

#endif
