/* SPDX-License-Identifier: MIT */
/*
 * OpenCL platform and device choice: the API's spec first, then the
 * environment (LIMN_PLATFORM, LIMN_DEVICE, LIMN_DEVICE_TYPE), then the first
 * device limn can use (opencl_usable.c): unusable ones are skipped with a
 * warning, unless the choice named one, which is then an error saying why.
 */
#include "device/opencl/opencl_select.h"
#include "base/context.h"
#include "device/device.h"
#include "device/opencl/opencl_errors.h"
#include "device/opencl/opencl_pocl_cache.h"
#include "device/opencl/opencl_usable.h"
#include "device/threads.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_PLATFORMS 16
#define MAX_DEVICES 64

static limn_status platforms(limn_context *ctx, cl_platform_id *ids, cl_uint *count)
{
    threads_apply(ctx); /* PoCL reads its thread count at the first platform query */
    cl_int err = device_test_fault("no-platform") ? -1001
                                                  : clGetPlatformIDs(MAX_PLATFORMS, ids, count);
    if (err == -1001 || (err == CL_SUCCESS && *count == 0))
        return ctx_fail(ctx, LIMN_ERR_DEVICE,
                         "no OpenCL platform found (clGetPlatformIDs: %s): install an OpenCL "
                         "driver, e.g. 'apt-get install pocl-opencl-icd' (the ICD loader finds "
                         "drivers through /etc/OpenCL/vendors or OCL_ICD_VENDORS), or run with "
                         "--device reference, or allow --fallback reference",
                         err == -1001 ? opencl_error_name(err) : "no platforms");
    if (err != CL_SUCCESS)
        return ctx_fail(ctx, LIMN_ERR_DEVICE, "clGetPlatformIDs failed: %s",
                         opencl_error_name(err));
    if (*count > MAX_PLATFORMS)
        *count = MAX_PLATFORMS;
    return LIMN_OK;
}

/* Every device of every platform, in platform.device order. */
static limn_status all_devices(limn_context *ctx, opencl_device_props *devs, size_t *count,
                               cl_uint *np_out)
{
    cl_platform_id plats[MAX_PLATFORMS];
    cl_uint np = 0;
    limn_status st = platforms(ctx, plats, &np);
    if (st)
        return st;
    *count = 0;
    *np_out = np;
    for (cl_uint p = 0; p < np; p++) {
        char pname[96];
        if (clGetPlatformInfo(plats[p], CL_PLATFORM_NAME, sizeof pname, pname, NULL) != CL_SUCCESS)
            snprintf(pname, sizeof pname, "?");
        pname[sizeof pname - 1] = '\0';
        cl_device_id ids[MAX_DEVICES];
        cl_uint nd = 0;
        cl_int err = clGetDeviceIDs(plats[p], CL_DEVICE_TYPE_ALL, MAX_DEVICES, ids, &nd);
        if (err == CL_DEVICE_NOT_FOUND || device_test_fault("no-device"))
            continue;
        if (err != CL_SUCCESS)
            return ctx_fail(ctx, LIMN_ERR_DEVICE, "clGetDeviceIDs on platform %u (%s) failed: %s",
                             p, pname, opencl_error_name(err));
        for (cl_uint d = 0; d < nd && d < MAX_DEVICES && *count < MAX_DEVICES; d++)
            opencl_read_props(plats[p], ids[d], p, d, pname, &devs[(*count)++]);
    }
    return LIMN_OK;
}

static int parse_index_pair(const char *s, unsigned *p, unsigned *d)
{
    char tail;
    return sscanf(s, "%u.%u%c", p, d, &tail) == 2;
}

static cl_device_type parse_type(const char *s, int *ok)
{
    *ok = 1;
    if (!s || !*s || strcmp(s, "all") == 0)
        return CL_DEVICE_TYPE_ALL;
    if (strcmp(s, "cpu") == 0)
        return CL_DEVICE_TYPE_CPU;
    if (strcmp(s, "gpu") == 0)
        return CL_DEVICE_TYPE_GPU;
    if (strcmp(s, "accelerator") == 0)
        return CL_DEVICE_TYPE_ACCELERATOR;
    *ok = 0;
    return CL_DEVICE_TYPE_ALL;
}

