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

/* OBJ records limn reads past without a word (mesh_obj.c). */
int obj_skipped_record(const char *word, size_t n);

/* The whole OBJ file after its byte order mark; *vertices gets the count. */
int obj_fast_read(mio_reader *r, mio_arrays *a, size_t *vertices);

/* The OFF body after a header of nv vertices (no colours) and nf faces. */
int off_fast_body(mio_reader *r, mio_arrays *a, long long nv, long long nf);

#endif
