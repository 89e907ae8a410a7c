/* SPDX-License-Identifier: MIT */
/*
 * Where outputs go (README "Command line", output rules), through the limn
 * command line: a symlink's target replaced (the link kept), dangling links
 * and relative chains; FIFOs, /dev/null and "-" written straight through;
 * "-" as input; /dev/full and a closed pipe as errors; the input never
 * overwritten through links; stale temporary files of dead processes
 * removed; the replaced file's mode kept; refusals before any work; and the
 * pair lock (a mesh and its report always from the same run).
 */
#ifndef _DEFAULT_SOURCE
#define _DEFAULT_SOURCE /* mkdtemp, symlink, setenv */
#endif
#include "shell.h"
#include "support.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmocka.h>

static char dir[64];
static char text[1 << 16];
static char *ref;       /* the reference output: interpolate spot, PLY, regular file */
static size_t ref_len;

#define RUN_OPTS "--device reference -q"

/* ------------------------------------------------------------------ helpers */

static const char *at(const char *name) { return test_join(dir, name); }
static const char *spot(void) { return test_data_path("spot_control_mesh.obj"); }

/* Runs a shell command (in dir) with stderr (and stdout unless redirected)
   in text; returns the exit status. */
#define run_sh(...) test_in_dir(text, sizeof text, dir, __VA_ARGS__)

/* `limn ARGS` in dir; messages in text. */
#define LIMN(...) run_sh("'%s' " __VA_ARGS__)
static const char *bin(void) { return getenv("LIMN_BIN"); }

static void same_as_ref(const char *path)
{
    size_t n;
    char *got = test_slurp(path, &n);
    if (!got)
        fail_msg("%s was not written; output:\n%s", path, text);
    assert_int_equal(n, ref_len);
    assert_memory_equal(got, ref, n);
    free(got);
}

/* No temporary file in d (a failed or finished run leaves none). */
static void no_temps(const char *d)
{
    DIR *h = opendir(d);
    assert_non_null(h);
    struct dirent *e;
    while ((e = readdir(h)))
        if (strstr(e->d_name, ".limn-tmp."))
            fail_msg("temporary file %s/%s left behind", d, e->d_name);
    closedir(h);
}

static int is_symlink_to(const char *path, const char *want)
{
    char buf[1024];
    ssize_t n = readlink(path, buf, sizeof buf - 1);
    if (n < 0)
        return 0;
    buf[n] = '\0';
    return strcmp(buf, want) == 0;
}

static int setup(void **s)
{
    (void)s;
    if (test_make_dir(dir, sizeof dir, "outputs") != 0 || chmod(dir, 0755) != 0)
        return -1;
    if (LIMN("interpolate '%s' -o ref.ply " RUN_OPTS, bin(), spot()) != 0) {
        fprintf(stderr, "reference run failed:\n%s\n", text);
        return -1;
    }
    ref = test_slurp(at("ref.ply"), &ref_len);
    return ref && ref_len > 0 ? 0 : -1;
}

static int teardown(void **s)
{
    (void)s;
    free(ref);
    return test_remove_dir(dir);
}

/* ----------------------------------------------------------------- symlinks */

static void symlink_target_replaced(void **s)
{
    (void)s;
    assert_int_equal(mkdir(at("sub"), 0755), 0);
    assert_int_equal(test_write_text(at("sub/t.ply"), "OLD\n"), 0);
    assert_int_equal(symlink("sub/t.ply", at("link.ply")), 0);
    assert_int_equal(LIMN("interpolate '%s' -o link.ply " RUN_OPTS, bin(), spot()), 0);
    assert_true(is_symlink_to(at("link.ply"), "sub/t.ply"));
    same_as_ref(at("sub/t.ply"));
    no_temps(dir);
    no_temps(at("sub"));
}

