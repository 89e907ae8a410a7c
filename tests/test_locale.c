/* SPDX-License-Identifier: MIT */
/*
 * Locale independence (issue 11.2): a host that calls
 * setlocale(LC_ALL, "de_DE.UTF-8") (decimal comma) reads and writes exactly
 * the bytes and meshes it would in the C locale, through the library
 * (every reader, every writer) and through the CLI (which calls
 * setlocale(LC_ALL, "") itself): `limn info --json`, a report, option values
 * such as --alpha 0.5, and the mesh written.
 *
 * de_DE.UTF-8 is generated with localedef when missing (scripts/deps.sh
 * --test installs the `locales` package); when it cannot be, the test is
 * skipped (exit 77) saying why.
 */
#ifndef _POSIX_C_SOURCE
#define _POSIX_C_SOURCE 200809L
#endif
#include "shell.h"
#include "support.h"

#include <locale.h>
#include <pthread.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmocka.h>

#define DE "de_DE.UTF-8"

static char dir[64];

static const char *path_in(const char *name) { return test_join(dir, name); }

/* Makes de_DE.UTF-8 available; 0 with a reason when it cannot be. Asked of
   `locale -a`, not setlocale: glibc maps the locale archive at the first
   setlocale and would not see one that localedef adds afterwards. */
static int have_german(char *why, size_t n)
{
    if (system("locale -a 2>/dev/null | grep -qix 'de_DE.utf-\\{0,1\\}8'") != 0 &&
        system("localedef -i de_DE -f UTF-8 de_DE.UTF-8 >/dev/null 2>&1") != 0) {
        snprintf(why, n, "de_DE.UTF-8 is not installed and localedef could not generate it "
                         "(needs root and the 'locales' package: scripts/deps.sh --test)");
        return 0;
    }
    if (!setlocale(LC_ALL, DE)) {
        snprintf(why, n, "setlocale(LC_ALL, \"%s\") fails even after localedef", DE);
        return 0;
    }
    setlocale(LC_ALL, "C");
    return 1;
}

/* ------------------------------------------------------------- the library */

/* Fractions everywhere, so that a decimal comma would show. */
static const struct {
    const char *name, *text;
} inputs[] = {
    {"q.obj", "v 0.5 0.25 -0.125\nv 1.75 0 0.0625\nv 0.3 1.5 0\nv 1e-3 2.5e2 0.1\n"
              "f 1 2 3\nf 1 3 4\n"},
    {"q.off", "OFF\n4 2 0\n0.5 0.25 -0.125\n1.75 0 0.0625\n0.3 1.5 0\n1e-3 2.5e2 0.1\n"
              "3 0 1 2\n3 0 2 3\n"},
    {"q.ply", "ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\n"
              "property double z\nelement face 2\nproperty list uchar int vertex_indices\n"
              "end_header\n0.5 0.25 -0.125\n1.75 0 0.0625\n0.3 1.5 0\n1e-3 2.5e2 0.1\n"
              "3 0 1 2\n3 0 2 3\n"},
    {"q.stl", "solid q\nfacet normal 0 0 1\nouter loop\nvertex 0.5 0.25 -0.125\n"
              "vertex 1.75 0 0.0625\nvertex 0.3 1.5 0\nendloop\nendfacet\nendsolid q\n"},
};

static const struct {
    const char *ext;
    limn_format format;
} outputs[] = {
    {"obj", LIMN_FORMAT_OBJ},       {"off", LIMN_FORMAT_OFF},
    {"ply", LIMN_FORMAT_PLY},       {"ply", LIMN_FORMAT_PLY_ASCII},
    {"ply", LIMN_FORMAT_PLY_BINARY_BE}, {"stl", LIMN_FORMAT_STL},
};

/* Reads every input and writes every output under the current locale,
   into files tagged with tag. */
static void read_and_write_all(const char *tag, limn_mesh **meshes)
{
    limn_context *ctx = limn_context_create();
    assert_non_null(ctx);
    for (size_t i = 0; i < sizeof inputs / sizeof *inputs; i++) {
        limn_status st = limn_mesh_read(ctx, path_in(inputs[i].name), LIMN_FORMAT_AUTO,
                                         &meshes[i]);
        if (st)
            fail_msg("%s locale: reading %s: %s", tag, inputs[i].name,
                     limn_context_message(ctx));
        for (size_t k = 0; k < sizeof outputs / sizeof *outputs; k++) {
            char name[64];
            snprintf(name, sizeof name, "%s_%zu_%zu.%s", tag, i, k, outputs[k].ext);
            st = limn_mesh_write(ctx, meshes[i], path_in(name), outputs[k].format);
            if (st)
                fail_msg("%s locale: writing %s: %s", tag, name, limn_context_message(ctx));
        }
    }
    limn_context_destroy(ctx);
}

