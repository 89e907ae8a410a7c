/* SPDX-License-Identifier: MIT */
/*
 * limn bench and limn_device_triad: the triad's result checked element by
 * element against the host (both backends) and its bad arguments refused;
 * `limn bench` at a small size on PoCL and on the reference backend writes
 * every documented JSON key with sane values (counts matching the refined
 * base mesh); bad options refused with messages and no JSON left; and
 * --host-threads reaching the context (the interpolate report says so).
 */
#include "shell.h"
#include "support.h"

#include "device/choice/choice.h"
#include "device/choice/triad.h"
#include "device/device.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

static int setup(void **s)
{
    (void)s;
    return test_scratch_make("bench", NULL);
}

/* The value after "KEY": in text (the first occurrence at or after from), or
   the test fails. */
static double key_number(const char *text, const char *key)
{
    char pat[128];
    snprintf(pat, sizeof pat, "\"%s\": ", key);
    const char *p = strstr(text, pat);
    if (!p)
        fail_msg("key %s missing from\n%s", key, text);
    return strtod(p + strlen(pat), NULL);
}

static void triad_on(const char *device)
{
    limn_context *ctx = limn_context_create();
    assert_int_equal(limn_context_set_device(ctx, device), LIMN_OK);
    limn_triad_report r = {.size = sizeof r};
    /* 1 MiB + 40 bytes: rounded down to whole 32-byte records */
    assert_int_equal(limn_device_triad(ctx, ((size_t)1 << 20) + 40, 3, &r), LIMN_OK);
    assert_int_equal(r.elements, ((size_t)1 << 20) / 8 + 4);
    assert_int_equal(r.array_bytes, 8 * r.elements);
    assert_int_equal(r.repeats, 3);
    assert_int_equal(r.mismatches, 0);
    assert_true(r.seconds_best > 0 && r.seconds_mean >= r.seconds_best);
    assert_true(r.gb_per_s > 0);
    assert_true(r.gb_per_s == 24.0 * (double)r.elements / r.seconds_best * 1e-9);
    assert_true(r.device[0] != '\0');

    /* the arrays themselves: a[i] = b[i] + 3 c[i] from the documented inputs,
       computed here (across the 2^19-element staging pieces) */
    struct device *dev;
    assert_int_equal(device_get(ctx, &dev), LIMN_OK);
    limn_triad_report q = {.size = sizeof q, .elements = ((size_t)1 << 19) + 1024};
    double *a = malloc(q.elements * sizeof *a);
    assert_non_null(a);
    assert_int_equal(device_triad(dev, 2, &q, a), LIMN_OK);
    size_t wrong = 0;
    for (size_t i = 0; i < q.elements; i++) {
        double b = 1.0 + (double)(i % 1024) / 2, c = (double)(i % 13) / 4;
        wrong += a[i] != b + 3.0 * c;
    }
    assert_int_equal(wrong, 0);
    assert_int_equal(q.mismatches, 0);
    free(a);
    limn_context_destroy(ctx);
}

static void triad_reference(void **s)
{
    (void)s;
    triad_on("reference");
}

static void triad_opencl(void **s)
{
    (void)s;
    triad_on("opencl");
}

static void expect_refusal(limn_context *ctx, size_t bytes, int repeats, limn_triad_report *r,
                           const char *words)
{
    assert_int_equal(limn_device_triad(ctx, bytes, repeats, r), LIMN_ERR_ARGUMENT);
    if (!strstr(limn_context_message(ctx), words))
        fail_msg("message '%s' lacks '%s'", limn_context_message(ctx), words);
}

static void triad_refusals(void **s)
{
    (void)s;
    limn_context *ctx = limn_context_create();
    assert_int_equal(limn_context_set_device(ctx, "reference"), LIMN_OK);
    limn_triad_report r = {.size = sizeof r};
    expect_refusal(ctx, 0, 1, &r, "bytes 0");
    expect_refusal(ctx, 31, 1, &r, "bytes 31");
    expect_refusal(ctx, 1024, 0, &r, "repeats 0");
    expect_refusal(ctx, 1024, 1001, &r, "repeats 1001");
    expect_refusal(ctx, 1024, 1, NULL, "report is NULL");
    limn_triad_report unsized = {0};
    expect_refusal(ctx, 1024, 1, &unsized, "size");
    assert_int_equal(limn_device_triad(NULL, 1024, 1, &r), LIMN_ERR_ARGUMENT);
    limn_context_destroy(ctx);
}

