/* SPDX-License-Identifier: MIT */
/*
 * The OpenCL runtime's thread count (host/device/threads.c): cores counted inside a
 * CPU set on synthetic hwloc topologies (SMT siblings, no core level); the
 * precedence of the user's variables, the API and the binding; the binding
 * of this process against an independent count from /sys; and end to end,
 * that PoCL really runs with that count (its compute units) for the API, the
 * binding and the variables, in fresh processes, and that the CLI reports it
 * (`limn devices`, the interpolate report) under `taskset` and without.
 */
#define _GNU_SOURCE /* sched_setaffinity, CPU_SET */
#include "shell.h"
#include "support.h"
#include "device/threads.h"

#include <sched.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmocka.h>

static char text[1 << 16];

/* ------------------------------------------------------------- counting */

static unsigned count_in(const char *synthetic, const char *cpus)
{
    hwloc_topology_t topo;
    assert_int_equal(hwloc_topology_init(&topo), 0);
    assert_int_equal(hwloc_topology_set_synthetic(topo, synthetic), 0);
    assert_int_equal(hwloc_topology_load(topo), 0);
    hwloc_bitmap_t set = hwloc_bitmap_alloc();
    assert_int_equal(hwloc_bitmap_list_sscanf(set, cpus), 0);
    unsigned n = cores_count(topo, set);
    hwloc_bitmap_free(set);
    hwloc_topology_destroy(topo);
    return n;
}

static void counts_cores_not_pus(void **s)
{
    (void)s;
    /* 2 packages x 4 cores x 2 PUs: core k holds PUs 2k and 2k+1 */
    const char *smt = "pack:2 core:4 pu:2";
    assert_int_equal(count_in(smt, "0-15"), 8);
    assert_int_equal(count_in(smt, "0"), 1);
    assert_int_equal(count_in(smt, "0-1"), 1);  /* SMT siblings: one core */
    assert_int_equal(count_in(smt, "0,2"), 2);
    assert_int_equal(count_in(smt, "1,15"), 2); /* one core in each package */
    assert_int_equal(count_in(smt, "8-15"), 4); /* the second package */
    assert_int_equal(count_in(smt, ""), 0);
    /* no core level: PUs count */
    assert_int_equal(count_in("pack:1 pu:4", "0-2"), 3);
    assert_int_equal(count_in("numa:2 core:3 pu:1", "0-5"), 6);
}

/* ----------------------------------------------------------- precedence */

static void plan_precedence(void **s)
{
    (void)s;
    threads_plan p;
    /* the binding, by default */
    threads_plan_make(&p, NULL, NULL, LIMN_THREADS_FROM_BINDING, 6, NULL);
    assert_int_equal(p.count, 6);
    assert_string_equal(p.source, THREADS_SOURCE_BINDING);
    assert_true(p.set_pthread && p.set_cu);
    assert_string_equal(p.warning, "");
    /* the API over the binding */
    threads_plan_make(&p, NULL, "", 3, 6, NULL);
    assert_int_equal(p.count, 3);
    assert_string_equal(p.source, THREADS_SOURCE_API);
    assert_true(p.set_pthread && p.set_cu);
    /* the user's variable over both, copied into the other name, never overwritten */
    threads_plan_make(&p, "5", NULL, 3, 6, NULL);
    assert_int_equal(p.count, 5);
    assert_string_equal(p.source, THREADS_SOURCE_PTHREAD);
    assert_true(!p.set_pthread && p.set_cu);
    assert_non_null(strstr(p.warning, "takes precedence over limn_context_set_threads(3)"));
    threads_plan_make(&p, "", "7", LIMN_THREADS_FROM_BINDING, 6, NULL);
    assert_int_equal(p.count, 7);
    assert_string_equal(p.source, THREADS_SOURCE_CU);
    assert_true(p.set_pthread && !p.set_cu);
    threads_plan_make(&p, "2", "4", LIMN_THREADS_FROM_BINDING, 6, NULL);
    assert_int_equal(p.count, 2);
    assert_true(!p.set_pthread && !p.set_cu);
    assert_non_null(strstr(p.warning, "differ"));
    /* a value that is no count is left alone, with a warning */
    threads_plan_make(&p, "many", NULL, LIMN_THREADS_FROM_BINDING, 6, NULL);
    assert_int_equal(p.count, 0);
    assert_true(!p.set_pthread && !p.set_cu);
    assert_non_null(strstr(p.warning, "POCL_MAX_PTHREAD_COUNT='many' is not a whole number"));
    /* disabled: nothing set */
    threads_plan_make(&p, NULL, NULL, LIMN_THREADS_RUNTIME_DEFAULT, 6, NULL);
    assert_int_equal(p.count, 0);
    assert_true(!p.set_pthread && !p.set_cu);
    assert_string_equal(p.source, THREADS_SOURCE_RUNTIME);
    /* hwloc failed: nothing set, the reason in the source and a warning */
    threads_plan_make(&p, NULL, NULL, LIMN_THREADS_FROM_BINDING, 0, "no topology");
    assert_int_equal(p.count, 0);
    assert_true(!p.set_pthread && !p.set_cu);
    assert_non_null(strstr(p.source, "no topology"));
    assert_non_null(strstr(p.warning, "no topology"));
}

