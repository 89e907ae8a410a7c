/* SPDX-License-Identifier: MIT */
/*
 * Which OpenCL devices limn can run on, and which ones a choice matches.
 * The kernels need double precision (every operator is double; float is
 * only the mixed solve's correction) and OpenCL 1.2 (clEnqueueFillBuffer, CL_PROGRAM_KERNEL_NAMES). Names match
 * as substrings, never exactly (PoCL's device names carry the CPU model).
 */
#include "device/opencl/opencl_usable.h"
#include "device/device.h"

#include <ctype.h>
#include <stdio.h>
#include <string.h>

static void info_string(cl_device_id d, cl_device_info what, char *buf, size_t size)
{
    if (clGetDeviceInfo(d, what, size, buf, NULL) != CL_SUCCESS)
        snprintf(buf, size, "?");
    buf[size - 1] = '\0';
}

void opencl_read_props(cl_platform_id platform, cl_device_id device, unsigned p, unsigned d,
                       const char *platform_name, opencl_device_props *out)
{
    memset(out, 0, sizeof *out);
    out->platform_id = platform;
    out->id = device;
    out->platform_index = p;
    out->device_index = d;
    snprintf(out->platform, sizeof out->platform, "%s", platform_name);
    info_string(device, CL_DEVICE_NAME, out->name, sizeof out->name);
    info_string(device, CL_DEVICE_VERSION, out->version, sizeof out->version);
    clGetDeviceInfo(device, CL_DEVICE_TYPE, sizeof out->type, &out->type, NULL);
    clGetDeviceInfo(device, CL_DEVICE_DOUBLE_FP_CONFIG, sizeof out->fp64, &out->fp64, NULL);
    /* a limit the driver does not report is not held against the device */
    if (clGetDeviceInfo(device, CL_DEVICE_MAX_WORK_GROUP_SIZE, sizeof out->max_work_group,
                        &out->max_work_group, NULL) != CL_SUCCESS)
        out->max_work_group = (size_t)-1;
    size_t sizes[64];
    cl_uint dims = 0;
    if (clGetDeviceInfo(device, CL_DEVICE_MAX_WORK_ITEM_DIMENSIONS, sizeof dims, &dims, NULL) ==
            CL_SUCCESS &&
        dims >= 1 && dims <= 64 &&
        clGetDeviceInfo(device, CL_DEVICE_MAX_WORK_ITEM_SIZES, dims * sizeof *sizes, sizes,
                        NULL) == CL_SUCCESS)
        out->max_item_size = sizes[0];
    else
        out->max_item_size = (size_t)-1;
    clGetDeviceInfo(device, CL_DEVICE_GLOBAL_MEM_SIZE, sizeof out->mem, &out->mem, NULL);
    clGetDeviceInfo(device, CL_DEVICE_MAX_MEM_ALLOC_SIZE, sizeof out->alloc, &out->alloc, NULL);
    clGetDeviceInfo(device, CL_DEVICE_MAX_COMPUTE_UNITS, sizeof out->units, &out->units, NULL);
    if (p == 0 && d == 0 && device_test_fault("no-fp64"))
        out->fp64 = 0;
}

int opencl_unusable(const opencl_device_props *d, char *why, size_t size)
{
    unsigned major = 0, minor = 0;
    if (sscanf(d->version, "OpenCL %u.%u", &major, &minor) != 2 ||
        major * 100 + minor < 102) {
        snprintf(why, size, "needs OpenCL 1.2, the device has '%s'", d->version);
        return 1;
    }
    if (!d->fp64) {
        snprintf(why, size, "no double precision (CL_DEVICE_DOUBLE_FP_CONFIG is 0: no "
                            "cl_khr_fp64)");
        return 1;
    }
    /* any group size runs: below DEVICE_WORKGROUP the gpu kernel shape
       (opencl_shape.c) takes groups as small as the device's */
    return 0;
}

int opencl_contains_ci(const char *hay, const char *needle)
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

const char *opencl_type_name(cl_device_type t)
{
    if (t & CL_DEVICE_TYPE_GPU)
        return "gpu";
    if (t & CL_DEVICE_TYPE_CPU)
        return "cpu";
    if (t & CL_DEVICE_TYPE_ACCELERATOR)
        return "accelerator";
    return "other";
}

static int matches(const opencl_device_props *d, const opencl_criteria *c)
{
    if (c->platform) {
        unsigned idx;
        char tail;
        int is_index = sscanf(c->platform, "%u%c", &idx, &tail) == 1;
        if (is_index ? idx != d->platform_index : !opencl_contains_ci(d->platform, c->platform))
            return 0;
    }
    if (c->by_index && (d->platform_index != c->p || d->device_index != c->d))
        return 0;
    if (c->name && !opencl_contains_ci(d->name, c->name))
        return 0;
    return (d->type & c->type) != 0;
}

size_t opencl_pick(const opencl_device_props *devs, size_t n, const opencl_criteria *c,
                   size_t *usable, size_t *unusable, size_t *n_unusable)
{
    size_t good = 0;
    char why[160];
    *n_unusable = 0;
    for (size_t i = 0; i < n; i++) {
        if (!matches(&devs[i], c))
            continue;
        if (opencl_unusable(&devs[i], why, sizeof why))
            unusable[(*n_unusable)++] = i;
        else
            usable[good++] = i;
    }
    return good;
}
