/* The OpenCL backend: context, queue, the stencil program and its kernels. */
#include "context.h"
#include "device.h"
#include "opencl_errors.h"
#include "opencl_select.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

extern const unsigned char limn_kernel_stencil[];
extern const size_t limn_kernel_stencil_size;
extern const unsigned char limn_kernel_series[];
extern const size_t limn_kernel_series_size;
extern const unsigned char limn_kernel_solve[];
extern const size_t limn_kernel_solve_size;

struct device_buffer {
    cl_mem mem;
    size_t bytes;
};

typedef struct opencl_impl {
    cl_context context;
    cl_command_queue queue;
    cl_program program;
    cl_kernel spmv;
    cl_kernel interp_step;
    cl_kernel series_step, axpby, norms;
    cl_kernel spmv_dot, pcg_update, cheb_step;
    cl_ulong max_alloc;
    cl_mem partials;          /* 3 doubles per work-item, grown on demand */
    size_t partials_items;
    double *host_partials;
} opencl_impl;

#define CHECK(call, what)                                                                      \
    do {                                                                                       \
        cl_int err_ = (call);                                                                  \
        if (err_ != CL_SUCCESS)                                                                \
            return limn_fail(dev->ctx, LIMN_ERR_DEVICE, "%s failed: %s (%d)", what,            \
                             opencl_error_name(err_), err_);                                   \
    } while (0)

static opencl_impl *impl_of(struct limn_device *dev) { return dev->impl; }

