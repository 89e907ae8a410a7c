/* SPDX-License-Identifier: MIT */
/* limn_device_triad: STREAM's triad on the context's device, through the
   backends' axpby (out = 1 x + s y is x + s y exactly), so the yardstick runs
   on the same kernels, buffers and queue as the solve it is compared with. */
#include "device/choice/triad.h"
#include "base/abi.h"
#include "base/clock.h"
#include "base/context.h"
#include "device/choice/choice.h"
#include "device/device.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Host staging in pieces of this many doubles: the triad's own memory is on
   the device, not in a host copy of each array (limn bench measures the job's
   peak separately, but an embedding caller need not pay 3 arrays twice). */
#define TRIAD_PIECE ((size_t)1 << 19)

double triad_b(size_t i) { return 1.0 + (double)(i % 1024) * 0.5; }
double triad_c(size_t i) { return (double)(i % 13) * 0.25; }

/* b or c (which: 0, 1) written to buf piece by piece. */
static limn_status fill(struct device *dev, device_buffer *buf, size_t n, int which,
                        double *piece)
{
    for (size_t at = 0; at < n; at += TRIAD_PIECE) {
        size_t m = n - at < TRIAD_PIECE ? n - at : TRIAD_PIECE;
        for (size_t k = 0; k < m; k++)
            piece[k] = which ? triad_c(at + k) : triad_b(at + k);
        limn_status st = dev->ops->buffer_write_at(dev, buf, at * 8, m * 8, piece);
        if (st)
            return st;
    }
    return LIMN_OK;
}

/* a read back piece by piece and compared with b + s c. */
static limn_status check(struct device *dev, device_buffer *a, size_t n, double *piece,
                         double *a_out, size_t *mismatches)
{
    *mismatches = 0;
    for (size_t at = 0; at < n; at += TRIAD_PIECE) {
        size_t m = n - at < TRIAD_PIECE ? n - at : TRIAD_PIECE;
        limn_status st = dev->ops->buffer_read_at(dev, a, at * 8, m * 8, piece);
        if (st)
            return st;
        for (size_t k = 0; k < m; k++)
            *mismatches += piece[k] != triad_b(at + k) + TRIAD_SCALE * triad_c(at + k);
        if (a_out)
            memcpy(a_out + at, piece, m * 8);
    }
    return LIMN_OK;
}

/* One triad and its wait: a blocking read of a's first record. */
static limn_status run_once(struct device *dev, size_t rows, device_buffer *v[3], double *secs)
{
    double t0 = clock_seconds(), first[4];
    limn_status st = dev->ops->axpby(dev, rows, 1.0, v[1], TRIAD_SCALE, v[2], v[0]);
    if (!st)
        st = dev->ops->buffer_read_at(dev, v[0], 0, sizeof first, first);
    *secs = clock_seconds() - t0;
    return st;
}

static limn_status timed_runs(struct device *dev, size_t rows, device_buffer *v[3], int repeats,
                              limn_triad_report *r)
{
    double secs, sum = 0;
    limn_status st = run_once(dev, rows, v, &secs); /* untimed: first touches, compiles */
    r->seconds_best = 0;
    for (int k = 0; !st && k < repeats; k++) {
        st = run_once(dev, rows, v, &secs);
        sum += secs;
        if (k == 0 || secs < r->seconds_best)
            r->seconds_best = secs;
    }
    r->seconds_mean = sum / repeats;
    r->gb_per_s = r->seconds_best > 0 ? 24.0 * (double)r->elements / r->seconds_best * 1e-9 : 0;
    return st;
}

limn_status device_triad(struct device *dev, int repeats, limn_triad_report *r, double *a_out)
{
    size_t n = r->elements;
    double *piece = malloc(TRIAD_PIECE * sizeof *piece);
    if (!piece)
        return ctx_fail(dev->ctx, LIMN_ERR_MEMORY, "out of host memory");
    device_buffer *v[3] = {NULL, NULL, NULL}; /* a, b, c */
    limn_status st = LIMN_OK;
    for (int k = 0; !st && k < 3; k++)
        st = dev->ops->buffer_create(dev, n * 8, NULL, &v[k]);
    for (int k = 1; !st && k < 3; k++)
        st = fill(dev, v[k], n, k - 1, piece);
    if (!st)
        st = timed_runs(dev, n / 4, v, repeats, r);
    if (!st)
        st = check(dev, v[0], n, piece, a_out, &r->mismatches);
    for (int k = 0; k < 3; k++)
        if (v[k])
            dev->ops->buffer_release(dev, v[k]);
    free(piece);
    r->repeats = repeats;
    snprintf(r->device, sizeof r->device, "%s", dev->name);
    return st;
}

static limn_status triad_sized(limn_context *ctx, size_t bytes, int repeats,
                               limn_triad_report *r)
{
    if (bytes < 32 || bytes > SIZE_MAX / 4)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                        "limn_device_triad: bytes %zu is not an array size (32 bytes up to "
                        "SIZE_MAX / 4)",
                        bytes);
    if (repeats < 1 || repeats > 1000)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                        "limn_device_triad: repeats %d is outside 1..1000", repeats);
    /* the axpby kernels take a 32-bit row count */
    if (bytes / 32 > UINT32_MAX)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                        "limn_device_triad: bytes %zu is beyond the kernels' 2^32 records", bytes);
    struct device *dev;
    limn_status st = device_get(ctx, &dev);
    if (st)
        return st;
    r->elements = bytes / 32 * 4;
    r->array_bytes = r->elements * 8;
    return device_triad(dev, repeats, r, NULL);
}

limn_status limn_device_triad(limn_context *ctx, size_t bytes, int repeats,
                              limn_triad_report *report)
{
    abi_call c;
    limn_status st =
        abi_enter_result(&c, ctx, "limn_device_triad", "report", &abi_triad_report, report);
    if (!st && !report)
        st = ctx_fail(ctx, LIMN_ERR_ARGUMENT, "limn_device_triad: report is NULL");
    return st ? st : abi_leave(&c, triad_sized(ctx, bytes, repeats, c.report));
}
