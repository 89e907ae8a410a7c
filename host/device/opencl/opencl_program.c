/* SPDX-License-Identifier: MIT */
/*
 * The OpenCL program: kernels/common.cl (the shared helpers), stencil.cl,
 * series.cl, solve.cl, mixed.cl and sgs.cl built as one program (the later
 * files use common.cl's row ranges and products), and
 * its kernels. One build, not one per family: with PoCL a warm-cache build
 * costs ~25 ms whatever the program's size, a cold one ~0.55 s (mostly
 * compiler start-up), so splitting would multiply the warm cost.
 */
#include "base/context.h"
#include "device/opencl/device_opencl.h"
#include "device/opencl/opencl_pocl_cache.h"
#include "base/clock.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* kernels/NAME.cl, embedded at build time (cmake/embed.cmake) */
#define KERNEL_SOURCE(name)                                                                    \
    extern const unsigned char kernel_source_##name[];                                         \
    extern const size_t kernel_source_##name##_size
KERNEL_SOURCE(common);
KERNEL_SOURCE(stencil);
KERNEL_SOURCE(series);
KERNEL_SOURCE(solve);
KERNEL_SOURCE(mixed);
KERNEL_SOURCE(sgs);

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

/* The device's whole build log (asked for its size first), or a note saying
   why there is none; heap, the caller frees it (NULL: out of memory). */
static char *build_log(cl_program program, cl_device_id device)
{
    size_t size = 0;
    cl_int err = clGetProgramBuildInfo(program, device, CL_PROGRAM_BUILD_LOG, 0, NULL, &size);
    char *log = NULL;
    if (err == CL_SUCCESS && size > 1 && (log = malloc(size + 1)) != NULL) {
        err = clGetProgramBuildInfo(program, device, CL_PROGRAM_BUILD_LOG, size, log, NULL);
        log[size] = '\0';
        if (err == CL_SUCCESS && log[0])
            return log;
        free(log);
    }
    const char *fmt = err != CL_SUCCESS ? "(none: clGetProgramBuildInfo(CL_PROGRAM_BUILD_LOG) "
                                          "failed: %s)"
                                        : "(empty: the driver gave none%s; PoCL prints its "
                                          "compiler's errors on stderr)";
    size_t n = 160;
    if ((log = malloc(n)) != NULL)
        snprintf(log, n, fmt, err != CL_SUCCESS ? opencl_error_name(err) : "");
    return log;
}

/* Builds with `options` and creates every kernel; on failure the message
   names the failing call and carries the device's whole build log, and
   *prefetch_suspect says whether prefetching may be the cause (the kernels
   built but one cannot be created, or the log names it). */
static limn_status build_with(struct device *dev, const char *options, int *prefetch_suspect)
{
    *prefetch_suspect = 0;
    opencl_impl *im = impl_of(dev);
    /* common.cl first: the helpers the other files use */
    const char *src[6] = {(const char *)kernel_source_common, (const char *)kernel_source_stencil,
                          (const char *)kernel_source_series, (const char *)kernel_source_solve,
                          (const char *)kernel_source_mixed, (const char *)kernel_source_sgs};
    size_t len[6] = {kernel_source_common_size, kernel_source_stencil_size,
                     kernel_source_series_size, kernel_source_solve_size,
                     kernel_source_mixed_size, kernel_source_sgs_size};
    cl_int err;
    im->program = clCreateProgramWithSource(im->context, 6, src, len, &err);
    CHECK(err, "clCreateProgramWithSource");
    err = clBuildProgram(im->program, 1, &im->device, options, NULL, NULL);
    if (err != CL_SUCCESS) {
        char *log = build_log(im->program, im->device);
        *prefetch_suspect = log && strstr(log, "prefetch") != NULL;
        char cache[1400] = "";
        int cache_bad = opencl_pocl_cache_problem(cache, sizeof cache);
        limn_status st = ctx_fail(
            dev->ctx, LIMN_ERR_DEVICE,
            "building the OpenCL kernels for %s (clBuildProgram) failed: %s: the device's OpenCL "
            "compiler rejected them; choose another device with --device (see 'limn devices') "
            "or use --device reference (or allow --fallback reference)%s%s\n"
            "build options: %s\nbuild log:\n%s",
            dev->name, opencl_error_name(err), cache_bad ? "; " : "", cache, options,
            log ? log : "(out of memory for it)");
        free(log);
        return st;
    }
    for (int k = 0; k < K_COUNT; k++) {
        im->kernels[k] = clCreateKernel(im->program, kernel_names[k], &err);
        /* test-only (device.h): a device that cannot run __builtin_prefetch */
        if (err == CL_SUCCESS && k == K_INTERP_STEP && strstr(options, "LIMN_PREFETCH") &&
            device_test_fault("prefetch"))
            err = CL_INVALID_KERNEL_NAME;
        *prefetch_suspect = err != CL_SUCCESS;
        if (err != CL_SUCCESS)
            return ctx_fail(dev->ctx, LIMN_ERR_DEVICE,
                             "clCreateKernel(%s) failed on %s: %s (%d); build options: %s",
                             kernel_names[k], dev->name, opencl_error_name(err), err, options);
    }
    return LIMN_OK;
}

