/* SPDX-License-Identifier: MIT */
#ifndef LIMN_OPENCL_POCL_CACHE_H
#define LIMN_OPENCL_POCL_CACHE_H
#include <stddef.h>
/* 1, with a sentence for the user in why, when PoCL's kernel cache directory
   cannot be written (creating it as PoCL would); 0 when it can. */
int opencl_pocl_cache_problem(char *why, size_t size);
#endif
