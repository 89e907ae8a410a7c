/* SPDX-License-Identifier: MIT */
/* The state of one parallel write (mpi_write.c: checks, moves, formatting;
   mpi_write_io.c: the temporary file, MPI-IO, the commit). Internal. */
#ifndef LIMN_MPI_WRITE_IO_H
#define LIMN_MPI_WRITE_IO_H

#include "mpi/mpi_write.h"

#include "base/atomic_file.h"
#include "base/growbuf.h"
#include "mesh/io/mesh_parts.h"

typedef struct mpi_writer {
    limn_context *ctx;
    MPI_Comm comm; /* a duplicate of the caller's */
    int rank, size;
    const char *path;
    const mpi_write_part *in;
    mesh_layout layout;
    size_t vbegin, vcount; /* this rank's vertex block */
    double *pos;           /* the block's positions (3 each) */
    uint8_t *colors;       /* the block's colours, or NULL */
    double *corners;       /* STL: positions of the vertices this rank's faces use */
    uint32_t *corner_idx;  /* STL: the faces' indices into corners */
    size_t n_corners;
    growbuf vbytes, fbytes; /* the formatted vertex block (rank 0: header first), faces */
    atomic_file af;         /* rank 0: the temporary file or the straight-through buffer */
    int streamed;           /* the target is no regular file: bytes through rank 0 */
    limn_output_set *stage; /* rank 0: the set that takes the finished file, or NULL */
    MPI_File fh;
    MPI_Comm file_comm; /* the file's (a duplicate of comm) */
} mpi_writer;

/* The lowest failing rank's status and message on every rank. */
limn_status mpi_writer_agree(mpi_writer *w, limn_status st);

/* Rank 0 opens the output (atomic_file_open), every rank the temporary file
   by MPI-IO; then the formatted bytes are written at their offsets (or sent
   to rank 0 for a straight-through output) and rank 0 commits (or hands the
   finished file to w->stage). Agreed at
   each step; on failure nothing is left. */
limn_status mpi_writer_output(mpi_writer *w);

#endif
