/* SPDX-License-Identifier: MIT */
/* The STREAM-like triad of limn_device_triad on an open device (triad.c). */
#ifndef LIMN_DEVICE_TRIAD_H
#define LIMN_DEVICE_TRIAD_H

#include "limn.h"

#include <stddef.h>

struct device;

/* The triad's inputs (exact in double, so a[i] = b[i] + s c[i] is exact on
   any device): b[i] = 1 + (i % 1024) / 2, c[i] = (i % 13) / 4, s = 3. */
#define TRIAD_SCALE 3.0
double triad_b(size_t i);
double triad_c(size_t i);

/* r->elements doubles per array (a multiple of 4) on dev: one untimed run,
   then `repeats` timed ones (r's seconds and gb_per_s), then a compared with
   b + s c on the host (r->mismatches). With a_out (r->elements doubles)
   the read-back a is copied there too (tests). */
limn_status device_triad(struct device *dev, int repeats, limn_triad_report *r, double *a_out);

#endif
