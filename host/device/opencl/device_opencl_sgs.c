/* SPDX-License-Identifier: MIT */
/* The OpenCL side of the SGS-preconditioned conjugate gradients
   (kernels/sgs.cl): a sweep is one launch per colour, enqueued without
   waiting (the queue is in order); the forward sweep's partials land in one
   stretch of the partials buffer, colour after colour, and are read once. */
#include "base/context.h"
#include "device/opencl/device_opencl.h"

static limn_status set_table(struct device *dev, cl_kernel k, cl_uint at,
                             const device_sgs *a, int with_split)
{
    CHECK(clSetKernelArg(k, at, sizeof(cl_mem), &a->row_offsets->mem), "clSetKernelArg(offsets)");
    CHECK(clSetKernelArg(k, at + 1, sizeof(cl_mem), &a->columns->mem), "clSetKernelArg(columns)");
    CHECK(clSetKernelArg(k, at + 2, sizeof(cl_mem), &a->weights->mem), "clSetKernelArg(weights)");
    if (with_split)
        CHECK(clSetKernelArg(k, at + 3, sizeof(cl_mem), &a->split->mem), "clSetKernelArg(split)");
    CHECK(clSetKernelArg(k, at + 3 + (with_split ? 1 : 0), sizeof(cl_mem), &a->info->mem),
          "clSetKernelArg(info)");
    return LIMN_OK;
}

static limn_status set_mem(struct device *dev, cl_kernel k, cl_uint at, device_buffer *b)
{
    CHECK(clSetKernelArg(k, at, sizeof(cl_mem), &b->mem), "clSetKernelArg(vector)");
    return LIMN_OK;
}

static limn_status set_rows(struct device *dev, cl_kernel k, size_t rows, size_t first)
{
    cl_uint r = (cl_uint)rows, f = (cl_uint)first;
    CHECK(clSetKernelArg(k, 0, sizeof r, &r), "clSetKernelArg(rows)");
    CHECK(clSetKernelArg(k, 1, sizeof f, &f), "clSetKernelArg(first)");
    return LIMN_OK;
}

static limn_status cl_sgs_upper(struct device *dev, const device_sgs *a, double beta,
                                const sgs_vectors *v)
{
    cl_kernel k = impl_of(dev)->kernels[K_SGS_UPPER];
    limn_status st = set_table(dev, k, 2, a, 1);
    device_buffer *vec[] = {v->rhat, v->phat, v->t};
    for (cl_uint i = 0; i < 3 && !st; i++)
        st = set_mem(dev, k, 7 + i, vec[i]);
    if (st)
        return st;
    CHECK(clSetKernelArg(k, 10, sizeof beta, &beta), "clSetKernelArg(beta)");
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
        items += opencl_work_items(a->colour_begin[c + 1] - a->colour_begin[c]);
    limn_status st = opencl_ensure_partials(dev, items, 0);
    if (!st)
        st = set_table(dev, k, 2, a, 1);
    device_buffer *vec[] = {v->b, v->x, v->r, v->phat, v->t, v->u, v->st, v->rhat};
    for (cl_uint i = 0; i < 8 && !st; i++)
        st = set_mem(dev, k, 7 + i, vec[i]);
    if (st)
        return st;
    cl_int s = start;
    CHECK(clSetKernelArg(k, 15, sizeof(cl_mem), &im->partials), "clSetKernelArg(partials)");
    CHECK(clSetKernelArg(k, 17, sizeof s, &s), "clSetKernelArg(start)");
    size_t base = 0;
    for (size_t c = 0; c < a->colours && !st; c++) {
        size_t first = a->colour_begin[c], rows = a->colour_begin[c + 1] - first;
        cl_uint b = (cl_uint)base;
        st = set_rows(dev, k, rows, first);
        if (st)
            break;
        CHECK(clSetKernelArg(k, 16, sizeof b, &b), "clSetKernelArg(base)");
        st = opencl_launch(dev, K_SGS_LOWER, 0, rows);
        base += opencl_work_items(rows);
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
        device_norms_finish(im->host_partials + 3 * base, (rows + DEVICE_ROWS_PER_ITEM - 1) /
                                                              DEVICE_ROWS_PER_ITEM, &n);
        out->max = n.max > out->max ? n.max : out->max;
        out->sum += n.sum;
        base += opencl_work_items(rows);
    }
    return LIMN_OK;
}

static limn_status cl_sgs_update(struct device *dev, const device_sgs *a, double alpha,
                                 const sgs_vectors *v, device_norms *norms)
{
    opencl_impl *im = impl_of(dev);
    cl_kernel k = im->kernels[K_SGS_UPDATE];
    cl_uint rows = (cl_uint)a->rows;
    limn_status st = opencl_ensure_partials(dev, 0, a->rows);
    if (st)
        return st;
    CHECK(clSetKernelArg(k, 0, sizeof rows, &rows), "clSetKernelArg(rows)");
    device_buffer *vec[] = {a->info, v->t, v->u, v->st, v->x, v->r, v->rhat};
    for (cl_uint i = 0; i < 7 && !st; i++)
        st = set_mem(dev, k, 1 + i, vec[i]);
    if (st)
        return st;
    CHECK(clSetKernelArg(k, 8, sizeof alpha, &alpha), "clSetKernelArg(alpha)");
    CHECK(clSetKernelArg(k, 9, sizeof(cl_mem), &im->partials), "clSetKernelArg(partials)");
    st = opencl_launch(dev, K_SGS_UPDATE, 0, a->rows);
    return st ? st : opencl_finish_partials(dev, 0, a->rows, norms);
}

const device_sgs_ops cl_sgs_ops = {cl_sgs_upper, cl_sgs_lower, cl_sgs_update};
