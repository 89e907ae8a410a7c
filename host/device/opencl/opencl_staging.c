/* SPDX-License-Identifier: MIT */
/* Large transfers through pinned staging memory (opencl_staging.h). */
#include "device/opencl/opencl_staging.h"
#include "base/context.h"
#include "base/parallel.h"

int opencl_staging_wanted(struct device *dev, size_t bytes)
{
    return !impl_of(dev)->host_unified && bytes > 0 &&
           (bytes >= OPENCL_STAGING_MIN || device_test_fault("small-staging"));
}

/* The staging buffer, made and mapped once; 0 when it cannot be (then the
   transfers go direct, as before). */
static int staging_ready(struct device *dev)
{
    opencl_impl *im = impl_of(dev);
    if (im->staging_host)
        return 1;
    if (im->staging_failed)
        return 0;
    cl_int err;
    size_t bytes = device_test_fault("small-staging") ? 4096 : OPENCL_STAGING_CHUNK;
    bytes = bytes < im->max_alloc ? bytes : im->max_alloc;
    im->staging = clCreateBuffer(im->context, CL_MEM_READ_WRITE | CL_MEM_ALLOC_HOST_PTR, bytes,
                                 NULL, &err);
    if (err == CL_SUCCESS)
        im->staging_host = clEnqueueMapBuffer(im->queue, im->staging, CL_TRUE,
                                              CL_MAP_READ | CL_MAP_WRITE, 0, bytes, 0, NULL,
                                              NULL, &err);
    if (err != CL_SUCCESS || !im->staging_host) {
        if (im->staging)
            clReleaseMemObject(im->staging);
        im->staging = NULL;
        im->staging_host = NULL;
        im->staging_failed = 1;
        return 0;
    }
    im->staging_bytes = bytes;
    return 1;
}

int opencl_staged_transfer(struct device *dev, cl_mem mem, size_t offset, size_t bytes,
                           const void *src, void *dst, limn_status *st)
{
    opencl_impl *im = impl_of(dev);
    if (!opencl_staging_wanted(dev, bytes) || !staging_ready(dev))
        return 0;
    *st = LIMN_OK;
    for (size_t at = 0; at < bytes; at += im->staging_bytes) {
        size_t n = bytes - at < im->staging_bytes ? bytes - at : im->staging_bytes;
        cl_int err;
        if (src) {
            parallel_copy(dev->ctx, im->staging_host, (const char *)src + at, n);
            err = clEnqueueWriteBuffer(im->queue, mem, CL_TRUE, offset + at, n,
                                       im->staging_host, 0, NULL, NULL);
        } else {
            err = clEnqueueReadBuffer(im->queue, mem, CL_TRUE, offset + at, n, im->staging_host,
                                      0, NULL, NULL);
            if (err == CL_SUCCESS)
                parallel_copy(dev->ctx, (char *)dst + at, im->staging_host, n);
        }
        if (err != CL_SUCCESS) {
            *st = ctx_fail(dev->ctx, LIMN_ERR_DEVICE, "%s failed: %s (%d)",
                           src ? "clEnqueueWriteBuffer" : "clEnqueueReadBuffer",
                           opencl_error_name(err), err);
            break;
        }
    }
    return 1;
}

void opencl_staging_release(opencl_impl *im)
{
    if (im->staging_host)
        clEnqueueUnmapMemObject(im->queue, im->staging, im->staging_host, 0, NULL, NULL);
    if (im->staging) {
        clFinish(im->queue);
        clReleaseMemObject(im->staging);
    }
    im->staging = NULL;
    im->staging_host = NULL;
}
