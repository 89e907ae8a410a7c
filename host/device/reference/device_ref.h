/* SPDX-License-Identifier: MIT */
/* Internals of the reference backend shared by device_ref.c,
   device_ref_mixed.c (the float operations of the mixed-precision solve) and
   device_ref_sgs.c (the SGS-preconditioned CG's sweeps). */
#ifndef LIMN_DEVICE_REF_H
#define LIMN_DEVICE_REF_H

#include "device/device.h"

struct device_buffer {
    size_t bytes;
    void *data;
};

/* The float family (device_ref_mixed.c) and the sweeps (device_ref_sgs.c). */
extern const device_mixed_ops ref_mixed_ops;
extern const device_sgs_ops ref_sgs_ops;

#endif
