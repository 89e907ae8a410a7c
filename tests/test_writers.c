/* SPDX-License-Identifier: MIT */
/*
 * The block writers (issue 13.4): number_format's "%.17g" against printf's
 * on millions of values; every format's bytes against the writers as they
 * were (oracle/write_oracle.c) for 1, 2 and 4 host threads; float32 PLY
 * (read back as (float)x, the reported error from the file read back, the
 * option refused where it does not apply); a failing write leaves nothing,
 * at every file size limit (64 KiB apart, and at the last byte).
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <signal.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cmocka.h>

#include "limn.h"
#include "mesh/io/number_format.h"
#include "shell.h"
#include "support.h"
#include "write_oracle.h"

static limn_context *ctx;
static char dir[] = "/tmp/limn_test_writers.XXXXXX";

static uint64_t state = 88172645463325252ull;
static uint64_t next(void)
{
    state ^= state << 13;
    state ^= state >> 7;
    state ^= state << 17;
    return state;
}

static long g17_mismatches(double x)
{
    char a[64], b[64];
    int n = snprintf(a, sizeof a, "%.17g", x);
    size_t m = number_g17(x, b);
    if ((size_t)n == m && memcmp(a, b, m) == 0)
        return 0;
    b[m] = 0;
    print_error("%%.17g %s, number_g17 %s\n", a, b);
    return 1;
}

static void g17_is_printf(void **s)
{
    (void)s;
    long bad = 0;
    for (long i = 0; i < 400000; i++) { /* any bits */
        uint64_t u = next();
        double x;
        memcpy(&x, &u, sizeof x);
        if (isfinite(x))
            bad += g17_mismatches(x);
    }
    for (long i = 0; i < 600000; i++) { /* coordinates of every scale, and their neighbours */
        double x = ((double)(next() >> 11) / 9007199254740992.0 - 0.5) *
                   pow(10, (int)(next() % 32) - 15);
        bad += g17_mismatches(x) + g17_mismatches(nextafter(x, 0));
    }
    for (int e = -20; e < 20; e++) { /* around the powers of ten: X off by one */
        double p = pow(10, e);
        bad += g17_mismatches(p) + g17_mismatches(nextafter(p, 0)) +
               g17_mismatches(nextafter(p, INFINITY)) + g17_mismatches(-p);
    }
    for (long i = 0; i < 100000; i++) { /* ties at the 17th digit: to even */
        double x = (double)(next() % (1ull << 52)) * 1.25 / (double)(1 << (next() % 4));
        bad += g17_mismatches(x) + g17_mismatches(x / 1e3);
    }
    double special[] = {0.0, -0.0, 1234567890123456.25, 1234567890123456.75, 0.1, 1e-5, 1e-11,
                        1e17, 99999999999999999.0, 5e-324, 2.2250738585072014e-308, 1.7e308};
    for (size_t i = 0; i < sizeof special / sizeof special[0]; i++)
        bad += g17_mismatches(special[i]) + g17_mismatches(-special[i]);
    assert_int_equal(bad, 0);
    char b[32];
    size_t n = number_u64(4294967296ull, b);
    assert_int_equal(n, 10);
    assert_memory_equal(b, "4294967296", 10);
    assert_int_equal(number_u64(0, b), 1);
    assert_int_equal(b[0], '0');
}

/* A mesh of n vertices (every scale of coordinate, colours) and faces of 3
   to 6 corners, one of 300 (the uint count type); big enough for 4 threads
   and several rounds of blocks. */
