/* SPDX-License-Identifier: MIT */
/*
 * Writing n items (vertices, faces) in large blocks: each round the host
 * threads format consecutive ranges into their own buffers, then the
 * buffers are written in order. An item's bytes depend on the item alone,
 * so the file is the same bytes for any thread count.
 */
#ifndef LIMN_MESH_IO_BLOCK_WRITE_H
#define LIMN_MESH_IO_BLOCK_WRITE_H

#include "limn.h"

#include <stddef.h>
#include <stdio.h>

typedef struct block_job {
    size_t n;          /* items */
    size_t item_bytes; /* a typical item's size: the thread count and the blocks */
    /* the most bytes items [begin, end) can take */
    size_t (*bound)(const void *arg, size_t begin, size_t end);
    /* writes items [begin, end) at out; returns the bytes written */
    size_t (*put)(const void *arg, size_t begin, size_t end, unsigned char *out);
    const void *arg;
} block_job;

/* Where the formatted bytes go, in order: a FILE, memory (mpi_write.c). */
typedef struct block_sink {
    /* appends n bytes; LIMN_OK or the failure with its message (naming path) */
    limn_status (*put)(void *arg, limn_context *ctx, const char *path, const void *bytes,
                       size_t n);
    /* NULL, or makes room for n more bytes at once (the job's bound: memory
       that is never touched costs no pages); 0 when it cannot */
    int (*reserve)(void *arg, size_t n);
    void *arg;
} block_sink;

/* The sinks: fwrite to f (LIMN_ERR_IO); appends to g (LIMN_ERR_MEMORY). */
block_sink block_sink_file(FILE *f);
struct growbuf;
block_sink block_sink_memory(struct growbuf *g);

/* Formats the job's items into sink (path for messages): LIMN_OK or the
   sink's failure / LIMN_ERR_MEMORY with the message. */
limn_status block_emit(limn_context *ctx, const char *path, const block_job *job,
                       const block_sink *sink);

#endif
