/*
 * OpenCL platform and device choice: the API's spec first, then the
 * environment (LIMN_PLATFORM, LIMN_DEVICE, LIMN_DEVICE_TYPE), then the first
 * device. Names match as substrings, never exactly (PoCL's device names
 * carry the CPU model).
 */
#include "opencl_select.h"
#include "context.h"
#include "device.h"
#include "opencl_errors.h"
#include "threads.h"

#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_PLATFORMS 16
#define MAX_DEVICES 64

static const char *type_name(cl_device_type t)
{
    if (t & CL_DEVICE_TYPE_GPU)
        return "gpu";
    if (t & CL_DEVICE_TYPE_CPU)
        return "cpu";
    if (t & CL_DEVICE_TYPE_ACCELERATOR)
        return "accelerator";
    return "other";
}

static limn_status platforms(limn_context *ctx, cl_platform_id *ids, cl_uint *count)
{
    threads_apply(ctx); /* PoCL reads its thread count at the first platform query */
    cl_int err = device_test_fault("no-platform") ? -1001
                                                  : clGetPlatformIDs(MAX_PLATFORMS, ids, count);
    if (err == -1001 || (err == CL_SUCCESS && *count == 0))
        return limn_fail(ctx, LIMN_ERR_DEVICE,
                         "no OpenCL platform found (clGetPlatformIDs: %s): install an OpenCL "
                         "driver, e.g. 'apt-get install pocl-opencl-icd' (the ICD loader finds "
                         "drivers through /etc/OpenCL/vendors or OCL_ICD_VENDORS), or run with "
                         "--device reference, or allow --fallback reference",
                         err == -1001 ? opencl_error_name(err) : "no platforms");
    if (err != CL_SUCCESS)
        return limn_fail(ctx, LIMN_ERR_DEVICE, "clGetPlatformIDs failed: %s",
                         opencl_error_name(err));
    if (*count > MAX_PLATFORMS)
        *count = MAX_PLATFORMS;
    return LIMN_OK;
}

static void info_string(cl_device_id d, cl_device_info what, char *buf, size_t size)
{
    if (clGetDeviceInfo(d, what, size, buf, NULL) != CL_SUCCESS)
        snprintf(buf, size, "?");
    buf[size - 1] = '\0';
}

