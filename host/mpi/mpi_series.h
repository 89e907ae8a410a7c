/* SPDX-License-Identifier: MIT */
/*
 * The distributed series core (mpi_series.c) shared by the root path
 * (limn_smooth_mpi etc.: the root holds the mesh, mpi_distribute) and the
 * distributed-mesh path (mpi_mesh_series.c: no rank holds the mesh, the
 * rows from mpi_local_build): the run's state, its four work vectors, and
 * the term, axpby and agreement of filter.c's engine on an mpi_part.
 * Internal to the MPI layer.
 */
#ifndef LIMN_MPI_SERIES_H
#define LIMN_MPI_SERIES_H

#include "mpi/mpi_part.h"
#include "series/filter.h"

typedef struct series_mpi {
    mpi_part p;
    device_buffer *buf[4];
    double *rows4;            /* owned and ghost rows, 4 doubles */
    double *xyz;              /* root path, root: 3 per input vertex */
    double *m4;               /* distributed-mesh path: the owned rows of M */
    const struct limn_mpi_mesh *mesh; /* distributed-mesh path: the input */
    struct limn_mpi_mesh **out;       /* distributed-mesh path: where the result goes */
    double t0;
} series_mpi;

/* Releases everything s holds and ends its part. */
void mpi_series_close(series_mpi *s);

/* After the rows are built on every rank (s->p filled): the scratch rows,
   the root's xyz (root_xyz: the root path), four device work vectors, the
   operator's part of r, the clock; agreed. */
limn_status mpi_series_buffers(series_mpi *s, int root_xyz, limn_series_report *r);

/* filter.c's term, axpby and agree on s = e->user (series_mpi). */
limn_status mpi_series_term(const series_engine *e, device_buffer *x, device_buffer *next,
                            device_buffer *acc, int flags, int mode, limn_status prior);
limn_status mpi_series_axpby(const series_engine *e, double a, device_buffer *x, double b,
                             device_buffer *y, device_buffer *out);
limn_status mpi_series_agree(const series_engine *e, limn_status st);

/* The bands of limn_bands on an open engine (buffers 0: M, uploaded from
   xyz_root; then remainders 1, 2 in turn; 3: the band): out gets band i in
   b for i = 0 .. count - 1, then the remainder (i = count). */
typedef limn_status (*mpi_band_fn)(const series_engine *e, device_buffer *b, int i, void *user);
limn_status mpi_series_bands(const series_engine *e, const double *xyz_root, int count,
                             mpi_band_fn out, void *user);

/* ------------------------------------------------------ mpi_mesh_series.c */

/* The start of a filter on a distributed mesh (limn_mpi_mesh_smooth etc.,
   after mpi_enter; st: the call's own checks): the checks, the rows
   (s->m4: the input's owned rows, uploaded by the engine's upload), four
   work vectors and the engine e (results into *out). Returns with
   s->p.comm MPI_COMM_NULL only when nothing could be agreed. */
limn_status mpi_mesh_series_open(limn_context *ctx, const char *fn,
                                 const struct limn_mpi_mesh *mesh, const limn_series_options *o,
                                 const limn_mpi_options *mpi, limn_status st,
                                 struct limn_mpi_mesh **out, series_mpi *s, series_engine *e,
                                 limn_series_report *r);
/* Its end: timing, statistics, *out dropped on failure, s released. */
limn_status mpi_mesh_series_close(series_mpi *s, limn_status st, limn_mpi_result *result,
                                  limn_series_report *r);

#endif
