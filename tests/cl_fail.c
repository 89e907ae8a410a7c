/* SPDX-License-Identifier: MIT */
/* OpenCL calls failing on demand (cl_fail.h): the link-time wrappers. */
#include "cl_fail.h"

#include <CL/cl.h>

static _Atomic int armed;
static _Atomic long count, fail_at;

void cl_fail_arm(long k)
{
    count = 0;
    fail_at = k;
    armed = 1;
}

long cl_fail_disarm(void)
{
    armed = 0;
    return count;
}

static int fails_now(void)
{
    return armed && ++count == fail_at;
}

cl_mem __real_clCreateBuffer(cl_context c, cl_mem_flags f, size_t n, void *host, cl_int *err);
cl_mem __wrap_clCreateBuffer(cl_context c, cl_mem_flags f, size_t n, void *host, cl_int *err);
cl_mem __wrap_clCreateBuffer(cl_context c, cl_mem_flags f, size_t n, void *host, cl_int *err)
{
    if (fails_now()) {
        if (err)
            *err = CL_MEM_OBJECT_ALLOCATION_FAILURE;
        return NULL;
    }
    return __real_clCreateBuffer(c, f, n, host, err);
}

cl_int __real_clEnqueueNDRangeKernel(cl_command_queue q, cl_kernel k, cl_uint dim,
                                     const size_t *off, const size_t *global,
                                     const size_t *local, cl_uint nw, const cl_event *w,
                                     cl_event *e);
cl_int __wrap_clEnqueueNDRangeKernel(cl_command_queue q, cl_kernel k, cl_uint dim,
                                     const size_t *off, const size_t *global,
                                     const size_t *local, cl_uint nw, const cl_event *w,
                                     cl_event *e);
cl_int __wrap_clEnqueueNDRangeKernel(cl_command_queue q, cl_kernel k, cl_uint dim,
                                     const size_t *off, const size_t *global,
                                     const size_t *local, cl_uint nw, const cl_event *w,
                                     cl_event *e)
{
    return fails_now() ? CL_OUT_OF_RESOURCES
                       : __real_clEnqueueNDRangeKernel(q, k, dim, off, global, local, nw, w, e);
}

cl_int __real_clEnqueueReadBuffer(cl_command_queue q, cl_mem b, cl_bool block, size_t off,
                                  size_t n, void *p, cl_uint nw, const cl_event *w, cl_event *e);
cl_int __wrap_clEnqueueReadBuffer(cl_command_queue q, cl_mem b, cl_bool block, size_t off,
                                  size_t n, void *p, cl_uint nw, const cl_event *w, cl_event *e);
cl_int __wrap_clEnqueueReadBuffer(cl_command_queue q, cl_mem b, cl_bool block, size_t off,
                                  size_t n, void *p, cl_uint nw, const cl_event *w, cl_event *e)
{
    return fails_now() ? CL_OUT_OF_RESOURCES
                       : __real_clEnqueueReadBuffer(q, b, block, off, n, p, nw, w, e);
}

cl_int __real_clEnqueueWriteBuffer(cl_command_queue q, cl_mem b, cl_bool block, size_t off,
                                   size_t n, const void *p, cl_uint nw, const cl_event *w,
                                   cl_event *e);
cl_int __wrap_clEnqueueWriteBuffer(cl_command_queue q, cl_mem b, cl_bool block, size_t off,
                                   size_t n, const void *p, cl_uint nw, const cl_event *w,
                                   cl_event *e);
cl_int __wrap_clEnqueueWriteBuffer(cl_command_queue q, cl_mem b, cl_bool block, size_t off,
                                   size_t n, const void *p, cl_uint nw, const cl_event *w,
                                   cl_event *e)
{
    return fails_now() ? CL_OUT_OF_RESOURCES
                       : __real_clEnqueueWriteBuffer(q, b, block, off, n, p, nw, w, e);
}

void *__real_clEnqueueMapBuffer(cl_command_queue q, cl_mem b, cl_bool block, cl_map_flags f,
                                size_t off, size_t n, cl_uint nw, const cl_event *w, cl_event *e,
                                cl_int *err);
void *__wrap_clEnqueueMapBuffer(cl_command_queue q, cl_mem b, cl_bool block, cl_map_flags f,
                                size_t off, size_t n, cl_uint nw, const cl_event *w, cl_event *e,
                                cl_int *err);
void *__wrap_clEnqueueMapBuffer(cl_command_queue q, cl_mem b, cl_bool block, cl_map_flags f,
                                size_t off, size_t n, cl_uint nw, const cl_event *w, cl_event *e,
                                cl_int *err)
{
    if (fails_now()) {
        if (err)
            *err = CL_OUT_OF_RESOURCES;
        return NULL;
    }
    return __real_clEnqueueMapBuffer(q, b, block, f, off, n, nw, w, e, err);
}

cl_int __real_clEnqueueUnmapMemObject(cl_command_queue q, cl_mem b, void *p, cl_uint nw,
                                      const cl_event *w, cl_event *e);
cl_int __wrap_clEnqueueUnmapMemObject(cl_command_queue q, cl_mem b, void *p, cl_uint nw,
                                      const cl_event *w, cl_event *e);
cl_int __wrap_clEnqueueUnmapMemObject(cl_command_queue q, cl_mem b, void *p, cl_uint nw,
                                      const cl_event *w, cl_event *e)
{
    return fails_now() ? CL_OUT_OF_RESOURCES : __real_clEnqueueUnmapMemObject(q, b, p, nw, w, e);
}

cl_int __real_clEnqueueFillBuffer(cl_command_queue q, cl_mem b, const void *pat, size_t ps,
                                  size_t off, size_t n, cl_uint nw, const cl_event *w,
                                  cl_event *e);
cl_int __wrap_clEnqueueFillBuffer(cl_command_queue q, cl_mem b, const void *pat, size_t ps,
                                  size_t off, size_t n, cl_uint nw, const cl_event *w,
                                  cl_event *e);
cl_int __wrap_clEnqueueFillBuffer(cl_command_queue q, cl_mem b, const void *pat, size_t ps,
                                  size_t off, size_t n, cl_uint nw, const cl_event *w,
                                  cl_event *e)
{
    return fails_now() ? CL_OUT_OF_RESOURCES
                       : __real_clEnqueueFillBuffer(q, b, pat, ps, off, n, nw, w, e);
}

cl_int __real_clFinish(cl_command_queue q);
cl_int __wrap_clFinish(cl_command_queue q);
cl_int __wrap_clFinish(cl_command_queue q)
{
    return fails_now() ? CL_OUT_OF_RESOURCES : __real_clFinish(q);
}