static void dangling_symlink(void **s)
{
    (void)s;
    mkdir(at("sub"), 0755);
    assert_int_equal(symlink("sub/new.ply", at("dangling.ply")), 0);
    assert_int_equal(LIMN("interpolate '%s' -o dangling.ply " RUN_OPTS, bin(), spot()), 0);
    assert_true(is_symlink_to(at("dangling.ply"), "sub/new.ply"));
    same_as_ref(at("sub/new.ply"));
    /* a dangling link into a missing directory: refused before any work */
    assert_int_equal(symlink("nowhere/x.ply", at("lost.ply")), 0);
    assert_int_equal(LIMN("interpolate '%s' -o lost.ply --report r1.json " RUN_OPTS, bin(),
                          spot()),
                     1);
    assert_non_null(strstr(text, "nowhere/"));
    assert_false(test_file_exists(at("r1.json")));
}

/* a/l1 -> ../b/l2 (relative to a/), b/l2 -> c/final.ply (relative to b/) */
static void relative_symlink_chain(void **s)
{
    (void)s;
    assert_int_equal(mkdir(at("a"), 0755), 0);
    assert_int_equal(mkdir(at("b"), 0755), 0);
    assert_int_equal(mkdir(at("b/c"), 0755), 0);
    assert_int_equal(symlink("../b/l2.ply", at("a/l1.ply")), 0);
    assert_int_equal(symlink("c/final.ply", at("b/l2.ply")), 0);
    assert_int_equal(LIMN("interpolate '%s' -o a/l1.ply " RUN_OPTS, bin(), spot()), 0);
    assert_true(is_symlink_to(at("a/l1.ply"), "../b/l2.ply"));
    assert_true(is_symlink_to(at("b/l2.ply"), "c/final.ply"));
    same_as_ref(at("b/c/final.ply"));
    no_temps(at("a"));
    no_temps(at("b"));
    no_temps(at("b/c"));
    /* a loop is refused */
    assert_int_equal(symlink("loop2.ply", at("loop1.ply")), 0);
    assert_int_equal(symlink("loop1.ply", at("loop2.ply")), 0);
    assert_int_equal(LIMN("interpolate '%s' -o loop1.ply " RUN_OPTS, bin(), spot()), 1);
    assert_non_null(strstr(text, "symbolic links"));
}

/* ------------------------------------------------------- straight through */

static void fifo_with_reader(void **s)
{
    (void)s;
    const char *fifo = at("pipe.ply");
    assert_int_equal(mkfifo(fifo, 0644), 0);
    pid_t child = fork();
    assert_true(child >= 0);
    if (child == 0) { /* the reader: the bytes must be the regular file's */
        FILE *f = fopen(fifo, "rb");
        if (!f)
            _exit(3);
        char *got = malloc(ref_len + 2);
        size_t n = fread(got, 1, ref_len + 1, f);
        _exit(n == ref_len && memcmp(got, ref, n) == 0 ? 0 : 1);
    }
    int rc = LIMN("interpolate '%s' -o pipe.ply " RUN_OPTS, bin(), spot());
    /* should limn not have opened it, release the reader waiting in open() */
    int fd = open(fifo, O_WRONLY | O_NONBLOCK);
    if (fd >= 0)
        close(fd);
    int status;
    assert_int_equal(waitpid(child, &status, 0), child);
    if (rc != 0)
        fail_msg("exit %d:\n%s", rc, text);
    assert_true(WIFEXITED(status));
    assert_int_equal(WEXITSTATUS(status), 0);
    struct stat sb;
    assert_int_equal(lstat(fifo, &sb), 0);
    assert_true(S_ISFIFO(sb.st_mode)); /* still the FIFO, not replaced */
    no_temps(dir);
}

static void dev_null(void **s)
{
    (void)s;
    assert_int_equal(LIMN("interpolate '%s' -o /dev/null --format ply --report /dev/null "
                          RUN_OPTS,
                          bin(), spot()),
                     0);
    struct stat sb;
    assert_int_equal(stat("/dev/null", &sb), 0);
    assert_true(S_ISCHR(sb.st_mode));
}

