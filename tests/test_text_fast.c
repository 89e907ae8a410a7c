/* SPDX-License-Identifier: MIT */
/*
 * The text readers' fast path (host/mesh/io/text_fast.c and the OBJ, OFF and
 * ASCII PLY line parsers, issue 13.1) against the general readers, forced by
 * the test-only LIMN_TEST_TEXT_GENERAL=1: every shared mesh written by limn
 * as OBJ, OFF and ASCII PLY, and hand-made files (tricky numbers, CRLF, no
 * final newline, tabs, comments, forms and errors the fast path leaves to
 * the general reader, ranges cut inside long lines) give the same status,
 * message, warnings and mesh bit for bit, for 1, 2 and 4 host threads and
 * under memory limits. The locale-free number parser (text_number.c) gives
 * strtod's double bit for bit. The fast path must actually run: it reports
 * progress once a MiB where the general reader reports it every 64 KiB.
 */
#ifndef _POSIX_C_SOURCE
#define _POSIX_C_SOURCE 200809L /* setenv */
#endif
#include "shell.h"
#include "support.h"
#include "mesh/io/text_number.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

static char dir[64];

/* What one read gave. */
typedef struct outcome {
    limn_status st;
    char msg[2048], warn[4096];
    limn_mesh *m;
    int progress;
    int marker, engaged; /* saw the fast path's 0.1; then its 1.0 next */
} outcome;

static void count_progress(void *user, const char *stage, double fraction)
{
    outcome *o = user;
    (void)stage;
    o->progress++;
    o->engaged |= o->marker && fraction == 1.0;
    o->marker = fraction == 0.1;
}

/* The fast path finished the read: it reports 0.1 after its first pass and
   1.0 right after its last (in a small file the general reader has read
   all in its first buffer, so it reports nothing more after giving way). */
static int engaged(const outcome *o) { return o->engaged; }
static int last_engaged;

static void read_way(const char *path, int general, size_t max_memory, int threads, outcome *o)
{
    assert_int_equal(setenv("LIMN_TEST_TEXT_GENERAL", general ? "1" : "0", 1), 0);
    limn_context *ctx = limn_context_create();
    assert_non_null(ctx);
    if (max_memory)
        limn_context_set_max_memory(ctx, max_memory);
    if (threads)
        assert_int_equal(limn_context_set_host_threads(ctx, threads), LIMN_OK);
    o->progress = 0;
    o->marker = o->engaged = 0;
    limn_context_set_progress(ctx, count_progress, o);
    o->m = NULL;
    o->st = limn_mesh_read(ctx, path, LIMN_FORMAT_AUTO, &o->m);
    const char *w = limn_context_warnings(ctx);
    snprintf(o->msg, sizeof o->msg, "%s", limn_context_message(ctx));
    snprintf(o->warn, sizeof o->warn, "%s", w ? w : "");
    limn_context_destroy(ctx);
    unsetenv("LIMN_TEST_TEXT_GENERAL");
}

/* Reads path both ways: the same status, message, warnings and mesh.
   Returns the status; *progress (may be NULL) gets both ways' calls. */
static limn_status both_ways(const char *path, size_t max_memory, int threads, int progress[2])
{
    static outcome a, b;
    read_way(path, 0, max_memory, threads, &a);
    read_way(path, 1, max_memory, threads, &b);
    if (a.st != b.st || strcmp(a.msg, b.msg) != 0 || strcmp(a.warn, b.warn) != 0)
        fail_msg("%s (%d threads): fast path %s '%s' [%s]; general reader %s '%s' [%s]", path,
                 threads, limn_status_name(a.st), a.msg, a.warn, limn_status_name(b.st), b.msg,
                 b.warn);
    if (a.m)
        test_assert_same_mesh(a.m, b.m);
    assert_false(engaged(&b));
    last_engaged = engaged(&a);
    limn_mesh_destroy(a.m);
    limn_mesh_destroy(b.m);
    if (progress) {
        progress[0] = a.progress;
        progress[1] = b.progress;
    }
    return a.st;
}

