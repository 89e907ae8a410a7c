/* SPDX-License-Identifier: MIT */
/* The operations shared by both backends (the choice of backend is in
   device/choice/choice.c). */
#include "device/device.h"
#include "base/large_alloc.h"
#include "base/context.h"
#include "base/parallel.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int device_test_fault(const char *name)
{
    const char *env = getenv("LIMN_TEST_FAULT");
    size_t n = strlen(name);
    for (const char *p = env; p && *p;) {
        const char *end = strchr(p, ',');
        size_t len = end ? (size_t)(end - p) : strlen(p);
        if (len == n && strncmp(p, name, n) == 0)
            return 1;
        p = end ? end + 1 : NULL;
    }
    return 0;
}

int device_fallback_allowed(const limn_context *ctx)
{
    if (ctx->fallback)
        return ctx->fallback == 2;
    const char *env = getenv("LIMN_FALLBACK");
    return env && (strcmp(env, "reference") == 0 || strcmp(env, "ref") == 0);
}

device_setup_times device_setup_of(const limn_context *ctx)
{
    device_setup_times none = {0, 0, 0, 0};
    return ctx->device ? ctx->device->setup : none;
}

void device_setup_report(const limn_context *ctx, const device_setup_times *before,
                         limn_report *r)
{
    device_setup_times now = device_setup_of(ctx);
    r->seconds_opencl_platform = now.platform - before->platform;
    r->seconds_opencl_context = now.context - before->context;
    r->seconds_opencl_build = now.build - before->build;
    r->seconds_opencl_kernels = now.kernels - before->kernels;
    r->seconds_solve -= r->seconds_opencl_kernels;
}

void device_close(struct device *dev)
{
    if (dev)
        dev->ops->close(dev);
}

/* Whether a table's gathers scatter over memory: over a tenth of the entries
   of every 16th row lie more than 16,384 rows (512 KiB of vertex records)
   from their row. Meshes refined in place, in their input order, score
   0.64 (igea, Loop, 2 levels) to 0.78 (bob_quad, Catmull-Clark, 4 levels);
   the same after RCM, 0.00; scans in RCM order 0.00. */
static int gathers_scatter(const stencil_csr *a)
{
    size_t far = 0, seen = 0;
    for (size_t r = 0; r < a->rows; r += 16)
        for (uint32_t k = a->row_offsets[r]; k < a->row_offsets[r + 1]; k++, seen++)
            far += (a->columns[k] > r ? a->columns[k] - r : r - a->columns[k]) > 16384;
    return far * 10 > seen;
}

typedef limn_status (*buffer_from_host)(struct device *dev, size_t bytes, const void *host,
                                        device_buffer **out);

/* The table in SELL slices (a device whose kernels want them,
   device.sell_slice): copied, the host layout freed at once. */
static limn_status sell_to_device(struct device *dev, const stencil_csr *host, device_csr *out)
{
    stencil_sell s;
    limn_status st = stencil_sell_build(dev->ctx, host, dev->sell_slice, &s);
    if (st)
        return st;
    out->rows = host->rows;
    out->nonzeros = s.slice_offsets[s.slices];
    st = dev->ops->buffer_create(dev, (s.slices + 1) * sizeof(uint32_t), s.slice_offsets,
                                 &out->row_offsets);
    if (!st)
        st = dev->ops->buffer_create(dev, out->nonzeros * sizeof(uint32_t), s.columns,
                                     &out->columns);
    if (!st)
        st = dev->ops->buffer_create(dev, out->nonzeros * sizeof(double), s.weights,
                                     &out->weights);
    stencil_sell_free(&s);
    if (st)
        device_csr_release(dev, out);
    return st;
}

static limn_status csr_to_device(struct device *dev, const stencil_csr *host,
                                 buffer_from_host make, device_csr *out)
{
    memset(out, 0, sizeof *out);
    if (dev->sell_slice) {
        out->gather_ahead = gathers_scatter(host);
        return sell_to_device(dev, host, out);
    }
    out->rows = host->rows;
    out->nonzeros = host->row_offsets[host->rows];
    out->gather_ahead = gathers_scatter(host);
    limn_status st = make(dev, (host->rows + 1) * sizeof(uint32_t), host->row_offsets,
                          &out->row_offsets);
    if (!st)
        st = make(dev, out->nonzeros * sizeof(uint32_t), host->columns, &out->columns);
    if (!st)
        st = make(dev, out->nonzeros * sizeof(double), host->weights, &out->weights);
    if (st)
        device_csr_release(dev, out);
    return st;
}