static limn_mesh *test_mesh(size_t n, int colors)
{
    double *pos = malloc(3 * n * sizeof *pos);
    size_t nf = n / 2, cap = nf * 6 + 300;
    uint32_t *off = malloc((nf + 1) * sizeof *off), *idx = malloc(cap * sizeof *idx);
    uint8_t *rgb = malloc(3 * n);
    assert_non_null(pos);
    assert_non_null(off);
    assert_non_null(idx);
    assert_non_null(rgb);
    for (size_t i = 0; i < 3 * n; i++) {
        pos[i] = ((double)(next() >> 11) / 9007199254740992.0 - 0.5) * pow(10, (int)(next() % 12) - 6);
        rgb[i] = (uint8_t)next();
    }
    off[0] = 0;
    for (size_t f = 0; f < nf; f++) {
        uint32_t d = f == nf / 2 ? 300 : 3 + (uint32_t)(next() % 4);
        for (uint32_t k = 0; k < d; k++)
            idx[off[f] + k] = (uint32_t)((f + k * 7919) % n);
        off[f + 1] = off[f] + d;
    }
    limn_mesh *m = NULL;
    assert_int_equal(limn_mesh_create(ctx, n, pos, nf, off, idx, &m), LIMN_OK);
    if (colors)
        assert_int_equal(limn_mesh_set_colors(ctx, m, rgb), LIMN_OK);
    free(pos);
    free(off);
    free(idx);
    free(rgb);
    return m;
}

static char *oracle_bytes(const limn_mesh *m, limn_format format, int single, size_t *len)
{
    char *buf = NULL;
    FILE *f = open_memstream(&buf, len);
    assert_non_null(f);
    assert_int_equal(write_oracle(m, format, single, f), 0);
    assert_int_equal(fclose(f), 0);
    return buf;
}

static void path_of(char *p, size_t cap, const char *name) { snprintf(p, cap, "%s/%s", dir, name); }

static const limn_format every_format[] = {LIMN_FORMAT_OBJ, LIMN_FORMAT_OFF, LIMN_FORMAT_PLY,
                                           LIMN_FORMAT_PLY_ASCII, LIMN_FORMAT_PLY_BINARY_BE};

/* Each format's bytes are the oracle's, for 1, 2 and 4 host threads. */
static void same_bytes_as_before(void **s)
{
    (void)s;
    for (int colors = 0; colors < 2; colors++) {
        limn_mesh *m = test_mesh(colors ? 20000 : 400000, colors);
        for (size_t k = 0; k < sizeof every_format / sizeof every_format[0]; k++) {
            size_t want_len;
            char *want = oracle_bytes(m, every_format[k], 0, &want_len);
            for (int t = 1; t <= 4; t *= 2) {
                char path[256];
                path_of(path, sizeof path, "out.mesh");
                assert_int_equal(limn_context_set_host_threads(ctx, t), LIMN_OK);
                assert_int_equal(limn_mesh_write(ctx, m, path, every_format[k]), LIMN_OK);
                size_t len;
                char *got = test_slurp(path, &len);
                assert_int_equal(len, want_len);
                assert_memory_equal(got, want, len);
                free(got);
                unlink(path);
            }
            free(want);
        }
        limn_mesh_destroy(m);
    }
    assert_int_equal(limn_context_set_host_threads(ctx, 0), LIMN_OK);
}

/* float32 PLY: the oracle's bytes, read back as (float)x, the error as the
   distances to the file read back. */
