/* SPDX-License-Identifier: MIT */
/*
 * limn denoise's default: the polynomial p(A) = E + sum_{i=1..N} d_i (E - A)^i
 * of degree N (N stencil products) whose coefficients minimise Stein's
 * unbiased estimate of the squared error to the unknown clean mesh (SURE,
 * Stein 1981), with the noise's deviation estimated from the mesh itself.
 */
#ifndef LIMN_SERIES_SURE_H
#define LIMN_SERIES_SURE_H

#include "series/series.h"

/* The noise deviation: the median over vertices and coordinates of
   |((E - A) y)_v| / |row v of E - A|_2, over 0.6745 (a Gaussian's median
   absolute value); r1 = (E - A) y, 3 doubles per vertex. */
double sure_sigma(const stencil_csr *a, const double *r1, size_t n);

/* sigma, lowered where the vectors r_i = B^{i+1} y (r + i*n3) hold less
   energy than noise of that deviation would put there alone:
   |B^k n|^2 ~ 3 sigma^2 tr(B^{2k}) (t[2k-1], from sure_traces up to 2N), so
   sigma^2 <= |r_{k}|^2 / (3 t[2k-1]) for every k. A clean mesh's curvature
   raises the median estimate; its smooth bands expose it. */
double sure_sigma_cap(const double *r, size_t n3, int degree, const double *t, double sigma);

/* Estimates of tr((E - A)^i), i = 1..N, into t[0..N-1]: n times the i-th
   moment of the regular lattice's symbol of the scheme, scaled so that the
   first is the exact trace. */
void sure_traces(const stencil_csr *a, limn_scheme scheme, int degree, double *t);

/* d solving (R^T R) d = rhs for the columns r_i = r + i*n3, i < degree (QR
   by modified Gram-Schmidt, twice; d_i = 0 where r_i lies in the span of the
   earlier ones). LIMN_ERR_MEMORY on allocation failure. */
limn_status sure_least_squares(limn_context *ctx, const double *r, size_t n3, int degree,
                               const double *rhs, double *d);

/* d[0..N-1] minimising |sum_i d_i r_i|^2 + 6 sigma^2 sum_i d_i t_i (SURE up to
   a constant) for r_i = r + i*3n, i = 0..N-1 (the vectors (E - A)^{i+1} y);
   0 where a vector adds nothing new. LIMN_ERR_MEMORY on allocation failure. */
limn_status sure_coefficients(limn_context *ctx, const double *r, size_t n3, int degree,
                              double sigma, const double *t, double *d);

/* The filter on an open run (4 work vectors): N products, the vectors read
   back, the coefficients fitted, the result on the host; *sigma (may be NULL)
   gets the estimate, *products counts the products. */
limn_status sure_denoise_run(limn_context *ctx, series_run *s, const limn_mesh *mesh,
                             int degree, limn_mesh **out, double *sigma, long long *products);

#endif
