/* SPDX-License-Identifier: MIT */
/* The OpenCL side of the SGS-preconditioned conjugate gradients
   (kernels/sgs.cl): a sweep is one launch per colour, enqueued without
   waiting (the queue is in order); the forward sweep's partials land in one
   stretch of the partials buffer, colour after colour, and are read once. */
#include "base/context.h"
#include "device/opencl/device_opencl.h"

/* The table at arguments 2-6: offsets, columns, weights, split, info. */
static limn_status set_table(struct device *dev, cl_kernel k, const device_sgs *a)
{
    opencl_arg args[] = {OPENCL_MEM(a->row_offsets, "offsets"), OPENCL_MEM(a->columns, "columns"),
                         OPENCL_MEM(a->weights, "weights"), OPENCL_MEM(a->split, "split"),
                         OPENCL_MEM(a->info, "info")};
    return opencl_bind(dev, k, 2, args, 5);
}

/* The vectors vec[0 .. count) at arguments at, at + 1, ... */
static limn_status set_vectors(struct device *dev, cl_kernel k, cl_uint at, device_buffer **vec,
                               size_t count)
{
    opencl_arg args[8];
    for (size_t i = 0; i < count; i++)
        args[i] = (opencl_arg)OPENCL_MEM(vec[i], "vector");
    return opencl_bind(dev, k, at, args, count);
}

static limn_status set_rows(struct device *dev, cl_kernel k, size_t rows, size_t first)
{
    cl_uint r = (cl_uint)rows, f = (cl_uint)first;
    opencl_arg args[] = {OPENCL_VALUE(r, "rows"), OPENCL_VALUE(f, "first")};
    return opencl_bind(dev, k, 0, args, 2);
}

static limn_status cl_sgs_upper(struct device *dev, const device_sgs *a, double beta,
                                const sgs_vectors *v)
{
    cl_kernel k = impl_of(dev)->kernels[K_SGS_UPPER];
    device_buffer *vec[] = {v->rhat, v->phat, v->t};
    opencl_arg beta_arg = OPENCL_VALUE(beta, "beta");
    limn_status st = set_table(dev, k, a);
    if (!st)
        st = set_vectors(dev, k, 7, vec, 3);
    if (!st)
        st = opencl_bind(dev, k, 10, &beta_arg, 1);
    for (size_t c = a->colours; c-- > 0 && !st;) {
        size_t first = a->colour_begin[c], rows = a->colour_begin[c + 1] - first;
        st = set_rows(dev, k, rows, first);
        if (!st)
            st = opencl_launch(dev, K_SGS_UPPER, 0, rows);
    }
    return st;
}

static limn_status cl_sgs_lower(struct device *dev, const device_sgs *a, int start,
                                const sgs_vectors *v, device_norms *out)
{
    opencl_impl *im = impl_of(dev);
    cl_kernel k = im->kernels[K_SGS_LOWER];
    size_t items = 0;
    for (size_t c = 0; c < a->colours; c++)
        items += opencl_shape_slots(&im->shape, a->colour_begin[c + 1] - a->colour_begin[c]);
    limn_status st = opencl_ensure_partials(dev, items, 0);
    if (!st)
        st = set_table(dev, k, a);
    device_buffer *vec[] = {v->b, v->x, v->r, v->phat, v->t, v->u, v->st, v->rhat};
    if (!st)
        st = set_vectors(dev, k, 7, vec, 8);
    cl_int s = start;
    opencl_arg partials = OPENCL_VALUE(im->partials, "partials");
    opencl_arg start_arg = OPENCL_VALUE(s, "start");
    if (!st)
        st = opencl_bind(dev, k, 15, &partials, 1);
    if (!st)
        st = opencl_bind(dev, k, 17, &start_arg, 1);
    if (st)
        return st;
    size_t base = 0;
    for (size_t c = 0; c < a->colours && !st; c++) {
        size_t first = a->colour_begin[c], rows = a->colour_begin[c + 1] - first;
        cl_uint b = (cl_uint)base;
        st = set_rows(dev, k, rows, first);
        if (st)
            break;
        opencl_arg base_arg = OPENCL_VALUE(b, "base");
        st = opencl_bind(dev, k, 16, &base_arg, 1);
        if (!st)
            st = opencl_launch(dev, K_SGS_LOWER, 0, rows);
        base += opencl_shape_slots(&im->shape, rows);
    }
    if (st)
        return st;
    if (items)
        CHECK(clEnqueueReadBuffer(im->queue, im->partials, CL_TRUE, 0, items * 3 * sizeof(double),
                                  im->host_partials, 0, NULL, NULL),
              "reading the reduction partials");
    out->max = out->sum = out->sum_sq = 0.0;
    base = 0;
    for (size_t c = 0; c < a->colours; c++) {
        size_t rows = a->colour_begin[c + 1] - a->colour_begin[c];
        device_norms n;
        device_norms_finish(im->host_partials + 3 * base, opencl_shape_chunks(&im->shape, rows),
                            &n);
        out->max = n.max > out->max ? n.max : out->max;
        out->sum += n.sum;
        base += opencl_shape_slots(&im->shape, rows);
    }
    return LIMN_OK;
}

static limn_status cl_sgs_update(struct device *dev, const device_sgs *a, double alpha,
                                 const sgs_vectors *v, device_norms *norms)
{
    cl_uint rows = (cl_uint)a->rows;
    opencl_arg args[] = {OPENCL_VALUE(rows, "rows"),   OPENCL_MEM(a->info, "vector"),
                         OPENCL_MEM(v->t, "vector"),   OPENCL_MEM(v->u, "vector"),
                         OPENCL_MEM(v->st, "vector"),  OPENCL_MEM(v->x, "vector"),
                         OPENCL_MEM(v->r, "vector"),   OPENCL_MEM(v->rhat, "vector"),
                         OPENCL_VALUE(alpha, "alpha"),
                         OPENCL_VALUE(impl_of(dev)->partials, "partials")};
    return opencl_reduce_rows(dev, K_SGS_UPDATE, a->rows, args, 10, norms);
}

const device_sgs_ops cl_sgs_ops = {cl_sgs_upper, cl_sgs_lower, cl_sgs_update};
