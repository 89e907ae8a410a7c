/* SPDX-License-Identifier: MIT */
/*
 * OpenCL beyond PoCL (issue 11 item 3, issue 18 item 5):
 *  - device choice: the pure rule (opencl_pick, opencl_unusable) on fake
 *    property structs; the real path with two PoCL devices
 *    (POCL_DEVICES="pthread pthread") of which LIMN_TEST_FAULT=no-fp64 makes
 *    0.0 lack double precision; and Mesa's Rusticl on llvmpipe, a real
 *    device without fp64, when it is installed;
 *  - the whole build log of a failing build (longer than any fixed buffer);
 *  - prefetching dropped, not fatal, when a device cannot run it;
 *  - an unwritable PoCL kernel cache named as the cause of "no device".
 */
#include "shell.h"
#include "support.h"
#include "device/device.h"
#include "device/opencl/opencl_usable.h"

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
    return test_scratch_make("opencl", NULL);
}

/* Runs `env ENV limn ARGS`; output (stdout and stderr) in test_text; returns the exit status. */
#define run(env, ...) test_limn(test_text, sizeof test_text, env, __VA_ARGS__)
static const char *spot(void) { return test_data_path("spot_control_mesh.obj"); }

static void expect(int rc, int want, const char *needle)
{
    if (rc != want || !strstr(test_text, needle))
        fail_msg("exit %d (wanted %d), output:\n%s\nwanted: %s", rc, want, test_text, needle);
}

static opencl_device_props fake(unsigned p, unsigned d, const char *name, const char *version,
                                cl_device_fp_config fp64, size_t group)
{
    opencl_device_props x;
    memset(&x, 0, sizeof x);
    x.platform_index = p;
    x.device_index = d;
    snprintf(x.platform, sizeof x.platform, "Fake platform %u", p);
    snprintf(x.name, sizeof x.name, "%s", name);
    snprintf(x.version, sizeof x.version, "%s", version);
    x.type = CL_DEVICE_TYPE_CPU;
    x.fp64 = fp64;
    x.max_work_group = group;
    x.max_item_size = group;
    return x;
}

/* The rule alone: which fakes are usable, and why not. */
static void pure_rule(void **s)
{
    (void)s;
    const cl_device_fp_config dbl = CL_FP_FMA | CL_FP_ROUND_TO_NEAREST | CL_FP_INF_NAN;
    opencl_device_props devs[5] = {
        fake(0, 0, "llvmpipe (no fp64)", "OpenCL 3.0 ", 0, 1024),
        fake(0, 1, "old one", "OpenCL 1.1 vendor", dbl, 1024),
        fake(1, 0, "old and tiny", "OpenCL 1.0", dbl, 4),
        fake(1, 1, "good cpu", "OpenCL 3.0 PoCL", dbl, 4096),
        fake(2, 0, "good gpu", "OpenCL 1.2 CUDA", dbl, 1024),
    };
    devs[4].type = CL_DEVICE_TYPE_GPU;
    char why[160];
    assert_int_equal(opencl_unusable(&devs[0], why, sizeof why), 1);
    assert_non_null(strstr(why, "no double precision"));
    assert_int_equal(opencl_unusable(&devs[1], why, sizeof why), 1);
    assert_non_null(strstr(why, "needs OpenCL 1.2, the device has 'OpenCL 1.1 vendor'"));
    assert_int_equal(opencl_unusable(&devs[2], why, sizeof why), 1);
    assert_non_null(strstr(why, "needs OpenCL 1.2"));
    /* groups below DEVICE_WORKGROUP run the gpu kernel shape (opencl_shape.c) */
    opencl_device_props tiny = fake(1, 0, "tiny groups", "OpenCL 1.2", dbl, 4);
    assert_int_equal(opencl_unusable(&tiny, why, sizeof why), 0);
    tiny.max_work_group = tiny.max_item_size = 1;
    assert_int_equal(opencl_unusable(&tiny, why, sizeof why), 0);
    assert_int_equal(opencl_unusable(&devs[3], why, sizeof why), 0);
    assert_int_equal(opencl_unusable(&devs[4], why, sizeof why), 0);

    size_t good[5], bad[5], nbad;
    opencl_criteria all = {NULL, NULL, 0, 0, 0, CL_DEVICE_TYPE_ALL};
    assert_int_equal(opencl_pick(devs, 5, &all, good, bad, &nbad), 2);
    assert_int_equal(good[0], 3); /* the first usable one is taken */
    assert_int_equal(good[1], 4);
    assert_int_equal(nbad, 3);
    assert_int_equal(bad[0], 0);
    assert_int_equal(bad[2], 2);
    /* an explicit choice of an unusable device matches it alone */
    opencl_criteria by_index = {NULL, NULL, 1, 0, 0, CL_DEVICE_TYPE_ALL};
    assert_int_equal(opencl_pick(devs, 5, &by_index, good, bad, &nbad), 0);
    assert_int_equal(nbad, 1);
    assert_int_equal(bad[0], 0);
    opencl_criteria by_name = {NULL, "GOOD", 0, 0, 0, CL_DEVICE_TYPE_ALL};
    assert_int_equal(opencl_pick(devs, 5, &by_name, good, bad, &nbad), 2);
    assert_int_equal(nbad, 0);
    opencl_criteria gpu = {NULL, NULL, 0, 0, 0, CL_DEVICE_TYPE_GPU};
    assert_int_equal(opencl_pick(devs, 5, &gpu, good, bad, &nbad), 1);
    assert_int_equal(good[0], 4);
    opencl_criteria platform0 = {"0", NULL, 0, 0, 0, CL_DEVICE_TYPE_ALL};
    assert_int_equal(opencl_pick(devs, 5, &platform0, good, bad, &nbad), 0);
    assert_int_equal(nbad, 2);
    opencl_criteria platform_name = {"fake PLATFORM 1", NULL, 0, 0, 0, CL_DEVICE_TYPE_ALL};
    assert_int_equal(opencl_pick(devs, 5, &platform_name, good, bad, &nbad), 1);
    assert_int_equal(good[0], 3);
}