static void float_ply(void **s)
{
    (void)s;
    limn_mesh *m = test_mesh(100000, 1);
    const double *p = limn_mesh_positions(m);
    size_t n = limn_mesh_vertex_count(m);
    limn_format formats[] = {LIMN_FORMAT_PLY, LIMN_FORMAT_PLY_ASCII, LIMN_FORMAT_PLY_BINARY_BE};
    for (int k = 0; k < 3; k++) {
        for (int t = 1; t <= 4; t *= 2) {
            char path[256];
            path_of(path, sizeof path, "float.ply");
            limn_write_options o;
            limn_write_options_default(&o);
            assert_int_equal(o.precision, LIMN_OUTPUT_DOUBLE);
            o.precision = LIMN_OUTPUT_FLOAT;
            limn_write_report r = {.size = sizeof r};
            assert_int_equal(limn_context_set_host_threads(ctx, t), LIMN_OK);
            assert_int_equal(limn_mesh_write_with(ctx, m, path, formats[k], &o, &r), LIMN_OK);
            size_t want_len, len;
            char *want = oracle_bytes(m, formats[k], 1, &want_len);
            char *got = test_slurp(path, &len);
            assert_int_equal(len, want_len);
            assert_memory_equal(got, want, len);
            free(got);
            free(want);
            limn_mesh *back = NULL;
            assert_int_equal(limn_mesh_read(ctx, path, LIMN_FORMAT_PLY, &back), LIMN_OK);
            const double *q = limn_mesh_positions(back);
            double most = 0, sum = 0;
            for (size_t i = 0; i < n; i++) {
                double d2 = 0;
                for (int j = 0; j < 3; j++) {
                    assert_true(q[3 * i + j] == (double)(float)p[3 * i + j]);
                    d2 += (p[3 * i + j] - q[3 * i + j]) * (p[3 * i + j] - q[3 * i + j]);
                }
                sum += sqrt(d2);
                most = fmax(most, sqrt(d2));
            }
            assert_true(most > 0);
            assert_true(r.max_error == most);
            assert_true(fabs(r.mean_error - sum / (double)n) <= 1e-12 * r.mean_error);
            assert_true(r.bbox_diagonal > 0);
            limn_mesh_destroy(back);
            unlink(path);
        }
    }
    limn_write_report r = {.size = sizeof r}; /* doubles: no error */
    char path[256];
    path_of(path, sizeof path, "double.ply");
    assert_int_equal(limn_mesh_write_with(ctx, m, path, LIMN_FORMAT_PLY, NULL, &r), LIMN_OK);
    assert_true(r.max_error == 0 && r.mean_error == 0 && r.bbox_diagonal > 0);
    unlink(path);
    limn_mesh_destroy(m);
    assert_int_equal(limn_context_set_host_threads(ctx, 0), LIMN_OK);
}

/* Float precision where it does not apply, a bad value, a bad size:
   refused, nothing written. */
static void float_refused(void **s)
{
    (void)s;
    limn_mesh *m = test_mesh(100, 0);
    char path[256];
    limn_write_options o;
    limn_write_options_default(&o);
    o.precision = LIMN_OUTPUT_FLOAT;
    const char *names[] = {"a.obj", "a.off", "a.stl"};
    for (int k = 0; k < 3; k++) {
        path_of(path, sizeof path, names[k]);
        assert_int_equal(limn_mesh_write_with(ctx, m, path, LIMN_FORMAT_AUTO, &o, NULL),
                         LIMN_ERR_ARGUMENT);
        assert_non_null(strstr(limn_context_message(ctx), "PLY only"));
        assert_int_not_equal(access(path, F_OK), 0);
    }
    path_of(path, sizeof path, "a.ply");
    o.precision = (limn_output_precision)7;
    assert_int_equal(limn_mesh_write_with(ctx, m, path, LIMN_FORMAT_AUTO, &o, NULL),
                     LIMN_ERR_ARGUMENT);
    assert_non_null(strstr(limn_context_message(ctx), "options->precision 7"));
    o.size = 0;
    assert_int_equal(limn_mesh_write_with(ctx, m, path, LIMN_FORMAT_AUTO, &o, NULL),
                     LIMN_ERR_ARGUMENT);
    assert_non_null(strstr(limn_context_message(ctx), "limn_write_options_default()"));
    assert_int_not_equal(access(path, F_OK), 0);
    limn_output_set *set = NULL;
    assert_int_equal(limn_output_set_create(ctx, &set), LIMN_OK);
    limn_write_options_default(&o);
    o.precision = LIMN_OUTPUT_FLOAT;
    path_of(path, sizeof path, "b.obj");
    assert_int_equal(limn_output_set_add_mesh_with(ctx, set, m, path, LIMN_FORMAT_AUTO, &o, NULL),
                     LIMN_ERR_ARGUMENT);
    assert_int_equal(limn_output_set_count(set), 0);
    limn_output_set_destroy(set);
    assert_int_not_equal(access(path, F_OK), 0);
    limn_mesh_destroy(m);
}