static void bad_requests(void **s)
{
    limn_context *ctx = *s;
    assert_int_equal(limn_context_set_threads(ctx, -2), LIMN_ERR_ARGUMENT);
    assert_non_null(strstr(limn_context_message(ctx), "-2 is not a thread count"));
    assert_int_equal(limn_context_set_threads(ctx, 1 << 20), LIMN_ERR_ARGUMENT);
    assert_int_equal(limn_context_set_threads(NULL, 1), LIMN_ERR_ARGUMENT);
    int n;
    const char *src;
    assert_int_equal(limn_context_threads(NULL, &n, &src), LIMN_ERR_ARGUMENT);
    assert_int_equal(limn_context_threads(ctx, NULL, &src), LIMN_ERR_ARGUMENT);
    /* no platform queried in this process yet */
    assert_int_equal(limn_context_threads(ctx, &n, &src), LIMN_OK);
    assert_int_equal(n, 0);
    assert_non_null(strstr(src, "not decided yet"));
}

/* ------------------------------------------------- this process's binding */

/* Cores of the CPUs in `set`, counted from /sys (package, core) pairs. */
static int sys_cores(const cpu_set_t *set)
{
    long pairs[CPU_SETSIZE][2];
    int n = 0;
    for (int c = 0; c < CPU_SETSIZE; c++) {
        if (!CPU_ISSET(c, set))
            continue;
        long core = c, pkg = 0;
        char path[128];
        snprintf(path, sizeof path, "/sys/devices/system/cpu/cpu%d/topology/core_id", c);
        FILE *f = fopen(path, "r");
        if (f) {
            if (fscanf(f, "%ld", &core) != 1)
                core = c;
            fclose(f);
        }
        snprintf(path, sizeof path, "/sys/devices/system/cpu/cpu%d/topology/physical_package_id",
                 c);
        if ((f = fopen(path, "r"))) {
            if (fscanf(f, "%ld", &pkg) != 1)
                pkg = 0;
            fclose(f);
        }
        int seen = 0;
        for (int i = 0; i < n && !seen; i++)
            seen = pairs[i][0] == pkg && pairs[i][1] == core;
        if (!seen) {
            pairs[n][0] = pkg;
            pairs[n][1] = core;
            n++;
        }
    }
    return n;
}

static int first_cpu(const cpu_set_t *set)
{
    for (int c = 0; c < CPU_SETSIZE; c++)
        if (CPU_ISSET(c, set))
            return c;
    return -1;
}

static void binding_of_this_process(void **s)
{
    (void)s;
    cpu_set_t all, one;
    assert_int_equal(sched_getaffinity(0, sizeof all, &all), 0);
    char why[160] = "";
    unsigned n = cores_in_binding(why, sizeof why);
    print_message("cores inside the binding: hwloc %u, /sys %d (%d CPUs)\n", n, sys_cores(&all),
                  CPU_COUNT(&all));
    assert_int_equal((int)n, sys_cores(&all));
    /* narrowed to one CPU, then given back */
    CPU_ZERO(&one);
    CPU_SET(first_cpu(&all), &one);
    assert_int_equal(sched_setaffinity(0, sizeof one, &one), 0);
    n = cores_in_binding(why, sizeof why);
    assert_int_equal(sched_setaffinity(0, sizeof all, &all), 0);
    assert_int_equal(n, 1);
}

