/* SPDX-License-Identifier: MIT */
/* Atomic file replacement: mkstemp + fsync + rename (+ fsync of the
   directory); straight-through outputs buffered until the commit. */
#ifndef _DEFAULT_SOURCE
#define _DEFAULT_SOURCE /* fchown, fsync, fdopen, mkstemp */
#endif
#include "base/atomic_file.h"
#include "base/context.h"

#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#define ATOMIC_FILE_BUFFER (1 << 20)

/* The process umask without changing it (umask() would race with other
   threads): Linux reports it in /proc/self/status. */
static mode_t current_umask(void)
{
    mode_t mask = 022;
    FILE *f = fopen("/proc/self/status", "r");
    if (!f)
        return mask;
    char line[256];
    while (fgets(line, sizeof line, f)) {
        if (strncmp(line, "Umask:", 6) == 0) {
            char *end;
            long v = strtol(line + 6, &end, 8);
            if (end != line + 6 && v >= 0 && v <= 0777)
                mask = (mode_t)v;
            break;
        }
    }
    fclose(f);
    return mask;
}

static limn_status write_failed(limn_context *ctx, const char *path, int e)
{
    return ctx_fail(ctx, LIMN_ERR_IO, "cannot write %s: %s", path, e ? strerror(e) : "write error");
}

/* The new file gets the replaced one's owner, group and mode where the
   process may set them, else the mode a new file would have. */
static int set_mode(int fd, const output_path *op)
{
    if (!op->exists)
        return fchmod(fd, 0666 & ~current_umask());
    mode_t mode = op->old_mode & 07777;
    if (fchown(fd, op->old_uid, op->old_gid) != 0) {
        if (errno != EPERM)
            return -1;
        mode &= ~(mode_t)(S_ISUID | S_ISGID); /* not for a file of another owner or group */
    }
    return fchmod(fd, mode);
}

static limn_status temp_failed(limn_context *ctx, atomic_file *af, int e)
{
    free(af->tmp_path);
    af->tmp_path = NULL; /* nothing to remove */
    const char *dir = af->out.dir;
    limn_status st =
        !strchr(af->out.target, '/')
            ? ctx_fail(ctx, LIMN_ERR_IO,
                        "cannot write %s: cannot create a temporary file in the current "
                        "directory: %s",
                        af->path, strerror(e))
            : ctx_fail(ctx, LIMN_ERR_IO, "cannot write %s: cannot create a temporary file in %s%s: %s",
                        af->path, dir, strcmp(dir, "/") ? "/" : "", strerror(e));
    atomic_file_abort(af);
    return st;
}

static limn_status open_regular(limn_context *ctx, atomic_file *af)
{
    limn_status st = output_check_rename(ctx, af->path, &af->out);
    if (st) {
        atomic_file_abort(af);
        return st;
    }
    output_remove_stale(&af->out);
    af->tmp_path = output_temp_template(&af->out);
    if (!af->tmp_path) {
        atomic_file_abort(af);
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory");
    }
    int fd = mkstemp(af->tmp_path);
    if (fd < 0)
        return temp_failed(ctx, af, errno);
    if (set_mode(fd, &af->out) != 0 || !(af->f = fdopen(fd, "wb"))) {
        int e = errno;
        if (!af->f)
            close(fd);
        /* the message before the abort, which frees af->path */
        limn_status st = write_failed(ctx, af->path, e);
        atomic_file_abort(af);
        return st;
    }
    return LIMN_OK;
}

