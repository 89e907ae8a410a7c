/* SPDX-License-Identifier: MIT */
/*
 * The readers against what other tools write and what a user may hand them
 * (issues 11.4, 18.1-18.3): a UTF-8 byte order mark, CR-only and CRLF line
 * ends (also split across the reader's buffer), the OFF family's header
 * words (MeshLab's NCOFF with colours), two OFF faces on one line, endless
 * or huge inputs (/dev/zero, a pipe, a limit on memory), pipes without a
 * format, PLY vertex properties that are dropped, and JSON that stays valid
 * for any file name.
 */
#ifndef _POSIX_C_SOURCE
#define _POSIX_C_SOURCE 200809L
#endif
#include "shell.h"
#include "support.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <cmocka.h>

static limn_context *ctx;

static const char *path_in(const char *name) { return test_join(test_dir, name); }

static const char *write_bytes(const char *name, const void *data, size_t n)
{
    return test_write_bytes(path_in(name), data, n);
}

static const char *write_str(const char *name, const char *s)
{
    return write_bytes(name, s, strlen(s));
}

/* Runs a shell command line in test_dir (stderr too into test_text); its exit status. */
#define run_sh(...) test_in_dir(test_text, sizeof test_text, test_dir, __VA_ARGS__)

static const char *bin(void)
{
    const char *b = getenv("LIMN_BIN");
    assert_non_null(b);
    return b;
}

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static limn_mesh *read_ok(const char *path, limn_format format)
{
    limn_mesh *m = NULL;
    if (limn_mesh_read(ctx, path, format, &m) != LIMN_OK)
        fail_msg("reading %s: %s", path, limn_context_message(ctx));
    return m;
}

static void read_fails(const char *path, limn_format format, limn_status want, const char *msg)
{
    limn_mesh *m = NULL;
    limn_status st = limn_mesh_read(ctx, path, format, &m);
    assert_null(m);
    if (st != want || !strstr(limn_context_message(ctx), msg))
        fail_msg("reading %s: %s (%s), wanted %s with '%s'", path, limn_status_name(st),
                 limn_context_message(ctx), limn_status_name(want), msg);
}

/* Reads name with its test_text as given and as the reference; they must agree. */
static void same_as(const char *name, const char *variant, size_t n, const char *reference)
{
    char ref[64];
    snprintf(ref, sizeof ref, "ref_%s", name);
    limn_mesh *a = read_ok(write_bytes(name, variant, n), LIMN_FORMAT_AUTO);
    limn_mesh *b = read_ok(write_str(ref, reference), LIMN_FORMAT_AUTO);
    test_assert_same_mesh(a, b);
    limn_mesh_destroy(a);
    limn_mesh_destroy(b);
}

static const char *const texts[][2] = {
    {"t.obj", "# quad\nv 0 0 0.5\nv 1 0 0\nv 1 1 0\nv 0 1 0.25\nf 1 2 3 4\n"},
    {"t.off", "OFF\n4 1 0\n0 0 0.5\n1 0 0\n1 1 0\n0 1 0.25\n4 0 1 2 3\n"},
    {"t.ply", "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
              "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
              "end_header\n0 0 0.5\n1 0 0\n1 1 0\n0 1 0.25\n4 0 1 2 3\n"},
    {"t.stl", "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0.5\nvertex 1 0 0\n"
              "vertex 1 1 0\nendloop\nendfacet\nendsolid t\n"},
};
enum { NTEXTS = sizeof texts / sizeof *texts };

/* ------------------------------------------------------- byte order mark */

static void bom_is_skipped(void **s)
{
    (void)s;
    for (size_t i = 0; i < NTEXTS; i++) {
        char b[1024];
        int n = snprintf(b, sizeof b, "\xEF\xBB\xBF%s", texts[i][1]);
        same_as(texts[i][0], b, (size_t)n, texts[i][1]);
    }
    /* an ascii STL with a BOM was taken for binary ("declares 540024952 triangles") */
    assert_null(strstr(limn_context_warnings(ctx), "triangles,"));
    /* a binary STL whose header happens to start with a BOM and "solid" stays binary */
    unsigned char stl[84 + 50];
    memset(stl, 0, sizeof stl);
    memcpy(stl, "\xEF\xBB\xBFsolid binary", 15);
    stl[80] = 1;
    float tri[12] = {0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0};
    memcpy(stl + 84, tri, sizeof tri);
    limn_mesh *m = read_ok(write_bytes("bom_bin.stl", stl, sizeof stl), LIMN_FORMAT_AUTO);
    assert_int_equal(limn_mesh_face_count(m), 1);
    assert_non_null(strstr(limn_context_warnings(ctx), "1 triangles"));
    limn_mesh_destroy(m);
}

