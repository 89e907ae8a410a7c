/* SPDX-License-Identifier: MIT */
/*
 * Large transfers to and from a discrete OpenCL device through pinned host
 * memory (opencl_staging.c): one CL_MEM_ALLOC_HOST_PTR buffer per device,
 * mapped for its whole life, that every large read and write goes through
 * in chunks, the copies between it and the caller's memory made over the
 * host threads. Measured on an NVIDIA H200 (docs/performance.md "Kernel
 * shapes"): a read or write from ordinary (pageable) memory moved ~1.3 GB/s.
 */
#ifndef LIMN_OPENCL_STAGING_H
#define LIMN_OPENCL_STAGING_H

#include "device/opencl/device_opencl.h"

/* Transfers that go direct: on a device sharing host memory, or this small.
   Test-only (device.h): LIMN_TEST_FAULT=small-staging stages every transfer
   in chunks of 4 KiB (how test_oclgrind covers the path on small meshes). */
#define OPENCL_STAGING_MIN ((size_t)1 << 20)
#define OPENCL_STAGING_CHUNK ((size_t)64 << 20)

/* Whether a transfer of `bytes` goes through the staging memory. */
int opencl_staging_wanted(struct device *dev, size_t bytes);

/* Writes src (a write) or reads into dst (a read) bytes at offset of mem
   through the staging memory, blocking. Returns 0 when it did not run (the
   device shares host memory, a small transfer, or no staging memory could be
   made): then the caller transfers directly. Otherwise 1, with *st the
   status (a failed OpenCL call, with its message). */
int opencl_staged_transfer(struct device *dev, cl_mem mem, size_t offset, size_t bytes,
                           const void *src, void *dst, limn_status *st);
/* Unmaps and releases the staging memory (cl_close). */
void opencl_staging_release(opencl_impl *im);

#endif
