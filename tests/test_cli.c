/* SPDX-License-Identifier: MIT */
/*
 * The limn command line as a user meets it: every class of bad input and bad
 * option gives its exit status and a message naming the file, line or element,
 * and writes nothing (an existing output file is left as it was). A good run
 * writes the mesh and a JSON report with the documented keys.
 */
#include "shell.h"
#include "support.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmocka.h>

static char out_path[256];

static int setup(void **s)
{
    (void)s;
    if (test_scratch_make("cli", NULL) != 0)
        return -1;
    snprintf(out_path, sizeof out_path, "%s/out.ply", test_dir);
    return 0;
}

/* Runs `limn ARGS` and captures stdout+stderr into test_text; returns the exit status. */
static int limn(const char *args)
{
    return test_limn(test_text, sizeof test_text, NULL, "%s", args);
}

static const char *in_dir(const char *name) { return test_join(test_dir, name); }

/* Writes an input file (in_* names survive no_output_left) and returns its path. */
static const char *write_input(const char *name, const char *content)
{
    const char *path = in_dir(name);
    assert_int_equal(test_write_text(path, content), 0);
    return path;
}

static void no_output_left(void)
{
    char cmd[512];
    snprintf(cmd, sizeof cmd, "ls -A '%s' | grep -v '^in_' | grep -q .", test_dir);
    if (system(cmd) == 0) {
        snprintf(cmd, sizeof cmd, "ls -la '%s' >&2", test_dir);
        (void)system(cmd);
        fail_msg("a failed run left files behind");
    }
}

static void expect_failure_opts(const char *name, const char *content, int status,
                                const char *message, const char *opts)
{
    const char *path = write_input(name, content);
    char args[1024];
    snprintf(args, sizeof args, "interpolate '%s' -o '%s' %s", path, out_path, opts);
    int rc = limn(args);
    if (rc != status || !strstr(test_text, message))
        fail_msg("%s: exit %d (want %d), output:\n%s\nwanted: %s", name, rc, status, test_text,
                 message);
    no_output_left();
    unlink(path);
}

/* `limn ARGS` (printf-style) exits with status and its output has message. */
static void expect_run(int status, const char *message, const char *fmt, ...)
{
    char args[2048];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(args, sizeof args, fmt, ap);
    va_end(ap);
    assert_int_equal(limn(args), status);
    assert_non_null(strstr(test_text, message));
}

static void expect_failure(const char *name, const char *content, int status, const char *message)
{
    expect_failure_opts(name, content, status, message, "");
}

static void malformed_inputs(void **s)
{
    (void)s;
    expect_failure("in_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n", 1,
                   "in_index.obj:4: face references vertex 9");
    expect_failure("in_neg.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n", 1, "in_neg.obj:4:");
    expect_failure("in_short.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n", 1, "in_short.obj:3:");
    expect_failure("in_word.obj", "v 0 zero 0\n", 1, "in_word.obj:1:");
    expect_failure("in_nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n", 1, "in_nan.obj:2:");
    expect_failure("in_empty.obj", "", 1, "in_empty.obj");
    /* repaired by default (tests/test_robust.c); refused with --no-repair */
    expect_failure_opts("in_degenerate.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 2\n",
                        1, "face 1 uses vertex 1 twice", "--no-repair");
    expect_failure("in_header.ply",
                   "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\n"
                   "property float x\nproperty float y\nproperty float z\nend_header\n",
                   1, "in_header.ply");
    expect_failure("in_trunc.ply",
                   "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                   "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                   "end_header\n0 0 0\n1 0 0\n",
                   1, "in_trunc.ply");
    expect_failure("in_format.ply", "ply\nformat binary_middle_endian 1.0\nend_header\n", 1,
                   "in_format.ply");
    expect_failure("in_counts.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n", 1, "in_counts.off");
    expect_failure("in_unknown.stlx", "solid x\n", 2, "in_unknown.stlx");
    expect_failure("in_trunc.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n", 1,
                   "in_trunc.stl:4: facet 0: the file ends inside the facet (truncated)");
}