static void dash_is_stdout(void **s)
{
    (void)s;
    assert_int_equal(LIMN("interpolate '%s' -o - --format ply " RUN_OPTS " > cap.ply", bin(),
                          spot()),
                     0);
    same_as_ref(at("cap.ply"));
    /* --report -: the JSON document on stdout, the mesh in its file */
    assert_int_equal(LIMN("interpolate '%s' -o m.ply --report - " RUN_OPTS " > cap.json", bin(),
                          spot()),
                     0);
    same_as_ref(at("m.ply"));
    size_t n;
    char *json = test_slurp(at("cap.json"), &n);
    assert_non_null(json);
    assert_true(n > 2 && json[0] == '{' && json[n - 2] == '}' && json[n - 1] == '\n');
    assert_non_null(strstr(json, "\"input\": "));
    free(json);
    /* /dev/stdout is the same as - */
    assert_int_equal(LIMN("interpolate '%s' -o /dev/stdout --format ply " RUN_OPTS " > cap2.ply",
                          bin(), spot()),
                     0);
    same_as_ref(at("cap2.ply"));
    /* two outputs on stdout: refused, nothing written */
    assert_int_equal(LIMN("interpolate '%s' -o - --format ply --report - " RUN_OPTS
                          " > cap3.out",
                          bin(), spot()),
                     2);
    assert_non_null(strstr(text, "both go to standard output"));
    struct stat sb;
    assert_int_equal(stat(at("cap3.out"), &sb), 0);
    assert_int_equal(sb.st_size, 0);
    /* a mesh on stdout needs --format */
    assert_int_equal(LIMN("interpolate '%s' -o - " RUN_OPTS " > cap4.out", bin(), spot()), 2);
    assert_non_null(strstr(text, "needs --format"));
}

static void dash_is_stdin(void **s)
{
    (void)s;
    assert_int_equal(LIMN("interpolate - --input-format obj -o in.ply " RUN_OPTS " < '%s'",
                          bin(), spot()),
                     0);
    same_as_ref(at("in.ply"));
    /* without --input-format: refused, saying so */
    assert_int_equal(LIMN("interpolate - -o in2.ply " RUN_OPTS " < '%s'", bin(), spot()), 2);
    assert_non_null(strstr(text, "needs --input-format"));
    assert_false(test_file_exists(at("in2.ply")));
    /* a file named - is ./- */
    assert_int_equal(run_sh("cp '%s' ./-", spot()), 0);
    assert_int_equal(LIMN("interpolate ./- --input-format obj -o in3.ply " RUN_OPTS
                          " < /dev/null",
                          bin()),
                     0);
    same_as_ref(at("in3.ply"));
    unlink(at("-"));
}

static void dev_full_fails(void **s)
{
    (void)s;
    assert_int_equal(LIMN("interpolate '%s' -o /dev/full --format ply " RUN_OPTS, bin(), spot()),
                     1);
    assert_non_null(strstr(text, "/dev/full"));
    assert_non_null(strstr(text, "No space left on device"));
}

/* stdout a pipe whose reader is gone: EPIPE is an error (exit 1), not SIGPIPE */
static void closed_pipe_fails(void **s)
{
    (void)s;
    int p[2];
    assert_int_equal(pipe(p), 0);
    int errp[2];
    assert_int_equal(pipe(errp), 0);
    pid_t child = fork();
    assert_true(child >= 0);
    if (child == 0) {
        dup2(p[1], STDOUT_FILENO);
        dup2(errp[1], STDERR_FILENO);
        close(p[0]);
        close(p[1]);
        close(errp[0]);
        close(errp[1]);
        execl(bin(), bin(), "interpolate", spot(), "-o", "-", "--format", "ply", "--device",
              "reference", "-q", (char *)NULL);
        _exit(127);
    }
    close(p[0]); /* no reader at all: every write fails */
    close(p[1]);
    close(errp[1]);
    size_t n = 0;
    ssize_t r;
    while ((r = read(errp[0], text + n, sizeof text - 1 - n)) > 0)
        n += (size_t)r;
    text[n] = '\0';
    close(errp[0]);
    int status;
    assert_int_equal(waitpid(child, &status, 0), child);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 1)
        fail_msg("status %d:\n%s", status, text);
    assert_non_null(strstr(text, "Broken pipe"));
}