static void describe(const opencl_device_props *d, char *buf, size_t size)
{
    snprintf(buf, size, "%s [%s, device %u.%u, %s]", d->name, d->platform, d->platform_index,
             d->device_index, opencl_type_name(d->type));
}

/* "NAME [..]: why; NAME [..]: why" for the unusable matches. */
static void reasons(const opencl_device_props *devs, const size_t *idx, size_t n, char *buf,
                    size_t size)
{
    size_t used = 0;
    buf[0] = '\0';
    for (size_t i = 0; i < n && used + 1 < size; i++) {
        char name[300], why[160];
        describe(&devs[idx[i]], name, sizeof name);
        opencl_unusable(&devs[idx[i]], why, sizeof why);
        int w = snprintf(buf + used, size - used, "%s%s: %s", i ? "; " : "", name, why);
        if (w < 0)
            break;
        used += (size_t)w;
    }
}

/* The no-device message, with PoCL's cache when that is the cause. */
static limn_status no_device(limn_context *ctx, cl_uint np)
{
    char cache[1400] = "";
    int cache_bad = opencl_pocl_cache_problem(cache, sizeof cache);
    if (cache_bad)
        return ctx_fail(ctx, LIMN_ERR_DEVICE,
                         "no OpenCL device found (%u platform%s, no device); likely cause: %s "
                         "(or use --device reference, or allow --fallback reference)",
                         np, np == 1 ? "" : "s", cache);
    return ctx_fail(ctx, LIMN_ERR_DEVICE,
                     "no OpenCL device found (%u platform%s, no device): check the driver "
                     "with 'limn devices' or clinfo, or use --device reference, or allow "
                     "--fallback reference",
                     np, np == 1 ? "" : "s");
}

/* What the caller asked for, and where it said so (for the messages). */
typedef struct device_request {
    const char *source, *value;
    opencl_criteria c;
} device_request;

/* --device and LIMN_DEVICE take the same value: "P.D" is a device's index
   pair, anything else a part of its name. */
static void index_or_name(device_request *r, const char *source, const char *s)
{
    r->source = source;
    r->value = s;
    if (parse_index_pair(s, &r->c.p, &r->c.d))
        r->c.by_index = 1;
    else
        r->c.name = s;
}

/* The API's spec, else the environment. */
static limn_status read_request(limn_context *ctx, const char *spec, device_request *r)
{
    *r = (device_request){"the first device", "", {NULL, NULL, 0, 0, 0, CL_DEVICE_TYPE_ALL}};
    if (spec && *spec) {
        index_or_name(r, "--device", spec);
        return LIMN_OK;
    }
    const char *env_platform = getenv("LIMN_PLATFORM");
    const char *env_device = getenv("LIMN_DEVICE");
    const char *env_type = getenv("LIMN_DEVICE_TYPE");
    if (env_platform && *env_platform) {
        r->c.platform = env_platform;
        r->source = "LIMN_PLATFORM";
        r->value = env_platform;
    }
    if (env_device && *env_device)
        index_or_name(r, "LIMN_DEVICE", env_device);
    int type_ok;
    r->c.type = parse_type(env_type, &type_ok);
    if (!type_ok)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                         "LIMN_DEVICE_TYPE='%s' is not one of cpu, gpu, accelerator, all",
                         env_type);
    if (env_type && *env_type && strcmp(r->source, "the first device") == 0) {
        r->source = "LIMN_DEVICE_TYPE";
        r->value = env_type;
    }
    return LIMN_OK;
}

/* The slot's usable match (MPI ranks of a node take them in turn), after a
   warning for each unusable device listed before the first usable one. */
static void take(limn_context *ctx, const opencl_device_props *devs, const size_t *usable,
                 size_t good, const size_t *bad, size_t n_bad, opencl_choice *out)
{
    const opencl_device_props *d =
        &devs[usable[(size_t)(ctx->device_slot >= 0 ? ctx->device_slot : 0) % good]];
    for (size_t i = 0; i < n_bad && bad[i] < usable[0]; i++) {
        char name[300], why[160];
        describe(&devs[bad[i]], name, sizeof name);
        opencl_unusable(&devs[bad[i]], why, sizeof why);
        ctx_warn(ctx, "skipping OpenCL device %s: limn cannot use it: %s", name, why);
    }
    out->platform = d->platform_id;
    out->device = d->id;
    describe(d, out->name, sizeof out->name);
}

