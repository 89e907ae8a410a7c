/* SPDX-License-Identifier: MIT */
/* Items formatted in parallel ranges, handed to a sink in order (block_write.h). */
#include "mesh/io/block_write.h"
#include "base/context.h"
#include "base/growbuf.h"
#include "base/parallel.h"
#include "mesh/io/toolkit.h"

#include <stdlib.h>

/* Bytes one thread formats per round: large writes, little memory. */
#define BLOCK_BYTES ((size_t)4 << 20)

typedef struct block_part {
    unsigned char *buf;
    size_t cap, len;
} block_part;

typedef struct block_round {
    const block_job *job;
    block_part *parts;
    unsigned count;      /* parts */
    size_t begin, items; /* this round's items */
} block_round;

static int format_parts(void *arg, size_t first, size_t last)
{
    block_round *r = arg;
    for (size_t i = first; i < last; i++) {
        block_part *p = &r->parts[i];
        size_t b = r->begin + parallel_cut(r->items, r->count, (unsigned)i);
        size_t e = r->begin + parallel_cut(r->items, r->count, (unsigned)i + 1);
        size_t need = r->job->bound(r->job->arg, b, e);
        if (need > p->cap) {
            unsigned char *grown = realloc(p->buf, need);
            if (!grown)
                return 1;
            p->buf = grown;
            p->cap = need;
        }
        p->len = b < e ? r->job->put(r->job->arg, b, e, p->buf) : 0;
    }
    return 0;
}

static limn_status file_put(void *arg, limn_context *ctx, const char *path, const void *bytes,
                            size_t n)
{
    return fwrite(bytes, 1, n, arg) == n ? LIMN_OK : mio_write_failed(ctx, path);
}

static limn_status memory_put(void *arg, limn_context *ctx, const char *path, const void *bytes,
                              size_t n)
{
    return growbuf_append(arg, bytes, n)
               ? LIMN_OK
               : ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory writing %s", path);
}

static int memory_reserve(void *arg, size_t n) { return growbuf_reserve(arg, n); }

block_sink block_sink_file(FILE *f) { return (block_sink){file_put, NULL, f}; }

block_sink block_sink_memory(struct growbuf *g)
{
    return (block_sink){memory_put, memory_reserve, g};
}

limn_status block_emit(limn_context *ctx, const char *path, const block_job *job,
                       const block_sink *sink)
{
    unsigned threads = parallel_threads(ctx, (uint64_t)job->n * job->item_bytes);
    size_t per_part = BLOCK_BYTES / (job->item_bytes ? job->item_bytes : 1);
    if (per_part == 0)
        per_part = 1;
    block_part parts[PARALLEL_MAX] = {{0}};
    block_round r = {job, parts, threads, 0, 0};
    limn_status st = LIMN_OK;
    if (sink->reserve && job->n && !sink->reserve(sink->arg, job->bound(job->arg, 0, job->n)))
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory writing %s", path);
    for (size_t at = 0; at < job->n && !st; at += r.items) {
        r.begin = at;
        r.items = job->n - at < per_part * threads ? job->n - at : per_part * threads;
        if (parallel_run(threads, threads, format_parts, &r)) {
            st = ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory writing %s", path);
            break;
        }
        for (unsigned i = 0; i < threads && !st; i++)
            if (parts[i].len)
                st = sink->put(sink->arg, ctx, path, parts[i].buf, parts[i].len);
        ctx_progress(ctx, "write", (double)(at + r.items) / (double)job->n);
    }
    for (unsigned i = 0; i < threads; i++)
        free(parts[i].buf);
    return st;
}
