/* SPDX-License-Identifier: MIT */
/*
 * The series filters written once (smooth, denoise, sharpen, morph) over an engine:
 * the single process (series.c) and MPI (mpi/mpi_series.c) each supply the
 * term (E - A)^i x and how vectors come in and out; the loops, the order of
 * the terms and the buffers' roles live here only, so both give the same
 * bits.
 */
#ifndef LIMN_SERIES_FILTER_H
#define LIMN_SERIES_FILTER_H

#include "device/device.h"

typedef struct series_engine series_engine;

/* What a side supplies (the single process in series.c, MPI in mpi_series.c). */
typedef struct series_engine_ops {
    /* One term: next = (E - A) x (SERIES_STORE_NEXT) and acc per mode; prior:
       the failure so far (only with carry). */
    limn_status (*term)(const series_engine *e, device_buffer *x, device_buffer *next,
                        device_buffer *acc, int flags, int mode, limn_status prior);
    limn_status (*axpby)(const series_engine *e, double a, device_buffer *x, double b,
                         device_buffer *y, device_buffer *out);
    /* The root's 3 doubles per vertex <-> a work vector (xyz read or written on the root). */
    limn_status (*upload)(const series_engine *e, const double *xyz, device_buffer *b);
    limn_status (*download)(const series_engine *e, device_buffer *b, double *xyz);
    /* b as a copy of mesh on the root, refused when not finite (what: for messages). */
    limn_status (*result)(const series_engine *e, device_buffer *b, const limn_mesh *mesh,
                          const char *what, limn_mesh **out);
    /* The same status on every rank (the single process: st). */
    limn_status (*agree)(const series_engine *e, limn_status st);
} series_engine_ops;

struct series_engine {
    limn_context *ctx;
    void *user;                /* the series_run, or the distributed run */
    device_buffer **buf;       /* four work vectors */
    long long *products;       /* the report's product count */
    int root;                  /* this rank holds the meshes and results */
    int carry;                 /* collective: a failed term still runs the later ones
                                  (every rank keeps exchanging), the failure carried */
    const series_engine_ops *ops;
};

/* acc = sum_{i=0..m} (E - A)^i A x, m + 1 terms; ra, rb scratch (x kept). */
limn_status series_terms(const series_engine *e, device_buffer *x, device_buffer *acc,
                         device_buffer *ra, device_buffer *rb, int m);

/* The filters on a checked, open engine (mesh: the root's). */
limn_status series_smooth_run(const series_engine *e, const limn_mesh *mesh, int terms,
                              limn_mesh **out);
limn_status series_denoise_run(const series_engine *e, const limn_mesh *mesh, int m, int steps,
                               int keep_volume, limn_mesh **out);
/* steps sharpening steps T <- T + sum_{i=from..to-1} r_i + r_to (r_0 = T,
   r_{i+1} = (E - A) r_i), the result on the root. */
limn_status series_sharpen_run(const series_engine *e, const limn_mesh *mesh, int from, int to,
                               int steps, limn_mesh **out);
/* Frames 0 .. frames-1 of the series morph; q (root: 3 per vertex) holds
   FROM - TO on entry and is the frames' scratch. */
limn_status series_morph_run(const series_engine *e, const limn_mesh *from, const limn_mesh *to,
                             const limn_morph_options *o, int closed, double diag, double *q,
                             limn_morph_frame_fn fn, void *user);

#endif