/* ------------------------------------------------------------- line ends */

/* test_text with every "\n" replaced by end */
static size_t with_ends(char *out, size_t cap, const char *in, const char *end)
{
    size_t n = 0, e = strlen(end);
    for (; *in && n + e < cap; in++)
        if (*in == '\n') {
            memcpy(out + n, end, e);
            n += e;
        } else {
            out[n++] = *in;
        }
    return n;
}

static void cr_and_crlf_line_ends(void **s)
{
    (void)s;
    char b[2048];
    for (size_t i = 0; i < NTEXTS; i++) {
        same_as(texts[i][0], b, with_ends(b, sizeof b, texts[i][1], "\r"), texts[i][1]);
        same_as(texts[i][0], b, with_ends(b, sizeof b, texts[i][1], "\r\n"), texts[i][1]);
    }
    /* line numbers count a CR-only or CRLF end once */
    const char *bad = "v 0 0 0\nv 1 0 0\nv x 1 0\n";
    read_fails(write_bytes("cr_bad.obj", b, with_ends(b, sizeof b, bad, "\r")), LIMN_FORMAT_AUTO,
               LIMN_ERR_FORMAT, "cr_bad.obj:3: vertex 3: coordinate 'x' is not a number");
    read_fails(write_bytes("crlf_bad.obj", b, with_ends(b, sizeof b, bad, "\r\n")),
               LIMN_FORMAT_AUTO, LIMN_ERR_FORMAT, "crlf_bad.obj:3: vertex 3");
    /* "\r\n" split by the reader's first fill (65535 bytes): still one line end */
    size_t fill = 65535, n = 0;
    char *big = malloc(fill + 256);
    assert_non_null(big);
    big[n++] = '#';
    while (n < fill - 1)
        big[n++] = 'c';
    big[n++] = '\r'; /* the last byte of the first fill */
    n += (size_t)sprintf(big + n, "\nv 0 0 0\r\nv 1 0 0\r\nv x 1 0\r\n");
    read_fails(write_bytes("split.obj", big, n), LIMN_FORMAT_AUTO, LIMN_ERR_FORMAT,
               "split.obj:4: vertex 3");
    /* the same with a CR-only end at the boundary */
    n = fill;
    n += (size_t)sprintf(big + n, "v 0 0 0\rv 1 0 0\rv x 1 0\r");
    read_fails(write_bytes("split_cr.obj", big, n), LIMN_FORMAT_AUTO, LIMN_ERR_FORMAT,
               "split_cr.obj:4: vertex 3");
    free(big);
}

/* ------------------------------------------------------------ OFF family */

static void off_header_words(void **s)
{
    (void)s;
    /* MeshLab (vcglib): NCOFF, then per vertex x y z, r g b a (0-255), nx ny nz */
    limn_mesh *m = read_ok(write_str("meshlab.off",
                                     "NCOFF\n4 2 0\n"
                                     "0 0 0 255 0 0 255 0 0 1 \n"
                                     "1 0 0 0 255 0 255 0 0 1 \n"
                                     "1 1 0 0 0 255 255 0 0 1 \n"
                                     "0 1 0 10 20 30 255 0 0 1 \n"
                                     "3 0 1 2 \n3 0 2 3 \n"),
                           LIMN_FORMAT_AUTO);
    static const uint8_t rgb[12] = {255, 0, 0, 0, 255, 0, 0, 0, 255, 10, 20, 30};
    assert_non_null(limn_mesh_colors(m));
    assert_memory_equal(limn_mesh_colors(m), rgb, sizeof rgb);
    assert_true(limn_mesh_positions(m)[3] == 1.0 && limn_mesh_positions(m)[2] == 0.0);
    assert_int_equal(limn_mesh_face_count(m), 2);
    limn_mesh_destroy(m);
    /* Geomview: CNOFF, normal first, then a colour in fractions; ST last */
    m = read_ok(write_str("geomview.off", "STCNOFF\n3 1 0\n0 0 0 0 0 1 1 0 0 1 0.5 0.5\n"
                                          "1 0 0 0 0 1 0 1 0 1 0 0\n"
                                          "0 1 0 0 0 1 0 0 0.5 1 1 1\n3 0 1 2\n"),
                LIMN_FORMAT_AUTO);
    static const uint8_t rgb2[9] = {255, 0, 0, 0, 255, 0, 0, 0, 128};
    assert_memory_equal(limn_mesh_colors(m), rgb2, sizeof rgb2);
    limn_mesh_destroy(m);
    /* other orders and prefixes */
    const char *const ok[] = {"NOFF\n3 1\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n",
                              "STOFF\n3 1\n0 0 0 0 0\n1 0 0 1 0\n0 1 0 0 1\n3 0 1 2\n",
                              "NSTOFF\n3 1\n0 0 0 0 0 1 0 0\n1 0 0 0 0 1 1 0\n"
                              "0 1 0 0 0 1 0 1\n3 0 1 2\n",
                              "nOFF\n3\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
                              "nOFF 3 3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"};
    for (size_t i = 0; i < sizeof ok / sizeof *ok; i++) {
        m = read_ok(write_str("ok.off", ok[i]), LIMN_FORMAT_AUTO);
        assert_int_equal(limn_mesh_vertex_count(m), 3);
        assert_null(limn_mesh_colors(m));
        limn_mesh_destroy(m);
    }
    read_fails(write_str("n4.off", "nOFF\n4\n1 0 0\n0 0 0 0\n"), LIMN_FORMAT_AUTO,
               LIMN_ERR_FORMAT, "n4.off:2: nOFF of dimension 4: only 3-D vertices");
    read_fails(write_str("4d.off", "4OFF\n1 0 0\n0 0 0 1\n"), LIMN_FORMAT_AUTO, LIMN_ERR_FORMAT,
               "4d.off:1: 4OFF and nOFF (not 3-D) files are not supported");
    read_fails(write_str("cc.off", "CCOFF\n"), LIMN_FORMAT_AUTO, LIMN_ERR_FORMAT,
               "cc.off:1: unknown OFF variant");
    /* two faces on one line: the message names the line, not only the end */
    read_fails(write_str("two.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n"
                                    "3 0 1 2 3 0 2 3\n"),
               LIMN_FORMAT_AUTO, LIMN_ERR_FORMAT,
               "two.off:7: face 0 has 3 indices declared but the line holds 7 values (two faces "
               "on one line?)");
    /* face colours after the indices are no such thing */
    m = read_ok(write_str("fc.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 255 0 0\n"),
                LIMN_FORMAT_AUTO);
    limn_mesh_destroy(m);
}

