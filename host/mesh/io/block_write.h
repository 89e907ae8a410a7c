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

/* Writes the job's items to f (path for messages): LIMN_OK or LIMN_ERR_IO /
   LIMN_ERR_MEMORY with the message. */
limn_status block_write(limn_context *ctx, const char *path, FILE *f, const block_job *job);

#endif
