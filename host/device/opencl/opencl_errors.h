/* SPDX-License-Identifier: MIT */
#ifndef LIMN_OPENCL_ERRORS_H
#define LIMN_OPENCL_ERRORS_H
#include <CL/cl.h>
const char *opencl_error_name(cl_int err);
#endif