/* The real path: device 0.0 without fp64 (the test hook) is skipped with a
   warning for 0.1, named as the reason when chosen, and listed as unusable. */
static void real_skip(void **s)
{
    (void)s;
    char ref[256], out[256];
    snprintf(ref, sizeof ref, "%s/ref.ply", test_dir);
    snprintf(out, sizeof out, "%s/out.ply", test_dir);
    const char *two = "POCL_DEVICES='pthread pthread'";
    const char *two_bad = "POCL_DEVICES='pthread pthread' LIMN_TEST_FAULT=no-fp64";
    assert_int_equal(run(two, "interpolate '%s' -o '%s' -q", spot(), ref), 0);
    int rc = run(two_bad, "interpolate '%s' -o '%s'", spot(), out);
    expect(rc, 0, "warning: skipping OpenCL device ");
    expect(rc, 0, "device 0.0, cpu]: limn cannot use it: no double precision");
    expect(rc, 0, "device 0.1, cpu]; threads");
    assert_true(test_same_bytes(ref, out));
    unlink(out);
    rc = run(two_bad, "interpolate '%s' -o '%s' --device opencl:0.0", spot(), out);
    expect(rc, 1, "the OpenCL device chosen by --device='0.0' cannot run limn: ");
    expect(rc, 1, "no double precision (CL_DEVICE_DOUBLE_FP_CONFIG is 0");
    assert_false(test_file_exists(out));
    rc = run("LIMN_DEVICE=0.0 LIMN_TEST_FAULT=no-fp64", "subdivide '%s' -o '%s'", spot(), out);
    expect(rc, 1, "the OpenCL device chosen by LIMN_DEVICE='0.0' cannot run limn: ");
    /* the only device unusable: an error, or the reference when allowed */
    rc = run("LIMN_TEST_FAULT=no-fp64", "interpolate '%s' -o '%s'", spot(), out);
    expect(rc, 1, "no OpenCL device can run limn: ");
    expect(rc, 1, "or use --device reference, or allow --fallback reference");
    rc = run("LIMN_TEST_FAULT=no-fp64", "interpolate '%s' -o '%s' -q --fallback reference",
             spot(), out);
    expect(rc, 0, "using the reference backend instead");
    unlink(out);
    rc = run(two_bad, "devices");
    expect(rc, 0, "double precision NO, max work-group ");
    expect(rc, 0, "; limn: NO, no double precision");
    expect(rc, 0, "; limn: usable\n");
    const char *last = strstr(test_text, "threads: ");
    assert_non_null(last);
    assert_null(strchr(last, '\n') ? strchr(strchr(last, '\n') + 1, '\n') : NULL);
    unlink(ref);
}

/* A real device without fp64: Mesa's Rusticl on llvmpipe (mesa-opencl-icd),
   beside PoCL through a private vendors directory; skipped where absent. */
static void real_rusticl(void **s)
{
    (void)s;
    const char *lib = getenv("LIMN_TEST_RUSTICL");
    if (!lib || !*lib)
        lib = "/usr/lib/x86_64-linux-gnu/libRusticlOpenCL.so.1";
    if (access(lib, R_OK) != 0 || access("/etc/OpenCL/vendors/pocl.icd", R_OK) != 0) {
        print_message("Rusticl (%s) not installed: this part is skipped\n", lib);
        skip();
    }
    char vendors[128], path[192], env[512], out[256];
    snprintf(vendors, sizeof vendors, "%s/vendors", test_dir);
    assert_int_equal(mkdir(vendors, 0755), 0);
    snprintf(path, sizeof path, "%s/rusticl.icd", vendors);
    char line[600];
    snprintf(line, sizeof line, "%s\n", lib);
    assert_int_equal(test_write_text(path, line), 0);
    snprintf(path, sizeof path, "%s/pocl.icd", vendors);
    assert_int_equal(test_write_text(path, "libpocl.so.2\n"), 0);
    snprintf(env, sizeof env, "OCL_ICD_VENDORS=%s RUSTICL_ENABLE=llvmpipe", vendors);
    snprintf(out, sizeof out, "%s/r.ply", test_dir);
    int rc = run(env, "devices");
    expect(rc, 0, "llvmpipe");
    expect(rc, 0, "double precision NO, max work-group ");
    expect(rc, 0, "; limn: NO, no double precision");
    rc = run(env, "interpolate '%s' -o '%s' --device opencl:llvmpipe", spot(), out);
    expect(rc, 1, "the OpenCL device chosen by --device='llvmpipe' cannot run limn: llvmpipe");
    snprintf(env, sizeof env, "OCL_ICD_VENDORS=%s RUSTICL_ENABLE=llvmpipe LIMN_PLATFORM=rusticl",
             vendors);
    rc = run(env, "interpolate '%s' -o '%s'", spot(), out);
    expect(rc, 1, "no OpenCL device can run limn: llvmpipe");
    snprintf(env, sizeof env, "OCL_ICD_VENDORS=%s RUSTICL_ENABLE=llvmpipe", vendors);
    rc = run(env, "interpolate '%s' -o '%s'", spot(), out);
    expect(rc, 0, "[Portable Computing Language, device");
    unlink(out);
}