static int contains_ci(const char *hay, const char *needle)
{
    size_t n = strlen(needle);
    for (; *hay; hay++) {
        size_t i = 0;
        while (i < n && hay[i] &&
               tolower((unsigned char)hay[i]) == tolower((unsigned char)needle[i]))
            i++;
        if (i == n)
            return 1;
    }
    return n == 0;
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

limn_status opencl_select_device(limn_context *ctx, const char *spec, opencl_choice *out)
{
    cl_platform_id plats[MAX_PLATFORMS];
    cl_uint np = 0;
    limn_status st = platforms(ctx, plats, &np);
    if (st)
        return st;

    const char *env_platform = getenv("LIMN_PLATFORM");
    const char *env_device = getenv("LIMN_DEVICE");
    const char *env_type = getenv("LIMN_DEVICE_TYPE");
    const char *name_filter = NULL, *platform_filter = NULL, *source = "the first device";
    const char *value = "";
    unsigned want_p = 0, want_d = 0;
    int by_index = 0, type_ok;
    cl_device_type type = CL_DEVICE_TYPE_ALL;

    if (spec && *spec) {
        source = "--device";
        value = spec;
        if (parse_index_pair(spec, &want_p, &want_d))
            by_index = 1;
        else
            name_filter = spec;
    } else {
        if (env_platform && *env_platform) {
            platform_filter = env_platform;
            source = "LIMN_PLATFORM";
            value = env_platform;
        }
        if (env_device && *env_device) {
            source = "LIMN_DEVICE";
            value = env_device;
            if (parse_index_pair(env_device, &want_p, &want_d))
                by_index = 1;
            else
                name_filter = env_device;
        }
        type = parse_type(env_type, &type_ok);
        if (!type_ok)
            return limn_fail(ctx, LIMN_ERR_ARGUMENT,
                             "LIMN_DEVICE_TYPE='%s' is not one of cpu, gpu, accelerator, all",
                             env_type);
        if (env_type && *env_type && strcmp(source, "the first device") == 0) {
            source = "LIMN_DEVICE_TYPE";
            value = env_type;
        }
    }

    opencl_choice match[MAX_DEVICES];
    size_t matches = 0;
    for (cl_uint p = 0; p < np; p++) {
        char pname[96];
        if (clGetPlatformInfo(plats[p], CL_PLATFORM_NAME, sizeof pname, pname, NULL) != CL_SUCCESS)
            snprintf(pname, sizeof pname, "?");
        pname[sizeof pname - 1] = '\0';
        if (platform_filter) {
            unsigned idx;
            char tail;
            int is_index = sscanf(platform_filter, "%u%c", &idx, &tail) == 1;
            if (is_index ? idx != p : !contains_ci(pname, platform_filter))
                continue;
        }
        cl_device_id devs[MAX_DEVICES];
        cl_uint nd = 0;
        cl_int err = clGetDeviceIDs(plats[p], CL_DEVICE_TYPE_ALL, MAX_DEVICES, devs, &nd);
        if (err == CL_DEVICE_NOT_FOUND || device_test_fault("no-device"))
            continue;
        if (err != CL_SUCCESS)
            return limn_fail(ctx, LIMN_ERR_DEVICE, "clGetDeviceIDs on platform %u (%s) failed: %s",
                             p, pname, opencl_error_name(err));
        if (nd > MAX_DEVICES)
            nd = MAX_DEVICES;
        for (cl_uint d = 0; d < nd; d++) {
            char dname[112];
            cl_device_type dt = 0;
            info_string(devs[d], CL_DEVICE_NAME, dname, sizeof dname);
            clGetDeviceInfo(devs[d], CL_DEVICE_TYPE, sizeof dt, &dt, NULL);
            if (by_index && (p != want_p || d != want_d))
                continue;
            if (name_filter && !contains_ci(dname, name_filter))
                continue;
            if (!(dt & type))
                continue;
            /* every match is recorded: MPI ranks of a node take them in turn */
            if (matches < MAX_DEVICES) {
                match[matches].platform = plats[p];
                match[matches].device = devs[d];
                snprintf(match[matches].name, sizeof match[matches].name,
                         "%s [%s, device %u.%u, %s]", dname, pname, p, d, type_name(dt));
                matches++;
            }
        }
    }
    if (matches > 0) {
        *out = match[(size_t)(ctx->device_slot >= 0 ? ctx->device_slot : 0) % matches];
        return LIMN_OK;
    }
    if (!*value)
        return limn_fail(ctx, LIMN_ERR_DEVICE,
                         "no OpenCL device found (%u platform%s, no device): check the driver "
                         "with 'limn devices' or clinfo, or use --device reference, or allow "
                         "--fallback reference",
                         np, np == 1 ? "" : "s");
    return limn_fail(ctx, LIMN_ERR_DEVICE,
                     "no OpenCL device matches %s%s%s%s: run 'limn devices' to list them, or use "
                     "--device reference",
                     source, *value ? "='" : "", value, *value ? "'" : "");
}

limn_status limn_list_devices(limn_context *ctx, char *buf, size_t size)
{
    if (!ctx)
        return LIMN_ERR_ARGUMENT;
    limn_clear(ctx);
    if (!buf || size == 0)
        return limn_fail(ctx, LIMN_ERR_ARGUMENT, "limn_list_devices: %s",
                         !buf ? "buf is NULL"
                              : "buf_size is 0: the buffer cannot hold even the terminating NUL");
    buf[0] = '\0';
    cl_platform_id plats[MAX_PLATFORMS];
    cl_uint np = 0;
    limn_status st = platforms(ctx, plats, &np);
    if (st)
        return st;
    size_t used = 0;
    for (cl_uint p = 0; p < np; p++) {
        char pname[256];
        if (clGetPlatformInfo(plats[p], CL_PLATFORM_NAME, sizeof pname, pname, NULL) != CL_SUCCESS)
            snprintf(pname, sizeof pname, "?");
        pname[sizeof pname - 1] = '\0';
        cl_device_id devs[MAX_DEVICES];
        cl_uint nd = 0;
        if (clGetDeviceIDs(plats[p], CL_DEVICE_TYPE_ALL, MAX_DEVICES, devs, &nd) != CL_SUCCESS)
            nd = 0;
        if (nd > MAX_DEVICES)
            nd = MAX_DEVICES;
        for (cl_uint d = 0; d < nd; d++) {
            char dname[256], version[128];
            cl_device_type dt = 0;
            cl_ulong mem = 0, alloc = 0;
            cl_uint units = 0;
            cl_device_fp_config fp64 = 0;
            info_string(devs[d], CL_DEVICE_NAME, dname, sizeof dname);
            info_string(devs[d], CL_DEVICE_VERSION, version, sizeof version);
            clGetDeviceInfo(devs[d], CL_DEVICE_TYPE, sizeof dt, &dt, NULL);
            clGetDeviceInfo(devs[d], CL_DEVICE_GLOBAL_MEM_SIZE, sizeof mem, &mem, NULL);
            clGetDeviceInfo(devs[d], CL_DEVICE_MAX_MEM_ALLOC_SIZE, sizeof alloc, &alloc, NULL);
            clGetDeviceInfo(devs[d], CL_DEVICE_MAX_COMPUTE_UNITS, sizeof units, &units, NULL);
            clGetDeviceInfo(devs[d], CL_DEVICE_DOUBLE_FP_CONFIG, sizeof fp64, &fp64, NULL);
            int n = snprintf(buf + used, size - used,
                             "%u.%u  %s  [%s, %s]  %s, %u compute units, %.1f GiB memory "
                             "(%.1f GiB per buffer), double precision %s\n",
                             p, d, dname, pname, version, type_name(dt), units,
                             (double)mem / (1 << 30), (double)alloc / (1 << 30),
                             fp64 ? "yes" : "NO");
            if (n < 0 || (size_t)n >= size - used)
                return limn_fail(ctx, LIMN_ERR_ARGUMENT,
                                 "limn_list_devices: the buffer of %zu bytes is too small for "
                                 "the device list",
                                 size);
            used += (size_t)n;
        }
    }
    return LIMN_OK;
}
