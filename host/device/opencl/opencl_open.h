/* SPDX-License-Identifier: MIT */
/* How the backend choice (device/choice/choice.c) opens the OpenCL backend;
   spec: "P.D", a name, or NULL for the first usable device. */
#ifndef LIMN_DEVICE_OPENCL_OPEN_H
#define LIMN_DEVICE_OPENCL_OPEN_H

#include "limn.h"

struct device;

limn_status device_open_opencl(limn_context *ctx, const char *spec, struct device **out);

#endif