limn_status atomic_file_open(limn_context *ctx, const char *path, atomic_file *af)
{
    memset(af, 0, sizeof *af);
    limn_status st = output_path_resolve(ctx, path, &af->out);
    if (st)
        return st;
    if (!(af->path = strdup(path))) {
        atomic_file_abort(af);
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory");
    }
    if (af->out.kind == OUTPUT_FILE) {
        if ((st = open_regular(ctx, af)))
            return st;
    } else if (!(af->f = tmpfile())) {
        /* unlinked at once: nothing is left behind, whatever happens */
        int e = errno;
        atomic_file_abort(af);
        return ctx_fail(ctx, LIMN_ERR_IO,
                         "cannot write %s: cannot create a buffer file in %s: %s", path, P_tmpdir,
                         strerror(e));
    }
    af->iobuf = malloc(ATOMIC_FILE_BUFFER);
    if (af->iobuf)
        setvbuf(af->f, af->iobuf, _IOFBF, ATOMIC_FILE_BUFFER);
    return LIMN_OK;
}

limn_status atomic_file_check(limn_context *ctx, const char *path)
{
    if (output_is_stdout(path)) {
        int fl = fcntl(STDOUT_FILENO, F_GETFL);
        if (fl < 0 || (fl & O_ACCMODE) == O_RDONLY)
            return ctx_fail(ctx, LIMN_ERR_IO, "cannot write %s: standard output is %s", path,
                             fl < 0 ? "closed" : "not open for writing");
        return LIMN_OK;
    }
    output_path op;
    limn_status st = output_path_resolve(ctx, path, &op);
    if (st)
        return st;
    int device = op.kind == OUTPUT_DEVICE;
    if (device && faccessat(AT_FDCWD, op.target, W_OK, AT_EACCESS) != 0)
        st = write_failed(ctx, path, errno);
    output_path_free(&op);
    if (st || device)
        return st;
    /* the temporary file is made beside the target and removed */
    atomic_file af;
    st = atomic_file_open(ctx, path, &af);
    if (!st)
        atomic_file_abort(&af);
    return st;
}

limn_status atomic_file_finish(limn_context *ctx, atomic_file *af)
{
    if (!af->f)
        return LIMN_OK;
    limn_status st = LIMN_OK;
    if (af->out.kind != OUTPUT_FILE) { /* the buffer stays open for the commit */
        if (fflush(af->f) != 0 || ferror(af->f))
            st = write_failed(ctx, af->path, errno);
        if (st)
            atomic_file_abort(af);
        return st;
    }
    if (fflush(af->f) != 0 || ferror(af->f) || fsync(fileno(af->f)) != 0)
        st = write_failed(ctx, af->path, errno);
    FILE *closing = af->f;
    af->f = NULL;
    if (fclose(closing) != 0 && !st)
        st = write_failed(ctx, af->path, errno);
    free(af->iobuf); /* a staged file waits for its commit without its 1 MiB buffer */
    af->iobuf = NULL;
    if (st)
        atomic_file_abort(af);
    return st;
}

/* Renames a finished regular output over its target and syncs the directory. */
static limn_status rename_over(limn_context *ctx, atomic_file *af)
{
    if (rename(af->tmp_path, af->out.target) != 0) {
        limn_status st = ctx_fail(ctx, LIMN_ERR_IO, "cannot write %s: cannot rename %s over it: %s",
                                   af->path, af->tmp_path, strerror(errno));
        atomic_file_abort(af);
        return st;
    }
    /* make the rename durable; a failure here does not undo the write */
    int dfd = open(af->out.dir, O_RDONLY | O_CLOEXEC);
    if (dfd >= 0) {
        (void)fsync(dfd);
        close(dfd);
    }
    free(af->tmp_path);
    af->tmp_path = NULL; /* renamed: nothing to remove */
    atomic_file_abort(af);
    return LIMN_OK;
}

static int write_all(int fd, const char *p, size_t n)
{
    while (n > 0) {
        ssize_t w = write(fd, p, n);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0) {
            if (w == 0)
                errno = EIO; /* no progress: do not loop */
            return -1;
        }
        p += w;
        n -= (size_t)w;
    }
    return 0;
}

