/* SPDX-License-Identifier: MIT */
/* The OpenCL side of the mixed-precision refinement (kernels/mixed.cl). */
#include "base/context.h"
#include "device/opencl/device_opencl.h"

static limn_status cl_residual_f(struct device *dev, const device_csr *a, device_buffer *m,
                                 device_buffer *p, device_buffer *r_f, device_norms *norms)
{
    opencl_impl *im = impl_of(dev);
    cl_kernel k;
    limn_status st = opencl_begin_reduce(dev, K_RESIDUAL_F, a, a->weights, &k);
    if (st)
        return st;
    CHECK(clSetKernelArg(k, 4, sizeof(cl_mem), &m->mem), "clSetKernelArg(m)");
    CHECK(clSetKernelArg(k, 5, sizeof(cl_mem), &p->mem), "clSetKernelArg(p)");
    CHECK(clSetKernelArg(k, 6, sizeof(cl_mem), &r_f->mem), "clSetKernelArg(r_f)");
    cl_uint ahead = (cl_uint)a->gather_ahead;
    CHECK(clSetKernelArg(k, 7, sizeof(cl_mem), &im->partials), "clSetKernelArg(partials)");
    CHECK(clSetKernelArg(k, 8, sizeof ahead, &ahead), "clSetKernelArg(ahead)");
    return opencl_end_reduce(dev, K_RESIDUAL_F, a, norms);
}

static limn_status cl_step_f(struct device *dev, const device_csr *a, device_buffer *b,
                             device_buffer *d, device_buffer *prev, device_buffer *next, float c1,
                             float c2, device_norms *norms)
{
    opencl_impl *im = impl_of(dev);
    if (!a->weights_f)
        return ctx_fail(dev->ctx, LIMN_ERR_ARGUMENT, "step_f: no float weights");
    cl_kernel k;
    limn_status st = opencl_begin_reduce(dev, K_STEP_F, a, a->weights_f, &k);
    if (st)
        return st;
    CHECK(clSetKernelArg(k, 4, sizeof(cl_mem), &b->mem), "clSetKernelArg(b)");
    CHECK(clSetKernelArg(k, 5, sizeof(cl_mem), &d->mem), "clSetKernelArg(d)");
    CHECK(clSetKernelArg(k, 6, sizeof(cl_mem), &prev->mem), "clSetKernelArg(prev)");
    CHECK(clSetKernelArg(k, 7, sizeof(cl_mem), &next->mem), "clSetKernelArg(next)");
    CHECK(clSetKernelArg(k, 8, sizeof(cl_mem), &im->partials), "clSetKernelArg(partials)");
    cl_uint ahead = (cl_uint)a->gather_ahead;
    CHECK(clSetKernelArg(k, 9, sizeof c1, &c1), "clSetKernelArg(c1)");
    CHECK(clSetKernelArg(k, 10, sizeof c2, &c2), "clSetKernelArg(c2)");
    CHECK(clSetKernelArg(k, 11, sizeof ahead, &ahead), "clSetKernelArg(ahead)");
    return opencl_end_reduce(dev, K_STEP_F, a, norms);
}

static limn_status cl_add_f(struct device *dev, size_t rows, device_buffer *p, device_buffer *d)
{
    cl_kernel k = impl_of(dev)->kernels[K_ADD_F];
    cl_uint r = (cl_uint)rows;
    CHECK(clSetKernelArg(k, 0, sizeof r, &r), "clSetKernelArg(rows)");
    CHECK(clSetKernelArg(k, 1, sizeof(cl_mem), &p->mem), "clSetKernelArg(p)");
    CHECK(clSetKernelArg(k, 2, sizeof(cl_mem), &d->mem), "clSetKernelArg(d)");
    return opencl_launch(dev, K_ADD_F, 0, rows);
}

static limn_status cl_to_float(struct device *dev, size_t count, device_buffer *w,
                               device_buffer *w_f)
{
    cl_kernel k = impl_of(dev)->kernels[K_TO_FLOAT];
    cl_uint c = (cl_uint)count;
    CHECK(clSetKernelArg(k, 0, sizeof c, &c), "clSetKernelArg(count)");
    CHECK(clSetKernelArg(k, 1, sizeof(cl_mem), &w->mem), "clSetKernelArg(w)");
    CHECK(clSetKernelArg(k, 2, sizeof(cl_mem), &w_f->mem), "clSetKernelArg(w_f)");
    return opencl_launch(dev, K_TO_FLOAT, 0, count);
}

const device_mixed_ops cl_mixed_ops = {cl_residual_f, cl_step_f, cl_add_f, cl_to_float};
