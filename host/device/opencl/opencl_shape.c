/* SPDX-License-Identifier: MIT */
/* The kernel shape of a device (opencl_shape.h). */
#include "device/opencl/opencl_shape.h"
#include "base/context.h"
#include "device/device.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The GPU shape's largest group (also the SELL row-range alignment: a
   device_csr.row_begin, a multiple of DEVICE_ROWS_PER_ITEM, is then a whole
   number of groups and slices). */
#define GPU_GROUP_MAX 256
/* Rows per SELL slice: NVIDIA's warp; a multiple of AMD's 64-lane
   wavefront's half, and a divisor of DEVICE_ROWS_PER_ITEM. */
#define GPU_SELL_C 32

static size_t floor_pow2(size_t n)
{
    size_t p = 1;
    while (p * 2 <= n)
        p *= 2;
    return p;
}

/* The device's group limit: the least of CL_DEVICE_MAX_WORK_GROUP_SIZE and
   the first dimension of CL_DEVICE_MAX_WORK_ITEM_SIZES (at least 1). */
static size_t device_group_limit(cl_device_id device)
{
    size_t max_group = 1, sizes[3] = {1, 1, 1};
    clGetDeviceInfo(device, CL_DEVICE_MAX_WORK_GROUP_SIZE, sizeof max_group, &max_group, NULL);
    clGetDeviceInfo(device, CL_DEVICE_MAX_WORK_ITEM_SIZES, sizeof sizes, sizes, NULL);
    size_t limit = max_group < sizes[0] ? max_group : sizes[0];
    return limit ? limit : 1;
}

static void set_shape(opencl_shape *s, int gpu, size_t limit)
{
    memset(s, 0, sizeof *s);
    s->gpu = gpu;
    if (gpu) {
        s->rows_per_item = 1;
        s->group = floor_pow2(limit < GPU_GROUP_MAX ? limit : GPU_GROUP_MAX);
        s->rows_per_slot = s->group;
        s->sell_slice = GPU_SELL_C;
    } else {
        s->rows_per_item = DEVICE_ROWS_PER_ITEM;
        s->group = limit < DEVICE_WORKGROUP ? limit : DEVICE_WORKGROUP;
        s->rows_per_slot = DEVICE_ROWS_PER_ITEM;
    }
}

limn_status opencl_shape_choose(limn_context *ctx, cl_device_id device, opencl_shape *out)
{
    cl_device_type type = 0;
    clGetDeviceInfo(device, CL_DEVICE_TYPE, sizeof type, &type, NULL);
    size_t limit = device_group_limit(device);
    int gpu = !(type & CL_DEVICE_TYPE_CPU) || limit < DEVICE_WORKGROUP;
    const char *force = getenv("LIMN_KERNEL_SHAPE"); /* test-only (docs/testing.md) */
    if (force && *force) {
        if (strcmp(force, "cpu") != 0 && strcmp(force, "gpu") != 0)
            return ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                            "LIMN_KERNEL_SHAPE is '%s'; it takes cpu or gpu (a test-only "
                            "override of the kernel shape), or unset it",
                            force);
        gpu = force[0] == 'g';
    }
    set_shape(out, gpu, limit);
    return LIMN_OK;
}

int opencl_shape_fit(opencl_shape *s, size_t min_kernel_group)
{
    if (min_kernel_group == 0 || min_kernel_group >= s->group)
        return 0;
    if (!s->gpu) {
        s->group = min_kernel_group; /* the cpu kernels do not depend on it */
        return 0;
    }
    s->group = floor_pow2(min_kernel_group);
    s->rows_per_slot = s->group;
    return 1;
}

void opencl_shape_options(const opencl_shape *s, char *buf, size_t size)
{
    if (s->gpu)
        snprintf(buf, size,
                 "-D ROWS_PER_ITEM=1 -D KERNEL_SHAPE_GPU=1 -D GROUP_SIZE=%zu -D SELL_C=%zu",
                 s->group, s->sell_slice);
    else
        snprintf(buf, size, "-D ROWS_PER_ITEM=%zu", s->rows_per_item);
}

const char *opencl_shape_name(const opencl_shape *s) { return s->gpu ? "gpu" : "cpu"; }

size_t opencl_shape_items(const opencl_shape *s, size_t rows)
{
    size_t items = (rows + s->rows_per_item - 1) / s->rows_per_item;
    return (items + s->group - 1) / s->group * s->group;
}

size_t opencl_shape_slots(const opencl_shape *s, size_t rows)
{
    size_t items = opencl_shape_items(s, rows);
    return s->gpu ? items / s->group : items;
}

size_t opencl_shape_chunks(const opencl_shape *s, size_t rows)
{
    return (rows + s->rows_per_slot - 1) / s->rows_per_slot;
}
