/* SPDX-License-Identifier: MIT */
/* The OpenCL backend: context, queue, buffers, launches and the
   double-precision operations (the program: opencl_program.c; the float
   operations: device_opencl_mixed.c). */
#include "base/context.h"
#include "device/opencl/device_opencl.h"
#include "device/opencl/opencl_select.h"
#include "base/clock.h"
#include "device/opencl/opencl_open.h"
#include "device/opencl/opencl_staging.h"
#include "base/large_alloc.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A buffer of `bytes` with `flags`; host is the pointer clCreateBuffer takes
   (NULL for none); a buffer without one is zero-filled when `zero`. */
static limn_status make_buffer(struct device *dev, size_t bytes, cl_mem_flags flags,
                               const void *host, int zero, device_buffer **out)
{
    opencl_impl *im = impl_of(dev);
    dev->ctx->device_failed = 1; /* cleared again on success */
    if (bytes > im->max_alloc)
        return ctx_fail(dev->ctx, LIMN_ERR_MEMORY,
                         "a %.1f MiB buffer exceeds the device's limit of %.1f MiB per buffer "
                         "(CL_DEVICE_MAX_MEM_ALLOC_SIZE; for PoCL raise POCL_MEMORY_LIMIT) — "
                         "the mesh is too large for this device",
                         (double)bytes / (1 << 20), (double)im->max_alloc / (1 << 20));
    device_buffer *b = calloc(1, sizeof *b);
    if (!b)
        return ctx_fail(dev->ctx, LIMN_ERR_MEMORY, "out of host memory");
    cl_int err;
    size_t n = bytes ? bytes : 16;
    b->mem = clCreateBuffer(im->context, flags, n, (void *)host, &err);
    if (err == CL_SUCCESS && !host && zero) {
        /* PoCL does not zero new buffers; start from a defined state. Not
           waited for: measured, waiting here (clFinish or a blocking read)
           made a 1.4-2.1M-vertex float solve 50-70 ms slower. */
        static const unsigned char zero = 0;
        err = clEnqueueFillBuffer(im->queue, b->mem, &zero, 1, 0, n, 0, NULL, NULL);
    }
    if (err == CL_SUCCESS && device_test_fault("alloc"))
        err = CL_MEM_OBJECT_ALLOCATION_FAILURE; /* test-only (device.h) */
    if (err != CL_SUCCESS) {
        if (b->mem)
            clReleaseMemObject(b->mem);
        free(b);
        int memory = err == CL_MEM_OBJECT_ALLOCATION_FAILURE || err == CL_OUT_OF_RESOURCES ||
                     err == CL_OUT_OF_HOST_MEMORY;
        return ctx_fail(dev->ctx, memory ? LIMN_ERR_MEMORY : LIMN_ERR_DEVICE,
                         "clCreateBuffer of %zu bytes on %s failed: %s%s", bytes, dev->name,
                         opencl_error_name(err),
                         memory ? ": the device is out of memory; use a device with more "
                                  "(--device, see 'limn devices'), a smaller mesh, or --device "
                                  "reference (or allow --fallback reference)"
                                : "");
    }
    dev->ctx->device_failed = 0;
    b->bytes = bytes;
    *out = b;
    return LIMN_OK;
}

static limn_status transfer(struct device *dev, device_buffer *buf, size_t offset, size_t bytes,
                            const void *src, void *dst, int skip_empty);
static void cl_buffer_release(struct device *dev, device_buffer *buf);

static limn_status cl_buffer_create(struct device *dev, size_t bytes, const void *init,
                                    device_buffer **out)
{
    int copy = init && bytes;
    if (copy && opencl_staging_wanted(dev, bytes)) {
        /* a discrete device: written through the pinned staging memory,
           not copied from the caller's (pageable) memory by the driver */
        limn_status st = make_buffer(dev, bytes, CL_MEM_READ_WRITE, NULL, 0, out);
        if (!st && (st = transfer(dev, *out, 0, bytes, init, NULL, 0))) {
            cl_buffer_release(dev, *out);
            *out = NULL;
        }
        return st;
    }
    return make_buffer(dev, bytes, CL_MEM_READ_WRITE | (copy ? CL_MEM_COPY_HOST_PTR : 0),
                       copy ? init : NULL, 1, out);
}

/* Scratch for the kernels alone. A device sharing host memory gets large
   scratch in host memory of limn's own (device_host_alloc: page-aligned and
   advised for huge pages, whose first touch by the kernels is several times
   cheaper than the runtime's 4 KiB pages), used in place and freed with
   the buffer. */