/* ------------------------------------------------------- bounded loading */

static void endless_inputs_are_bounded(void **s)
{
    (void)s;
    const char *formats[] = {"obj", "off", "ply", "stl"};
    for (size_t i = 0; i < 4; i++) {
        double t0 = now();
        int rc = run_sh("'%s' info /dev/zero --input-format %s --max-memory 64M", bin(),
                        formats[i]);
        double t = now() - t0;
        if (rc != 1 || !strstr(test_text, "/dev/zero"))
            fail_msg("/dev/zero as %s: exit %d:\n%s", formats[i], rc, test_text);
        assert_true(t < 10.0); /* a mechanism, not a speed: it ends, well before 64M */
    }
    /* test_text without NUL bytes and without end: the memory limit, or the line cap */
    assert_int_equal(run_sh("yes 'v 0 0 0' | '%s' info /dev/stdin --input-format obj "
                            "--max-memory 16M", bin()), 1);
    assert_non_null(strstr(test_text, "/dev/stdin:"));
    assert_non_null(strstr(test_text, "reading stopped at the memory limit of 16.0 MiB"));
    assert_int_equal(run_sh("head -c 70000000 /dev/zero | tr '\\0' a | '%s' info /dev/stdin "
                            "--input-format off", bin()), 1);
    assert_non_null(strstr(test_text, "/dev/stdin:1: a line longer than 64 MiB"));
    /* the library: a file larger than the context's limit */
    FILE *f = fopen(path_in("many.obj"), "w");
    assert_non_null(f);
    for (int v = 0; v < 100000; v++)
        fprintf(f, "v %d 0 0\n", v);
    fclose(f);
    limn_context_set_max_memory(ctx, 1 << 20);
    read_fails(path_in("many.obj"), LIMN_FORMAT_AUTO, LIMN_ERR_MEMORY,
               "reading stopped at the memory limit of 1.0 MiB");
    limn_context_set_max_memory(ctx, 0);
    limn_mesh_destroy(read_ok(path_in("many.obj"), LIMN_FORMAT_AUTO));
}

static void pipes_need_a_format(void **s)
{
    (void)s;
    write_str("p.obj", texts[0][1]);
    assert_int_equal(run_sh("cat p.obj | '%s' info /dev/stdin", bin()), 1);
    assert_non_null(strstr(test_text,
                           "/dev/stdin: not a regular file (a pipe: its size is unknown): "
                           "name its format (--input-format)"));
    assert_int_equal(run_sh("cat p.obj | '%s' info /dev/stdin --input-format obj", bin()), 0);
    assert_non_null(strstr(test_text, "vertices   4"));
    /* a FIFO with a mesh extension: refused without waiting for a writer */
    assert_int_equal(mkfifo(path_in("fifo.obj"), 0600), 0);
    assert_int_equal(run_sh("timeout 10 '%s' info fifo.obj", bin()), 1);
    assert_non_null(strstr(test_text, "fifo.obj: not a regular file (a pipe"));
}

