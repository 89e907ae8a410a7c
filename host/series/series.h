/* SPDX-License-Identifier: MIT */
/* Internal pieces of the series drivers (series.c), shared with texture.c. */
#ifndef LIMN_SERIES_H
#define LIMN_SERIES_H

#include "device/device.h"
#include "solve/operator.h"

#define SERIES_MAX_BUFFERS 6

/* One operator on the device with work vectors (4 doubles per vertex). */
typedef struct series_run {
    stencil_operator op;
    int open;
    struct device *dev;
    size_t n;
    device_buffer *buf[SERIES_MAX_BUFFERS];
    double *host;             /* 4 * n staging doubles */
    double t0;                /* when the operator was ready */
} series_run;

limn_status series_check_options(limn_context *ctx, const limn_series_options *o);
/* limn_morph's checks of frames, m, p (the last two for the series morph)
   and FROM, TO of one topology (fn names the call in messages). */
limn_status series_check_morph(limn_context *ctx, const char *fn, const limn_mesh *from,
                               const limn_mesh *to, const limn_morph_options *o);
/* The first part of it: frames, m, p (distributed meshes check the topology
   their own way). */
limn_status series_check_morph_counts(limn_context *ctx, const char *fn,
                                      const limn_morph_options *o);
/* limn_sharpen's checks of from, to and steps (fn names the call). */
limn_status series_check_sharpen(limn_context *ctx, const char *fn, int from, int to, int steps);
void series_report_init(limn_series_report *r, const limn_mesh *mesh);
void series_report_operator(limn_series_report *r, const stencil_operator *op);

/* Builds A for mesh and `buffers` zeroed device vectors; r may be NULL. */
limn_status series_open(limn_context *ctx, const limn_mesh *mesh, limn_scheme scheme,
                        double alpha, int buffers, series_run *s, limn_series_report *r);
void series_close(series_run *s);
/* 3 doubles per vertex <-> a device vector. */
limn_status series_upload(series_run *s, device_buffer *b, const double *xyz);
limn_status series_download(series_run *s, device_buffer *b, double *xyz);

/* Refuses a non-finite coordinate of a result, naming the vertex. */
limn_status series_check_finite(limn_context *ctx, const double *xyz, size_t n, const char *what);
/* denoise --keep-volume: scales out about the mean of its vertices to mesh's volume. */
limn_status series_keep_volume(limn_context *ctx, const limn_mesh *mesh, limn_mesh *out);
/* Fills a morph frame's measures (pos: 3 per vertex) and calls fn. */
limn_status series_emit_frame(const limn_mesh *from, const limn_mesh *to, int closed, double diag,
                              int index, const double *pos, limn_morph_frame_fn fn, void *user);

/* limn_texture's checks of its options (shared with the MPI layer's texture). */
limn_status texture_check_options(limn_context *ctx, const limn_texture_options *o);
/* The texture's colours: values[stride * v] (n of them) normalised by the
   field's range [mn, mx] (over the whole mesh) and mapped through the
   B-spline of o's colours, 3 bytes per vertex into rgb. */
limn_status texture_map_colors(limn_context *ctx, const limn_texture_options *o,
                               const double *values, size_t stride, size_t n, double mn,
                               double mx, uint8_t *rgb);

#endif