limn_status device_csr_upload(struct device *dev, const stencil_csr *host, device_csr *out)
{
    return csr_to_device(dev, host, dev->ops->buffer_create, out);
}

limn_status device_csr_share(struct device *dev, const stencil_csr *host, device_csr *out)
{
    return csr_to_device(dev, host, dev->ops->buffer_share, out);
}

limn_status device_csr_add_float(struct device *dev, device_csr *csr)
{
    if (csr->weights_f)
        return LIMN_OK;
    /* to_float writes every entry */
    limn_status st = dev->ops->buffer_scratch(dev, csr->nonzeros * sizeof(float),
                                              &csr->weights_f);
    if (!st)
        st = dev->ops->mixed->to_float(dev, csr->nonzeros, csr->weights, csr->weights_f);
    return st;
}

void device_csr_release(struct device *dev, device_csr *csr)
{
    if (csr->row_offsets)
        dev->ops->buffer_release(dev, csr->row_offsets);
    if (csr->columns)
        dev->ops->buffer_release(dev, csr->columns);
    if (csr->weights)
        dev->ops->buffer_release(dev, csr->weights);
    if (csr->weights_f)
        dev->ops->buffer_release(dev, csr->weights_f);
    memset(csr, 0, sizeof *csr);
}

void device_norms_finish(const double *partials, size_t chunks, device_norms *out)
{
    out->max = 0;
    out->sum = 0;
    out->sum_sq = 0;
    for (size_t i = 0; i < chunks; i++) {
        if (partials[3 * i] > out->max)
            out->max = partials[3 * i];
        out->sum += partials[3 * i + 1];
        out->sum_sq += partials[3 * i + 2];
    }
}

limn_status device_sgs_upload(struct device *dev, const sgs_table *t, device_sgs *out)
{
    memset(out, 0, sizeof *out);
    const device_ops *ops = dev->ops;
    size_t n = t->rows, nnz = t->row_offsets[n];
    out->rows = n;
    out->colours = t->colours;
    out->colour_begin = malloc((t->colours + 1) * sizeof *out->colour_begin);
    if (!out->colour_begin)
        return ctx_fail(dev->ctx, LIMN_ERR_MEMORY, "out of memory for the Gauss-Seidel table");
    memcpy(out->colour_begin, t->colour_begin, (t->colours + 1) * sizeof *out->colour_begin);
    limn_status st = ops->buffer_create(dev, (n + 1) * sizeof(uint32_t), t->row_offsets,
                                        &out->row_offsets);
    if (!st)
        st = ops->buffer_create(dev, n * sizeof(uint32_t), t->split, &out->split);
    if (!st)
        st = ops->buffer_create(dev, nnz * sizeof(uint32_t), t->columns, &out->columns);
    if (!st)
        st = ops->buffer_create(dev, nnz * sizeof(double), t->weights, &out->weights);
    if (!st)
        st = ops->buffer_create(dev, 4 * n * sizeof(double), t->info, &out->info);
    if (st)
        device_sgs_release(dev, out);
    return st;
}

void device_sgs_release(struct device *dev, device_sgs *d)
{
    device_buffer *bufs[] = {d->row_offsets, d->split, d->columns, d->weights, d->info};
    for (int i = 0; i < 5; i++)
        if (bufs[i])
            dev->ops->buffer_release(dev, bufs[i]);
    free(d->colour_begin);
    memset(d, 0, sizeof *d);
}

void *device_host_alloc(size_t bytes)
{
    const size_t page = 4096;
    size_t rounded = bytes ? (bytes + page - 1) / page * page : page;
    if (rounded < bytes)
        return NULL;
    if (rounded >= LARGE_ALLOC_HUGE) /* 2 MiB aligned, advised from its first byte */
        return large_malloc(rounded);
    return aligned_alloc(page, rounded);
}

limn_status device_vector_create(struct device *dev, limn_context *ctx, size_t bytes,
                                 const void *init, void **host, device_buffer **out)
{
    *host = NULL;
    if (!dev->host_shared)
        return dev->ops->buffer_create(dev, bytes, init, out);
    void *h = device_host_alloc(bytes);
    if (!h)
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for a vector of %zu bytes", bytes);
    if (init)
        parallel_copy(ctx, h, init, bytes);
    else
        parallel_zero(ctx, h, bytes);
    limn_status st = dev->ops->buffer_share(dev, bytes, h, out);
    if (st)
        free(h);
    else
        *host = h;
    return st;
}
