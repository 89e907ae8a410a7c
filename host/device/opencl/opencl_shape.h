/* SPDX-License-Identifier: MIT */
/*
 * The kernels' shape on one device, chosen when the program is built
 * (opencl_shape.c; the kernels: kernels/common.cl, KERNEL_SHAPE_GPU).
 *   cpu: DEVICE_ROWS_PER_ITEM consecutive rows per work-item, groups of
 *        DEVICE_WORKGROUP items (fewer where the device allows fewer), one
 *        partial reduction per item, the CSR table. PoCL's CPU device.
 *   gpu: one row per work-item (consecutive items: consecutive rows, so the
 *        4-double vectors are read coalesced), the table in SELL-C slices
 *        (host/stencil/stencil_sell.h: coalesced gathers of columns and
 *        weights; the SGS sweeps keep CSR), groups of a power of two up to
 *        256 that the device and every kernel allow, one partial per group
 *        reduced in local memory by a fixed pairwise tree.
 * Either way the per-slot partials are finished on the host in slot order,
 * so results are deterministic per device and shape.
 */
#ifndef LIMN_OPENCL_SHAPE_H
#define LIMN_OPENCL_SHAPE_H

#include "device/opencl/opencl_errors.h"
#include "limn.h"

#include <stddef.h>

typedef struct opencl_shape {
    int gpu;              /* the GPU shape */
    size_t rows_per_item; /* cpu: DEVICE_ROWS_PER_ITEM; gpu: 1 */
    size_t group;         /* work-group size */
    size_t rows_per_slot; /* rows behind one partial: cpu an item's, gpu a group's */
    size_t sell_slice;    /* gpu: rows per SELL slice (SELL_C); cpu: 0, CSR */
} opencl_shape;

/* The device's shape: CPU devices whose groups reach DEVICE_WORKGROUP get
   the cpu shape, others the gpu shape; LIMN_KERNEL_SHAPE=cpu|gpu (a
   test-only override, docs/testing.md) forces either. Fails on another
   value of it, naming it. */
limn_status opencl_shape_choose(limn_context *ctx, cl_device_id device, opencl_shape *out);
/* Narrows the group to what every kernel allows (the least
   CL_KERNEL_WORK_GROUP_SIZE, min_kernel_group); 1 when the gpu shape's group
   changed, so the program must be built again (its GROUP_SIZE is a -D). */
int opencl_shape_fit(opencl_shape *s, size_t min_kernel_group);
/* The build options that select the shape ("-D ROWS_PER_ITEM=... ..."). */
void opencl_shape_options(const opencl_shape *s, char *buf, size_t size);
/* "cpu" or "gpu". */
const char *opencl_shape_name(const opencl_shape *s);

/* Work-items for `rows` rows, rounded up to whole groups. */
size_t opencl_shape_items(const opencl_shape *s, size_t rows);
/* The partial slots a launch over `rows` rows spans (its items or groups). */
size_t opencl_shape_slots(const opencl_shape *s, size_t rows);
/* The slots of those that hold partials (the rest belong to no row). */
size_t opencl_shape_chunks(const opencl_shape *s, size_t rows);

#endif