/* A failing build reports the failing call and the device's whole log. */
static void whole_build_log(void **s)
{
    (void)s;
    char out[256];
    snprintf(out, sizeof out, "%s/b.ply", test_dir);
    int rc = run("LIMN_TEST_EXTRA_BUILD_OPTIONS='-D LIMN_FORCE_BUILD_ERROR'",
                 "interpolate '%s' -o '%s'", spot(), out);
    expect(rc, 1, "(clBuildProgram) failed: CL_BUILD_PROGRAM_FAILURE");
    expect(rc, 1, "-D LIMN_FORCE_BUILD_ERROR\nbuild log:\n");
    const char *log = strstr(test_text, "build log:\n");
    assert_non_null(strstr(log, "forced build error 01"));
    assert_non_null(strstr(log, "forced build error: the end of the log"));
    if (strlen(log) <= 1500)
        fail_msg("build log of %zu bytes, wanted all of it (> 1,499):\n%s", strlen(log), log);
    assert_false(test_file_exists(out));
}

/* A device whose compiler takes __builtin_prefetch but cannot run it (the
   test hook; Oclgrind was one): built again without, same bytes. */
static void prefetch_dropped(void **s)
{
    (void)s;
    char ref[256], out[256];
    snprintf(ref, sizeof ref, "%s/p_ref.ply", test_dir);
    snprintf(out, sizeof out, "%s/p_out.ply", test_dir);
    assert_int_equal(run("", "interpolate '%s' -o '%s' -q", spot(), ref), 0);
    int rc = run("LIMN_TEST_FAULT=prefetch", "interpolate '%s' -o '%s' -q", spot(), out);
    expect(rc, 0, "built without prefetching the gathers (with it: clCreateKernel(interp_step) "
                  "failed");
    assert_true(test_same_bytes(ref, out));
    unlink(ref);
    unlink(out);
}

/* PoCL drops its devices when its cache cannot be made: say so. HOME under
   /proc/self and a cache path under a plain file stop root too. */
static void unwritable_pocl_cache(void **s)
{
    (void)s;
    char out[256], file[192], env[512];
    snprintf(out, sizeof out, "%s/c.ply", test_dir);
    snprintf(file, sizeof file, "%s/a_file", test_dir);
    assert_int_equal(test_write_text(file, "not a directory\n"), 0);
    const char *home = "-u POCL_CACHE_DIR -u XDG_CACHE_HOME HOME=/proc/self";
    int rc = run(home, "interpolate '%s' -o '%s'", spot(), out);
    expect(rc, 1, "no OpenCL device found");
    expect(rc, 1, "PoCL's kernel cache directory /proc/self/.cache/pocl/kcache (from HOME) is "
                  "not writable");
    expect(rc, 1, "set POCL_CACHE_DIR to a writable directory");
    assert_false(test_file_exists(out));
    rc = run(home, "devices");
    expect(rc, 0, "set POCL_CACHE_DIR to a writable directory");
    expect(rc, 0, "threads: ");
    snprintf(env, sizeof env, "POCL_CACHE_DIR=%s/kcache", file);
    rc = run(env, "interpolate '%s' -o '%s'", spot(), out);
    expect(rc, 1, "(POCL_CACHE_DIR) is not writable (Not a directory): set POCL_CACHE_DIR to a "
                  "writable directory");
    snprintf(env, sizeof env, "-u POCL_CACHE_DIR XDG_CACHE_HOME=%s HOME=/proc/self", file);
    rc = run(env, "interpolate '%s' -o '%s'", spot(), out);
    expect(rc, 1, "(from XDG_CACHE_HOME) is not writable");
    assert_false(test_file_exists(out));
}

TEST_MAIN(setup, test_scratch_teardown, cmocka_unit_test(pure_rule), cmocka_unit_test(real_skip),
          cmocka_unit_test(real_rusticl), cmocka_unit_test(whole_build_log),
          cmocka_unit_test(prefetch_dropped), cmocka_unit_test(unwritable_pocl_cache))