static limn_status cl_buffer_create(struct limn_device *dev, size_t bytes, const void *init,
                                    device_buffer **out)
{
    opencl_impl *im = impl_of(dev);
    dev->ctx->device_failed = 1; /* cleared again on success */
    if (bytes > im->max_alloc)
        return limn_fail(dev->ctx, LIMN_ERR_MEMORY,
                         "a %.1f MiB buffer exceeds the device's limit of %.1f MiB per buffer "
                         "(CL_DEVICE_MAX_MEM_ALLOC_SIZE; for PoCL raise POCL_MEMORY_LIMIT) — "
                         "the mesh is too large for this device",
                         (double)bytes / (1 << 20), (double)im->max_alloc / (1 << 20));
    device_buffer *b = calloc(1, sizeof *b);
    if (!b)
        return limn_fail(dev->ctx, LIMN_ERR_MEMORY, "out of host memory");
    cl_int err;
    size_t n = bytes ? bytes : 16;
    cl_mem_flags flags = CL_MEM_READ_WRITE | (init && bytes ? CL_MEM_COPY_HOST_PTR : 0);
    b->mem = clCreateBuffer(im->context, flags, n, init && bytes ? (void *)init : NULL, &err);
    if (err == CL_SUCCESS && !init) {
        /* PoCL does not zero new buffers; start from a defined state. */
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
        return limn_fail(dev->ctx, memory ? LIMN_ERR_MEMORY : LIMN_ERR_DEVICE,
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

static limn_status cl_buffer_write(struct limn_device *dev, device_buffer *buf, size_t bytes,
                                   const void *src)
{
    if (bytes > buf->bytes)
        return limn_fail(dev->ctx, LIMN_ERR_ARGUMENT, "buffer write past its end");
    CHECK(clEnqueueWriteBuffer(impl_of(dev)->queue, buf->mem, CL_TRUE, 0, bytes, src, 0, NULL,
                               NULL),
          "clEnqueueWriteBuffer");
    return LIMN_OK;
}

static limn_status cl_buffer_read(struct limn_device *dev, device_buffer *buf, size_t bytes,
                                  void *dst)
{
    if (bytes > buf->bytes)
        return limn_fail(dev->ctx, LIMN_ERR_ARGUMENT, "buffer read past its end");
    CHECK(clEnqueueReadBuffer(impl_of(dev)->queue, buf->mem, CL_TRUE, 0, bytes, dst, 0, NULL,
                              NULL),
          "clEnqueueReadBuffer");
    return LIMN_OK;
}

static limn_status cl_buffer_write_at(struct limn_device *dev, device_buffer *buf,
                                      size_t offset, size_t bytes, const void *src)
{
    if (offset > buf->bytes || bytes > buf->bytes - offset)
        return limn_fail(dev->ctx, LIMN_ERR_ARGUMENT, "buffer write past its end");
    if (bytes)
        CHECK(clEnqueueWriteBuffer(impl_of(dev)->queue, buf->mem, CL_TRUE, offset, bytes, src, 0,
                                   NULL, NULL),
              "clEnqueueWriteBuffer");
    return LIMN_OK;
}

static limn_status cl_buffer_read_at(struct limn_device *dev, device_buffer *buf, size_t offset,
                                     size_t bytes, void *dst)
{
    if (offset > buf->bytes || bytes > buf->bytes - offset)
        return limn_fail(dev->ctx, LIMN_ERR_ARGUMENT, "buffer read past its end");
    if (bytes)
        CHECK(clEnqueueReadBuffer(impl_of(dev)->queue, buf->mem, CL_TRUE, offset, bytes, dst, 0,
                                  NULL, NULL),
              "clEnqueueReadBuffer");
    return LIMN_OK;
}

static void cl_buffer_release(struct limn_device *dev, device_buffer *buf)
{
    (void)dev;
    if (buf) {
        clReleaseMemObject(buf->mem);
        free(buf);
    }
}

static size_t work_items(size_t rows)
{
    size_t chunks = (rows + DEVICE_ROWS_PER_ITEM - 1) / DEVICE_ROWS_PER_ITEM;
    return (chunks + DEVICE_WORKGROUP - 1) / DEVICE_WORKGROUP * DEVICE_WORKGROUP;
}

static limn_status set_csr_args(struct limn_device *dev, cl_kernel k, const device_csr *a)
{
    cl_uint rows = (cl_uint)(a->row_begin + a->rows); /* kernels stop at the range's end */
    CHECK(clSetKernelArg(k, 0, sizeof rows, &rows), "clSetKernelArg(rows)");
    CHECK(clSetKernelArg(k, 1, sizeof(cl_mem), &a->row_offsets->mem), "clSetKernelArg(offsets)");
    CHECK(clSetKernelArg(k, 2, sizeof(cl_mem), &a->columns->mem), "clSetKernelArg(columns)");
    CHECK(clSetKernelArg(k, 3, sizeof(cl_mem), &a->weights->mem), "clSetKernelArg(weights)");
    return LIMN_OK;
}

/* Launches work-items first_item .. for `rows` rows: a row range starting at
   row first_item * DEVICE_ROWS_PER_ITEM uses the global work offset, so the
   kernels need no argument for it (device_csr.row_begin). */
static limn_status launch_at(struct limn_device *dev, cl_kernel k, size_t first_item,
                             size_t rows, const char *name)
{
    if (rows == 0)
        return LIMN_OK;
    size_t global = work_items(rows), local = DEVICE_WORKGROUP, offset = first_item;
    cl_int err = clEnqueueNDRangeKernel(impl_of(dev)->queue, k, 1, first_item ? &offset : NULL,
                                        &global, &local, 0, NULL, NULL);
    if (err == CL_SUCCESS && device_test_fault("enqueue"))
        err = CL_OUT_OF_RESOURCES; /* test-only (device.h) */
    if (err != CL_SUCCESS)
        return limn_fail(dev->ctx, LIMN_ERR_DEVICE,
                         "launching kernel %s on %s failed: %s (%d): the device could not run "
                         "it; try another device (--device, see 'limn devices') or --device "
                         "reference (or allow --fallback reference)",
                         name, dev->name, opencl_error_name(err), err);
    return LIMN_OK;
}

static limn_status launch(struct limn_device *dev, cl_kernel k, size_t rows, const char *name)
{
    return launch_at(dev, k, 0, rows, name);
}

static size_t first_item(const device_csr *a) { return a->row_begin / DEVICE_ROWS_PER_ITEM; }

/* Finishes the partials of `rows` rows written by items from `first`. */
static limn_status read_partials(struct limn_device *dev, size_t first, size_t rows,
                                 device_norms *out)
{
    opencl_impl *im = impl_of(dev);
    size_t chunks = (rows + DEVICE_ROWS_PER_ITEM - 1) / DEVICE_ROWS_PER_ITEM;
    if (chunks)
        CHECK(clEnqueueReadBuffer(im->queue, im->partials, CL_TRUE, first * 3 * sizeof(double),
                                  chunks * 3 * sizeof(double), im->host_partials, 0, NULL, NULL),
              "reading the reduction partials");
    device_norms_finish(im->host_partials, chunks, out);
    return LIMN_OK;
}

static limn_status cl_spmv(struct limn_device *dev, const device_csr *a, device_buffer *x,
                           device_buffer *y)
{
    cl_kernel k = impl_of(dev)->spmv;
    limn_status st = set_csr_args(dev, k, a);
    if (st)
        return st;
    CHECK(clSetKernelArg(k, 4, sizeof(cl_mem), &x->mem), "clSetKernelArg(x)");
    CHECK(clSetKernelArg(k, 5, sizeof(cl_mem), &y->mem), "clSetKernelArg(y)");
    return launch_at(dev, k, first_item(a), a->rows, "spmv");
}

static limn_status ensure_partials(struct limn_device *dev, size_t items)
{
    opencl_impl *im = impl_of(dev);
    if (items <= im->partials_items)
        return LIMN_OK;
    if (im->partials)
        clReleaseMemObject(im->partials);
    im->partials = NULL;
    free(im->host_partials);
    im->partials_items = 0;
    im->host_partials = malloc(items * 3 * sizeof(double));
    if (!im->host_partials)
        return limn_fail(dev->ctx, LIMN_ERR_MEMORY, "out of memory for reductions");
    cl_int err;
    im->partials = clCreateBuffer(im->context, CL_MEM_READ_WRITE, items * 3 * sizeof(double),
                                  NULL, &err);
    CHECK(err, "clCreateBuffer(partials)");
    im->partials_items = items;
    return LIMN_OK;
}

static limn_status cl_interp_step(struct limn_device *dev, const device_csr *a,
                                  device_buffer *m, device_buffer *p, device_buffer *p_next,
                                  double omega, device_norms *norms)
{
    opencl_impl *im = impl_of(dev);
    limn_status st = ensure_partials(dev, first_item(a) + work_items(a->rows) + 1);
    if (!st)
        st = set_csr_args(dev, im->interp_step, a);
    if (st)
        return st;
    cl_kernel k = im->interp_step;
    CHECK(clSetKernelArg(k, 4, sizeof(cl_mem), &m->mem), "clSetKernelArg(m)");
    CHECK(clSetKernelArg(k, 5, sizeof(cl_mem), &p->mem), "clSetKernelArg(p)");
    CHECK(clSetKernelArg(k, 6, sizeof(cl_mem), &p_next->mem), "clSetKernelArg(p_next)");
    CHECK(clSetKernelArg(k, 7, sizeof(cl_mem), &im->partials), "clSetKernelArg(partials)");
    CHECK(clSetKernelArg(k, 8, sizeof omega, &omega), "clSetKernelArg(omega)");
    st = launch_at(dev, k, first_item(a), a->rows, "interp_step");
    return st ? st : read_partials(dev, first_item(a), a->rows, norms);
}

static limn_status cl_series_step(struct limn_device *dev, const device_csr *a,
                                  device_buffer *x, device_buffer *x_next, device_buffer *ax,
                                  device_buffer *acc, int flags, int acc_mode,
                                  device_norms *norms)
{
    opencl_impl *im = impl_of(dev);
    limn_status st = ensure_partials(dev, first_item(a) + work_items(a->rows) + 1);
    if (!st)
        st = set_csr_args(dev, im->series_step, a);
    if (st)
        return st;
    cl_kernel k = im->series_step;
    /* buffers this launch does not use are bound to x and never touched */
    cl_mem xn = (flags & SERIES_STORE_NEXT) ? x_next->mem : x->mem;
    cl_mem axm = (flags & SERIES_STORE_AX) ? ax->mem : x->mem;
    cl_mem accm = acc_mode != SERIES_ACC_NONE ? acc->mem : x->mem;
    cl_int fl = flags, mode = acc_mode;
    CHECK(clSetKernelArg(k, 4, sizeof(cl_mem), &x->mem), "clSetKernelArg(x)");
    CHECK(clSetKernelArg(k, 5, sizeof(cl_mem), &xn), "clSetKernelArg(x_next)");
    CHECK(clSetKernelArg(k, 6, sizeof(cl_mem), &axm), "clSetKernelArg(ax)");
    CHECK(clSetKernelArg(k, 7, sizeof(cl_mem), &accm), "clSetKernelArg(acc)");
    CHECK(clSetKernelArg(k, 8, sizeof fl, &fl), "clSetKernelArg(flags)");
    CHECK(clSetKernelArg(k, 9, sizeof mode, &mode), "clSetKernelArg(acc_mode)");
    CHECK(clSetKernelArg(k, 10, sizeof(cl_mem), &im->partials), "clSetKernelArg(partials)");
    st = launch_at(dev, k, first_item(a), a->rows, "series_step");
    return st ? st : read_partials(dev, first_item(a), a->rows, norms);
}

static limn_status cl_axpby(struct limn_device *dev, size_t rows, double a, device_buffer *x,
                            double b, device_buffer *y, device_buffer *out)
{
    cl_kernel k = impl_of(dev)->axpby;
    cl_uint r = (cl_uint)rows;
    CHECK(clSetKernelArg(k, 0, sizeof r, &r), "clSetKernelArg(rows)");
    CHECK(clSetKernelArg(k, 1, sizeof a, &a), "clSetKernelArg(a)");
    CHECK(clSetKernelArg(k, 2, sizeof(cl_mem), &x->mem), "clSetKernelArg(x)");
    CHECK(clSetKernelArg(k, 3, sizeof b, &b), "clSetKernelArg(b)");
    CHECK(clSetKernelArg(k, 4, sizeof(cl_mem), &y->mem), "clSetKernelArg(y)");
    CHECK(clSetKernelArg(k, 5, sizeof(cl_mem), &out->mem), "clSetKernelArg(out)");
    return launch(dev, k, rows, "axpby");
}

static limn_status cl_norms(struct limn_device *dev, size_t rows, device_buffer *x,
                            device_norms *out)
{
    opencl_impl *im = impl_of(dev);
    size_t chunks = (rows + DEVICE_ROWS_PER_ITEM - 1) / DEVICE_ROWS_PER_ITEM;
    limn_status st = ensure_partials(dev, work_items(rows) ? work_items(rows) : 1);
    if (st)
        return st;
    cl_kernel k = im->norms;
    cl_uint r = (cl_uint)rows;
    CHECK(clSetKernelArg(k, 0, sizeof r, &r), "clSetKernelArg(rows)");
    CHECK(clSetKernelArg(k, 1, sizeof(cl_mem), &x->mem), "clSetKernelArg(x)");
    CHECK(clSetKernelArg(k, 2, sizeof(cl_mem), &im->partials), "clSetKernelArg(partials)");
    st = launch(dev, k, rows, "norms");
    if (st)
        return st;
    if (chunks)
        CHECK(clEnqueueReadBuffer(im->queue, im->partials, CL_TRUE, 0, chunks * 3 * sizeof(double),
                                  im->host_partials, 0, NULL, NULL),
              "reading the reduction partials");
    device_norms_finish(im->host_partials, chunks, out);
    return LIMN_OK;
}

/* Reads the first `items` partial triples and finishes them in order. */
static limn_status finish_partials(struct limn_device *dev, size_t rows, device_norms *out)
{
    opencl_impl *im = impl_of(dev);
    size_t chunks = (rows + DEVICE_ROWS_PER_ITEM - 1) / DEVICE_ROWS_PER_ITEM;
    if (chunks)
        CHECK(clEnqueueReadBuffer(im->queue, im->partials, CL_TRUE, 0, chunks * 3 * sizeof(double),
                                  im->host_partials, 0, NULL, NULL),
              "reading the reduction partials");
    device_norms_finish(im->host_partials, chunks, out);
    return LIMN_OK;
}

static limn_status cl_spmv_dot(struct limn_device *dev, const device_csr *a, device_buffer *x,
                               device_buffer *y, device_buffer *dinv, double *dot)
{
    opencl_impl *im = impl_of(dev);
    limn_status st = ensure_partials(dev, first_item(a) + work_items(a->rows) + 1);
    if (!st)
        st = set_csr_args(dev, im->spmv_dot, a);
    if (st)
        return st;
    cl_kernel k = im->spmv_dot;
    CHECK(clSetKernelArg(k, 4, sizeof(cl_mem), &x->mem), "clSetKernelArg(x)");
    CHECK(clSetKernelArg(k, 5, sizeof(cl_mem), &y->mem), "clSetKernelArg(y)");
    CHECK(clSetKernelArg(k, 6, sizeof(cl_mem), &dinv->mem), "clSetKernelArg(dinv)");
    CHECK(clSetKernelArg(k, 7, sizeof(cl_mem), &im->partials), "clSetKernelArg(partials)");
    st = launch_at(dev, k, first_item(a), a->rows, "spmv_dot");
    device_norms n;
    if (!st)
        st = read_partials(dev, first_item(a), a->rows, &n);
    if (!st)
        *dot = n.sum;
    return st;
}

static limn_status cl_cheb_step(struct limn_device *dev, const device_csr *a,
                                device_buffer *m, device_buffer *p, device_buffer *prev_next,
                                double c1, double c2, device_norms *norms)
{
    opencl_impl *im = impl_of(dev);
    limn_status st = ensure_partials(dev, first_item(a) + work_items(a->rows) + 1);
    if (!st)
        st = set_csr_args(dev, im->cheb_step, a);
    if (st)
        return st;
    cl_kernel k = im->cheb_step;
    CHECK(clSetKernelArg(k, 4, sizeof(cl_mem), &m->mem), "clSetKernelArg(m)");
    CHECK(clSetKernelArg(k, 5, sizeof(cl_mem), &p->mem), "clSetKernelArg(p)");
    CHECK(clSetKernelArg(k, 6, sizeof(cl_mem), &prev_next->mem), "clSetKernelArg(prev_next)");
    CHECK(clSetKernelArg(k, 7, sizeof(cl_mem), &im->partials), "clSetKernelArg(partials)");
    CHECK(clSetKernelArg(k, 8, sizeof c1, &c1), "clSetKernelArg(c1)");
    CHECK(clSetKernelArg(k, 9, sizeof c2, &c2), "clSetKernelArg(c2)");
    st = launch_at(dev, k, first_item(a), a->rows, "cheb_step");
    return st ? st : read_partials(dev, first_item(a), a->rows, norms);
}

static limn_status cl_pcg_update(struct limn_device *dev, size_t rows, double alpha,
                                 device_buffer *p, device_buffer *q, device_buffer *x,
                                 device_buffer *z, device_buffer *dinv, device_norms *norms)
{
    opencl_impl *im = impl_of(dev);
    limn_status st = ensure_partials(dev, work_items(rows) ? work_items(rows) : 1);
    if (st)
        return st;
    cl_kernel k = im->pcg_update;
    cl_uint r = (cl_uint)rows;
    CHECK(clSetKernelArg(k, 0, sizeof r, &r), "clSetKernelArg(rows)");
    CHECK(clSetKernelArg(k, 1, sizeof alpha, &alpha), "clSetKernelArg(alpha)");
    CHECK(clSetKernelArg(k, 2, sizeof(cl_mem), &p->mem), "clSetKernelArg(p)");
    CHECK(clSetKernelArg(k, 3, sizeof(cl_mem), &q->mem), "clSetKernelArg(q)");
    CHECK(clSetKernelArg(k, 4, sizeof(cl_mem), &x->mem), "clSetKernelArg(x)");
    CHECK(clSetKernelArg(k, 5, sizeof(cl_mem), &z->mem), "clSetKernelArg(z)");
    CHECK(clSetKernelArg(k, 6, sizeof(cl_mem), &dinv->mem), "clSetKernelArg(dinv)");
    CHECK(clSetKernelArg(k, 7, sizeof(cl_mem), &im->partials), "clSetKernelArg(partials)");
    st = launch(dev, k, rows, "pcg_update");
    if (!st)
        st = finish_partials(dev, rows, norms);
    return st;
}

static void cl_close(struct limn_device *dev)
{
    opencl_impl *im = impl_of(dev);
    if (im) {
        if (im->partials)
            clReleaseMemObject(im->partials);
        free(im->host_partials);
        if (im->spmv)
            clReleaseKernel(im->spmv);
        if (im->interp_step)
            clReleaseKernel(im->interp_step);
        if (im->series_step)
            clReleaseKernel(im->series_step);
        if (im->axpby)
            clReleaseKernel(im->axpby);
        if (im->norms)
            clReleaseKernel(im->norms);
        if (im->spmv_dot)
            clReleaseKernel(im->spmv_dot);
        if (im->pcg_update)
            clReleaseKernel(im->pcg_update);
        if (im->cheb_step)
            clReleaseKernel(im->cheb_step);
        if (im->program)
            clReleaseProgram(im->program);
        if (im->queue)
            clReleaseCommandQueue(im->queue);
        if (im->context)
            clReleaseContext(im->context);
        free(im);
    }
    free(dev);
}

static const device_ops opencl_ops = {
    .kind = "opencl",
    .buffer_create = cl_buffer_create,
    .buffer_write = cl_buffer_write,
    .buffer_read = cl_buffer_read,
    .buffer_release = cl_buffer_release,
    .buffer_write_at = cl_buffer_write_at,
    .buffer_read_at = cl_buffer_read_at,
    .spmv = cl_spmv,
    .interp_step = cl_interp_step,
    .spmv_dot = cl_spmv_dot,
    .pcg_update = cl_pcg_update,
    .cheb_step = cl_cheb_step,
    .series_step = cl_series_step,
    .axpby = cl_axpby,
    .norms = cl_norms,
    .close = cl_close,
};

/* Builds the stencil program; on failure the message carries the build log. */
static limn_status build_program(struct limn_device *dev, cl_device_id device)
{
    opencl_impl *im = impl_of(dev);
    /* one program: stencil.cl, then series.cl and solve.cl (which use its
       row_product) */
    const char *src[3] = {(const char *)limn_kernel_stencil, (const char *)limn_kernel_series,
                          (const char *)limn_kernel_solve};
    size_t len[3] = {limn_kernel_stencil_size, limn_kernel_series_size, limn_kernel_solve_size};
    cl_int err;
    im->program = clCreateProgramWithSource(im->context, 3, src, len, &err);
    CHECK(err, "clCreateProgramWithSource");
    char options[128];
    snprintf(options, sizeof options, "-D ROWS_PER_ITEM=%d", DEVICE_ROWS_PER_ITEM);
    if (device_test_fault("build")) /* test-only (device.h): a genuine compile error */
        snprintf(options, sizeof options, "-D ROWS_PER_ITEM=limn_test_fault_build");
    err = clBuildProgram(im->program, 1, &device, options, NULL, NULL);
    if (err != CL_SUCCESS) {
        char log[1500] = "";
        clGetProgramBuildInfo(im->program, device, CL_PROGRAM_BUILD_LOG, sizeof log - 1, log, NULL);
        log[sizeof log - 1] = '\0';
        if (!log[0])
            snprintf(log, sizeof log, "(empty: the driver gave none; PoCL prints its compiler's "
                                      "errors on stderr)");
        return limn_fail(dev->ctx, LIMN_ERR_DEVICE,
                         "building the OpenCL kernels for %s failed: %s: the device's OpenCL "
                         "compiler rejected them; choose another device with --device (see "
                         "'limn devices') or use --device reference (or allow --fallback "
                         "reference); for PoCL, check that its kernel cache (POCL_CACHE_DIR, "
                         "default ~/.cache/pocl) is writable\nbuild log:\n%s",
                         dev->name, opencl_error_name(err), log);
    }
    im->spmv = clCreateKernel(im->program, "spmv", &err);
    CHECK(err, "clCreateKernel(spmv)");
    im->interp_step = clCreateKernel(im->program, "interp_step", &err);
    CHECK(err, "clCreateKernel(interp_step)");
    im->series_step = clCreateKernel(im->program, "series_step", &err);
    CHECK(err, "clCreateKernel(series_step)");
    im->axpby = clCreateKernel(im->program, "axpby", &err);
    CHECK(err, "clCreateKernel(axpby)");
    im->norms = clCreateKernel(im->program, "norms", &err);
    CHECK(err, "clCreateKernel(norms)");
    im->spmv_dot = clCreateKernel(im->program, "spmv_dot", &err);
    CHECK(err, "clCreateKernel(spmv_dot)");
    im->pcg_update = clCreateKernel(im->program, "pcg_update", &err);
    CHECK(err, "clCreateKernel(pcg_update)");
    im->cheb_step = clCreateKernel(im->program, "cheb_step", &err);
    CHECK(err, "clCreateKernel(cheb_step)");
    return LIMN_OK;
}

static limn_status open_device(struct limn_device *dev, const char *spec)
{
    opencl_choice choice;
    limn_status st = opencl_select_device(dev->ctx, spec, &choice);
    if (st)
        return st;
    snprintf(dev->name, sizeof dev->name, "%s", choice.name);
    cl_device_fp_config fp64 = 0;
    clGetDeviceInfo(choice.device, CL_DEVICE_DOUBLE_FP_CONFIG, sizeof fp64, &fp64, NULL);
    if (!fp64)
        return limn_fail(dev->ctx, LIMN_ERR_DEVICE,
                         "OpenCL device %s has no double precision, which limn needs; choose "
                         "another with --device (see 'limn devices') or use --device reference",
                         dev->name);
    opencl_impl *im = impl_of(dev);
    CHECK(clGetDeviceInfo(choice.device, CL_DEVICE_MAX_MEM_ALLOC_SIZE, sizeof im->max_alloc,
                          &im->max_alloc, NULL),
          "clGetDeviceInfo(CL_DEVICE_MAX_MEM_ALLOC_SIZE)");
    cl_int err;
    cl_context_properties props[] = {CL_CONTEXT_PLATFORM, (cl_context_properties)choice.platform,
                                     0};
    im->context = clCreateContext(props, 1, &choice.device, NULL, NULL, &err);
    CHECK(err, "clCreateContext");
    im->queue = clCreateCommandQueue(im->context, choice.device, 0, &err);
    CHECK(err, "clCreateCommandQueue");
    return build_program(dev, choice.device);
}

limn_status device_open_opencl(limn_context *ctx, const char *spec, struct limn_device **out)
{
    struct limn_device *dev = calloc(1, sizeof *dev);
    opencl_impl *im = calloc(1, sizeof *im);
    if (!dev || !im) {
        free(dev);
        free(im);
        return limn_fail(ctx, LIMN_ERR_MEMORY, "out of memory opening OpenCL");
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