static limn_status cl_buffer_scratch(struct device *dev, size_t bytes, device_buffer **out)
{
    if (!impl_of(dev)->host_unified || bytes < LARGE_ALLOC_HUGE)
        return make_buffer(dev, bytes, CL_MEM_READ_WRITE, NULL, 0, out);
    void *host = device_host_alloc(bytes);
    if (!host)
        return ctx_fail(dev->ctx, LIMN_ERR_MEMORY, "out of host memory for a %.1f MiB buffer",
                        (double)bytes / (1 << 20));
    limn_status st =
        make_buffer(dev, bytes, CL_MEM_READ_WRITE | CL_MEM_USE_HOST_PTR, host, 0, out);
    if (st) {
        free(host);
        return st;
    }
    (*out)->shared = 1;
    (*out)->host = host;
    (*out)->owns_host = 1;
    return LIMN_OK;
}

/* In place on a device sharing host memory (PoCL's CPU device then neither
   allocates nor copies: measured, the 2.1M-vertex table's 190 MB); a copy on
   a discrete one. */
static limn_status cl_buffer_share(struct device *dev, size_t bytes, const void *host,
                                   device_buffer **out)
{
    if (!bytes || !impl_of(dev)->host_unified)
        return cl_buffer_create(dev, bytes, host, out);
    limn_status st =
        make_buffer(dev, bytes, CL_MEM_READ_WRITE | CL_MEM_USE_HOST_PTR, host, 0, out);
    if (!st) {
        (*out)->shared = 1;
        (*out)->host = (void *)host;
    }
    return st;
}

/* A read of a shared buffer into its own host memory: a map, which waits for
   the kernels and makes that memory current (PoCL's CPU device: no copy). */
static limn_status read_in_place(struct device *dev, device_buffer *buf, size_t offset,
                                 size_t bytes, void *dst)
{
    cl_int err;
    cl_command_queue q = impl_of(dev)->queue;
    void *mapped = clEnqueueMapBuffer(q, buf->mem, CL_TRUE, CL_MAP_READ, offset, bytes, 0, NULL,
                                      NULL, &err);
    CHECK(err, "clEnqueueMapBuffer");
    if (mapped != dst)
        memcpy(dst, mapped, bytes); /* a runtime that mapped a copy */
    CHECK(clEnqueueUnmapMemObject(q, buf->mem, mapped, 0, NULL, NULL), "clEnqueueUnmapMemObject");
    CHECK(clFinish(q), "clFinish");
    return LIMN_OK;
}

/* One blocking transfer between buf's bytes [offset, offset + bytes) and the
   host: from src when it is given (a write), else to dst. The _at forms skip
   an empty transfer; the whole-buffer forms enqueue it, as they always have. */
static limn_status transfer(struct device *dev, device_buffer *buf, size_t offset, size_t bytes,
                            const void *src, void *dst, int skip_empty)
{
    if (offset > buf->bytes || bytes > buf->bytes - offset)
        return ctx_fail(dev->ctx, LIMN_ERR_ARGUMENT, "buffer %s past its end",
                         src ? "write" : "read");
    if (!bytes && skip_empty)
        return LIMN_OK;
    if (!src && buf->shared && bytes && dst == (char *)buf->host + offset)
        return read_in_place(dev, buf, offset, bytes, dst);
    limn_status staged;
    if (!buf->shared && opencl_staged_transfer(dev, buf->mem, offset, bytes, src, dst, &staged))
        return staged;
    cl_command_queue q = impl_of(dev)->queue;
    if (src)
        CHECK(clEnqueueWriteBuffer(q, buf->mem, CL_TRUE, offset, bytes, src, 0, NULL, NULL),
              "clEnqueueWriteBuffer");
    else
        CHECK(clEnqueueReadBuffer(q, buf->mem, CL_TRUE, offset, bytes, dst, 0, NULL, NULL),
              "clEnqueueReadBuffer");
    return LIMN_OK;
}

static limn_status cl_buffer_write(struct device *dev, device_buffer *buf, size_t bytes,
                                   const void *src)
{
    return transfer(dev, buf, 0, bytes, src, NULL, 0);
}

static limn_status cl_buffer_read(struct device *dev, device_buffer *buf, size_t bytes,
                                  void *dst)
{
    return transfer(dev, buf, 0, bytes, NULL, dst, 0);
}

