/* SPDX-License-Identifier: MIT */
/*
 * OpenCL faults (issue 6): no ICD / no platform, no device matching the
 * user's choice, a program that does not build, device memory exhausted, a
 * kernel that fails at launch. Each gives exit status 1, a message saying
 * what to do and no output; with the fallback allowed (--fallback reference
 * or LIMN_FALLBACK=reference) the run completes on the reference backend,
 * says so in a warning, and writes exactly the reference backend's bytes.
 * Faults are injected with the test-only LIMN_TEST_FAULT hook (host/device/device.h)
 * and, for the missing ICD, for real with OCL_ICD_VENDORS naming an empty
 * directory.
 */
#include "shell.h"
#include "support.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmocka.h>


static int setup(void **s)
{
    (void)s;
    if (test_scratch_make("faults", NULL) != 0)
        return -1;
    char empty[128];
    snprintf(empty, sizeof empty, "%s/no_icd", test_dir);
    return mkdir(empty, 0755);
}

/* Runs `env ENV limn ARGS`; output in test_text; returns the exit status. */
#define run(env, ...) test_limn(test_text, sizeof test_text, env, __VA_ARGS__)
static const char *spot(void) { return test_data_path("spot_control_mesh.obj"); }

typedef struct fault {
    const char *env;          /* what breaks the device */
    const char *message;      /* the error names the fault ... */
    const char *advice;       /* ... and says what to do */
    int at_open;              /* the device fails to open (else during the run) */
} fault;

static fault faults(size_t i, char *env, size_t size)
{
    static const fault table[] = {
        {"OCL_ICD_VENDORS=%s/no_icd", "no OpenCL platform found (clGetPlatformIDs: "
                                      "CL_PLATFORM_NOT_FOUND_KHR)",
         "install an OpenCL driver, e.g. 'apt-get install pocl-opencl-icd'", 1},
        {"LIMN_TEST_FAULT=no-platform", "no OpenCL platform found",
         "or run with --device reference, or allow --fallback reference", 1},
        {"LIMN_TEST_FAULT=no-device", "no OpenCL device found (1 platform, no device)",
         "check the driver with 'limn devices' or clinfo, or use --device reference", 1},
        {"LIMN_TEST_FAULT=build", "building the OpenCL kernels for",
         "failed: CL_BUILD_PROGRAM_FAILURE: the device's OpenCL compiler rejected them; choose "
         "another device with --device (see 'limn devices') or use --device reference",
         1},
        {"LIMN_TEST_FAULT=alloc", "failed: CL_MEM_OBJECT_ALLOCATION_FAILURE",
         "the device is out of memory; use a device with more (--device, see 'limn devices'), "
         "a smaller mesh, or --device reference",
         0},
        {"LIMN_TEST_FAULT=enqueue", "launching kernel ",
         "failed: CL_OUT_OF_RESOURCES (-5): the device could not run it; try another device", 0},
    };
    if (i >= sizeof table / sizeof *table)
        return (fault){NULL, NULL, NULL, 0};
    snprintf(env, size, table[i].env, test_dir);
    return table[i];
}

/* Each fault: refused without the fallback, completed on the reference
   backend with it (flag or environment), for interpolate and subdivide
   (--limit: the refined positions are made on the host, the limit points on
   the device). */
static void each_fault(void **s)
{
    (void)s;
    char out[256], ref[256], env[512], env2[600];
    snprintf(out, sizeof out, "%s/out.ply", test_dir);
    static const char *const commands[] = {"interpolate '%s' -o '%s' %s",
                                           "subdivide '%s' -o '%s' --levels 2 --limit %s"};
    for (size_t c = 0; c < 2; c++) {
        snprintf(ref, sizeof ref, "%s/ref%zu.ply", test_dir, c);
        assert_int_equal(run("", commands[c], spot(), ref, "--device reference -q"), 0);
        fault f;
        for (size_t i = 0; (f = faults(i, env, sizeof env)).env; i++) {
            int rc = run(env, commands[c], spot(), out, "");
            if (rc != 1 || !strstr(test_text, f.message) || !strstr(test_text, f.advice))
                fail_msg("%s, %s: exit %d:\n%s\nwanted: %s ... %s", env, commands[c], rc, test_text,
                         f.message, f.advice);
            assert_false(test_file_exists(out));
            /* allowed by the flag */
            rc = run(env, commands[c], spot(), out, "--fallback reference");
            if (rc != 0 || !strstr(test_text, "warning: ") ||
                !strstr(test_text, f.at_open ? "using the reference backend instead (the fallback "
                                          "was allowed)"
                                        : "running again on the reference backend (the "
                                          "fallback was allowed)"))
                fail_msg("%s, %s --fallback reference: exit %d:\n%s", env, commands[c], rc,
                         test_text);
            assert_non_null(strstr(test_text, "reference (plain C"));
            assert_true(test_same_bytes(out, ref));
            unlink(out);
            /* allowed by the environment; forbidden again by the flag */
            snprintf(env2, sizeof env2, "%s LIMN_FALLBACK=reference", env);
            assert_int_equal(run(env2, commands[c], spot(), out, "-q"), 0);
            assert_true(test_same_bytes(out, ref));
            unlink(out);
            assert_int_equal(run(env2, commands[c], spot(), out, "--fallback none"), 1);
            assert_false(test_file_exists(out));
        }
        unlink(ref);
    }
}

