/* Backend choice and the operations shared by both backends. */
#include "device.h"
#include "context.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

limn_status limn_context_set_device(limn_context *ctx, const char *spec)
{
    if (!ctx)
        return LIMN_ERR_ARGUMENT;
    limn_clear(ctx);
    if (!spec)
        spec = "";
    if (strlen(spec) >= sizeof ctx->device_spec)
        return limn_fail(ctx, LIMN_ERR_ARGUMENT, "device spec is too long (%zu characters)",
                         strlen(spec));
    if (spec[0] && strcmp(spec, "reference") != 0 && strcmp(spec, "ref") != 0 &&
        strcmp(spec, "opencl") != 0 && strncmp(spec, "opencl:", 7) != 0)
        return limn_fail(ctx, LIMN_ERR_ARGUMENT,
                         "unknown device '%s': use 'reference', 'opencl', 'opencl:P.D' or "
                         "'opencl:NAME' (see 'limn devices')",
                         spec);
    device_close(ctx->device);
    ctx->device = NULL;
    ctx->device_name[0] = '\0';
    strcpy(ctx->device_spec, spec);
    return LIMN_OK;
}

limn_status device_open(limn_context *ctx, struct limn_device **out)
{
    const char *spec = ctx->device_spec;
    const char *env = getenv("LIMN_DEVICE");
    if (!spec[0] && env && (strcmp(env, "reference") == 0 || strcmp(env, "ref") == 0))
        spec = "reference";
    if (strcmp(spec, "reference") == 0 || strcmp(spec, "ref") == 0)
        return device_open_reference(ctx, out);
    if (strncmp(spec, "opencl:", 7) == 0)
        return device_open_opencl(ctx, spec + 7, out);
    return device_open_opencl(ctx, NULL, out);
}

limn_status device_get(limn_context *ctx, struct limn_device **out)
{
    if (!ctx->device) {
        limn_status st = device_open(ctx, &ctx->device);
        if (st)
            return st;
        snprintf(ctx->device_name, sizeof ctx->device_name, "%s", ctx->device->name);
    }
    *out = ctx->device;
    return LIMN_OK;
}

void device_close(struct limn_device *dev)
{
    if (dev)
        dev->ops->close(dev);
}

limn_status device_csr_upload(struct limn_device *dev, const stencil_csr *host, device_csr *out)
{
    memset(out, 0, sizeof *out);
    out->rows = host->rows;
    out->nonzeros = host->row_offsets[host->rows];
    limn_status st = dev->ops->buffer_create(dev, (host->rows + 1) * sizeof(uint32_t),
                                             host->row_offsets, &out->row_offsets);
    if (!st)
        st = dev->ops->buffer_create(dev, out->nonzeros * sizeof(uint32_t), host->columns,
                                     &out->columns);
    if (!st)
        st = dev->ops->buffer_create(dev, out->nonzeros * sizeof(double), host->weights,
                                     &out->weights);
    if (st)
        device_csr_release(dev, out);
    return st;
}

void device_csr_release(struct limn_device *dev, device_csr *csr)
{
    if (csr->row_offsets)
        dev->ops->buffer_release(dev, csr->row_offsets);
    if (csr->columns)
        dev->ops->buffer_release(dev, csr->columns);
    if (csr->weights)
        dev->ops->buffer_release(dev, csr->weights);
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