static limn_status cl_buffer_write_at(struct device *dev, device_buffer *buf,
                                      size_t offset, size_t bytes, const void *src)
{
    return transfer(dev, buf, offset, bytes, src, NULL, 1);
}

static limn_status cl_buffer_read_at(struct device *dev, device_buffer *buf, size_t offset,
                                     size_t bytes, void *dst)
{
    return transfer(dev, buf, offset, bytes, NULL, dst, 1);
}

static void cl_buffer_release(struct device *dev, device_buffer *buf)
{
    /* a kernel still queued (say, after a failed launch's report) may read the
       caller's memory, which is freed once this returns */
    if (buf && buf->shared)
        clFinish(impl_of(dev)->queue);
    if (buf) {
        clReleaseMemObject(buf->mem);
        if (buf->owns_host)
            free(buf->host);
        free(buf);
    }
}

limn_status opencl_bind(struct device *dev, cl_kernel k, cl_uint first, const opencl_arg *args,
                        size_t count)
{
    for (size_t i = 0; i < count; i++) {
        cl_int err = clSetKernelArg(k, first + (cl_uint)i, args[i].size, args[i].value);
        if (err != CL_SUCCESS)
            return ctx_fail(dev->ctx, LIMN_ERR_DEVICE, "clSetKernelArg(%s) failed: %s (%d)",
                            args[i].name, opencl_error_name(err), err);
    }
    return LIMN_OK;
}

limn_status opencl_set_csr_args(struct device *dev, cl_kernel k, const device_csr *a,
                                device_buffer *weights)
{
    cl_uint rows = (cl_uint)(a->row_begin + a->rows); /* kernels stop at the range's end */
    opencl_arg args[] = {OPENCL_VALUE(rows, "rows"), OPENCL_MEM(a->row_offsets, "offsets"),
                         OPENCL_MEM(a->columns, "columns"), OPENCL_MEM(weights, "weights")};
    return opencl_bind(dev, k, 0, args, 4);
}

/* PoCL compiles a kernel's work-group function on its first launch (~55 ms
   with a cold cache, nothing with a warm one). A launch over no rows first
   triggers that compile alone, so it is timed as set-up (dev->setup.kernels)
   rather than hidden in the first step; the kernels do nothing for rows = 0. */
static limn_status compile_on_first_launch(struct device *dev, opencl_kernel_id id,
                                           size_t rows_arg)
{
    opencl_impl *im = impl_of(dev);
    if (im->compiled[id])
        return LIMN_OK;
    double t0 = clock_seconds();
    cl_kernel k = im->kernels[id];
    cl_uint none = 0, all = (cl_uint)rows_arg; /* argument 0 restored after */
    size_t size = im->shape.group;
    CHECK(clSetKernelArg(k, 0, sizeof none, &none), "clSetKernelArg(rows)");
    cl_int err = clEnqueueNDRangeKernel(im->queue, k, 1, NULL, &size, &size, 0, NULL, NULL);
    if (err == CL_SUCCESS)
        err = clFinish(im->queue);
    CHECK(clSetKernelArg(k, 0, sizeof all, &all), "clSetKernelArg(rows)");
    if (err != CL_SUCCESS)
        return LIMN_OK; /* the real launch reports it, with advice */
    im->compiled[id] = 1;
    dev->setup.kernels += clock_seconds() - t0;
    return LIMN_OK;
}

/* A row range starting at row first_item * rows_per_item uses the global
   work offset, so the kernels need no argument for it (device_csr.row_begin). */
limn_status opencl_launch(struct device *dev, opencl_kernel_id id, size_t first_item,
                          size_t rows)
{
    if (rows == 0)
        return LIMN_OK;
    const opencl_shape *shape = &impl_of(dev)->shape;
    limn_status st = compile_on_first_launch(dev, id, first_item * shape->rows_per_item + rows);
    if (st)
        return st;
    size_t global = opencl_shape_items(shape, rows), local = shape->group, offset = first_item;
    cl_int err = clEnqueueNDRangeKernel(impl_of(dev)->queue, impl_of(dev)->kernels[id], 1,
                                        first_item ? &offset : NULL, &global, &local, 0, NULL,
                                        NULL);
    if (err == CL_SUCCESS && device_test_fault("enqueue"))
        err = CL_OUT_OF_RESOURCES; /* test-only (device.h) */
    if (err != CL_SUCCESS)
        return ctx_fail(dev->ctx, LIMN_ERR_DEVICE,
                         "launching kernel %s on %s failed: %s (%d): the device could not run "
                         "it; try another device (--device, see 'limn devices') or --device "
                         "reference (or allow --fallback reference)",
                         opencl_kernel_name(id), dev->name, opencl_error_name(err), err);
    return LIMN_OK;
}