/* Copies the buffered bytes of a straight-through output to it. */
static limn_status write_through(limn_context *ctx, atomic_file *af)
{
    int to_stdout = af->out.kind == OUTPUT_STDOUT;
    fflush(stdout); /* whatever stdio holds goes first */
    int fd = to_stdout ? STDOUT_FILENO : open(af->out.target, O_WRONLY | O_NOCTTY | O_CLOEXEC);
    int e = 0;
    if (fd < 0 || fseek(af->f, 0, SEEK_SET) != 0)
        e = errno;
    char buf[1 << 16];
    size_t n;
    while (!e && (n = fread(buf, 1, sizeof buf, af->f)) > 0)
        if (write_all(fd, buf, n) != 0)
            e = errno;
    if (!e && ferror(af->f))
        e = EIO;
    if (fd >= 0 && !to_stdout && close(fd) != 0 && !e)
        e = errno;
    limn_status st = e ? write_failed(ctx, to_stdout ? "standard output" : af->path, e) : LIMN_OK;
    atomic_file_abort(af);
    return st;
}

/* Test-only hook (inert unless set): LIMN_TEST_COMMIT_PAUSE_MS waits
   between the renames of a set, so that tests/test_outputs.c can show that
   another run's set cannot come in between. */
static void test_pause(void)
{
    const char *ms = getenv("LIMN_TEST_COMMIT_PAUSE_MS");
    long v = ms ? strtol(ms, NULL, 10) : 0;
    if (v > 0 && v <= 10000) {
        struct timespec ts = {v / 1000, (v % 1000) * 1000000L};
        while (nanosleep(&ts, &ts) != 0 && errno == EINTR)
            ;
    }
}

/* The directories of the set's renames, each named once (a set of many
   files in one directory locks it once), at most OUTPUT_LOCK_MAX of them
   (more: best effort, the first ones locked). */
static void lock_set(atomic_file *af, int n, int *fds, int *nfds)
{
    const char *dirs[OUTPUT_LOCK_MAX];
    int k = 0, renames = 0;
    for (int i = 0; i < n; i++) {
        if (af[i].out.kind != OUTPUT_FILE || !af[i].tmp_path)
            continue;
        renames++;
        int seen = 0;
        for (int j = 0; j < k && !seen; j++)
            seen = strcmp(dirs[j], af[i].out.dir) == 0;
        if (!seen && k < OUTPUT_LOCK_MAX)
            dirs[k++] = af[i].out.dir;
    }
    *nfds = renames > 1 ? k : 0; /* one rename is atomic by itself */
    if (*nfds)
        output_lock_dirs(dirs, k, fds);
}

limn_status atomic_file_commit_all(limn_context *ctx, atomic_file *af, int n)
{
    limn_status st = LIMN_OK;
    for (int i = 0; i < n && !st; i++)
        st = atomic_file_finish(ctx, &af[i]);
    int fds[OUTPUT_LOCK_MAX], nfds = 0;
    if (!st)
        lock_set(af, n, fds, &nfds);
    int renamed = 0;
    for (int i = 0; i < n; i++) {
        if (af[i].out.kind != OUTPUT_FILE)
            continue;
        if (!st && af[i].tmp_path) {
            if (renamed++)
                test_pause();
            st = rename_over(ctx, &af[i]);
        } else {
            atomic_file_abort(&af[i]);
        }
    }
    output_unlock(fds, nfds);
    /* last: these cannot be undone once written */
    for (int i = 0; i < n; i++) {
        if (!st && af[i].f)
            st = write_through(ctx, &af[i]);
        else
            atomic_file_abort(&af[i]);
    }
    return st;
}

limn_status atomic_file_commit(limn_context *ctx, atomic_file *af)
{
    return atomic_file_commit_all(ctx, af, 1);
}

void atomic_file_abort(atomic_file *af)
{
    if (af->f)
        fclose(af->f);
    if (af->tmp_path)
        unlink(af->tmp_path);
    free(af->iobuf);
    free(af->path);
    free(af->tmp_path);
    output_path_free(&af->out);
    memset(af, 0, sizeof *af);
}