/* A write that fails (no room: /dev/full) reports it; a staged file that
   fails leaves nothing beside its target. */
static void failing_write(void **s)
{
    (void)s;
    limn_mesh *m = test_mesh(50000, 0);
    for (size_t k = 0; k < sizeof every_format / sizeof every_format[0]; k++) {
        assert_int_equal(limn_mesh_write(ctx, m, "/dev/full", every_format[k]), LIMN_ERR_IO);
        assert_non_null(strstr(limn_context_message(ctx), "/dev/full"));
    }
    limn_mesh_destroy(m);
}

static size_t next_limit(size_t limit, size_t full)
{
    size_t next = limit == 0 ? 1 : limit == 1 ? 65536 : limit + 65536;
    return limit >= full - 1 ? limit + 1 : next < full - 1 ? next : full - 1;
}

/* The file size limit (RLIMIT_FSIZE, SIGXFSZ ignored: the write fails with
   EFBIG) at every 64 KiB, and at 0, 1 and one byte short, of each format's
   file (with colours, 2 host threads): every write below the size refused
   (LIMN_ERR_IO naming the file), the old file's bytes kept, nothing left
   beside it; at the size itself the write works. */
static void size_limit_sweep(void **s)
{
    (void)s;
    limn_mesh *m = test_mesh(30000, 1);
    char path[300];
    path_of(path, sizeof path, "limited");
    static const char old[] = "old bytes a refused write keeps\n";
    assert_int_equal(limn_context_set_host_threads(ctx, 2), LIMN_OK);
    void (*prev)(int) = signal(SIGXFSZ, SIG_IGN);
    struct rlimit was;
    assert_int_equal(getrlimit(RLIMIT_FSIZE, &was), 0);
    long refused = 0;
    for (size_t k = 0; k < sizeof every_format / sizeof every_format[0]; k++) {
        assert_int_equal(limn_mesh_write(ctx, m, path, every_format[k]), LIMN_OK);
        size_t full = 0;
        free(test_slurp(path, &full));
        /* 0, 1, 64 KiB, 128 KiB, ... below full - 1, then full - 1 and full */
        for (size_t limit = 0; limit <= full; limit = next_limit(limit, full)) {
            assert_int_equal(test_write_text(path, old), 0);
            int before = test_dir_entries(dir);
            struct rlimit small = was;
            small.rlim_cur = limit;
            assert_int_equal(setrlimit(RLIMIT_FSIZE, &small), 0);
            limn_status st = limn_mesh_write(ctx, m, path, every_format[k]);
            assert_int_equal(setrlimit(RLIMIT_FSIZE, &was), 0);
            size_t n = 0;
            char *now = test_slurp(path, &n);
            if (limit < full) {
                if (st != LIMN_ERR_IO || !strstr(limn_context_message(ctx), "limited"))
                    fail_msg("format %zu, limit %zu of %zu: status %d '%s'", k, limit, full,
                             (int)st, limn_context_message(ctx));
                assert_int_equal(n, strlen(old));
                assert_memory_equal(now, old, n);
                assert_int_equal(test_dir_entries(dir), before);
                refused++;
            } else {
                assert_int_equal(st, LIMN_OK);
                assert_int_equal(n, full);
            }
            free(now);
        }
    }
    signal(SIGXFSZ, prev);
    limn_context_set_host_threads(ctx, 0);
    unlink(path);
    print_message("  %ld writes over the size limit refused, the old file kept\n", refused);
    limn_mesh_destroy(m);
}

static int setup(void **s)
{
    (void)s;
    ctx = limn_context_create();
    return !ctx || !mkdtemp(dir);
}

static int teardown(void **s)
{
    (void)s;
    limn_context_destroy(ctx);
    return rmdir(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(g17_is_printf),
        cmocka_unit_test(same_bytes_as_before),
        cmocka_unit_test(float_ply),
        cmocka_unit_test(float_refused),
        cmocka_unit_test(failing_write),
        cmocka_unit_test(size_limit_sweep),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