static limn_status cl_spmv(struct device *dev, const device_csr *a, device_buffer *x,
                           device_buffer *y)
{
    cl_kernel k = impl_of(dev)->kernels[K_SPMV];
    limn_status st = opencl_set_csr_args(dev, k, a, a->weights);
    if (st)
        return st;
    opencl_arg args[] = {OPENCL_MEM(x, "x"), OPENCL_MEM(y, "y")};
    st = opencl_bind(dev, k, 4, args, 2);
    return st ? st : opencl_launch(dev, K_SPMV, opencl_first_item(dev, a), a->rows);
}

limn_status opencl_ensure_partials(struct device *dev, size_t first_slot, size_t rows)
{
    opencl_impl *im = impl_of(dev);
    size_t items = first_slot + opencl_shape_slots(&im->shape, rows) + 1;
    if (items <= im->partials_items)
        return LIMN_OK;
    if (im->partials)
        clReleaseMemObject(im->partials);
    im->partials = NULL;
    free(im->host_partials);
    im->partials_items = 0;
    im->host_partials = malloc(items * 3 * sizeof(double));
    if (!im->host_partials)
        return ctx_fail(dev->ctx, LIMN_ERR_MEMORY, "out of memory for reductions");
    cl_int err;
    im->partials = clCreateBuffer(im->context, CL_MEM_READ_WRITE, items * 3 * sizeof(double),
                                  NULL, &err);
    CHECK(err, "clCreateBuffer(partials)");
    im->partials_items = items;
    return LIMN_OK;
}

limn_status opencl_reduce(struct device *dev, opencl_kernel_id id, const device_csr *a,
                          device_buffer *weights, const opencl_arg *args, size_t count,
                          device_norms *out)
{
    cl_kernel k = impl_of(dev)->kernels[id];
    size_t slot = opencl_first_slot(dev, a);
    limn_status st = opencl_ensure_partials(dev, slot, a->rows);
    if (!st)
        st = opencl_set_csr_args(dev, k, a, weights);
    if (!st)
        st = opencl_bind(dev, k, 4, args, count);
    if (!st)
        st = opencl_launch(dev, id, opencl_first_item(dev, a), a->rows);
    return st ? st : opencl_finish_partials(dev, slot, a->rows, out);
}

limn_status opencl_reduce_rows(struct device *dev, opencl_kernel_id id, size_t rows,
                               const opencl_arg *args, size_t count, device_norms *out)
{
    limn_status st = opencl_ensure_partials(dev, 0, rows);
    if (!st)
        st = opencl_bind(dev, impl_of(dev)->kernels[id], 0, args, count);
    if (!st)
        st = opencl_launch(dev, id, 0, rows);
    return st ? st : opencl_finish_partials(dev, 0, rows, out);
}

limn_status opencl_finish_partials(struct device *dev, size_t first_slot, size_t rows,
                                   device_norms *out)
{
    opencl_impl *im = impl_of(dev);
    size_t chunks = opencl_shape_chunks(&im->shape, rows);
    if (chunks)
        CHECK(clEnqueueReadBuffer(im->queue, im->partials, CL_TRUE,
                                  first_slot * 3 * sizeof(double), chunks * 3 * sizeof(double),
                                  im->host_partials, 0, NULL, NULL),
              "reading the reduction partials");
    device_norms_finish(im->host_partials, chunks, out);
    return LIMN_OK;
}

static limn_status cl_interp_step(struct device *dev, const device_csr *a,
                                  device_buffer *m, device_buffer *p, device_buffer *p_next,
                                  double omega, device_norms *norms)
{
    opencl_impl *im = impl_of(dev);
    cl_uint ahead = (cl_uint)a->gather_ahead;
    opencl_arg args[] = {OPENCL_MEM(m, "m"), OPENCL_MEM(p, "p"), OPENCL_MEM(p_next, "p_next"),
                         OPENCL_VALUE(im->partials, "partials"), OPENCL_VALUE(omega, "omega"),
                         OPENCL_VALUE(ahead, "ahead")};
    return opencl_reduce(dev, K_INTERP_STEP, a, a->weights, args, 6, norms);
}