/* ------------------------------------------------------------- numbers */

static unsigned long long rng = 88172645463325252ull;
static unsigned long long next(void)
{
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    return rng;
}

/* tn_double's value, where it gives one, is strtod's bit for bit. */
static long long check_number(const char *s)
{
    double a, b = strtod(s, NULL);
    const char *end = tn_double(s, s + strlen(s), &a);
    if (!end || *end)
        return 0;
    if (memcmp(&a, &b, sizeof a) != 0)
        fail_msg("'%s': %.17g, strtod %.17g", s, a, b);
    return 1;
}

static void numbers(void **state)
{
    (void)state;
    char buf[64];
    long long fast = 0, n = 0;
    for (int i = 0; i < 400000; i++, n += 3) {
        unsigned long long u = next();
        double x;
        memcpy(&x, &u, 8);
        if (isfinite(x)) {
            snprintf(buf, sizeof buf, "%.17g", x);
            fast += check_number(buf);
        }
        x = ((double)(next() >> 11) / 9007199254740992.0 - 0.5) * pow(10.0, (int)(u % 9) - 4);
        snprintf(buf, sizeof buf, "%.*g", 1 + (int)(u >> 8) % 19, x);
        fast += check_number(buf);
        /* integers past 2^53 with ".0" and halves: exact ties, to even */
        unsigned long long big = ((1ull << 53) + (next() >> 11)) >> (u >> 20 & 1);
        snprintf(buf, sizeof buf, u >> 30 & 1 ? "%llu.0" : "%llu.5", big >> 3);
        fast += check_number(buf);
    }
    static const char *const hand[] = {
        "1.", ".5", "+3", "-0", "-0.0", "1E+10", "1e-320", "4.9406564584124654e-324",
        "2.2250738585072011e-308", "1.7976931348623157e308", "0.10000000000000001",
        "9007199254740993", "9007199254740993.0", "123456789012345678.9e-5",
        "0.00012345678901234567", "1.2345678901234567e-05", "99999999999999999999",
        "0x1p3", "inf", "nan", "1e", "-.", ".", "1e400", "1.5e-22", "007", "0e999999"};
    for (size_t i = 0; i < sizeof hand / sizeof *hand; i++)
        fast += check_number(hand[i]);
    print_message("%lld of %lld numbers by the fast route\n", fast, n);
    assert_true(fast > n / 2);
}

/* --------------------------------------------------------- shared meshes */

static const limn_format text_formats[] = {LIMN_FORMAT_OBJ, LIMN_FORMAT_OFF,
                                           LIMN_FORMAT_PLY_ASCII};
static const char *const text_names[] = {"m.obj", "m.off", "m.ply"};

/* Writes m in the three text formats, then reads each both ways. */
static void text_round(const limn_mesh *m, const int *threads, size_t nthreads)
{
    limn_context *ctx = limn_context_create();
    for (size_t f = 0; f < 3; f++) {
        const char *path = test_join(dir, text_names[f]);
        assert_int_equal(limn_mesh_write(ctx, m, path, text_formats[f]), LIMN_OK);
        for (size_t t = 0; t < nthreads; t++) {
            int progress[2];
            assert_int_equal(both_ways(path, 0, threads[t], progress), LIMN_OK);
            /* read by the fast path: its 0.1 then 1.0 (small files), or far
               fewer reports than the general reader's one per 64 KiB */
            if (!last_engaged && progress[0] * 4 >= progress[1])
                fail_msg("%s: the fast path gave way (progress calls %d, general %d)", path,
                         progress[0], progress[1]);
        }
    }
    limn_context_destroy(ctx);
}

