/* SPDX-License-Identifier: MIT */
/*
 * Feature-preserving denoising (limn_denoise_features, docs/series.md): the
 * face normals are filtered by a data-dependent face operator W, rebuilt from
 * the current normals before every product (bilateral weights: rows sum to
 * 1, weights >= 0), then the vertices move to fit the filtered normals (Sun
 * et al. 2007) with a tangential relaxation. The pieces here are plain
 * functions of the mesh so that tests can check W.
 */
#ifndef LIMN_SERIES_FEATURES_H
#define LIMN_SERIES_FEATURES_H

#include "device/device.h"
#include "stencil/stencil.h"

#include <stddef.h>
#include <stdint.h>

/* The faces of one polygon mesh: vertex -> faces, the face ring pattern and
   per-face geometry of the current positions. */
typedef struct feature_mesh {
    size_t vertices, faces;
    const uint32_t *offsets, *indices; /* the mesh's faces (not owned) */
    uint32_t *vf_offsets, *vf;         /* faces around each vertex */
    stencil_csr ring;                  /* W: row f, the faces sharing a vertex with f */
    double *normal, *area, *centroid;  /* 3, 1, 3 per face */
    double sigma_s;                    /* the spatial kernel's width */
    uint8_t *keep;                     /* per W nonzero, 0 where a crease cuts the pair;
                                          NULL: every pair kept (feature_cut_creases) */
    unsigned threads;                  /* host threads of the loops over faces, W's rows
                                          and vertices (each element on its own: the
                                          same bytes for any count) */
} feature_mesh;

limn_status feature_mesh_build(limn_context *ctx, const limn_mesh *mesh, feature_mesh *fm);
void feature_mesh_free(feature_mesh *fm);

/* Unit (Newell) normals, areas and centroids of the faces at positions x. */
void feature_faces_update(feature_mesh *fm, const double *x);
/* The mean distance between the centroids of ring neighbours. */
double feature_mean_spacing(const feature_mesh *fm);
/* sum plus the distances of rows [begin, end) to their neighbours, added
   in row and column order as feature_mean_spacing adds them; *count grows
   by their number (the MPI path carries sum from rank to rank). */
double feature_spacing_add(const feature_mesh *fm, size_t begin, size_t end, double sum,
                           size_t *count);
/* W's weights from the normals n (3 per face): a_j exp(-|c_i - c_j|^2 /
   2 sigma_s^2) exp(-|n_i - n_j|^2 / 2 sigma_r^2), 0 where fm->keep cuts the
   pair, each row divided by its sum (a row of zero weights keeps its own
   face). */
void feature_weights(feature_mesh *fm, const double *n, double sigma_r);
/* steps Jacobi sweeps of x_v += (1 / |F_v|) (sum_f n_f (n_f . (c_f - x_v))
   + tangential P_v sum_f (c_f - x_v)), P_v the projection onto the plane
   of the area-weighted mean of the n_f around v. */
/* What a caller spreading the faces over ranks does between the steps
   (NULL: nothing): after each product of W, the normals n; after each
   vertex sweep (and once before the first), the positions x; the noise
   histogram of rows [rows_begin, rows_end) (its block) summed over the
   ranks in place. Each gets the status so far and returns it agreed (all
   ranks call each in step). */
typedef struct feature_sync {
    limn_status (*normals)(void *user, limn_status st, double *n);
    limn_status (*positions)(void *user, limn_status st, double *x);
    limn_status (*counts)(void *user, limn_status st, uint64_t *bins, size_t n);
    size_t rows_begin, rows_end;
    void *user;
} feature_sync;
limn_status feature_fit_vertices(limn_context *ctx, feature_mesh *fm, const double *n, double *x,
                                 int steps, double tangential, const feature_sync *sync);

/* ---------------------------------------------------- feature_creases.c */

/* fm->keep (allocated on first use) from the normals n (3 per face): pair
   (f, j) of W kept iff f and j meet around a shared vertex without crossing
   an edge whose faces' normals have a dot product below cos_limit (f's own
   entry always kept, so every row keeps a weight). */
limn_status feature_cut_creases(limn_context *ctx, feature_mesh *fm, const double *n,
                                double cos_limit);

/* ------------------------------------------------------ feature_noise.c */

/* The noise left in the normals for the adaptive rounds: |n_f - n_j| over
   the ring pairs (j != f) counted in FEATURE_NOISE_BINS bins of [0, 2]. */
enum { FEATURE_NOISE_BINS = 4096 };
#define FEATURE_ADAPTIVE_GAIN 1.5
#define FEATURE_ADAPTIVE_FLOOR 0.05
/* Adds the pairs of rows [begin, end) (n: 3 per face) to bins. */
void feature_noise_count(const feature_mesh *fm, const double *n, size_t begin, size_t end,
                         uint64_t bins[FEATURE_NOISE_BINS]);
/* The median of the counted pairs, linear within its bin; 0 if none. */
double feature_noise_median(const uint64_t bins[FEATURE_NOISE_BINS]);
/* A later round's sigma_r from that median: FEATURE_ADAPTIVE_GAIN times
   it, at least FEATURE_ADAPTIVE_FLOOR. */
double feature_adaptive_sigma(double median);

/* ------------------------------------------------- denoise_features.c */

/* The checks of limn_denoise_features' options (fn: for messages). */
limn_status feature_check_options(limn_context *ctx, const char *fn,
                                  const limn_feature_options *o);
/* W and two face vectors (4 doubles a face) on the device, the host's
   staging copy. */
typedef struct feature_run {
    struct device *dev;
    device_csr w;
    device_buffer *in, *out;
    double *host;
    size_t faces;
} feature_run;
limn_status feature_run_open(limn_context *ctx, const feature_mesh *fm, feature_run *r);
void feature_run_close(feature_run *r);
/* The crease pass's first round (the later ones as the first pass's): few
   products with a wide range kernel, the cut keeping the creases
   (docs/series.md "The crease pass"). */
#define FEATURE_CREASE_PRODUCTS 3
#define FEATURE_CREASE_SIGMA_R 1.0
/* The whole filter on positions x (3 per vertex; fm's faces current at
   x): the rounds, then with a crease angle the rounds again from x's
   starting values with W cut at the creases of the first result. n (3 per
   face) ends with the last round's filtered normals. */
limn_status feature_passes(limn_context *ctx, feature_mesh *fm, feature_run *run,
                           const limn_feature_options *o, double *x, double *n,
                           limn_series_report *r, const feature_sync *sync);

#endif
