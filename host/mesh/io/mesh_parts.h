/* SPDX-License-Identifier: MIT */
/*
 * A mesh file in three parts: the header, made from the whole mesh's figures
 * (a mesh_layout); the vertex records of any range of vertices; the face
 * records of any range of faces. Each record's bytes depend on the record
 * alone, so the header followed by the parts of consecutive ranges, in
 * order, is the file limn_mesh_write writes of the whole mesh. The single
 * process writes one range of each (mesh_parts_write); the MPI layer
 * (host/mpi/mpi_write.c) formats each rank's ranges into memory and writes
 * them at their offsets. One formatter per format: mesh_text_write.c (OBJ,
 * OFF, the lines of ascii PLY), mesh_ply_write.c, mesh_stl_write.c.
 */
#ifndef LIMN_MESH_IO_MESH_PARTS_H
#define LIMN_MESH_IO_MESH_PARTS_H

#include "limn.h"
#include "mesh/io/block_write.h"

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

/* What the header says: figures of the whole mesh. */
typedef struct mesh_layout {
    limn_format format;    /* OBJ, PLY, PLY_ASCII, PLY_BINARY_BE, OFF or STL (not AUTO) */
    int single;            /* PLY: positions as float32 */
    int colors;            /* the vertices carry colours (PLY writes them, others drop them) */
    size_t vertex_total, face_total;
    uint32_t max_face;     /* the most corners of a face: PLY's list count type */
    uint64_t triangles;    /* STL: the fan triangles of every face */
} mesh_layout;

/* A range of a mesh: vertices (positions, colours or NULL) and faces (CSR
   from 0, vertex indices of the whole mesh). For STL's faces, positions are
   indexed by those indices (the caller gives a mesh whose vertices the
   indices name). */
typedef struct mesh_block {
    size_t vertex_count;
    const double *positions;
    const uint8_t *colors;
    size_t face_count;
    const uint32_t *face_offsets, *face_indices;
} mesh_block;

/* The figures of faces [0, face_count) of a CSR: the most corners and the
   fan triangles (merge the ranges' with max and sum). */
void mesh_layout_faces(const uint32_t *face_offsets, size_t face_count, uint32_t *max_face,
                       uint64_t *triangles);

/* Refuses a layout the format cannot hold (STL: more than 2^32 - 1 triangles);
   the message names path. */
limn_status mesh_layout_check(limn_context *ctx, const char *path, const mesh_layout *l);

/* The header's bytes; C locale numbers (no printf of a double). */
limn_status mesh_part_header(limn_context *ctx, const char *path, const mesh_layout *l,
                             const block_sink *sink);
/* The records of block's vertices, the first being vertex `first` of the
   whole mesh (messages: STL refuses a coordinate outside float's range). */
limn_status mesh_part_vertices(limn_context *ctx, const char *path, const mesh_layout *l,
                               const mesh_block *block, size_t first, const block_sink *sink);
/* The records of block's faces. */
limn_status mesh_part_faces(limn_context *ctx, const char *path, const mesh_layout *l,
                            const mesh_block *block, const block_sink *sink);

/* The single process: the whole mesh into f, header, vertices, faces. */
limn_status mesh_parts_write(limn_context *ctx, const limn_mesh *mesh, const char *path,
                             FILE *f, limn_format format, int single);

/* ---------------------------------------------------- the formats' parts */
/* mesh_text_write.c: OBJ, OFF and ascii PLY's lines (headers: OBJ, OFF). */
limn_status text_header(limn_context *ctx, const char *path, const mesh_layout *l,
                        const block_sink *sink);
limn_status text_vertices(limn_context *ctx, const char *path, const mesh_layout *l,
                          const mesh_block *b, const block_sink *sink);
limn_status text_faces(limn_context *ctx, const char *path, const mesh_layout *l,
                       const mesh_block *b, const block_sink *sink);
/* mesh_ply_write.c: the header of every PLY, the binary records. */
limn_status ply_header(limn_context *ctx, const char *path, const mesh_layout *l,
                       const block_sink *sink);
limn_status ply_vertices(limn_context *ctx, const char *path, const mesh_layout *l,
                         const mesh_block *b, const block_sink *sink);
limn_status ply_faces(limn_context *ctx, const char *path, const mesh_layout *l,
                      const mesh_block *b, const block_sink *sink);
/* mesh_stl_write.c: no vertex records (the check of float's range only). */
limn_status stl_header(limn_context *ctx, const char *path, const mesh_layout *l,
                       const block_sink *sink);
limn_status stl_vertices(limn_context *ctx, const char *path, const mesh_block *b, size_t first);
limn_status stl_faces(limn_context *ctx, const char *path, const mesh_block *b,
                      const block_sink *sink);

#endif
