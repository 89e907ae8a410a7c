/* SPDX-License-Identifier: MIT */
/*
 * Reading one part of a mesh file (issue 14 item 1): part p of P reads its
 * own contiguous block of the vertices and of the faces, with the file's
 * global numbering, and never the whole mesh; the concatenation of parts
 * 0..P-1 is limn_mesh_read's mesh (positions, face offsets, indices) bit for
 * bit. No MPI here: the caller (host/mpi) runs the parts, one per rank.
 *
 * Two phases, so text formats (whose numbering needs the counts of the
 * parts before) work without any part reading the whole file:
 *   1. mesh_slice_count: what part p holds (a scan of its byte range);
 *   2. the caller sums the counts of the parts before p (`before`, an
 *      exclusive prefix sum) and of all parts (`total`);
 *   3. mesh_slice_read: part p's slice.
 *
 * Formats (docs/mpi.md "Reading in slices"):
 *  - binary PLY (little and big endian, any scalar types, extra vertex
 *    properties, elements without lists around the vertex and face ones):
 *    even blocks, part p gets vertices [p*N/P, (p+1)*N/P) and faces likewise.
 *    Vertex records by direct byte offset. Face records by direct offset
 *    when every list count is the first one's (each part checks its own
 *    block in phase 1 and reports `irregular`; the sum says whether every
 *    block was), else every part streams the count bytes of the faces before
 *    its block (O(F) time, O(1) memory). Not taken: tristrips, lists in
 *    other elements or beside the face indices, lists in the vertex element.
 *  - OBJ, OFF, ASCII PLY: part p takes the byte range [p*B/P, (p+1)*B/P) of
 *    the body (B bytes after the header), both ends moved to the next line
 *    start; its blocks are the records whose lines start in the range
 *    (uneven). OBJ negative indices count back from the global vertex count
 *    before their line. One record a line; a NUL byte, a lone '\r', an OBJ
 *    '\' continuation or a record the fast line parsers do not take is an
 *    error naming the line (limn_mesh_read then names the problem).
 *  - STL: refused (its vertices are welded over the whole file).
 *  - split input: mesh_slice_split.c (files NAME.r<p>.ply).
 *
 * Memory: a part allocates its own slice only (binary PLY: exactly; text:
 * growing arrays shrunk at the end, at most twice the slice). The file is
 * mapped, read-only.
 */
#ifndef LIMN_MESH_IO_MESH_SLICE_H
#define LIMN_MESH_IO_MESH_SLICE_H

#include "limn.h"
#include "base/atomic_file.h"

#include <stddef.h>
#include <stdint.h>

/* One part's contiguous block of a mesh file (global numbering). */
typedef struct mesh_slice {
    size_t vertex_total, face_total;     /* the whole file */
    size_t vertex_begin, vertex_count;   /* vertices [begin, begin+count) of the file */
    double *positions;                   /* 3 * vertex_count */
    size_t face_begin, face_count;       /* faces [begin, begin+count) of the file */
    uint32_t *face_offsets;              /* face_count + 1, starting at 0 */
    uint32_t *face_indices;              /* GLOBAL vertex indices, checked < vertex_total */
} mesh_slice;

/* Frees the arrays and zeroes s (NULL or zeroed: nothing). */
void mesh_slice_free(mesh_slice *s);

/* Phase 1's counts of one part; every field is summed over parts. Text:
   lines ('\n' in the range), records (content lines), OBJ vertex and face
   lines and face corners. Binary PLY: its vertex, face and (fixed lists)
   corner blocks, irregular 1 when its face block is not at the fixed
   stride. */
typedef struct mesh_slice_counts {
    uint64_t lines, records, vertices, faces, corners, irregular;
} mesh_slice_counts;
#define MESH_SLICE_COUNT_FIELDS 6 /* uint64_t fields, for an MPI reduction */

void mesh_slice_counts_add(mesh_slice_counts *sum, const mesh_slice_counts *c);

/* Phase 1 for part `part` of `parts` (part < parts) of the file at path in
   the format (LIMN_FORMAT_AUTO: from the extension, .ply .obj .off; any PLY
   format: PLY, its header tells which). *out zeroed on failure. */
limn_status mesh_slice_count(limn_context *ctx, const char *path, limn_format format,
                             unsigned part, unsigned parts, mesh_slice_counts *out);

/* Phase 3: before = the sum of the counts of parts 0..part-1, total = of
   all parts. On success *out is the part's slice (the caller frees it with
   mesh_slice_free); on failure a message "PATH:LINE: ..." or "PATH: byte N:
   ..." naming the element, and *out zeroed. */
limn_status mesh_slice_read(limn_context *ctx, const char *path, limn_format format,
                            unsigned part, unsigned parts, const mesh_slice_counts *before,
                            const mesh_slice_counts *total, mesh_slice *out);

/* Where block p of `parts` over n items starts: floor(p * n / parts). */
size_t mesh_slice_cut(size_t n, unsigned parts, unsigned p);

/* Part `part` of `parts` of a mesh in memory, even blocks as binary PLY's
   (a copy; the faces' indices are global). */
limn_status mesh_slice_of(limn_context *ctx, const limn_mesh *mesh, unsigned part,
                          unsigned parts, mesh_slice *out);

/* ------------------------------------------------- split input (one file a part)
 * mesh_slice_split.c: part p of P in the file NAME.r<p>.ply beside NAME.ply
 * (the name given, ".ply" dropped), a binary little-endian PLY with double
 * x y z and `uchar uint` (or `uint uint` over 255 corners) face lists holding
 * GLOBAL vertex indices, and one header comment
 *   comment limn-slice part p parts P vertex_begin B vertex_total N face_begin F face_total M
 * Its vertex element holds the part's vertices, its face element the part's
 * faces. */

/* The file name of part p: 0 when it does not fit in size bytes. */
int mesh_slice_split_name(const char *name, unsigned part, char *buf, size_t size);
/* Writes s as part `part` of `parts` (atomic: whole or not at all). */
limn_status mesh_slice_write_split(limn_context *ctx, const char *name, unsigned part,
                                   unsigned parts, const mesh_slice *s);
/* The same staged: *af holds the part complete and synced under its
   temporary name, for atomic_file_commit (or atomic_file_abort) once every
   part is staged; on failure nothing is left and *af is empty. */
limn_status mesh_slice_stage_split(limn_context *ctx, const char *name, unsigned part,
                                   unsigned parts, const mesh_slice *s, atomic_file *af);
/* Reads part `part`'s file, checking it against its own header and the
   neighbouring parts' headers (part p-1 ends where p begins, the same totals;
   the last part ends at the totals and no file NAME.r<parts>.ply exists), so
   that parts that all succeed agree. */
limn_status mesh_slice_read_split(limn_context *ctx, const char *name, unsigned part,
                                  unsigned parts, mesh_slice *out);

#endif