static void library_reads_and_writes_in_any_locale(void **s)
{
    (void)s;
    for (size_t i = 0; i < sizeof inputs / sizeof *inputs; i++)
        assert_int_equal(test_write_text(path_in(inputs[i].name), inputs[i].text), 0);
    enum { N = sizeof inputs / sizeof *inputs };
    limn_mesh *c[N], *de[N];
    assert_non_null(setlocale(LC_ALL, "C"));
    read_and_write_all("c", c);

    assert_non_null(setlocale(LC_ALL, DE));
    char buf[32];
    snprintf(buf, sizeof buf, "%g", 0.5);
    assert_string_equal(buf, "0,5"); /* else this test would prove nothing */
    read_and_write_all("de", de);
    /* the host's own locale is left as it was */
    snprintf(buf, sizeof buf, "%g", 0.5);
    assert_string_equal(buf, "0,5");
    setlocale(LC_ALL, "C");

    for (size_t i = 0; i < N; i++) {
        size_t nv = limn_mesh_vertex_count(c[i]);
        assert_int_equal(nv, limn_mesh_vertex_count(de[i]));
        assert_int_equal(limn_mesh_face_count(c[i]), limn_mesh_face_count(de[i]));
        assert_memory_equal(limn_mesh_positions(c[i]), limn_mesh_positions(de[i]),
                            nv * 3 * sizeof(double));
        assert_true(limn_mesh_positions(c[i])[0] == 0.5);
        for (size_t k = 0; k < sizeof outputs / sizeof *outputs; k++) {
            char a[64], b[64];
            snprintf(a, sizeof a, "c_%zu_%zu.%s", i, k, outputs[k].ext);
            snprintf(b, sizeof b, "de_%zu_%zu.%s", i, k, outputs[k].ext);
            size_t na, nb;
            char *ta = test_slurp(path_in(a), &na), *tb = test_slurp(path_in(b), &nb);
            assert_non_null(ta);
            assert_non_null(tb);
            if (na != nb || memcmp(ta, tb, na) != 0)
                fail_msg("%s and %s differ:\n%s\n---\n%s", a, b, ta, tb);
            free(ta);
            free(tb);
        }
        limn_mesh_destroy(c[i]);
        limn_mesh_destroy(de[i]);
    }
}

/* A thread with its own German locale (uselocale, the process stays in C):
   reads as the C locale does and keeps its locale afterwards. */
static void *german_thread(void *arg)
{
    double *x = arg;
    locale_t de = newlocale(LC_ALL_MASK, DE, (locale_t)0);
    if (de == (locale_t)0)
        return NULL;
    locale_t prev = uselocale(de);
    limn_context *ctx = limn_context_create();
    limn_mesh *m = NULL;
    if (ctx && limn_mesh_read(ctx, path_in("q.off"), LIMN_FORMAT_AUTO, &m) == LIMN_OK)
        x[0] = limn_mesh_positions(m)[0];
    char buf[32];
    snprintf(buf, sizeof buf, "%g", 0.5);
    x[1] = strcmp(buf, "0,5") == 0;
    limn_mesh_destroy(m);
    limn_context_destroy(ctx);
    uselocale(prev);
    freelocale(de);
    return NULL;
}

static void thread_locale_is_kept(void **s)
{
    (void)s;
    assert_int_equal(test_write_text(path_in("q.off"), inputs[1].text), 0);
    double x[2] = {0, 0};
    pthread_t t;
    assert_int_equal(pthread_create(&t, NULL, german_thread, x), 0);
    assert_int_equal(pthread_join(t, NULL), 0);
    assert_true(x[0] == 0.5); /* read with a '.' */
    assert_true(x[1] == 1);   /* and the thread's locale is German again */
}

/* ------------------------------------------------------------------ the CLI */

