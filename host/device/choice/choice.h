/* SPDX-License-Identifier: MIT */
/* The context's device (choice.c): chosen, opened on first use. */
#ifndef LIMN_DEVICE_CHOICE_H
#define LIMN_DEVICE_CHOICE_H

#include "limn.h"

struct device;

/* Opens the device named by ctx->device_spec (or the environment). With a
   fallback allowed (limn_context_set_fallback, LIMN_FALLBACK=reference), an
   OpenCL device that cannot be opened gives way to the reference backend,
   with a warning. */
limn_status device_open(limn_context *ctx, struct device **out);
/* The context's device, opened on first use. */
limn_status device_get(limn_context *ctx, struct device **out);

#endif
