/* SPDX-License-Identifier: MIT */
#ifndef LIMN_OPENCL_SELECT_H
#define LIMN_OPENCL_SELECT_H
#include "limn.h"
#include <CL/cl.h>

typedef struct opencl_choice {
    cl_platform_id platform;
    cl_device_id device;
    char name[256];
} opencl_choice;

/* spec: NULL/"" (environment, then first), "P.D", or a name substring. */
limn_status opencl_select_device(limn_context *ctx, const char *spec, opencl_choice *out);
#endif
