/* SPDX-License-Identifier: MIT */
/* Three-component double vectors stored as three consecutive doubles. */
#ifndef LIMN_VEC3_H
#define LIMN_VEC3_H

static inline double vec3_dot(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

#endif
