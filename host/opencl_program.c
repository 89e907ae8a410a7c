/*
 * The OpenCL program: kernels/stencil.cl, series.cl, solve.cl and mixed.cl
 * built as one program (the later files use stencil.cl's row_product), and
 * its kernels. One build, not one per family: with PoCL a warm-cache build
 * costs ~25 ms whatever the program's size, a cold one ~0.55 s (mostly
 * compiler start-up), so splitting would multiply the warm cost.
 */
#include "context.h"
#include "device_opencl.h"
#include "operator.h"

#include <stdio.h>
#include <string.h>

extern const unsigned char limn_kernel_stencil[];
extern const size_t limn_kernel_stencil_size;
extern const unsigned char limn_kernel_series[];
extern const size_t limn_kernel_series_size;
extern const unsigned char limn_kernel_solve[];
extern const size_t limn_kernel_solve_size;
extern const unsigned char limn_kernel_mixed[];
extern const size_t limn_kernel_mixed_size;
extern const unsigned char limn_kernel_sgs[];
extern const size_t limn_kernel_sgs_size;

static const char *const kernel_names[K_COUNT] = {
    [K_SPMV] = "spmv",
    [K_INTERP_STEP] = "interp_step",
    [K_SERIES_STEP] = "series_step",
    [K_AXPBY] = "axpby",
    [K_NORMS] = "norms",
    [K_SPMV_DOT] = "spmv_dot",
    [K_PCG_UPDATE] = "pcg_update",
    [K_CHEB_STEP] = "cheb_step",
    [K_RESIDUAL_F] = "residual_f",
    [K_STEP_F] = "step_f",
    [K_ADD_F] = "add_f",
    [K_TO_FLOAT] = "to_float",
    [K_SGS_UPPER] = "sgs_upper",
    [K_SGS_LOWER] = "sgs_lower",
    [K_SGS_UPDATE] = "sgs_update",
};

const char *opencl_kernel_name(opencl_kernel_id id) { return kernel_names[id]; }

limn_status opencl_build_program(struct limn_device *dev)
{
    opencl_impl *im = impl_of(dev);
    double t0 = limn_seconds();
    const char *src[5] = {(const char *)limn_kernel_stencil, (const char *)limn_kernel_series,
                          (const char *)limn_kernel_solve, (const char *)limn_kernel_mixed,
                          (const char *)limn_kernel_sgs};
    size_t len[5] = {limn_kernel_stencil_size, limn_kernel_series_size, limn_kernel_solve_size,
                     limn_kernel_mixed_size, limn_kernel_sgs_size};
    cl_int err;
    im->program = clCreateProgramWithSource(im->context, 5, src, len, &err);
    CHECK(err, "clCreateProgramWithSource");
    /* gathers prefetched ahead on CPU devices only (kernels/stencil.cl) */
    cl_device_type type = 0;
    clGetDeviceInfo(im->device, CL_DEVICE_TYPE, sizeof type, &type, NULL);
    char options[128];
    snprintf(options, sizeof options, "-D ROWS_PER_ITEM=%d%s", DEVICE_ROWS_PER_ITEM,
             type & CL_DEVICE_TYPE_CPU ? " -D LIMN_PREFETCH=96" : "");
    if (device_test_fault("build")) /* test-only (device.h): a genuine compile error */
        snprintf(options, sizeof options, "-D ROWS_PER_ITEM=limn_test_fault_build");
    err = clBuildProgram(im->program, 1, &im->device, options, NULL, NULL);
    if (err != CL_SUCCESS) {
        char log[1500] = "";
        clGetProgramBuildInfo(im->program, im->device, CL_PROGRAM_BUILD_LOG, sizeof log - 1, log,
                              NULL);
        log[sizeof log - 1] = '\0';
        if (!log[0])
            snprintf(log, sizeof log, "(empty: the driver gave none; PoCL prints its compiler's "
                                      "errors on stderr)");
        return limn_fail(dev->ctx, LIMN_ERR_DEVICE,
                         "building the OpenCL kernels for %s failed: %s: the device's OpenCL "
                         "compiler rejected them; choose another device with --device (see "
                         "'limn devices') or use --device reference (or allow --fallback "
                         "reference); for PoCL, check that its kernel cache (POCL_CACHE_DIR, "
                         "default ~/.cache/pocl) is writable\nbuild log:\n%s",
                         dev->name, opencl_error_name(err), log);
    }
    for (int k = 0; k < K_COUNT; k++) {
        im->kernels[k] = clCreateKernel(im->program, kernel_names[k], &err);
        if (err != CL_SUCCESS)
            return limn_fail(dev->ctx, LIMN_ERR_DEVICE, "clCreateKernel(%s) failed: %s (%d)",
                             kernel_names[k], opencl_error_name(err), err);
    }
    dev->setup.build += limn_seconds() - t0;
    return LIMN_OK;
}

void opencl_release_program(opencl_impl *im)
{
    for (int k = 0; k < K_COUNT; k++)
        if (im->kernels[k])
            clReleaseKernel(im->kernels[k]);
    if (im->program)
        clReleaseProgram(im->program);
}
