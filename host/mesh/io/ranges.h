/* SPDX-License-Identifier: MIT */
/*
 * Work split into contiguous ranges, one thread each (plain pthreads: the
 * readers sit below the device layer). Each range writes only its own part
 * of the output, so the result is the same for any thread count.
 */
#ifndef LIMN_MESH_IO_RANGES_H
#define LIMN_MESH_IO_RANGES_H

#include "limn.h"

#include <stddef.h>
#include <stdint.h>

/* One range [begin, end) of the work; nonzero reports a problem. */
typedef int (*ranges_fn)(void *arg, size_t begin, size_t end);

/* Runs fn over [0, n) split into `parts` ranges of nearly equal size (the
   first on the calling thread; a range whose thread cannot start runs
   there too). Returns 1 when any call returned nonzero. */
int ranges_run(size_t n, unsigned parts, ranges_fn fn, void *arg);

/* Threads for `bytes` of work: limn_context_set_threads's count, else the
   CPUs this process may run on; one per RANGES_GRAIN bytes at most. */
#define RANGES_GRAIN ((uint64_t)4 << 20)
unsigned ranges_threads(const limn_context *ctx, uint64_t bytes);

#endif