/* The user's own choice of a device that does not exist is never replaced
   silently... unless the fallback is allowed; a bad fallback value is a usage
   error; `limn devices` explains a missing ICD. */
static void choices_and_usage(void **s)
{
    (void)s;
    char out[256], env[300];
    snprintf(out, sizeof out, "%s/out.ply", test_dir);
    int rc = run("", "interpolate '%s' -o '%s' --device opencl:no-such-device", spot(), out);
    assert_int_equal(rc, 1);
    assert_non_null(strstr(test_text,
                           "no OpenCL device matches --device='no-such-device': run 'limn "
                           "devices' to list them, or use --device reference"));
    rc = run("", "interpolate '%s' -o '%s' --device opencl:no-such-device --fallback reference -q",
             spot(), out);
    assert_int_equal(rc, 0);
    assert_non_null(strstr(test_text, "no OpenCL device matches --device='no-such-device'"));
    assert_non_null(strstr(test_text, "using the reference backend instead"));
    unlink(out);
    rc = run("LIMN_DEVICE=9.9", "subdivide '%s' -o '%s'", spot(), out);
    assert_int_equal(rc, 1);
    assert_non_null(strstr(test_text, "no OpenCL device matches LIMN_DEVICE='9.9'"));
    assert_false(test_file_exists(out));
    rc = run("", "interpolate '%s' -o '%s' --fallback gpu", spot(), out);
    assert_int_equal(rc, 2);
    assert_non_null(strstr(test_text, "unknown fallback 'gpu': use 'reference' or 'none'"));
    assert_false(test_file_exists(out));
    snprintf(env, sizeof env, "OCL_ICD_VENDORS=%s/no_icd", test_dir);
    assert_int_equal(run(env, "devices"), 1);
    assert_non_null(strstr(test_text, "no OpenCL platform found"));
}

/* The library calls behind the flag. */
static void library(void **s)
{
    limn_context *ctx = *s;
    assert_int_equal(limn_context_set_fallback(ctx, "reference"), LIMN_OK);
    assert_int_equal(limn_context_set_fallback(ctx, "none"), LIMN_OK);
    assert_int_equal(limn_context_set_fallback(ctx, "cuda"), LIMN_ERR_ARGUMENT);
    /* nothing to fall back from: the status stays */
    assert_int_equal(limn_context_fall_back(ctx, LIMN_ERR_DEVICE), LIMN_ERR_DEVICE);
    assert_int_equal(limn_context_set_fallback(ctx, "reference"), LIMN_OK);
    assert_int_equal(limn_context_fall_back(ctx, LIMN_ERR_FORMAT), LIMN_ERR_FORMAT);
    /* an operation that fails on the device, then runs on the reference */
    limn_mesh *m = test_mesh_cube(ctx);
    double pos[24];
    assert_int_equal(limn_context_set_device(ctx, "opencl"), LIMN_OK);
    assert_int_equal(limn_limit_positions(ctx, m, LIMN_SCHEME_CATMARK, 0.5, pos), LIMN_OK);
    assert_int_equal(limn_context_fall_back(ctx, LIMN_ERR_DEVICE), LIMN_OK);
    assert_non_null(strstr(limn_context_warnings(ctx), "running again on the reference backend"));
    assert_int_equal(limn_limit_positions(ctx, m, LIMN_SCHEME_CATMARK, 0.5, pos), LIMN_OK);
    assert_non_null(strstr(limn_context_device_name(ctx), "reference"));
    limn_mesh_destroy(m);
}

TEST_MAIN(setup, test_scratch_teardown, cmocka_unit_test(each_fault),
          cmocka_unit_test(choices_and_usage), CONTEXT_TEST(library))