static limn_status cl_series_step(struct device *dev, const device_csr *a,
                                  device_buffer *x, device_buffer *x_next, device_buffer *ax,
                                  device_buffer *acc, int flags, int acc_mode,
                                  device_norms *norms)
{
    opencl_impl *im = impl_of(dev);
    /* buffers this launch does not use are bound to x and never touched */
    cl_mem xn = (flags & SERIES_STORE_NEXT) ? x_next->mem : x->mem;
    cl_mem axm = (flags & SERIES_STORE_AX) ? ax->mem : x->mem;
    cl_mem accm = acc_mode != SERIES_ACC_NONE ? acc->mem : x->mem;
    cl_int fl = flags, mode = acc_mode;
    opencl_arg args[] = {OPENCL_MEM(x, "x"),          OPENCL_VALUE(xn, "x_next"),
                         OPENCL_VALUE(axm, "ax"),      OPENCL_VALUE(accm, "acc"),
                         OPENCL_VALUE(fl, "flags"),    OPENCL_VALUE(mode, "acc_mode"),
                         OPENCL_VALUE(im->partials, "partials")};
    return opencl_reduce(dev, K_SERIES_STEP, a, a->weights, args, 7, norms);
}

static limn_status cl_axpby(struct device *dev, size_t rows, double a, device_buffer *x,
                            double b, device_buffer *y, device_buffer *out)
{
    cl_kernel k = impl_of(dev)->kernels[K_AXPBY];
    cl_uint r = (cl_uint)rows;
    opencl_arg args[] = {OPENCL_VALUE(r, "rows"), OPENCL_VALUE(a, "a"), OPENCL_MEM(x, "x"),
                         OPENCL_VALUE(b, "b"),    OPENCL_MEM(y, "y"),   OPENCL_MEM(out, "out")};
    limn_status st = opencl_bind(dev, k, 0, args, 6);
    return st ? st : opencl_launch(dev, K_AXPBY, 0, rows);
}

static limn_status cl_norms(struct device *dev, size_t rows, device_buffer *x,
                            device_norms *out)
{
    cl_uint r = (cl_uint)rows;
    opencl_arg args[] = {OPENCL_VALUE(r, "rows"), OPENCL_MEM(x, "x"),
                         OPENCL_VALUE(impl_of(dev)->partials, "partials")};
    return opencl_reduce_rows(dev, K_NORMS, rows, args, 3, out);
}

static limn_status cl_spmv_dot(struct device *dev, const device_csr *a, device_buffer *x,
                               device_buffer *y, device_buffer *dinv, double *dot)
{
    opencl_arg args[] = {OPENCL_MEM(x, "x"), OPENCL_MEM(y, "y"), OPENCL_MEM(dinv, "dinv"),
                         OPENCL_VALUE(impl_of(dev)->partials, "partials")};
    device_norms n;
    limn_status st = opencl_reduce(dev, K_SPMV_DOT, a, a->weights, args, 4, &n);
    if (!st)
        *dot = n.sum;
    return st;
}

static limn_status cl_cheb_step(struct device *dev, const device_csr *a,
                                device_buffer *m, device_buffer *p, device_buffer *prev_next,
                                double c1, double c2, device_norms *norms)
{
    opencl_impl *im = impl_of(dev);
    cl_uint ahead = (cl_uint)a->gather_ahead;
    opencl_arg args[] = {OPENCL_MEM(m, "m"),       OPENCL_MEM(p, "p"),
                         OPENCL_MEM(prev_next, "prev_next"),
                         OPENCL_VALUE(im->partials, "partials"),
                         OPENCL_VALUE(c1, "c1"),   OPENCL_VALUE(c2, "c2"),
                         OPENCL_VALUE(ahead, "ahead")};
    return opencl_reduce(dev, K_CHEB_STEP, a, a->weights, args, 7, norms);
}

static limn_status cl_pcg_update(struct device *dev, size_t rows, double alpha,
                                 device_buffer *p, device_buffer *q, device_buffer *x,
                                 device_buffer *z, device_buffer *dinv, device_norms *norms)
{
    opencl_impl *im = impl_of(dev);
    cl_uint r = (cl_uint)rows;
    opencl_arg args[] = {OPENCL_VALUE(r, "rows"), OPENCL_VALUE(alpha, "alpha"),
                         OPENCL_MEM(p, "p"),      OPENCL_MEM(q, "q"),
                         OPENCL_MEM(x, "x"),      OPENCL_MEM(z, "z"),
                         OPENCL_MEM(dinv, "dinv"), OPENCL_VALUE(im->partials, "partials")};
    return opencl_reduce_rows(dev, K_PCG_UPDATE, rows, args, 8, norms);
}