static const char *const top_keys[] = {
    "limn_version", "command", "scheme", "base_mesh", "levels", "vertices_requested",
    "vertices", "faces", "input_bytes", "stencil_nonzeros", "method", "precision",
    "iterations", "products", "products_float", "max_rel_error", "device", "threads",
    "threads_source", "host_threads", "host_threads_source", "peak_rss_bytes",
    "peak_bytes_per_vertex", "seconds", "vertices_per_second", "solve_loop", "triad"};
static const char *const stage_keys[] = {"read", "repair", "opencl_setup", "topology",
                                         "stencil", "solve", "iterations", "write", "total"};

/* Runs limn bench with args and checks its JSON: every key, positive
   figures, the counts of the base mesh refined `levels` times. */
static void bench_json(const char *args, size_t vertices, size_t faces, int levels)
{
    const char *json = test_join(test_dir, "bench.json");
    remove(json);
    int rc = test_limn(test_text, sizeof test_text, NULL, "bench %s --triad-bytes 4M --json '%s' -q",
                       args, json);
    if (rc != 0)
        fail_msg("limn bench %s: exit %d\n%s", args, rc, test_text);
    assert_string_equal(test_text, ""); /* -q: nothing printed */
    size_t n;
    char *t = test_slurp(json, &n);
    assert_non_null(t);
    for (size_t k = 0; k < sizeof top_keys / sizeof *top_keys; k++) {
        char pat[64];
        snprintf(pat, sizeof pat, "\"%s\": ", top_keys[k]);
        if (!strstr(t, pat))
            fail_msg("limn bench %s: no key %s in\n%s", args, top_keys[k], t);
    }
    assert_int_equal((size_t)key_number(t, "vertices"), vertices);
    assert_int_equal((size_t)key_number(t, "faces"), faces);
    assert_int_equal((int)key_number(t, "levels"), levels);
    assert_true(key_number(t, "stencil_nonzeros") > (double)vertices);
    assert_true(key_number(t, "iterations") >= 1 && key_number(t, "products") >= 1);
    assert_true(key_number(t, "max_rel_error") <= 1e-6);
    assert_true(key_number(t, "threads") >= 1 && key_number(t, "host_threads") >= 1);
    assert_true(key_number(t, "peak_rss_bytes") > 0);
    assert_true(key_number(t, "input_bytes") > 12.0 * (double)vertices);
    const char *sec = strstr(t, "\"seconds\""), *vps = strstr(t, "\"vertices_per_second\"");
    for (size_t k = 0; k < sizeof stage_keys / sizeof *stage_keys; k++) {
        if (strcmp(stage_keys[k], "opencl_setup") != 0) /* 0 on the reference backend */
            assert_true(key_number(sec, stage_keys[k]) > 0);
        double v = key_number(vps, stage_keys[k]);
        assert_true(v >= 0);
    }
    assert_true(key_number(sec, "total") >= key_number(sec, "read") + key_number(sec, "write"));
    const char *loop = strstr(t, "\"solve_loop\""), *triad = strstr(t, "\"triad\"");
    assert_true(key_number(loop, "bytes") > 0 && key_number(loop, "gb_per_s") > 0);
    assert_true(key_number(loop, "triad_fraction") > 0);
    assert_int_equal((size_t)key_number(triad, "array_bytes"), (size_t)4 << 20);
    assert_int_equal((int)key_number(triad, "repeats"), 5);
    assert_int_equal((int)key_number(triad, "mismatches"), 0);
    assert_true(key_number(triad, "gb_per_s") > 0);
    free(t);
}

static void bench_small(void **s)
{
    (void)s;
    /* icosahedron: 10 4^L + 2 vertices, 20 4^L faces; 20k is nearest L = 5 */
    bench_json("--vertices 20k", 10242, 20480, 5);
    bench_json("--vertices 20k --device reference", 10242, 20480, 5);
    /* cube: 6 4^L + 2 vertices, 6 4^L faces; 1000 is nearest L = 4 */
    bench_json("--vertices 1000 --scheme catmark --host-threads 1", 1538, 1536, 4);
    size_t n;
    char *t = test_slurp(test_join(test_dir, "bench.json"), &n);
    assert_non_null(strstr(t, "\"host_threads\": 1,"));
    assert_non_null(strstr(t, "\"host_threads_source\": \"API (host threads)\""));
    free(t);
    /* the summary on stdout without -q, nothing left in the temporary directory */
    char env[128];
    snprintf(env, sizeof env, "TMPDIR=%s", test_dir);
    assert_int_equal(test_limn(test_text, sizeof test_text, env, "bench --vertices 500 "
                               "--triad-bytes 1M"), 0);
    assert_non_null(strstr(test_text, "of the triad"));
    assert_non_null(strstr(test_text, "bytes a vertex"));
    assert_int_equal(test_runf(test_text, sizeof test_text, "ls -d '%s'/limn_bench_* 2>/dev/null",
                               test_dir), 2);
}