/* ------------------------------------------------------------- the input */

static void input_not_overwritten_through_links(void **s)
{
    (void)s;
    assert_int_equal(run_sh("cp '%s' in.obj && ln in.obj hard.obj && ln -s in.obj sym.obj && "
                            "ln -s in.obj sym.json",
                            spot()),
                     0);
    size_t n0, n1;
    char *orig = test_slurp(at("in.obj"), &n0);
    /* output a symlink to the input, a hard link of it; input through a symlink */
    const char *cases[][2] = {{"in.obj", "sym.obj"}, {"in.obj", "hard.obj"},
                              {"sym.obj", "in.obj"}};
    for (int k = 0; k < 3; k++) {
        const char *in = cases[k][0], *out = cases[k][1];
        int rc = LIMN("interpolate %s -o %s " RUN_OPTS, bin(), in, out);
        if (rc != 2 || !strstr(text, "is the input file"))
            fail_msg("-o %s (input %s): exit %d:\n%s", out, in, rc, text);
        rc = LIMN("interpolate %s -o x.ply --surface %s " RUN_OPTS, bin(), in, out);
        if (rc != 2 || !strstr(text, "is the input file"))
            fail_msg("--surface %s (input %s): exit %d:\n%s", out, in, rc, text);
    }
    assert_int_equal(LIMN("interpolate in.obj -o x.ply --report sym.json " RUN_OPTS, bin()), 2);
    assert_non_null(strstr(text, "is the input file"));
    assert_int_equal(LIMN("interpolate sym.obj -o x.ply --report hard.obj " RUN_OPTS, bin()), 2);
    char *now = test_slurp(at("in.obj"), &n1);
    assert_int_equal(n0, n1);
    assert_memory_equal(orig, now, n0);
    assert_true(is_symlink_to(at("sym.obj"), "in.obj"));
    assert_false(test_file_exists(at("x.ply")));
    free(now);
    free(orig);
}

/* --------------------------------------------------------------- temporaries */

static void stale_temps_removed(void **s)
{
    (void)s;
    pid_t dead = fork();
    assert_true(dead >= 0);
    if (dead == 0)
        _exit(0);
    assert_int_equal(waitpid(dead, NULL, 0), dead);
    char name[5][128];
    snprintf(name[0], sizeof name[0], ".x.ply.limn-tmp.%ld.abc", (long)dead);       /* removed */
    snprintf(name[1], sizeof name[1], ".x.ply.limn-tmp.%ld.abc", (long)getpid());   /* live */
    snprintf(name[2], sizeof name[2], ".x.ply.limn-tmp.%ld.ab.c", (long)dead);      /* no match */
    snprintf(name[3], sizeof name[3], ".y.ply.limn-tmp.%ld.abc", (long)dead);       /* other file */
    snprintf(name[4], sizeof name[4], ".x.ply.limn-tmp.%ldz.abc", (long)dead);      /* no match */
    for (int i = 0; i < 5; i++)
        assert_int_equal(test_write_text(at(name[i]), "stale\n"), 0);
    assert_int_equal(LIMN("interpolate '%s' -o x.ply " RUN_OPTS, bin(), spot()), 0);
    same_as_ref(at("x.ply"));
    assert_false(test_file_exists(at(name[0])));
    for (int i = 1; i < 5; i++)
        if (!test_file_exists(at(name[i])))
            fail_msg("%s was removed", name[i]);
    for (int i = 1; i < 5; i++)
        unlink(at(name[i]));
}

