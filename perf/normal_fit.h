/* SPDX-License-Identifier: MIT */
/*
 * The normal-error oracle of issue 16's bench: the coefficients d of
 * p = y + sum_i d_i c_i (columns c_i, 3 n values each) that minimise the mean
 * angle between p's face normals and the clean mesh's (Newell normals, as
 * limn_mesh_compare measures them), by BFGS from given starts. The angle is
 * not convex in d, so the result is the best local minimum found from those
 * starts: evidence of what the form can reach in normal error, not a bound.
 */
#ifndef LIMN_PERF_NORMAL_FIT_H
#define LIMN_PERF_NORMAL_FIT_H

#include "limn.h"

/* d (cols values) from the best of nstarts (at least 1) starts (starts: nstarts x cols)
   and then restarts more, each from the best so far moved at random (seeded:
   the same run gives the same d); returns the mean angle in degrees at d. */
double normal_fit(const limn_mesh *clean, const double *y, const double *c, size_t n3, int cols,
                  const double *starts, int nstarts, int restarts, double *d);

#endif