static void shared_meshes(void **state)
{
    (void)state;
    static const char *const subs[] = {"small", "medium", "large"};
    static const int all[] = {1, 2, 4}, two[] = {2};
    size_t seen = 0;
    for (size_t s = 0; s < 3; s++) {
        const char *names[256];
        size_t n = test_list_meshes(subs[s], names, 256);
        for (size_t i = 0; i < n; i++) {
            limn_context *ctx = limn_context_create();
            limn_mesh *m = NULL;
            if (limn_mesh_read(ctx, test_shared_path(names[i]), LIMN_FORMAT_AUTO, &m) == LIMN_OK) {
                text_round(m, s == 2 ? two : all, s == 2 ? 1 : 3);
                seen++;
            }
            limn_mesh_destroy(m);
            limn_context_destroy(ctx);
        }
    }
    if (!seen)
        print_message("no shared meshes (LIMN_SHARED_MESHES): hand-made files only\n");
}

/* --------------------------------------------------------- hand-made files */

/* Each file read both ways with 1 and 4 threads; want: the status expected;
   fast: whether the fast path reads it (else it gives way). */
static void hand(const char *name, const char *text, limn_status want, int fast)
{
    const char *path = test_write_bytes(test_join(dir, name), text, strlen(text));
    for (int t = 1; t <= 4; t += 3) {
        limn_status st = both_ways(path, 0, t, NULL);
        if (st != want || last_engaged != fast)
            fail_msg("%s: %s, expected %s; fast path %s, expected %s:\n%s", name,
                     limn_status_name(st), limn_status_name(want),
                     last_engaged ? "read it" : "gave way", fast ? "read it" : "gave way", text);
    }
}

#define TRICKY "1. .5 +3\n-0 1E+10 1e-320\n0.12345678901234567 -9007199254740993 0x1p3\n" \
               "4.9406564584124654e-324 17.000000000000000001 1e22\n"