/* Reads a whole small file into buf (NUL-terminated); returns its length. */
static size_t slurp(const char *path, char *buf, size_t cap)
{
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    size_t n = fread(buf, 1, cap - 1, f);
    buf[n] = '\0';
    fclose(f);
    return n;
}

/* getopt_long in every command: "--tol=1e-8" is "--tol 1e-8" (same report
   tolerance, same mesh), an unknown option gets the nearest long one, and
   every message has the one prefix "limn COMMAND: error: ". */
static void option_spellings(void **s)
{
    (void)s;
    char spot[512], args[2048];
    snprintf(spot, sizeof spot, "%s/spot_control_mesh.obj", getenv("LIMN_TEST_DATA"));
    static char mesh[2][1 << 16], report[2][1 << 14];
    size_t mesh_len[2];
    const char *spelling[2] = {"--tol=1e-8", "--tol 1e-8"};
    for (int k = 0; k < 2; k++) {
        snprintf(args, sizeof args,
                 "interpolate '%s' -o '%s/in_eq%d.obj' --report='%s/in_eq%d.json' %s -q", spot,
                 test_dir, k, test_dir, k, spelling[k]);
        if (limn(args) != 0)
            fail_msg("%s: %s", spelling[k], test_text);
        char path[512];
        snprintf(path, sizeof path, "%s/in_eq%d.obj", test_dir, k);
        mesh_len[k] = slurp(path, mesh[k], sizeof mesh[k]);
        snprintf(path, sizeof path, "%s/in_eq%d.json", test_dir, k);
        slurp(path, report[k], sizeof report[k]);
        if (!strstr(report[k], "\"tolerance\": 1e-08,"))
            fail_msg("%s: the report's tolerance is not 1e-08:\n%s", spelling[k], report[k]);
    }
    assert_int_equal(mesh_len[0], mesh_len[1]);
    assert_memory_equal(mesh[0], mesh[1], mesh_len[0]);
    /* an unambiguous prefix is the option */
    snprintf(args, sizeof args, "interpolate '%s' -o '%s/in_eq2.obj' --max-it 3 -q", spot,
             test_dir);
    int rc = limn(args); /* 1 when 3 iterations do not converge */
    if (rc == 2 || strstr(test_text, "unknown option"))
        fail_msg("--max-it was not taken for --max-iter: exit %d, %s", rc, test_text);

    struct {
        const char *args;
        const char *message;
    } cases[] = {
        {"interpolate '%s' -o out.ply --tl 1e-6",
         "limn interpolate: error: unknown option '--tl'; did you mean --tol? (see 'limn "
         "interpolate --help')\n"},
        {"interpolate '%s' -o out.ply --tl=1e-6", "unknown option '--tl=1e-6'; did you mean --tol?"},
        {"interpolate '%s' -o out.ply --frobnicate", "limn interpolate: error: unknown option "
                                                     "'--frobnicate' (see"},
        {"interpolate '%s' -o out.ply --quiet=yes", "limn interpolate: error: --quiet takes no value"},
        {"interpolate '%s' -o out.ply --alpha=x", "limn interpolate: error: --alpha expects a number"},
        {"subdivide '%s' -o out.ply --levles 2", "did you mean --levels?"},
        {"smooth '%s' -o out.ply --trems 3", "limn smooth: error: unknown option '--trems'; did you "
                                             "mean --terms?"},
        {"info '%s' --jsno", "limn info: error: unknown option '--jsno'; did you mean --json?"},
        {"render '%s' -o r.png --sise 64x64", "did you mean --size?"},
        {"interpolate '%s' -o out.ply --s 1", "option '--s' is ambiguous: --scheme, --surface"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        char line[1024];
        snprintf(line, sizeof line, cases[i].args, spot);
        snprintf(args, sizeof args, "%s", line);
        int rc = limn(args);
        if (rc != 2 || !strstr(test_text, cases[i].message))
            fail_msg("limn %s: exit %d, output:\n%s\nwanted exit 2 and: %s", line, rc, test_text,
                     cases[i].message);
    }
    assert_int_equal(limn("frobnicate"), 2);
    assert_non_null(strstr(test_text, "limn: error: unknown command 'frobnicate'"));
}

static void bad_usage(void **s)
{
    (void)s;
    const char *spot_env = getenv("LIMN_TEST_DATA");
    char spot[512], args[2048];
    snprintf(spot, sizeof spot, "%s/spot_control_mesh.obj", spot_env);
    struct {
        const char *opts;
        const char *message;
    } cases[] = {
        {"--alpha 2", "--alpha 2 is outside [0, 1]"},
        {"--alpha x", "--alpha expects a number"},
        {"--tol -1", "--tol -1 must be positive"},
        {"--max-iter 0", "--max-iter 0 must be at least 1"},
        {"--scheme butterfly", "--scheme 'butterfly' is not one of"},
        {"--frobnicate", "unknown option '--frobnicate'"},
        {"--format gltf", "--format 'gltf' is not one of"},
        {"--device cuda", "unknown device 'cuda'"},
        {"--device opencl:no-such-device", "no OpenCL device matches --device='no-such-device'"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        snprintf(args, sizeof args, "interpolate '%s' -o '%s' %s", spot, out_path, cases[i].opts);
        int rc = limn(args);
        if (rc == 0 || !strstr(test_text, cases[i].message))
            fail_msg("%s: exit %d, output:\n%s\nwanted: %s", cases[i].opts, rc, test_text,
                     cases[i].message);
        no_output_left();
    }
    expect_run(2, "no output given", "interpolate '%s'", spot);
    expect_run(2, "cannot tell the format", "interpolate '%s' -o '%s/out.xyz'", spot, test_dir);
    expect_run(1, "missing/dir/out.ply", "interpolate '%s' -o '%s/missing/dir/out.ply'", spot,
               test_dir);
    /* Loop on a mesh with quads */
    expect_run(1, "Loop subdivision needs triangles",
               "interpolate '%s' -o '%s' --scheme loop", spot, out_path);
    no_output_left();
    assert_int_equal(limn("frobnicate"), 2);
    assert_int_equal(limn(""), 2);
    /* output = input is refused */
    const char *copy = in_dir("in_copy.obj");
    snprintf(args, sizeof args, "cp '%s' '%s'", spot, copy);
    assert_int_equal(system(args), 0);
    expect_run(2, "is the input file", "interpolate '%s' -o '%s'", copy, copy);
    unlink(copy);
}

/* A perturbed cube with alpha = 0 is singular: clear message, nothing written,
   and an existing output file is left exactly as it was. */
static void singular_keeps_existing_output(void **s)
{
    (void)s;
    const char *cube = write_input("in_cube.obj",
                                   "v -1 -1 -1\nv 1 -1 -1.1\nv 1 1 -1\nv -1 1 -1\n"
                                   "v -1 -1 1\nv 1.2 -1 1\nv 1 1 1\nv -1 1 1\n"
                                   "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\n"
                                   "f 3 4 8 7\nf 4 1 5 8\n");
    assert_int_equal(test_write_text(out_path, "KEEP"), 0);
    char args[1024];
    expect_run(1, "--alpha 0.5", "interpolate '%s' -o '%s'", cube, out_path);
    FILE *f = fopen(out_path, "rb");
    char buf[8] = "";
    assert_non_null(f);
    assert_int_equal(fread(buf, 1, sizeof buf, f), 4);
    fclose(f);
    assert_memory_equal(buf, "KEEP", 4);
    unlink(out_path);
    no_output_left();
    snprintf(args, sizeof args, "interpolate '%s' -o '%s' --alpha 0.5 -q", cube, out_path);
    assert_int_equal(limn(args), 0);
    assert_true(test_file_exists(out_path));
    unlink(out_path);
    unlink(cube);
}

static void good_run_and_report(void **s)
{
    (void)s;
    char spot[512], report[300];
    snprintf(spot, sizeof spot, "%s/spot_control_mesh.obj", getenv("LIMN_TEST_DATA"));
    snprintf(report, sizeof report, "%s/report.json", test_dir);
    expect_run(0, "iterations",
               "interpolate '%s' -o '%s' --report '%s' --tol 1e-7", spot, out_path, report);
    assert_true(test_file_exists(out_path));
    FILE *f = fopen(report, "r");
    assert_non_null(f);
    char json[8192];
    size_t n = fread(json, 1, sizeof json - 1, f);
    json[n] = '\0';
    fclose(f);
    static const char *keys[] = {"\"vertices\": 188", "\"faces\": 180", "\"scheme\": \"catmark\"",
                                 "\"alpha\": 0", "\"method\": \"chebyshev\"",
                                 "\"iterations\": ", "\"products\": ",
                                 "\"max_rel_error\": ", "\"mean_rel_error\": ", "\"device\": ",
                                 "\"seconds\": {", "\"load\": ", "\"topology\": ",
                                 "\"stencil\": ", "\"solve\": ", "\"write\": "};
    for (size_t i = 0; i < sizeof keys / sizeof *keys; i++)
        if (!strstr(json, keys[i]))
            fail_msg("report lacks %s:\n%s", keys[i], json);
    double rel = strtod(strstr(json, "\"max_rel_error\": ") + 17, NULL);
    assert_true(rel <= 1e-7);
    /* the written control mesh reads back with the input's counts */
    expect_run(0, "\"vertices\": 188, \"faces\": 180", "info '%s' --json", out_path);
    unlink(report);
    unlink(out_path);
    assert_int_equal(limn("devices"), 0);
    assert_non_null(strstr(test_text, "reference"));
}

/* Issue 13.6: reading, the repair and its topology, and writing show
   progress on a terminal (script(1) gives the run one), never on a pipe or with -q. */
static void progress_on_a_terminal(void **s)
{
    (void)s;
    if (system("command -v script >/dev/null 2>&1") != 0)
        skip(); /* util-linux's script: the pty */
    char spot[512];
    snprintf(spot, sizeof spot, "%s/spot_control_mesh.obj", getenv("LIMN_TEST_DATA"));
    static const char *stages[] = {"read", "repair", "topology"};
    assert_int_equal(test_runf(test_text, sizeof test_text,
                               "script -qec \"'%s' info '%s'\" /dev/null", getenv("LIMN_BIN"),
                               spot),
                     0);
    for (size_t i = 0; i < sizeof stages / sizeof *stages; i++) {
        char line[64];
        snprintf(line, sizeof line, "\r  %-10s 100%%", stages[i]);
        if (!strstr(test_text, line))
            fail_msg("no '%s' progress on a terminal:\n%s", stages[i], test_text);
    }
    assert_non_null(strstr(test_text, "vertices   188"));
    assert_int_equal(test_runf(test_text, sizeof test_text,
                               "script -qec \"'%s' interpolate '%s' -o '%s'\" /dev/null",
                               getenv("LIMN_BIN"), spot, out_path),
                     0);
    if (!strstr(test_text, "\r  write      100%"))
        fail_msg("no write progress on a terminal:\n%s", test_text);
    assert_int_equal(test_runf(test_text, sizeof test_text,
                               "script -qec \"'%s' interpolate -q '%s' -o '%s'\" /dev/null",
                               getenv("LIMN_BIN"), spot, out_path),
                     0);
    assert_null(strstr(test_text, "100%")); /* -q: none */
    unlink(out_path);
    expect_run(0, "vertices", "info '%s'", spot); /* a pipe: no progress */
    assert_null(strchr(test_text, '\r'));
}

/* Issue 11.4: subdivide drops vertex colours, and says so. */
static void subdivide_warns_of_dropped_colours(void **s)
{
    (void)s;
    const char *in = write_input("in_rgb.ply",
                                 "ply\nformat ascii 1.0\nelement vertex 4\n"
                                 "property float x\nproperty float y\nproperty float z\n"
                                 "property uchar red\nproperty uchar green\n"
                                 "property uchar blue\nelement face 4\n"
                                 "property list uchar int vertex_indices\nend_header\n"
                                 "0 0 0 255 0 0\n1 0 0 0 255 0\n0 1 0 0 0 255\n"
                                 "0 0 1 9 9 9\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
    char args[1024];
    snprintf(args, sizeof args, "subdivide '%s' -o '%s' -q", in, out_path);
    assert_int_equal(limn(args), 0);
    if (!strstr(test_text, "limn subdivide: warning: the input's vertex colours were dropped"))
        fail_msg("no warning about the colours:\n%s", test_text);
    unlink(out_path);
    unlink(in);
}

/* --output-precision float (issue 13.4): the PLY reads back as (float) of
   the double output, the report's error is the distance between the two
   read back; OBJ and a bad value refused before any work, nothing written. */
static double report_number(const char *json, const char *key)
{
    const char *at = strstr(json, key);
    assert_non_null(at);
    return strtod(at + strlen(key) + 3, NULL); /* past `key": ` */
}

static void output_precision_float(void **s)
{
    (void)s;
    char spot[512], args[4096], f[300], d[300], rep[300];
    snprintf(spot, sizeof spot, "%s/spot_control_mesh.obj", getenv("LIMN_TEST_DATA"));
    snprintf(f, sizeof f, "%s/float.ply", test_dir);
    snprintf(d, sizeof d, "%s/double.ply", test_dir);
    snprintf(rep, sizeof rep, "%s/float.json", test_dir);
    snprintf(args, sizeof args, "subdivide '%s' -o '%s' --output-precision float --report '%s'",
             spot, f, rep);
    assert_int_equal(limn(args), 0);
    assert_non_null(strstr(test_text, "output: float32 positions, error max"));
    snprintf(args, sizeof args, "subdivide '%s' -o '%s' -q --output-precision double", spot, d);
    assert_int_equal(limn(args), 0);
    limn_context *ctx = limn_context_create();
    limn_mesh *mf = NULL, *md = NULL;
    assert_int_equal(limn_mesh_read(ctx, f, LIMN_FORMAT_AUTO, &mf), LIMN_OK);
    assert_int_equal(limn_mesh_read(ctx, d, LIMN_FORMAT_AUTO, &md), LIMN_OK);
    size_t n = limn_mesh_vertex_count(md);
    assert_int_equal(limn_mesh_vertex_count(mf), n);
    const double *pf = limn_mesh_positions(mf), *pd = limn_mesh_positions(md);
    double most = 0, sum = 0;
    for (size_t v = 0; v < n; v++) {
        double d2 = 0;
        for (int j = 0; j < 3; j++) {
            assert_true(pf[3 * v + j] == (double)(float)pd[3 * v + j]);
            d2 += (pf[3 * v + j] - pd[3 * v + j]) * (pf[3 * v + j] - pd[3 * v + j]);
        }
        sum += sqrt(d2);
        most = fmax(most, sqrt(d2));
    }
    size_t len;
    char *json = test_slurp(rep, &len);
    assert_non_null(json);
    assert_non_null(strstr(json, "\"precision\": \"float\""));
    assert_true(most > 0 && report_number(json, "max_error") == most);
    assert_true(fabs(report_number(json, "mean_error") - sum / (double)n) <= 1e-12 * most);
    free(json);
    limn_mesh_destroy(mf);
    limn_mesh_destroy(md);
    limn_context_destroy(ctx);
    snprintf(f, sizeof f, "%s/float.obj", test_dir);
    snprintf(args, sizeof args, "subdivide '%s' -o '%s' --output-precision float", spot, f);
    assert_int_equal(limn(args), 2);
    assert_non_null(strstr(test_text, "--output-precision float is for PLY output only"));
    assert_int_not_equal(access(f, F_OK), 0);
    snprintf(args, sizeof args, "interpolate '%s' -o '%s' --output-precision half", spot, d);
    assert_int_equal(limn(args), 2);
    assert_non_null(strstr(test_text, "'half' is not one of float, double"));
    unlink(d);
    unlink(rep);
    snprintf(f, sizeof f, "%s/float.ply", test_dir);
    unlink(f);
}

static void subdivide_and_surface(void **s)
{
    (void)s;
    char spot[512], args[4096], report[300], ctrl[300], surf[300];
    snprintf(spot, sizeof spot, "%s/spot_control_mesh.obj", getenv("LIMN_TEST_DATA"));
    snprintf(report, sizeof report, "%s/sub.json", test_dir);
    snprintf(ctrl, sizeof ctrl, "%s/ctrl.ply", test_dir);
    snprintf(surf, sizeof surf, "%s/surf.obj", test_dir);
    expect_run(0, "2930 vertices, 2928 faces",
               "subdivide '%s' -o '%s' --levels 2 --report '%s'", spot, out_path, report);
    FILE *f = fopen(report, "r");
    assert_non_null(f);
    char json[8192];
    size_t n = fread(json, 1, sizeof json - 1, f);
    json[n] = '\0';
    fclose(f);
    assert_non_null(strstr(json, "\"output_vertices\": 2930"));
    assert_non_null(strstr(json, "\"levels\": 2"));
    assert_non_null(strstr(json, "\"peak_rss_bytes\": "));
    unlink(report);
    unlink(out_path);
    /* bad usage and refusals write nothing */
    expect_run(2, "--levels 17 is outside 0..16",
               "subdivide '%s' -o '%s' --levels 17", spot, out_path);
    expect_run(1, "raise --max-memory",
               "subdivide '%s' -o '%s' --levels 7 --max-memory 64M", spot, out_path);
    expect_run(2, "--max-memory expects a size",
               "subdivide '%s' -o '%s' --max-memory lots", spot, out_path);
    no_output_left();
    /* interpolate + surface in one run; the refusal comes before solving */
    expect_run(2, "need --surface", "interpolate '%s' -o '%s' --levels 2", spot, ctrl);
    snprintf(args, sizeof args,
             "interpolate '%s' -o '%s' --surface '%s' --levels 7 --max-memory 64M", spot, ctrl,
             surf);
    assert_int_equal(limn(args), 1);
    assert_non_null(strstr(test_text, "raise --max-memory"));
    no_output_left();
    snprintf(args, sizeof args,
             "interpolate '%s' -o '%s' --surface '%s' --levels 2 --limit --alpha 0.5", spot, ctrl,
             surf);
    assert_int_equal(limn(args), 0);
    assert_non_null(strstr(test_text, "surface: "));
    assert_true(test_file_exists(ctrl));
    assert_true(test_file_exists(surf));
    expect_run(0, "\"vertices\": 2930, \"faces\": 2928", "info '%s' --json", surf);
    unlink(ctrl);
    unlink(surf);
}

/* --help lists --version, which prints the library's version. */
static void version_and_help(void **s)
{
    (void)s;
    assert_int_equal(limn("--help"), 0);
    assert_non_null(strstr(test_text, "--version"));
    assert_int_equal(limn("--version"), 0);
    char expect[64];
    snprintf(expect, sizeof expect, "limn %d.%d.%d\n", LIMN_VERSION_MAJOR, LIMN_VERSION_MINOR,
             LIMN_VERSION_PATCH);
    assert_string_equal(test_text, expect);
}

TEST_MAIN(setup, test_scratch_teardown, cmocka_unit_test(version_and_help),
          cmocka_unit_test(malformed_inputs), cmocka_unit_test(bad_usage),
          cmocka_unit_test(option_spellings), cmocka_unit_test(singular_keeps_existing_output),
          cmocka_unit_test(good_run_and_report), cmocka_unit_test(subdivide_and_surface),
          cmocka_unit_test(subdivide_warns_of_dropped_colours),
          cmocka_unit_test(output_precision_float), cmocka_unit_test(progress_on_a_terminal))