/* limn bench ARGS: exit status 2, the message holds words, no JSON. */
static void refused(const char *args, const char *words)
{
    const char *json = test_join(test_dir, "refused.json");
    size_t n;
    int rc = test_limn(test_text, sizeof test_text, NULL, "bench %s --json '%s' -q", args, json);
    if (rc != 2 || !strstr(test_text, words))
        fail_msg("limn bench %s: exit %d, wanted 2 and '%s':\n%s", args, rc, words, test_text);
    assert_null(test_slurp(json, &n));
}

static void bench_refusals(void **s)
{
    (void)s;
    refused("--vertices 0", "--vertices 0 is outside 100..4G");
    refused("--vertices 5G", "--vertices 5G is outside 100..4G");
    refused("--vertices 12q", "--vertices '12q' is not a count");
    refused("--vertices -3", "is not a count");
    refused("--scheme auto", "--scheme 'auto' is not one of loop, catmark");
    refused("--repeat 0", "--repeat 0 is outside 1..1000");
    refused("--repeat x", "--repeat");
    refused("--host-threads 0", "--host-threads 0 is outside 1..64");
    refused("--host-threads 65", "--host-threads 65 is outside 1..64");
    refused("--triad-bytes 8", "--triad-bytes 8: at least 32");
    refused("--device nowhere", "unknown device 'nowhere'");
    refused("mesh.ply", "unexpected argument 'mesh.ply' (bench reads no file)");
    refused("--vertcies 20k", "did you mean --vertices?");
    int rc = test_limn(test_text, sizeof test_text, NULL, "bench -q --vertices");
    assert_int_equal(rc, 2);
    assert_non_null(strstr(test_text, "--vertices needs a value"));
    rc = test_limn(test_text, sizeof test_text, NULL, "bench --json /nonexistent/dir/b.json");
    assert_int_equal(rc, 1);
    assert_non_null(strstr(test_text, "/nonexistent/dir"));
}

/* --host-threads reaches the context: the interpolate report states it. */
static void host_threads_option(void **s)
{
    (void)s;
    size_t n;
    const char *out = test_join(test_dir, "spot.ply"), *rep = test_join(test_dir, "spot.json");
    assert_int_equal(test_limn(test_text, sizeof test_text, NULL,
                               "interpolate '%s' -o '%s' --report '%s' --host-threads 3 -q",
                               test_data_path("spot_control_mesh.obj"), out, rep), 0);
    char *t = test_slurp(rep, &n);
    assert_non_null(t);
    assert_non_null(strstr(t, "\"host_threads\": 3,"));
    assert_non_null(strstr(t, "\"host_threads_source\": \"API (host threads)\""));
    free(t);
    assert_int_equal(test_limn(test_text, sizeof test_text, NULL,
                               "interpolate '%s' -o '%s' --report '%s' -q",
                               test_data_path("spot_control_mesh.obj"), out, rep), 0);
    t = test_slurp(rep, &n);
    assert_non_null(strstr(t, "\"host_threads_source\": "));
    assert_null(strstr(t, "API (host threads)"));
    free(t);
    static const char *const cmds[] = {"interpolate", "subdivide", "smooth", "info", "render",
                                       "bench"};
    for (size_t k = 0; k < sizeof cmds / sizeof *cmds; k++) {
        assert_int_equal(test_limn(test_text, sizeof test_text, NULL, "%s --help", cmds[k]), 0);
        if (!strstr(test_text, "--host-threads N"))
            fail_msg("limn %s --help does not document --host-threads", cmds[k]);
    }
    assert_int_equal(test_limn(test_text, sizeof test_text, NULL, "info '%s' --host-threads 2x",
                               test_data_path("spot_control_mesh.obj")), 2);
    assert_non_null(strstr(test_text, "--host-threads"));
    assert_int_equal(test_limn(test_text, sizeof test_text, NULL,
                               "subdivide '%s' -o '%s' --levels 1 --host-threads 70",
                               test_data_path("spot_control_mesh.obj"), out), 2);
    assert_non_null(strstr(test_text, "--host-threads 70 is outside 1..64"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(triad_reference),   cmocka_unit_test(triad_opencl),
        cmocka_unit_test(triad_refusals),    cmocka_unit_test(bench_small),
        cmocka_unit_test(bench_refusals),    cmocka_unit_test(host_threads_option),
    };
    return cmocka_run_group_tests(tests, setup, test_scratch_teardown);
}