static void mode_kept(void **s)
{
    (void)s;
    assert_int_equal(test_write_text(at("moded.ply"), "OLD\n"), 0);
    assert_int_equal(chmod(at("moded.ply"), 0640), 0);
    int root = geteuid() == 0;
    if (root)
        assert_int_equal(chown(at("moded.ply"), 65534, 65534), 0);
    struct stat before, after;
    assert_int_equal(stat(at("moded.ply"), &before), 0);
    assert_int_equal(LIMN("interpolate '%s' -o moded.ply " RUN_OPTS, bin(), spot()), 0);
    assert_int_equal(stat(at("moded.ply"), &after), 0);
    assert_true(before.st_ino != after.st_ino); /* replaced, not rewritten */
    assert_int_equal(after.st_mode & 07777, 0640);
    if (root) { /* root may set the owner: it is kept */
        assert_int_equal(after.st_uid, 65534);
        assert_int_equal(after.st_gid, 65534);
    }
    same_as_ref(at("moded.ply"));
}

/* --------------------------------------------- refusals before any work */

/* A refused output: exit 1, the message, and nothing written (the report
   of the same run does not appear: no work was done). */
static void refused_early(const char *output, const char *message)
{
    unlink(at("early.json"));
    int rc = LIMN("interpolate '%s' -o '%s' --report early.json --device reference", bin(),
                  spot(), output);
    if (rc != 1 || !strstr(text, message))
        fail_msg("-o %s: exit %d (want 1, '%s'):\n%s", output, rc, message, text);
    assert_false(test_file_exists(at("early.json")));
    assert_null(strstr(text, "iterations")); /* no summary: nothing was computed */
    no_temps(dir);
}

static void early_refusals(void **s)
{
    (void)s;
    assert_int_equal(mkdir(at("adir.ply"), 0755), 0);
    refused_early("adir.ply", "it is a directory");
    assert_int_equal(symlink("adir.ply", at("todir.ply")), 0);
    refused_early("todir.ply", "it is a directory");
    char longname[300];
    memset(longname, 'n', 252);
    strcpy(longname + 252, ".ply"); /* 256 bytes */
    refused_early(longname, "bytes long");
    refused_early("missing/out.ply", "missing/");
}

/* A sticky directory owned by someone else, holding a file of someone
   else: the rename would fail at the end, so the run is refused at once.
   Needs root (to make the files of another user and run as nobody). */
static void sticky_directory(void **s)
{
    (void)s;
    if (geteuid() != 0) {
        print_message("  sticky_directory: skipped (needs root to give files to another user)\n");
        return;
    }
    assert_int_equal(mkdir(at("sticky"), 0755), 0);
    assert_int_equal(chmod(at("sticky"), 01777), 0);
    assert_int_equal(test_write_text(at("sticky/theirs.ply"), "THEIRS\n"), 0);
    assert_int_equal(chmod(at("sticky/theirs.ply"), 0666), 0);
    assert_int_equal(chmod(dir, 0755), 0);
    int rc = run_sh("setpriv --reuid=65534 --regid=65534 --clear-groups '%s' interpolate '%s' "
                    "-o sticky/theirs.ply --report sticky/r.json --device reference",
                    bin(), spot());
    if (rc != 1 && strstr(text, "setpriv")) {
        print_message("  sticky_directory: cannot run as another user here: %s\n", text);
        return;
    }
    if (rc != 1 || !strstr(text, "sticky directory"))
        fail_msg("exit %d:\n%s", rc, text);
    size_t n;
    char *kept = test_slurp(at("sticky/theirs.ply"), &n);
    assert_string_equal(kept, "THEIRS\n");
    free(kept);
    assert_false(test_file_exists(at("sticky/r.json")));
    no_temps(at("sticky"));
}

/* ------------------------------------------------------------- the pair lock */

