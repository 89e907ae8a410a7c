/* SPDX-License-Identifier: MIT */
/*
 * The parallel write of a distributed mesh (docs/mpi.md "Writing in
 * parallel"): no rank holds the whole mesh. Each rank has the results of the
 * vertices it owns (any set: a partition's part, not a block) and a block of
 * the faces; the results move to the vertex blocks of vtxdist (one
 * Alltoallv), each rank formats its vertex block and its face block with the
 * single process's formatters (mesh/io/mesh_parts.h), the sizes are
 * prefix-summed (MPI_Exscan) and every rank writes its bytes at its offset
 * with MPI_File_write_at_all, rank 0's starting with the header, into a
 * temporary file beside the target that rank 0 renames over it only after
 * every rank succeeded (host/base/atomic_file.c's rules: symlinks followed,
 * mode kept, fsync; standard output, a FIFO or a character device get the
 * bytes through rank 0, in order, at the end). The file is the same bytes as
 * limn_mesh_write of the whole mesh with the same format and options.
 *
 * Collective over comm (duplicated inside). Every rank returns the same
 * status and has the same message in ctx: that of the lowest rank that
 * failed; on failure nothing is written and no temporary file is left.
 */
#ifndef LIMN_MPI_WRITE_H
#define LIMN_MPI_WRITE_H

#include "limn.h"

#include <mpi.h>
#include <stddef.h>
#include <stdint.h>

/* One rank's share of the mesh to write. */
typedef struct mpi_write_part {
    /* vtxdist[size + 1]: block r is vertices [vtxdist[r], vtxdist[r + 1]); the same on
       every rank, vtxdist[0] = 0, vtxdist[size] the vertex count */
    const size_t *vtxdist;
    /* this rank's owned vertices: n_owned global indices (every vertex owned by exactly
       one rank), their positions (3 doubles each) and colours (3 bytes each, or NULL on
       every rank) */
    size_t n_owned;
    const uint32_t *owned_ids;
    const double *pos;
    const uint8_t *colors;
    /* this rank's faces [face_begin, face_begin + face_count) of the mesh, in rank order
       (rank r's begin where rank r - 1's end); CSR from 0, global vertex indices */
    size_t face_begin, face_count;
    const uint32_t *face_offsets, *face_indices;
} mpi_write_part;

/* Writes path in format (LIMN_FORMAT_AUTO: from its extension) with options
   (NULL: the defaults); the same format and options on every rank. stage:
   NULL, the file appears at once; else (rank 0's; the other ranks' is not
   used) the finished temporary file goes to that set instead (it must have
   room: output_set_room), to appear at its commit. */
limn_status mpi_write_mesh_part(limn_context *ctx, MPI_Comm comm, const char *path,
                                limn_format format, const limn_write_options *options,
                                const mpi_write_part *part, limn_output_set *stage);

/* mpi_write_mesh_part without colours, the format from path's extension. */
limn_status mpi_write_mesh(limn_context *ctx, MPI_Comm comm, const char *path,
                           const limn_write_options *options, const size_t *vtxdist,
                           size_t n_owned, const uint32_t *owned_ids, const double *pos,
                           size_t face_begin, size_t face_count, const uint32_t *face_offsets,
                           const uint32_t *face_indices);

#endif
