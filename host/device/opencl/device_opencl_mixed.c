/* SPDX-License-Identifier: MIT */
/* The OpenCL side of the mixed-precision refinement (kernels/mixed.cl). */
#include "base/context.h"
#include "device/opencl/device_opencl.h"

static limn_status cl_residual_f(struct device *dev, const device_csr *a, device_buffer *m,
                                 device_buffer *p, device_buffer *r_f, device_norms *norms)
{
    opencl_impl *im = impl_of(dev);
    cl_uint ahead = (cl_uint)a->gather_ahead;
    opencl_arg args[] = {OPENCL_MEM(m, "m"), OPENCL_MEM(p, "p"), OPENCL_MEM(r_f, "r_f"),
                         OPENCL_VALUE(im->partials, "partials"), OPENCL_VALUE(ahead, "ahead")};
    return opencl_reduce(dev, K_RESIDUAL_F, a, a->weights, args, 5, norms);
}

static limn_status cl_step_f(struct device *dev, const device_csr *a, device_buffer *b,
                             device_buffer *d, device_buffer *prev, device_buffer *next, float c1,
                             float c2, device_norms *norms)
{
    opencl_impl *im = impl_of(dev);
    if (!a->weights_f)
        return ctx_fail(dev->ctx, LIMN_ERR_ARGUMENT, "step_f: no float weights");
    cl_uint ahead = (cl_uint)a->gather_ahead;
    opencl_arg args[] = {OPENCL_MEM(b, "b"),       OPENCL_MEM(d, "d"),
                         OPENCL_MEM(prev, "prev"), OPENCL_MEM(next, "next"),
                         OPENCL_VALUE(im->partials, "partials"),
                         OPENCL_VALUE(c1, "c1"),   OPENCL_VALUE(c2, "c2"),
                         OPENCL_VALUE(ahead, "ahead")};
    return opencl_reduce(dev, K_STEP_F, a, a->weights_f, args, 8, norms);
}

static limn_status cl_add_f(struct device *dev, size_t rows, device_buffer *p, device_buffer *d)
{
    cl_kernel k = impl_of(dev)->kernels[K_ADD_F];
    cl_uint r = (cl_uint)rows;
    opencl_arg args[] = {OPENCL_VALUE(r, "rows"), OPENCL_MEM(p, "p"), OPENCL_MEM(d, "d")};
    limn_status st = opencl_bind(dev, k, 0, args, 3);
    return st ? st : opencl_launch(dev, K_ADD_F, 0, rows);
}

static limn_status cl_to_float(struct device *dev, size_t count, device_buffer *w,
                               device_buffer *w_f)
{
    cl_kernel k = impl_of(dev)->kernels[K_TO_FLOAT];
    cl_uint c = (cl_uint)count;
    opencl_arg args[] = {OPENCL_VALUE(c, "count"), OPENCL_MEM(w, "w"), OPENCL_MEM(w_f, "w_f")};
    limn_status st = opencl_bind(dev, k, 0, args, 3);
    return st ? st : opencl_launch(dev, K_TO_FLOAT, 0, count);
}

const device_mixed_ops cl_mixed_ops = {cl_residual_f, cl_step_f, cl_add_f, cl_to_float};