/* ------------------------------------------------------------------- JSON */

/* Parses file with python3's json module when there is one, checking the
   value of key holds every hostile character; else checks the escapes. */
static void json_valid(const char *file, const char *key)
{
    if (run_sh("command -v python3 >/dev/null") == 0) {
        int rc = run_sh("python3 -c 'import json,sys; d=json.load(open(sys.argv[1], "
                        "encoding=\"utf-8\")); v=d[sys.argv[2]]; "
                        "assert d[\"limn_version\"] == \"0.1.0\"; "
                        "assert all(c in v for c in \"\\\"\\\\\\n\\t\\ufffd\"), repr(v)' "
                        "'%s' '%s'", file, key);
        if (rc != 0)
            fail_msg("%s is not the JSON expected: %s", file, test_text);
        return;
    }
    size_t n = 0;
    FILE *f = fopen(path_in(file), "rb");
    assert_non_null(f);
    static char b[1 << 16];
    n = fread(b, 1, sizeof b - 1, f);
    fclose(f);
    b[n] = '\0';
    for (size_t i = 0; i < n; i++)
        assert_true((unsigned char)b[i] >= 0x20 || b[i] == '\n');
    const char *const escapes[] = {"\\\"", "\\\\", "\\n", "\\t", "\\ufffd"};
    for (size_t i = 0; i < 5; i++)
        assert_non_null(strstr(b, escapes[i]));
}

static void json_escapes_hostile_names(void **s)
{
    (void)s;
    const char *name = "q\"uo\\te\nnew\tl\xff.obj";
    write_str(name, texts[0][1]);
    assert_int_equal(run_sh("'%s' info \"$(printf 'q\"uo\\\\te\\nnew\\tl\\377.obj')\" --json "
                            ">info.json",
                            bin()),
                     0);
    json_valid("info.json", "file");
    assert_int_equal(run_sh("'%s' subdivide \"$(printf 'q\"uo\\\\te\\nnew\\tl\\377.obj')\" -o "
                            "s.obj --levels 1 --device reference --report r.json -q",
                            bin()),
                     0);
    json_valid("r.json", "input");
    assert_int_equal(run_sh("grep -c '\"limit\": false' r.json"), 0);
}

/* ---------------------------------------------------------- PLY attributes */

static void ply_dropped_properties_named(void **s)
{
    (void)s;
    limn_mesh *m = read_ok(write_str("attr.ply",
                                     "ply\nformat ascii 1.0\nelement vertex 3\n"
                                     "property float x\nproperty float y\nproperty float z\n"
                                     "property float nx\nproperty float confidence\n"
                                     "property uchar red\nproperty uchar green\n"
                                     "property uchar blue\nproperty float intensity\n"
                                     "property float u\nelement face 1\n"
                                     "property list uchar int vertex_indices\nend_header\n"
                                     "0 0 0 0 1 255 0 0 7 0\n1 0 0 0 1 0 255 0 7 0\n"
                                     "0 1 0 0 1 0 0 255 7 0\n3 0 1 2\n"),
                           LIMN_FORMAT_AUTO);
    assert_non_null(limn_mesh_colors(m)); /* colours kept as before */
    assert_int_equal(limn_mesh_colors(m)[4], 255);
    const char *w = limn_context_warnings(ctx);
    if (!strstr(w, "attr.ply: 4 vertex properties dropped (limn keeps x, y, z and red, green, "
                   "blue): 'nx', 'confidence', 'intensity', 'u'"))
        fail_msg("warnings: %s", w);
    limn_mesh_destroy(m);
    /* nothing dropped, nothing said */
    limn_mesh_destroy(read_ok(write_str("plain.ply", texts[2][1]), LIMN_FORMAT_AUTO));
    assert_null(strstr(limn_context_warnings(ctx), "dropped"));
}

static int setup(void **s)
{
    (void)s;
    return test_scratch_make("readers", &ctx);
}

static int teardown(void **s)
{
    (void)s;
    limn_context_destroy(ctx);
    return test_scratch_teardown(s);
}

TEST_MAIN(setup, teardown, cmocka_unit_test(bom_is_skipped),
          cmocka_unit_test(cr_and_crlf_line_ends), cmocka_unit_test(off_header_words),
          cmocka_unit_test(endless_inputs_are_bounded), cmocka_unit_test(pipes_need_a_format),
          cmocka_unit_test(json_escapes_hostile_names),
          cmocka_unit_test(ply_dropped_properties_named))
