/* SPDX-License-Identifier: MIT */
/*
 * Host work split into contiguous ranges, one thread each (plain pthreads:
 * readers, topology and stencils sit below the device layer). Each range
 * writes only its own part of the output, so results are the same bytes
 * for any thread count.
 */
#ifndef LIMN_BASE_PARALLEL_H
#define LIMN_BASE_PARALLEL_H

#include "limn.h"

#include <stddef.h>
#include <stdint.h>

/* One range [begin, end) of the work; nonzero reports a problem. */
typedef int (*parallel_fn)(void *arg, size_t begin, size_t end);

/* Runs fn over [0, n) split into `parts` ranges of nearly equal size (the
   first on the calling thread; a range whose thread cannot start runs
   there too). Returns 1 when any call returned nonzero. */
int parallel_run(size_t n, unsigned parts, parallel_fn fn, void *arg);

/* Where range i of `parts` over [0, n) starts (parallel_run's split). */
size_t parallel_cut(size_t n, unsigned parts, unsigned i);
/* Which of parallel_run's ranges (same clamping of parts) starts at begin:
   for fn to find its own slot of per-range results. */
unsigned parallel_part(size_t n, unsigned parts, size_t begin);

/*
 * Counts into offsets in place over `parts` ranges: a[1..n] hold counts on
 * entry, and on return a[0] = 0 and a[i + 1] = a[i] + count i (uint32: the
 * caller knows the total fits). Each range sums its counts, the sums are
 * scanned in range order, then each range adds its start: the same values
 * for any parts (one pass when parts is 1).
 */
void parallel_prefix_u32(uint32_t *a, size_t n, unsigned parts);

/* memcpy over the context's host threads (parallel_threads of bytes): for
   large copies whose destination may be fresh memory, whose first touches
   then spread over the threads too. */
void parallel_copy(limn_context *ctx, void *to, const void *from, size_t bytes);
/* memset(to, 0, bytes) the same way. */
void parallel_zero(limn_context *ctx, void *to, size_t bytes);

/*
 * Threads for `bytes` of work: the context's host thread count
 * (parallel_host_threads), one per PARALLEL_GRAIN bytes at most, so small
 * meshes stay on the calling thread.
 */
#define PARALLEL_GRAIN ((uint64_t)4 << 20)
#define PARALLEL_MAX 64
unsigned parallel_threads(limn_context *ctx, uint64_t bytes);

/*
 * The host thread count (README "Embedding limn"): limn_context_set_host_threads's
 * count, else limn_context_set_threads's, else the cores inside the CPU
 * binding (hwloc; the count PoCL gets), else the CPUs of the affinity mask;
 * counted once per context. *source (may be NULL) says which.
 */
unsigned parallel_host_threads(limn_context *ctx, const char **source);

#endif