/* The "input" string of a report. */
static void report_input(const char *path, char *out, size_t cap)
{
    size_t n;
    char *json = test_slurp(path, &n);
    assert_non_null(json);
    const char *p = strstr(json, "\"input\": \"");
    assert_non_null(p);
    p += strlen("\"input\": \"");
    const char *q = strchr(p, '"');
    assert_non_null(q);
    snprintf(out, cap, "%.*s", (int)(q - p), p);
    free(json);
}

static int file_is(const char *path, const char *bytes, size_t len)
{
    size_t n;
    char *got = test_slurp(path, &n);
    int same = got && n == len && memcmp(got, bytes, n) == 0;
    free(got);
    return same;
}

/* Two runs at once write the same mesh + report pair from two inputs of
   the same size. Run A waits 300 ms between its two renames (test hook):
   without the lock, B's pair could land in between and leave A's report
   beside B's mesh. With it, the pair is always one run's. */
static void pair_lock(void **s)
{
    (void)s;
    limn_context *ctx = limn_context_create();
    limn_mesh *m = NULL;
    assert_int_equal(limn_mesh_read(ctx, spot(), LIMN_FORMAT_AUTO, &m), LIMN_OK);
    test_perturb(m, 0.01, 7);
    assert_int_equal(limn_mesh_write(ctx, m, at("spot_b.obj"), LIMN_FORMAT_OBJ), LIMN_OK);
    limn_mesh_destroy(m);
    limn_context_destroy(ctx);
    assert_int_equal(LIMN("interpolate spot_b.obj -o ref_b.ply " RUN_OPTS, bin()), 0);
    size_t ref_b_len;
    char *ref_b = test_slurp(at("ref_b.ply"), &ref_b_len);
    assert_non_null(ref_b);
    for (int round = 0; round < 20; round++) {
        int rc = run_sh("{ LIMN_TEST_COMMIT_PAUSE_MS=300 '%s' interpolate '%s' -o pair.ply "
                        "--report pair.json " RUN_OPTS " & a=$!; '%s' interpolate spot_b.obj "
                        "-o pair.ply --report pair.json " RUN_OPTS " & b=$!; wait $a && wait $b; }",
                        bin(), spot(), bin());
        if (rc != 0)
            fail_msg("round %d: exit %d:\n%s", round, rc, text);
        char input[1024];
        report_input(at("pair.json"), input, sizeof input);
        int from_b = strcmp(input, "spot_b.obj") == 0;
        if (!from_b && strcmp(input, spot()) != 0)
            fail_msg("round %d: report input '%s'", round, input);
        if (!(from_b ? file_is(at("pair.ply"), ref_b, ref_b_len)
                     : file_is(at("pair.ply"), ref, ref_len)))
            fail_msg("round %d: the report is %s's, the mesh is not", round, input);
        no_temps(dir);
    }
    free(ref_b);
}

int main(void)
{
    if (!getenv("LIMN_BIN") || !getenv("LIMN_TEST_DATA")) {
        fprintf(stderr, "test_outputs: LIMN_BIN and LIMN_TEST_DATA must be set (run by ctest)\n");
        return 77;
    }
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(symlink_target_replaced),
        cmocka_unit_test(dangling_symlink),
        cmocka_unit_test(relative_symlink_chain),
        cmocka_unit_test(fifo_with_reader),
        cmocka_unit_test(dev_null),
        cmocka_unit_test(dash_is_stdout),
        cmocka_unit_test(dash_is_stdin),
        cmocka_unit_test(dev_full_fails),
        cmocka_unit_test(closed_pipe_fails),
        cmocka_unit_test(input_not_overwritten_through_links),
        cmocka_unit_test(stale_temps_removed),
        cmocka_unit_test(mode_kept),
        cmocka_unit_test(early_refusals),
        cmocka_unit_test(sticky_directory),
        cmocka_unit_test(pair_lock),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
