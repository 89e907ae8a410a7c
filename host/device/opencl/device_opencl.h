/* SPDX-License-Identifier: MIT */
/*
 * Internals of the OpenCL backend shared by its files: device_opencl.c
 * (context, buffers, double-precision operations), opencl_program.c (the
 * program and its kernels) and device_opencl_mixed.c (the float operations
 * of the mixed-precision refinement).
 */
#ifndef LIMN_DEVICE_OPENCL_H
#define LIMN_DEVICE_OPENCL_H

#include "device/device.h"
#include "device/opencl/opencl_errors.h"
#include "device/opencl/opencl_shape.h"

/* Every kernel of the program; each takes `uint rows` as its first argument. */
typedef enum opencl_kernel_id {
    K_SPMV,
    K_INTERP_STEP,
    K_SERIES_STEP,
    K_AXPBY,
    K_NORMS,
    K_SPMV_DOT,
    K_PCG_UPDATE,
    K_CHEB_STEP,
    K_RESIDUAL_F,
    K_STEP_F,
    K_ADD_F,
    K_TO_FLOAT,
    K_SGS_UPPER,
    K_SGS_LOWER,
    K_SGS_UPDATE,
    K_COUNT
} opencl_kernel_id;

struct device_buffer {
    cl_mem mem;
    size_t bytes;
    int shared;   /* CL_MEM_USE_HOST_PTR: the queue finishes before it is released */
    void *host;   /* that host memory, when shared */
    int owns_host; /* host came from device_host_alloc for this buffer: freed with it */
};

typedef struct opencl_impl {
    cl_context context;
    cl_command_queue queue;
    cl_device_id device;
    cl_program program;
    cl_kernel kernels[K_COUNT];
    int compiled[K_COUNT];    /* launched once (PoCL compiled its work-group function) */
    cl_ulong max_alloc;
    cl_bool host_unified;     /* CL_DEVICE_HOST_UNIFIED_MEMORY: buffers may use host memory */
    opencl_shape shape;       /* the kernels' shape (opencl_shape.h), fixed at build */
    cl_mem partials;          /* 3 doubles per partial slot, grown on demand */
    size_t partials_items;
    double *host_partials;
    cl_mem staging;           /* pinned staging of large transfers (opencl_staging.h) */
    void *staging_host;       /* its mapping, for the device's life */
    size_t staging_bytes;
    int staging_failed;       /* could not be made: transfers go direct */
} opencl_impl;

#define CHECK(call, what)                                                                      \
    do {                                                                                       \
        cl_int err_ = (call);                                                                  \
        if (err_ != CL_SUCCESS)                                                                \
            return ctx_fail(dev->ctx, LIMN_ERR_DEVICE, "%s failed: %s (%d)", what,            \
                             opencl_error_name(err_), err_);                                   \
    } while (0)

static inline opencl_impl *impl_of(struct device *dev) { return dev->impl; }

/* Builds the program (all kernels, one build: PoCL's warm-cache cost hardly
   depends on its size) and creates its kernels; times dev->setup.build. */
limn_status opencl_build_program(struct device *dev);
void opencl_release_program(opencl_impl *im);
const char *opencl_kernel_name(opencl_kernel_id id);

/* One kernel argument: its size, a pointer to its value, and its name for
   the error message. */
typedef struct opencl_arg {
    size_t size;
    const void *value;
    const char *name;
} opencl_arg;
#define OPENCL_MEM(buf, name) {sizeof(cl_mem), &(buf)->mem, name}
#define OPENCL_VALUE(var, name) {sizeof(var), &(var), name}
/* Binds args[0 .. count) to arguments first, first + 1, ... of k. */
limn_status opencl_bind(struct device *dev, cl_kernel k, cl_uint first, const opencl_arg *args,
                        size_t count);
/* Binds rows and the CSR table to arguments 0-3. */
limn_status opencl_set_csr_args(struct device *dev, cl_kernel k, const device_csr *a,
                                device_buffer *weights);
/* Enqueues kernel `id` over `rows` rows from work-item first_item (arguments
   already set). */
limn_status opencl_launch(struct device *dev, opencl_kernel_id id, size_t first_item,
                          size_t rows);
/* A row range's first work-item and first partial slot (device_csr.row_begin
   is a multiple of DEVICE_ROWS_PER_ITEM, so of either shape's rows per item
   and per slot). */
static inline size_t opencl_first_item(struct device *dev, const device_csr *a)
{
    return a->row_begin / impl_of(dev)->shape.rows_per_item;
}
static inline size_t opencl_first_slot(struct device *dev, const device_csr *a)
{
    return a->row_begin / impl_of(dev)->shape.rows_per_slot;
}
/* Makes room for the partial norms of `rows` rows from slot first_slot. */
limn_status opencl_ensure_partials(struct device *dev, size_t first_slot, size_t rows);
/* Reads those partial norms and finishes them in slot order. */
limn_status opencl_finish_partials(struct device *dev, size_t first_slot, size_t rows,
                                   device_norms *out);
/* A reducing kernel over table a: room for its partials, the table bound as
   arguments 0-3 (with `weights`), args[0 .. count) from argument 4, the
   launch over a's rows, its partial norms finished into out. An argument
   that names im->partials is read when bound, after the room is made. */
limn_status opencl_reduce(struct device *dev, opencl_kernel_id id, const device_csr *a,
                          device_buffer *weights, const opencl_arg *args, size_t count,
                          device_norms *out);
/* The same for a kernel over rows [0, rows) without a table: args from 0. */
limn_status opencl_reduce_rows(struct device *dev, opencl_kernel_id id, size_t rows,
                               const opencl_arg *args, size_t count, device_norms *out);

/* The float family (device_opencl_mixed.c) and the sweeps (device_opencl_sgs.c). */
extern const device_mixed_ops cl_mixed_ops;
extern const device_sgs_ops cl_sgs_ops;

#endif