/* No usable match: why, in the words of the request. */
static limn_status no_match(limn_context *ctx, const device_request *r,
                            const opencl_device_props *devs, size_t n, cl_uint np,
                            const size_t *bad, size_t n_bad)
{
    if (n_bad > 0) {
        char list[1500];
        reasons(devs, bad, n_bad, list, sizeof list);
        /* an explicit choice names its device: an unusable one is an error,
           not skipped for another */
        if (strcmp(r->source, "--device") == 0 || strcmp(r->source, "LIMN_DEVICE") == 0)
            return ctx_fail(ctx, LIMN_ERR_DEVICE,
                             "the OpenCL device chosen by %s='%s' cannot run limn: %s; choose "
                             "another (see 'limn devices') or use --device reference",
                             r->source, r->value, list);
        return ctx_fail(ctx, LIMN_ERR_DEVICE,
                         "no OpenCL device can run limn: %s; install a driver whose device "
                         "has double precision (e.g. pocl-opencl-icd), or use --device "
                         "reference, or allow --fallback reference",
                         list);
    }
    if (n == 0 && !*r->value)
        return no_device(ctx, np);
    return ctx_fail(ctx, LIMN_ERR_DEVICE,
                     "no OpenCL device matches %s%s%s%s: run 'limn devices' to list them, or "
                     "use --device reference",
                     r->source, *r->value ? "='" : "", r->value, *r->value ? "'" : "");
}

limn_status opencl_select_device(limn_context *ctx, const char *spec, opencl_choice *out)
{
    device_request r;
    limn_status st = read_request(ctx, spec, &r);
    if (st)
        return st;
    opencl_device_props *devs = malloc(MAX_DEVICES * sizeof *devs);
    size_t *usable = malloc(2 * MAX_DEVICES * sizeof *usable), n = 0, n_bad = 0;
    if (!devs || !usable) {
        free(devs);
        free(usable);
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of host memory");
    }
    size_t *bad = usable + MAX_DEVICES;
    cl_uint np = 0;
    st = all_devices(ctx, devs, &n, &np);
    size_t good = st ? 0 : opencl_pick(devs, n, &r.c, usable, bad, &n_bad);
    if (!st && good > 0)
        take(ctx, devs, usable, good, bad, n_bad, out);
    else if (!st)
        st = no_match(ctx, &r, devs, n, np, bad, n_bad);
    free(devs);
    free(usable);
    return st;
}

limn_status limn_list_devices(limn_context *ctx, char *buf, size_t size)
{
    if (!ctx)
        return LIMN_ERR_ARGUMENT;
    ctx_clear(ctx);
    if (!buf || size == 0)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "limn_list_devices: %s",
                         !buf ? "buf is NULL"
                              : "buf_size is 0: the buffer cannot hold even the terminating NUL");
    buf[0] = '\0';
    opencl_device_props *devs = malloc(MAX_DEVICES * sizeof *devs);
    if (!devs)
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of host memory");
    size_t n = 0, used = 0;
    cl_uint np = 0;
    limn_status st = all_devices(ctx, devs, &n, &np);
    for (size_t i = 0; !st && i < n; i++) {
        const opencl_device_props *d = &devs[i];
        char why[160];
        int bad = opencl_unusable(d, why, sizeof why);
        int w = snprintf(buf + used, size - used,
                         "%u.%u  %s  [%s, %s]  %s, %u compute units, %.1f GiB memory "
                         "(%.1f GiB per buffer), double precision %s, max work-group %zu; "
                         "limn: %s%s\n",
                         d->platform_index, d->device_index, d->name, d->platform, d->version,
                         opencl_type_name(d->type), d->units, (double)d->mem / (1 << 30),
                         (double)d->alloc / (1 << 30), d->fp64 ? "yes" : "NO", d->max_work_group,
                         bad ? "NO, " : "usable", bad ? why : "");
        if (w < 0 || (size_t)w >= size - used)
            st = ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                           "limn_list_devices: the buffer of %zu bytes is too small for "
                           "the device list",
                           size);
        else
            used += (size_t)w;
    }
    if (!st && n == 0) {
        char cache[1400];
        if (opencl_pocl_cache_problem(cache, sizeof cache))
            ctx_warn(ctx, "no OpenCL device found (%u platform%s); likely cause: %s", np,
                      np == 1 ? "" : "s", cache);
    }
    free(devs);
    return st;
}