/* Host threads: set_host_threads, else set_threads, else the binding's cores. */
static void host_threads_precedence(void **s)
{
    limn_context *ctx = *s;
    cpu_set_t all;
    assert_int_equal(sched_getaffinity(0, sizeof all, &all), 0);
    int n;
    const char *src;
    assert_int_equal(limn_context_host_threads(ctx, &n, &src), LIMN_OK);
    assert_int_equal(n, sys_cores(&all));
    assert_string_equal(src, "binding via hwloc");
    assert_int_equal(limn_context_set_threads(ctx, 3), LIMN_OK);
    assert_int_equal(limn_context_host_threads(ctx, &n, &src), LIMN_OK);
    assert_int_equal(n, 3);
    assert_string_equal(src, "API");
    assert_int_equal(limn_context_set_host_threads(ctx, 5), LIMN_OK);
    assert_int_equal(limn_context_host_threads(ctx, &n, &src), LIMN_OK);
    assert_int_equal(n, 5);
    assert_string_equal(src, "API (host threads)");
    assert_int_equal(limn_context_set_host_threads(ctx, -1), LIMN_ERR_ARGUMENT);
    assert_non_null(strstr(limn_context_message(ctx), "-1 is not a host thread count"));
    assert_int_equal(limn_context_set_host_threads(ctx, 1000), LIMN_ERR_ARGUMENT);
    assert_int_equal(limn_context_set_host_threads(NULL, 1), LIMN_ERR_ARGUMENT);
    assert_int_equal(limn_context_host_threads(ctx, NULL, &src), LIMN_ERR_ARGUMENT);
    assert_int_equal(limn_context_host_threads(NULL, &n, &src), LIMN_ERR_ARGUMENT);
}

/* --------------------------------------------- PoCL's compute units, in-process */

/* Compute units of the first device in a limn_list_devices listing, or -1. */
static int compute_units(const char *listing)
{
    const char *p = strstr(listing, " compute units");
    if (!p)
        return -1;
    while (p > listing && p[-1] >= '0' && p[-1] <= '9')
        p--;
    return atoi(p);
}

#define CHILD_CHECK(cond, ...)                                                                 \
    do {                                                                                       \
        if (!(cond)) {                                                                         \
            fprintf(stderr, "child: " __VA_ARGS__);                                            \
            fputc('\n', stderr);                                                               \
            _exit(1);                                                                          \
        }                                                                                      \
    } while (0)

/* In a fresh process (PoCL reads the count once): `request` on the first
   context, optionally narrowed to one CPU; checks the runtime's compute units
   and the reported count and source; a second context's other request only
   warns. */
static void child_run(int request, int one_cpu, int want, const char *want_source)
{
    unsetenv("POCL_MAX_PTHREAD_COUNT");
    unsetenv("POCL_CPU_MAX_CU_COUNT");
    if (one_cpu) {
        cpu_set_t all, one;
        sched_getaffinity(0, sizeof all, &all);
        CPU_ZERO(&one);
        CPU_SET(first_cpu(&all), &one);
        CHILD_CHECK(sched_setaffinity(0, sizeof one, &one) == 0, "sched_setaffinity");
    }
    static char list[1 << 16];
    limn_context *ctx = limn_context_create();
    CHILD_CHECK(limn_context_set_threads(ctx, request) == LIMN_OK, "set_threads");
    limn_status st = limn_list_devices(ctx, list, sizeof list);
    if (st == LIMN_ERR_DEVICE)
        _exit(77); /* no OpenCL platform: nothing to check */
    CHILD_CHECK(st == LIMN_OK, "list: %s", limn_context_message(ctx));
    int n;
    const char *src;
    limn_context_threads(ctx, &n, &src);
    CHILD_CHECK(n == want, "threads %d, expected %d", n, want);
    CHILD_CHECK(strstr(src, want_source) == src, "source '%s', expected '%s'", src, want_source);
    const char *pocl = getenv("POCL_MAX_PTHREAD_COUNT"), *cu = getenv("POCL_CPU_MAX_CU_COUNT");
    if (want > 0) {
        CHILD_CHECK(compute_units(list) == want, "PoCL reports %d compute units, expected %d",
                    compute_units(list), want);
        CHILD_CHECK(pocl && cu && atoi(pocl) == want && atoi(cu) == want, "variables not set");
    } else {
        CHILD_CHECK(!pocl && !cu, "a variable was set for the runtime default");
    }
    limn_context *later = limn_context_create();
    limn_context_set_threads(later, request == 1 ? 2 : 1);
    CHILD_CHECK(limn_list_devices(later, list, sizeof list) == LIMN_OK, "second list");
    CHILD_CHECK(strstr(limn_context_warnings(later), "has no effect") != NULL,
                "no warning for the later request: '%s'", limn_context_warnings(later));
    limn_context_threads(later, &n, &src);
    CHILD_CHECK(n == want, "the later context reports %d", n);
    limn_context_destroy(later);
    limn_context_destroy(ctx);
    _exit(0);
}

static void in_child(int request, int one_cpu, int want, const char *want_source)
{
    fflush(NULL);
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0)
        child_run(request, one_cpu, want, want_source);
    int status;
    assert_int_equal(waitpid(pid, &status, 0), pid);
    assert_true(WIFEXITED(status));
    if (WEXITSTATUS(status) == 77)
        skip();
    assert_int_equal(WEXITSTATUS(status), 0);
}

