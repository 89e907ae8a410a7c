/* SPDX-License-Identifier: MIT */
/*
 * limn denoise's default: the polynomial p(A) = E + sum_{i=1..N} d_i (E - A)^i
 * of degree N (N stencil products) whose coefficients minimise Stein's
 * unbiased estimate of the squared error to the unknown clean mesh (SURE,
 * Stein 1981), with the noise's deviation estimated from the mesh itself:
 * one such polynomial for the part of each vector along the vertex normals
 * of A^k y (sure_split, sure_frame_positions) and one for the part across
 * them, from the same N products.
 */
#ifndef LIMN_SERIES_SURE_H
#define LIMN_SERIES_SURE_H

#include "series/series.h"

/* A global inner product: dot(user, x, y, n) over every process's part of
   the vectors (n: this process's length), the same sum on all of them (the
   MPI twins pass it rank to rank). NULL where one process holds the whole. */
typedef struct sure_sum {
    double (*dot)(void *user, const double *x, const double *y, size_t n);
    /* every process's status (the first failure's) after an allocation that
       precedes a dot: one that failed on one process alone would leave the
       others waiting in the dot */
    limn_status (*agree)(void *user, limn_status st);
    void *user;
} sure_sum;

/* s + sum_i x_i y_i, added in index order (the single process's dot from s). */
double sure_dot_from(double s, const double *x, const double *y, size_t n);

/* The noise deviation per coordinate: the smallest over k = 1..N of
   sqrt(|B^k y|^2 / (3 tr B^{2k})) (r + (k-1)*n3 = B^k y; t from sure_traces
   up to 2N, t[2k-1] = tr B^{2k}): noise alone puts |B^k n|^2 ~ 3 sigma^2
   tr B^{2k} there, the signal only adds, and at high k little of a smooth
   surface is left, so a clean mesh finds a small sigma. Energies, not
   medians: right for noise along the normals too (a median of coordinates
   is not). 0 when no trace is positive. sum: the inner product (NULL: this
   process's own). */
double sure_sigma(const double *r, size_t n3, int degree, const double *t, const sure_sum *sum);

/* Estimates of tr((E - A)^i), i = 1..degree, into t[0..degree-1]: n times the i-th
   moment of the regular lattice's symbol of the scheme, scaled so that the
   first is the exact trace. */
void sure_traces(const stencil_csr *a, limn_scheme scheme, int degree, double *t);
/* The same from tr(E - A) = tr1 over n rows (sure_traces sums
   sure_row_diagonal in row order: 1 - a_vv of row v). */
void sure_traces_from(double tr1, size_t n, limn_scheme scheme, int degree, double *t);
double sure_row_diagonal(const stencil_csr *a, size_t v);

/* d minimising |R d|^2 - 2 rhs . d for the columns r_i = r + i*n3, i < degree
   (QR by modified Gram-Schmidt, twice; d_i = 0 where r_i lies in the span of
   the earlier ones; the inner products sum's, NULL: this process's): mu_max =
   0 solves (R^T R) d = rhs; mu_max > 0 keeps the gain 1 + sum_i d_i mu^{i+1}
   in [0, 1] on a grid of mu in (0, mu_max] (no band amplified or turned
   over; the same on every rank, from the same R^T R and mu_max).
   LIMN_ERR_MEMORY on allocation failure. */
limn_status sure_least_squares(limn_context *ctx, const double *r, size_t n3, int degree,
                               const double *rhs, const sure_sum *sum, double mu_max, double *d);

/* A bound on the spectral radius of B = E - A (Gershgorin: the largest
   absolute row sum of B; over rows, so the max of the slices' bounds). */
double sure_spectrum_bound(const stencil_csr *a);

/* d[0..N-1] minimising |sum_i d_i r_i|^2 + 6 sigma^2 sum_i d_i t_i (SURE up to
   a constant) for r_i = r + i*3n, i = 0..N-1 (the vectors (E - A)^{i+1} y);
   0 where a vector adds nothing new; mu_max as in sure_least_squares.
   LIMN_ERR_MEMORY on allocation failure. */
limn_status sure_coefficients(limn_context *ctx, const double *r, size_t n3, int degree,
                              double sigma, const double *t, const sure_sum *sum, double mu_max,
                              double *d);

/* sure_sigma into *sigma, then sure_coefficients with it into d: the one
   polynomial (the default before sure_split; test_denoise_default measures
   the split against it). */
limn_status sure_fit(limn_context *ctx, const double *r, size_t n3, int degree, const double *t,
                     const sure_sum *sum, double mu_max, double *sigma, double *d);

/* out = y + sum_i d_i r_i (r_i = r + i*n3): the filter's result. */
void sure_combine(const double *y, const double *r, size_t n3, int degree, const double *d,
                  double *out);

/* The split's frame comes from A^k y, k = min(degree, SURE_FRAME_POWER): the
   smoothest vector the products give, combined from them with binomial
   coefficients (C(12, 6) = 924: rounding ~1e-13 of y, nothing for normals). */
enum { SURE_FRAME_POWER = 12 };

/* out = A^k y = (E - B)^k y from y and r_i = B^{i+1} y (r + i*n3), k as above. */
void sure_frame_positions(const double *y, const double *r, size_t n3, int degree, double *out);

/* Unit normals of mesh's vertices at positions x (3 per vertex) into nrm:
   the sum of their faces' Newell normals (area-weighted), added in face
   order; 0 for a vertex where that sum is 0. */
void sure_vertex_normals(const limn_mesh *mesh, const double *x, double *nrm);

/* The split fit, limn denoise's default: the vectors r_i = B^{i+1} y
   (r + i*n3, i < degree) written in the frame of the vertex normals nrm (3
   per vertex, unit or 0; the default takes those of sure_frame_positions): their normal parts s_i = n . r_i and their
   tangential parts r_i - s_i n, each fitted by SURE alone with its own
   noise estimate (sigma[0] from the s_i as one coordinate, sigma[1] from
   the tangential parts as two; sure_sigma's rule), both gains kept in
   [0, 1] up to mu_max. out = y + sum_i dn_i s_i n + sum_i dt_i (r_i - s_i n).
   Noise along the normals (a range scanner's) finds sigma[1] near 0 and
   leaves the vertices where they are along the surface; isotropic noise
   gets the fit each part's own signal asks for. Each part is fitted in
   place (its vectors become the QR's orthonormal ones, the combination taken
   through U d): r is overwritten, and the only copy made is the normal
   parts (N / 3 of r). LIMN_ERR_MEMORY on allocation failure. */
limn_status sure_split(limn_context *ctx, const double *y, double *r, size_t n3, int degree,
                       const double *t, const sure_sum *sum, double mu_max, const double *nrm,
                       double sigma[2], double *out);

/* The default filter on one process's whole vectors r (sure_vectors' or
   gathered; overwritten) of mesh, traces t (up to 2 degree): *sigma the
   isotropic noise estimate (sure_sigma), out (3 per vertex) the split's
   result in the frame of sure_frame_positions' normals. */
limn_status sure_filter(limn_context *ctx, const limn_mesh *mesh, double *r, int degree,
                        const double *t, double mu_max, double *sigma, double *out);

/* The filter on an open run (4 work vectors): N products, the vectors read
   back, the coefficients fitted, the result on the host; *sigma (may be NULL)
   gets the estimate, *products counts the products. */
limn_status sure_denoise_run(limn_context *ctx, series_run *s, const limn_mesh *mesh,
                             int degree, limn_mesh **out, double *sigma, long long *products);

#endif