static void hand_obj(void)
{
    static const char quad[] = "f 1 2 3\nf 2 3 4\n";
    char buf[1024];
    snprintf(buf, sizeof buf, "v %s", TRICKY);
    for (char *p = strchr(buf, '\n'); p && p[1]; p = strchr(p + 1, '\n'))
        memmove(p + 3, p + 1, strlen(p + 1) + 1), p[1] = 'v', p[2] = ' ';
    strcat(buf, quad);
    hand("tricky.obj", buf, LIMN_OK, 1);
    hand("crlf.obj", "v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf 1 2 3\r\n", LIMN_OK, 1);
    hand("tabs.obj", "#c\n\tv\t0 0 0 extra\nv 1\t0 0\n  v 0 1 0\n\nvn 0 0 1\nvt 0 0\n"
                     "o x\ng y\ns 1\nusemtl m\nf 1/1/1 2//1 3/1\n", LIMN_OK, 1);
    hand("nofinal.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3", LIMN_OK, 0);
    hand("relative.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\n", LIMN_OK, 0);
    hand("unknown.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nfoo bar\nf 1 2 3\n", LIMN_OK, 0);
    hand("cont.obj", "v 0 0 \\\n0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", LIMN_OK, 0);
    hand("lonecr.obj", "v 0 0 0\rv 1 0 0\nv 0 1 0\nf 1 2 3\n", LIMN_OK, 0);
    hand("later.obj", "f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n", LIMN_OK, 1);
    hand("nan.obj", "v 0 0 nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", LIMN_ERR_FORMAT, 0);
    hand("inf.obj", "v 0 0 1e999\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", LIMN_ERR_FORMAT, 0);
    hand("badref.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", LIMN_ERR_FORMAT, 0);
    hand("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", LIMN_ERR_FORMAT, 0);
    hand("two.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n", LIMN_ERR_FORMAT, 0);
    hand("short.obj", "v 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", LIMN_ERR_FORMAT, 0);
    hand("novert.obj", "# nothing\n", LIMN_ERR_FORMAT, 0);
    static const char nul[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n# \0 x\n";
    const char *path = test_write_bytes(test_join(dir, "nul.obj"), nul, sizeof nul - 1);
    assert_int_equal(both_ways(path, 0, 1, NULL), LIMN_ERR_FORMAT);
}

static void hand_off(void)
{
    char buf[1024];
    snprintf(buf, sizeof buf, "OFF\n# comment\n8 2 0\n%s\n0 0 0\n1 1 1\n1 0 1\n0 1 1\n"
             "3 0 1 2\n4 4 5 6 7 0.5 0.5 0.5 # colour\n", TRICKY);
    /* TRICKY is 12 numbers on 4 lines: 4 vertices */
    hand("tricky.off", buf, LIMN_OK, 1);
    hand("crlf.off", "OFF\r\n3 1 0\r\n0 0 0\r\n1 0 0\r\n0 1 0\r\n3 0 1 2\r\n", LIMN_OK, 1);
    hand("header.off", "OFF 3 1 0\n\t0 0 0 # a\n\n1 0 0\n0 1 0\n3 0 1 2\n", LIMN_OK, 1);
    hand("nofinal.off", "OFF\n3 1 0\n0.0 0.0 0.0\n1 0 0\n0 1 0\n3 0 1 2", LIMN_OK, 1);
    hand("trailing.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 2\n", LIMN_OK, 1);
    hand("coff.off", "COFF\n3 1 0\n0 0 0 255 0 0\n1 0 0 0 255 0\n0 1 0 0 0 255\n3 0 1 2\n",
         LIMN_OK, 0);
    hand("noff.off", "NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n", LIMN_OK, 1);
    hand("crowded.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n3 0 1 2 3 1 3 2\n",
         LIMN_ERR_FORMAT, 0);
    hand("badidx.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", LIMN_ERR_FORMAT, 0);
    hand("fewidx.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1\n", LIMN_ERR_FORMAT, 0);
    hand("hash.off", "OFF\n3 1 0\n0 0 #0\n1 0 0\n0 1 0\n3 0 1 2\n", LIMN_ERR_FORMAT, 0);
    hand("nan.off", "OFF\n3 1 0\n0 0 nan\n1 0 0\n0 1 0\n3 0 1 2\n", LIMN_ERR_FORMAT, 0);
    hand("short.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n", LIMN_ERR_FORMAT, 0);
}

static void hand_ply(void)
{
    static const char head[] = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\n"
                               "property double y\nproperty int z\nelement face 2\n"
                               "property list uchar int vertex_indices\nend_header\n";
    char buf[1024];
    snprintf(buf, sizeof buf, "%s%s3 0 1 2\n3 1 2 3\n", head, TRICKY);
    hand("tricky.ply", buf, LIMN_OK, 1);
    hand("colour.ply", "ply\nformat ascii 1.0\nelement face 1\nproperty uchar flag\n"
                       "property list uchar uint vertex_indices\nproperty float q\n"
                       "element vertex 3\nproperty float c\nproperty float x\nproperty float y\n"
                       "property float z\nproperty uchar red\nproperty uchar green\n"
                       "property uchar blue\nend_header\n7 3 0 1 2 0.5\r\n"
                       "1 0 0 0 255 0 0\r\n1 1 0 0 0 255 0\r\n\t1 0 1 0 0 0 255\r\n", LIMN_OK, 1);
    hand("split.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                      "property float y\nproperty float z\nelement face 1\n"
                      "property list uchar int vertex_indices\nend_header\n0 0 0 1 0\n0\n0 1 0\n"
                      "3 0 1 2\n", LIMN_OK, 0);
    hand("nofinal.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                        "property float y\nproperty float z\nelement face 1\n"
                        "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n"
                        "0 1 0\n3 0 1 2", LIMN_OK, 1);
    hand("extra.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                      "property float y\nproperty float z\nend_header\n0 0 0\n1 0 0\n0 1 0\n9\n",
         LIMN_OK, 1);
    hand("ucharidx.ply", "ply\nformat ascii 1.0\nelement vertex 300\nproperty float x\n"
                         "property float y\nproperty float z\nelement face 1\n"
                         "property list uchar uchar vertex_indices\nend_header\n"
                         "0 0 0\n0 0 0\n0 0 0\n3 0 1 299\n", LIMN_ERR_FORMAT, 0);
    hand("badcol.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                       "property float y\nproperty float z\nproperty uchar red\n"
                       "property uchar green\nproperty uchar blue\nend_header\n"
                       "0 0 0 1 2 3\n1 0 0 1 2 256\n0 1 0 1 2 3\n", LIMN_ERR_FORMAT, 0);
}

static void hand_made(void **state)
{
    (void)state;
    hand_obj();
    hand_off();
    hand_ply();
}

/* ----------------------------------------------- large files, ranges, limits */

/* A grid of n x n vertices in format f, each vertex line padded by pad
   spaces (so range cuts fall inside long lines); returns the path. */
static const char *grid_file(int f, int n, int pad)
{
    size_t cap = (size_t)n * n * (80 + (size_t)pad) + (size_t)n * n * 40 + 512, len = 0;
    char *b = malloc(cap);
    assert_non_null(b);
    int nv = n * n, nf = (n - 1) * (n - 1);
    if (f == 1)
        len += (size_t)sprintf(b + len, "OFF\n%d %d 0\n", nv, nf);
    if (f == 2)
        len += (size_t)sprintf(b + len, "ply\nformat ascii 1.0\nelement vertex %d\nproperty "
                               "double x\nproperty double y\nproperty double z\nelement face %d\n"
                               "property list uchar int vertex_indices\nend_header\n", nv, nf);
    for (int v = 0; v < nv; v++) {
        len += (size_t)sprintf(b + len, "%s%.17g %.17g %.17g", f == 0 ? "v " : "",
                               0.1 * (v % n) + 1e-7 * v, 0.37 * (v / n), sin(0.01 * v));
        if (f != 2)
            for (int k = 0; k < pad && v % 3 == 0; k++)
                b[len++] = ' ';
        b[len++] = '\n';
    }
    for (int c = 0; c < nf; c++) {
        int i = c % (n - 1), j = c / (n - 1), a = j * n + i;
        len += (size_t)sprintf(b + len, f == 0 ? "f %d %d %d %d\n" : "4 %d %d %d %d\n",
                               a + (f == 0), a + 1 + (f == 0), a + n + 1 + (f == 0),
                               a + n + (f == 0));
    }
    assert_true(len <= cap);
    const char *path = test_write_bytes(test_join(dir, text_names[f]), b, len);
    free(b);
    return path;
}

static void threads_and_engaged(void **state)
{
    (void)state;
    static const int threads[] = {1, 2, 4};
    for (int f = 0; f < 3; f++) {
        const char *path = grid_file(f, 420, 9000);
        for (size_t t = 0; t < 3; t++) {
            int progress[2];
            assert_int_equal(both_ways(path, 0, threads[t], progress), LIMN_OK);
            if (progress[0] * 8 > progress[1])
                fail_msg("%s: progress calls: fast path %d, general reader %d", path,
                         progress[0], progress[1]);
        }
    }
}

/* Under memory limits the fast path gives way and the general reader's
   message stands. */
static void memory_limit(void **state)
{
    (void)state;
    for (int f = 0; f < 3; f++) {
        const char *path = grid_file(f, 60, 0);
        int refused = 0, read = 0;
        for (size_t limit = 66000; limit < 900000; limit += 30011) {
            limn_status st = both_ways(path, limit, 2, NULL);
            refused += st == LIMN_ERR_MEMORY;
            read += st == LIMN_OK;
        }
        assert_true(refused > 0 && read > 0);
    }
}

static int setup(void **state)
{
    (void)state;
    return test_make_dir(dir, sizeof dir, "text_fast");
}

static int teardown(void **state)
{
    (void)state;
    return test_remove_dir(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(numbers),
        cmocka_unit_test(hand_made),
        cmocka_unit_test(threads_and_engaged),
        cmocka_unit_test(memory_limit),
        cmocka_unit_test(shared_meshes),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
