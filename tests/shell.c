/* SPDX-License-Identifier: MIT */
#include "shell.h"
#include "slurp.h"

#include <setjmp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

#include <cmocka.h>

/* room for a command line: the longest any test builds */
#define LINE_MAX_ 16384

int test_make_dir(char *dir, size_t cap, const char *name)
{
    snprintf(dir, cap, "/tmp/limn_%s_XXXXXX", name);
    return mkdtemp(dir) ? 0 : -1;
}

int test_remove_dir(const char *dir)
{
    char cmd[4200];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    return system(cmd) == 0 ? 0 : -1;
}

char test_dir[64];
char test_text[1 << 17];

int test_scratch_make(const char *name, limn_context **ctx)
{
    if (test_make_dir(test_dir, sizeof test_dir, name) != 0)
        return -1;
    if (!ctx)
        return 0;
    *ctx = limn_context_create();
    return *ctx ? 0 : -1;
}

int test_scratch_teardown(void **state)
{
    (void)state;
    return test_remove_dir(test_dir);
}

const char *test_join(const char *dir, const char *name)
{
    static char path[8][4200];
    static int k;
    k = (k + 1) % 8;
    snprintf(path[k], sizeof path[k], "%s/%s", dir, name);
    return path[k];
}

const char *test_data_path(const char *name)
{
    return test_join(getenv("LIMN_TEST_DATA"), name);
}

const char *test_write_bytes(const char *path, const void *data, size_t n)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(data, 1, n, f), n);
    assert_int_equal(fclose(f), 0);
    return path;
}

char *test_slurp(const char *path, size_t *n)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    char *b = test_read_stream(f, n);
    fclose(f);
    return b;
}

int test_same_bytes(const char *a, const char *b)
{
    /* in process, not `cmp`: the MPI tests must not fork */
    size_t na = 0, nb = 0;
    char *x = test_slurp(a, &na), *y = test_slurp(b, &nb);
    int same = x && y && na == nb && memcmp(x, y, na) == 0;
    free(x);
    free(y);
    return same;
}

int test_run(char *out, size_t cap, const char *cmd)
{
    FILE *p = popen(cmd, "r");
    assert_non_null(p);
    size_t n = fread(out, 1, cap - 1, p);
    out[n] = '\0';
    int st = pclose(p);
    return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

int test_vrunf(char *out, size_t cap, const char *fmt, va_list ap)
{
    char cmd[LINE_MAX_];
    vsnprintf(cmd, sizeof cmd, fmt, ap);
    return test_run(out, cap, cmd);
}

int test_runf(char *out, size_t cap, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int rc = test_vrunf(out, cap, fmt, ap);
    va_end(ap);
    return rc;
}

/* The caller's printf-style part of a command line, formatted into part. */
#define FORMAT_PART(part, fmt)                                                                 \
    char part[LINE_MAX_ / 2];                                                                  \
    do {                                                                                       \
        va_list ap_;                                                                           \
        va_start(ap_, fmt);                                                                    \
        vsnprintf(part, sizeof part, fmt, ap_);                                                \
        va_end(ap_);                                                                           \
    } while (0)

int test_limn(char *out, size_t cap, const char *env, const char *fmt, ...)
{
    FORMAT_PART(args, fmt);
    return test_runf(out, cap, "%s%s '%s' %s 2>&1", env ? "env " : "", env ? env : "",
                     getenv("LIMN_BIN"), args);
}

int test_in_dir(char *out, size_t cap, const char *dir, const char *fmt, ...)
{
    FORMAT_PART(line, fmt);
    return test_runf(out, cap, "cd '%s' && { %s; } 2>&1", dir, line);
}
