/* SPDX-License-Identifier: MIT */
/*
 * The text formats' fast paths (text_fast.h) as their general readers call
 * them: mesh_obj_fast.c and mesh_off_fast.c. Each returns 1 when it read
 * the body into the arrays and moved the reader after it, 0 with nothing
 * changed (the general reader then reads the file).
 */
#ifndef LIMN_MESH_IO_TEXT_FORMATS_H
#define LIMN_MESH_IO_TEXT_FORMATS_H

#include "mesh/io/toolkit.h"

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

/* OBJ records limn reads past without a word (mesh_obj.c). */
int obj_skipped_record(const char *word, size_t n);

/* The whole OBJ file after its byte order mark; *vertices gets the count. */
int obj_fast_read(mio_reader *r, mio_arrays *a, size_t *vertices);

/* The OFF body after a header of nv vertices (no colours) and nf faces. */
int off_fast_body(mio_reader *r, mio_arrays *a, long long nv, long long nf);

/* For readers of parts of a file (mesh_slice_text.c). */
struct tf_chunk;
struct tf_text;
/* One OBJ content line [s, e) into c as the fast path reads it: 1 when
   read or skipped (records limn reads past), 0 otherwise (an unknown
   record, a form or value it leaves to the general reader). Negative
   vertex numbers count back from `before` + the vertices already in c
   (before < 0: refused, as in the fast path). */
int obj_fast_record(struct tf_chunk *c, const char *s, const char *e, long long before);
/* Sets t's line function and counts for an OFF body of nv vertices and nf
   faces (positions only: colours and normals are read past); 0 for counts
   it does not take. */
int off_fast_setup(struct tf_text *t, long long nv, long long nf);
/* The OFF header of f (off_read's checks) read: the body's file offset and
   the counts. */
limn_status off_read_header(limn_context *ctx, const char *path, FILE *f, uint64_t *body,
                            long long *nv, long long *nf);

#endif