static void cl_close(struct device *dev)
{
    opencl_impl *im = impl_of(dev);
    if (im) {
        if (im->partials)
            clReleaseMemObject(im->partials);
        free(im->host_partials);
        opencl_staging_release(im);
        opencl_release_program(im);
        if (im->queue)
            clReleaseCommandQueue(im->queue);
        if (im->context)
            clReleaseContext(im->context);
        free(im);
    }
    free(dev);
}

static const device_stationary_ops opencl_stationary = {cl_interp_step, cl_cheb_step};
static const device_cg_ops opencl_cg = {cl_spmv_dot, cl_pcg_update};
static const device_series_ops opencl_series = {cl_series_step};

static const device_ops opencl_ops = {
    .kind = "opencl",
    .buffer_create = cl_buffer_create,
    .buffer_share = cl_buffer_share,
    .buffer_scratch = cl_buffer_scratch,
    .buffer_write = cl_buffer_write,
    .buffer_read = cl_buffer_read,
    .buffer_release = cl_buffer_release,
    .buffer_write_at = cl_buffer_write_at,
    .buffer_read_at = cl_buffer_read_at,
    .spmv = cl_spmv,
    .axpby = cl_axpby,
    .norms = cl_norms,
    .close = cl_close,
    .stationary = &opencl_stationary,
    .cg = &opencl_cg,
    .mixed = &cl_mixed_ops,
    .sgs = &cl_sgs_ops,
    .series = &opencl_series,
};

static limn_status open_device(struct device *dev, const char *spec)
{
    double t0 = clock_seconds();
    opencl_choice choice;
    limn_status st = opencl_select_device(dev->ctx, spec, &choice);
    if (st)
        return st;
    snprintf(dev->name, sizeof dev->name, "%s", choice.name);
    cl_device_fp_config fp64 = 0;
    clGetDeviceInfo(choice.device, CL_DEVICE_DOUBLE_FP_CONFIG, sizeof fp64, &fp64, NULL);
    if (!fp64)
        return ctx_fail(dev->ctx, LIMN_ERR_DEVICE,
                         "OpenCL device %s has no double precision, which limn needs; choose "
                         "another with --device (see 'limn devices') or use --device reference",
                         dev->name);
    opencl_impl *im = impl_of(dev);
    im->device = choice.device;
    CHECK(clGetDeviceInfo(choice.device, CL_DEVICE_MAX_MEM_ALLOC_SIZE, sizeof im->max_alloc,
                          &im->max_alloc, NULL),
          "clGetDeviceInfo(CL_DEVICE_MAX_MEM_ALLOC_SIZE)");
    if (clGetDeviceInfo(choice.device, CL_DEVICE_HOST_UNIFIED_MEMORY, sizeof im->host_unified,
                        &im->host_unified, NULL) != CL_SUCCESS)
        im->host_unified = CL_FALSE; /* then copies, as for a discrete device */
    dev->host_shared = im->host_unified == CL_TRUE;
    double t1 = clock_seconds();
    dev->setup.platform += t1 - t0;
    cl_int err;
    cl_context_properties props[] = {CL_CONTEXT_PLATFORM, (cl_context_properties)choice.platform,
                                     0};
    im->context = clCreateContext(props, 1, &choice.device, NULL, NULL, &err);
    CHECK(err, "clCreateContext");
    im->queue = clCreateCommandQueue(im->context, choice.device, 0, &err);
    CHECK(err, "clCreateCommandQueue");
    dev->setup.context += clock_seconds() - t1;
    return opencl_build_program(dev);
}

limn_status device_open_opencl(limn_context *ctx, const char *spec, struct device **out)
{
    struct device *dev = calloc(1, sizeof *dev);
    opencl_impl *im = calloc(1, sizeof *im);
    if (!dev || !im) {
        free(dev);
        free(im);
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory opening OpenCL");
    }
    dev->ops = &opencl_ops;
    dev->ctx = ctx;
    dev->impl = im;
    limn_status st = open_device(dev, spec);
    if (st) {
        cl_close(dev);
        return st;
    }
    *out = dev;
    return LIMN_OK;
}
