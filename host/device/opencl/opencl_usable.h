/* SPDX-License-Identifier: MIT */
/*
 * What limn needs of an OpenCL device, and which devices a choice matches:
 * pure functions over a properties array (opencl_select.c fills it from the
 * driver; tests/test_opencl.c feeds fakes).
 */
#ifndef LIMN_OPENCL_USABLE_H
#define LIMN_OPENCL_USABLE_H
#include <CL/cl.h>
#include <stddef.h>

typedef struct opencl_device_props {
    cl_platform_id platform_id;
    cl_device_id id;
    unsigned platform_index, device_index;
    char platform[96];
    char name[112];
    char version[96];          /* CL_DEVICE_VERSION, "OpenCL X.Y ..." */
    cl_device_type type;
    cl_device_fp_config fp64;  /* CL_DEVICE_DOUBLE_FP_CONFIG; 0: no double */
    size_t max_work_group;     /* CL_DEVICE_MAX_WORK_GROUP_SIZE */
    size_t max_item_size;      /* CL_DEVICE_MAX_WORK_ITEM_SIZES[0] */
    cl_ulong mem, alloc;
    cl_uint units;
} opencl_device_props;

/* The device's properties; LIMN_TEST_FAULT=no-fp64 (test-only, device.h)
   makes device 0.0 report no double precision. */
void opencl_read_props(cl_platform_id platform, cl_device_id device, unsigned p, unsigned d,
                       const char *platform_name, opencl_device_props *out);

/* 0 when limn can run on the device; else 1 and why not, in a few words. */
int opencl_unusable(const opencl_device_props *d, char *why, size_t size);

typedef struct opencl_criteria {
    const char *platform;      /* platform name substring or index; NULL: any */
    const char *name;          /* device name substring; NULL: any */
    int by_index;              /* only device p.d */
    unsigned p, d;
    cl_device_type type;       /* CL_DEVICE_TYPE_ALL: any */
} opencl_criteria;

/* Of the n devices, the matches of c in order: the usable ones' indices to
   usable[] (returns their count), the others' to unusable[] (*n_unusable);
   both arrays hold n. */
size_t opencl_pick(const opencl_device_props *devs, size_t n, const opencl_criteria *c,
                   size_t *usable, size_t *unusable, size_t *n_unusable);

/* Case-insensitive substring test ("" matches). */
int opencl_contains_ci(const char *hay, const char *needle);
const char *opencl_type_name(cl_device_type t);
#endif