/* The build options: the shape's (opencl_shape_options), prefetching when
   `prefetch`, then the test's extra ones. */
static void program_options(const opencl_impl *im, int prefetch, char *options, size_t size)
{
    /* test-only: options appended to the build (tests/test_opencl.c) */
    const char *extra = getenv("LIMN_TEST_EXTRA_BUILD_OPTIONS");
    char shape[160];
    opencl_shape_options(&im->shape, shape, sizeof shape);
    snprintf(options, size, "%s%s%s%s", shape, prefetch ? " -D LIMN_PREFETCH=96" : "",
             extra && *extra ? " " : "", extra ? extra : "");
    if (device_test_fault("build")) /* test-only (device.h): a genuine compile error */
        snprintf(options, size, "-D ROWS_PER_ITEM=limn_test_fault_build");
}

static void drop_program(opencl_impl *im)
{
    opencl_release_program(im);
    memset(im->kernels, 0, sizeof im->kernels);
    im->program = NULL;
}

/* Builds with prefetching when `prefetch`; if that fails in a way prefetching
   may cause, once more without, with a warning. */
static limn_status build_shaped(struct device *dev, int prefetch)
{
    opencl_impl *im = impl_of(dev);
    char options[512];
    program_options(im, prefetch, options, sizeof options);
    int suspect;
    limn_status st = build_with(dev, options, &suspect);
    if (st && prefetch && suspect) {
        /* a compiler that takes __builtin_prefetch but cannot run it: once
           more without, so that prefetching never costs the device */
        char first[sizeof dev->ctx->message];
        snprintf(first, sizeof first, "%s", limn_context_message(dev->ctx));
        drop_program(im);
        program_options(im, 0, options, sizeof options);
        st = build_with(dev, options, &suspect);
        if (!st)
            ctx_warn(dev->ctx, "%s: built without prefetching the gathers (with it: %.600s)",
                      dev->name, first);
    }
    return st;
}

/* The least CL_KERNEL_WORK_GROUP_SIZE over the program's kernels (0: none
   reported). */
static size_t least_kernel_group(const opencl_impl *im)
{
    size_t least = 0;
    for (int k = 0; k < K_COUNT; k++) {
        size_t g = 0;
        if (clGetKernelWorkGroupInfo(im->kernels[k], im->device, CL_KERNEL_WORK_GROUP_SIZE,
                                     sizeof g, &g, NULL) == CL_SUCCESS &&
            g && (!least || g < least))
            least = g;
    }
    return least;
}

limn_status opencl_build_program(struct device *dev)
{
    opencl_impl *im = impl_of(dev);
    double t0 = clock_seconds();
    limn_status st = opencl_shape_choose(dev->ctx, im->device, &im->shape);
    if (st)
        return st;
    /* gathers prefetched ahead on CPU devices whose compiler targets the
       machine (kernels/common.cl: not SPIR, e.g. Oclgrind), in the cpu shape */
    cl_device_type type = 0;
    clGetDeviceInfo(im->device, CL_DEVICE_TYPE, sizeof type, &type, NULL);
    int prefetch = (type & CL_DEVICE_TYPE_CPU) != 0 && !im->shape.gpu;
    st = build_shaped(dev, prefetch);
    if (!st && opencl_shape_fit(&im->shape, least_kernel_group(im))) {
        /* a kernel allows smaller groups than the device: its GROUP_SIZE */
        drop_program(im);
        st = build_shaped(dev, prefetch);
    }
    dev->sell_slice = im->shape.sell_slice;
    dev->setup.build += clock_seconds() - t0;
    return st;
}

void opencl_release_program(opencl_impl *im)
{
    for (int k = 0; k < K_COUNT; k++)
        if (im->kernels[k])
            clReleaseKernel(im->kernels[k]);
    if (im->program)
        clReleaseProgram(im->program);
}
