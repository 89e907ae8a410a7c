/* SPDX-License-Identifier: MIT */
/*
 * Between the slice reader's dispatcher (mesh_slice.c) and its format files:
 * the mapped file, binary PLY (mesh_slice_ply.c), the text formats
 * (mesh_slice_text.c). mesh_slice.h is the interface.
 */
#ifndef LIMN_MESH_IO_MESH_SLICE_FORMATS_H
#define LIMN_MESH_IO_MESH_SLICE_FORMATS_H

#include "mesh/io/mesh_ply.h"
#include "mesh/io/mesh_slice.h"

#include <stdio.h>

/* The file, open and mapped read-only. */
typedef struct slice_file {
    limn_context *ctx;
    const char *path;
    FILE *f;
    const unsigned char *map;
    size_t size;
} slice_file;

/* Opens and maps path (an empty file, a directory or a special file is
   refused with a message); slice_file_close undoes what was done. */
limn_status slice_file_open(limn_context *ctx, const char *path, slice_file *sf);
void slice_file_close(slice_file *sf);
/* Drops the pages of [begin, end) read so far from the process (they stay
   in the page cache): a scan over what is not the part's keeps its resident
   memory to the part's own. */
void slice_file_release(const slice_file *sf, uint64_t begin, uint64_t end);

/* Moves s's arrays into out (zeroed on failure: s freed). */
limn_status slice_hand_over(limn_status st, mesh_slice *s, mesh_slice *out);

/* Binary PLY, its header in p (read from sf->f). index_limit: the vertex
   numbers faces may use (the header's vertex count; the split format's
   total). */
limn_status slice_ply_count(const slice_file *sf, const ply *p, unsigned part, unsigned parts,
                            mesh_slice_counts *out);
limn_status slice_ply_read(const slice_file *sf, const ply *p, unsigned part, unsigned parts,
                           int regular, uint64_t index_limit, mesh_slice *out);

/* OBJ, OFF and ASCII PLY (p: the PLY header, else NULL). */
typedef enum { SLICE_OBJ, SLICE_OFF, SLICE_PLY } slice_text_kind;
limn_status slice_text_count(const slice_file *sf, slice_text_kind kind, const ply *p,
                             unsigned part, unsigned parts, mesh_slice_counts *out);
limn_status slice_text_read(const slice_file *sf, slice_text_kind kind, const ply *p,
                            unsigned part, unsigned parts, const mesh_slice_counts *before,
                            const mesh_slice_counts *total, mesh_slice *out);

#endif