/* Runs the CLI with LC_ALL=locale in dir/locale/; its output into out. */
static int run_cli(const char *locale, char *out, size_t n, const char *fmt, ...)
{
    char args[2048], cmd[4096];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(args, sizeof args, fmt, ap);
    va_end(ap);
    const char *bin = getenv("LIMN_BIN");
    assert_non_null(bin);
    snprintf(cmd, sizeof cmd, "mkdir -p '%s/%s' && cd '%s/%s' && LC_ALL=%s '%s' %s 2>&1", dir,
             locale, dir, locale, locale, bin, args);
    return test_run(out, n, cmd);
}

/* The report without what differs between two runs anyway (times, memory). */
static void stable_lines(char *json)
{
    char *w = json;
    int in_seconds = 0;
    for (char *line = strtok(json, "\n"); line; line = strtok(NULL, "\n")) {
        if (strstr(line, "\"seconds\": {") || strstr(line, "\"opencl_setup\": {"))
            in_seconds = 1;
        int skip = in_seconds || strstr(line, "\"peak_rss_bytes\"") != NULL;
        if (in_seconds && strchr(line, '}'))
            in_seconds = 0;
        if (skip)
            continue;
        size_t n = strlen(line);
        memmove(w, line, n);
        w[n] = '\n';
        w += n + 1;
    }
    *w = '\0';
}

static void cli_reports_the_same_numbers(void **s)
{
    (void)s;
    static char c[1 << 14], de[1 << 14];
    const char *mesh = path_in("q.obj");
    assert_int_equal(test_write_text(mesh, inputs[0].text), 0);
    assert_int_equal(run_cli("C", c, sizeof c, "info '%s' --json", mesh), 0);
    assert_int_equal(run_cli(DE, de, sizeof de, "info '%s' --json", mesh), 0);
    assert_string_equal(c, de);
    assert_non_null(strstr(c, "\"bbox\": [[0.001, 0, -0.125], [1.75, 250, 0.1]]"));
    /* the text summary too */
    assert_int_equal(run_cli("C", c, sizeof c, "info '%s'", mesh), 0);
    assert_int_equal(run_cli(DE, de, sizeof de, "info '%s'", mesh), 0);
    assert_string_equal(c, de);

    /* a report with fractions, an option with a decimal point, the mesh written */
    const char *sub = "subdivide '%s' -o s.obj --levels 1 --limit --alpha 0.5 --scheme catmark "
                      "--device reference --report s.json -q";
    assert_int_equal(run_cli("C", c, sizeof c, sub, mesh), 0);
    if (run_cli(DE, de, sizeof de, sub, mesh) != 0)
        fail_msg("subdivide under %s failed:\n%s", DE, de);
    size_t na, nb;
    char *ra = test_slurp(path_in("C/s.json"), &na), *rb = test_slurp(path_in(DE "/s.json"), &nb);
    assert_non_null(ra);
    assert_non_null(rb);
    assert_non_null(strstr(ra, "\"alpha\": 0.5"));
    assert_non_null(strstr(ra, "\"limit\": true"));
    stable_lines(ra);
    stable_lines(rb);
    assert_string_equal(ra, rb);
    free(ra);
    free(rb);
    /* option values with a decimal point, and one with a comma between two numbers */
    if (run_cli(DE, de, sizeof de, "render '%s' -o r.png --view 30.5,20 --size 32x32", mesh) != 0)
        fail_msg("render --view 30.5,20 under %s failed:\n%s", DE, de);
    char *ma = test_slurp(path_in("C/s.obj"), &na), *mb = test_slurp(path_in(DE "/s.obj"), &nb);
    assert_non_null(ma);
    assert_non_null(mb);
    assert_int_equal(na, nb);
    assert_memory_equal(ma, mb, na);
    free(ma);
    free(mb);
}

int main(void)
{
    char why[256];
    if (!have_german(why, sizeof why)) {
        printf("test_locale: skipped: %s\n", why);
        return 77;
    }
    if (test_make_dir(dir, sizeof dir, "locale") != 0)
        return 1;
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(library_reads_and_writes_in_any_locale),
        cmocka_unit_test(thread_locale_is_kept),
        cmocka_unit_test(cli_reports_the_same_numbers),
    };
    int failed = cmocka_run_group_tests(tests, NULL, NULL);
    if (test_remove_dir(dir) != 0)
        failed = 1;
    return failed;
}