static void pocl_follows_the_api(void **s)
{
    (void)s;
    in_child(3, 0, 3, THREADS_SOURCE_API);
}

static void pocl_follows_the_binding(void **s)
{
    (void)s;
    in_child(LIMN_THREADS_FROM_BINDING, 1, 1, THREADS_SOURCE_BINDING);
}

static void runtime_default_sets_nothing(void **s)
{
    (void)s;
    in_child(LIMN_THREADS_RUNTIME_DEFAULT, 1, 0, THREADS_SOURCE_RUNTIME);
}

/* ------------------------------------------------------------------ CLI */

static int run(const char *cmd) { return test_run(text, sizeof text, cmd); }

/* `limn devices` with env/prefix; checks its threads line and compute units. */
static void devices_say(const char *prefix, int want, const char *source)
{
    char cmd[1024], line[256];
    snprintf(cmd, sizeof cmd,
             "env -u POCL_MAX_PTHREAD_COUNT -u POCL_CPU_MAX_CU_COUNT %s '%s' devices 2>&1", prefix,
             getenv("LIMN_BIN"));
    int rc = run(cmd);
    if (rc == 1 && strstr(text, "no OpenCL platform"))
        skip();
    assert_int_equal(rc, 0);
    snprintf(line, sizeof line, "threads: %d (%s)\n", want, source);
    if (!strstr(text, line))
        fail_msg("'%s' printed\n%s\nwithout '%s'", cmd, text, line);
    assert_int_equal(compute_units(text), want);
}

static int have_taskset(void) { return system("taskset -V >/dev/null 2>&1") == 0; }

static void cli_reports_the_count(void **s)
{
    (void)s;
    cpu_set_t all;
    assert_int_equal(sched_getaffinity(0, sizeof all, &all), 0);
    int cores = sys_cores(&all);
    devices_say("", cores, "binding via hwloc");
    devices_say("POCL_MAX_PTHREAD_COUNT=3", 3, "POCL_MAX_PTHREAD_COUNT");
    /* PoCL 3.1 reads only POCL_MAX_PTHREAD_COUNT: limn copied the 4.x name into it */
    devices_say("POCL_CPU_MAX_CU_COUNT=3", 3, "POCL_CPU_MAX_CU_COUNT");
    if (!have_taskset())
        skip(); /* util-linux; present on every Debian */
    char prefix[64];
    snprintf(prefix, sizeof prefix, "taskset -c %d", first_cpu(&all));
    devices_say(prefix, 1, "binding via hwloc");
}

static void interpolate_report_has_the_count(void **s)
{
    (void)s;
    if (!have_taskset())
        skip();
    cpu_set_t all;
    assert_int_equal(sched_getaffinity(0, sizeof all, &all), 0);
    char dir[64];
    assert_int_equal(test_make_dir(dir, sizeof dir, "threads"), 0);
    char cmd[2048];
    for (int bound = 0; bound < 2; bound++) {
        char prefix[64] = "";
        if (bound)
            snprintf(prefix, sizeof prefix, "taskset -c %d", first_cpu(&all));
        snprintf(cmd, sizeof cmd,
                 "env -u POCL_MAX_PTHREAD_COUNT -u POCL_CPU_MAX_CU_COUNT %s '%s' interpolate "
                 "'%s/spot_control_mesh.obj' -o '%s/c.ply' --report '%s/r.json' -q 2>&1 && "
                 "cat '%s/r.json'",
                 prefix, getenv("LIMN_BIN"), getenv("LIMN_TEST_DATA"), dir, dir, dir);
        int rc = run(cmd);
        if (rc == 1 && strstr(text, "no OpenCL platform"))
            skip();
        assert_int_equal(rc, 0);
        char want[64];
        snprintf(want, sizeof want, "\"threads\": %d,", bound ? 1 : sys_cores(&all));
        if (!strstr(text, want) || !strstr(text, "\"threads_source\": \"binding via hwloc\""))
            fail_msg("report without %s from the binding:\n%s", want, text);
    }
    assert_int_equal(test_remove_dir(dir), 0);
}

TEST_MAIN(NULL, NULL, cmocka_unit_test(counts_cores_not_pus), cmocka_unit_test(plan_precedence),
          CONTEXT_TEST(bad_requests), cmocka_unit_test(binding_of_this_process),
          CONTEXT_TEST(host_threads_precedence),
          cmocka_unit_test(pocl_follows_the_api), cmocka_unit_test(pocl_follows_the_binding),
          cmocka_unit_test(runtime_default_sets_nothing), cmocka_unit_test(cli_reports_the_count),
          cmocka_unit_test(interpolate_report_has_the_count))
