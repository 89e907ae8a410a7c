/* SPDX-License-Identifier: MIT */
/* Output paths: classification, symlink resolution, temporary names, stale
   temporary files, rename preflight, the commit lock (see output_path.h). */
#ifndef _DEFAULT_SOURCE
#define _DEFAULT_SOURCE /* readlink, lstat, flock, fstatat */
#endif
#include "base/output_path.h"
#include "base/context.h"

#include <ctype.h>
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#define LINK_HOPS 40          /* as the kernel's own limit (ELOOP) */
#define TEMP_TAG ".limn-tmp."
#define TEMP_PID_DIGITS 10    /* reserved whatever the pid, so BASE is cut the same by every run */
#define TEMP_RANDOM "XXXXXX"

int output_is_stdout(const char *path)
{
    return path && (strcmp(path, "-") == 0 || strcmp(path, "/dev/stdout") == 0 ||
                    strcmp(path, "/dev/fd/1") == 0 || strcmp(path, "/proc/self/fd/1") == 0);
}

void output_path_free(output_path *op)
{
    free(op->target);
    free(op->dir);
    memset(op, 0, sizeof *op);
}

/* The directory part of p with its '/' ("" when none) joined with rel. */
static char *join_beside(const char *p, const char *rel)
{
    const char *slash = strrchr(p, '/');
    size_t dirlen = slash ? (size_t)(slash - p) + 1 : 0;
    char *out = malloc(dirlen + strlen(rel) + 1);
    if (out) {
        memcpy(out, p, dirlen);
        strcpy(out + dirlen, rel);
    }
    return out;
}

/* Follows the symlink chain from *p (replaced by the final path); *sb gets
   the final file's lstat, *exists whether there is one. */
static limn_status follow_links(limn_context *ctx, const char *path, char **p, struct stat *sb,
                                int *exists)
{
    for (int hops = 0;; hops++) {
        if (lstat(*p, sb) != 0) {
            /* a new file, or a dangling link's target; a name too long is
               refused with the directory's limit by split_target */
            if (errno == ENOENT || errno == ENAMETOOLONG) {
                *exists = 0;
                return LIMN_OK;
            }
            return ctx_fail(ctx, LIMN_ERR_IO, "cannot write %s: %s", path, strerror(errno));
        }
        if (!S_ISLNK(sb->st_mode)) {
            *exists = 1;
            return LIMN_OK;
        }
        if (hops == LINK_HOPS)
            return ctx_fail(ctx, LIMN_ERR_IO,
                             "cannot write %s: more than %d symbolic links to follow (a loop?)",
                             path, LINK_HOPS);
        size_t cap = sb->st_size > 0 ? (size_t)sb->st_size + 1 : PATH_MAX;
        char *link = malloc(cap);
        ssize_t n = link ? readlink(*p, link, cap) : -1;
        if (n < 0 || (size_t)n >= cap) {
            int e = link ? errno : ENOMEM;
            free(link);
            return ctx_fail(ctx, LIMN_ERR_IO, "cannot write %s: cannot read the link %s: %s",
                             path, *p, n < 0 ? strerror(e) : "it changed while read");
        }
        link[n] = '\0';
        /* a relative link is relative to the link's own directory */
        char *next = link[0] == '/' ? strdup(link) : join_beside(*p, link);
        free(link);
        if (!next)
            return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory");
        free(*p);
        *p = next;
    }
}

/* Fills dir, base and name_max of a regular output; refuses a name that
   names a directory or is longer than its directory allows. */
static limn_status split_target(limn_context *ctx, const char *path, output_path *op)
{
    char *slash = strrchr(op->target, '/');
    op->base = slash ? slash + 1 : op->target;
    if (!*op->base || strcmp(op->base, ".") == 0 || strcmp(op->base, "..") == 0)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "cannot write %s: it names a directory", path);
    size_t dirlen = slash ? (slash == op->target ? 1 : (size_t)(slash - op->target)) : 1;
    op->dir = malloc(dirlen + 1);
    if (!op->dir)
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory");
    memcpy(op->dir, slash ? op->target : ".", dirlen);
    op->dir[dirlen] = '\0';
    errno = 0;
    long nm = pathconf(op->dir, _PC_NAME_MAX);
    op->name_max = nm > 0 ? nm : NAME_MAX;
    size_t len = strlen(op->base);
    if (len > (size_t)op->name_max)
        return ctx_fail(ctx, LIMN_ERR_IO,
                         "cannot write %s: its name is %zu bytes long, over the %ld a file "
                         "name may have in %s",
                         path, len, op->name_max, op->dir);
    return LIMN_OK;
}

limn_status output_path_resolve(limn_context *ctx, const char *path, output_path *op)
{
    memset(op, 0, sizeof *op);
    if (!path || !*path)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "empty output file name");
    if (output_is_stdout(path)) {
        op->kind = OUTPUT_STDOUT;
        return LIMN_OK;
    }
    op->target = strdup(path);
    if (!op->target)
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory");
    struct stat sb;
    limn_status st = follow_links(ctx, path, &op->target, &sb, &op->exists);
    if (!st && op->exists) {
        if (S_ISDIR(sb.st_mode))
            st = ctx_fail(ctx, LIMN_ERR_IO, "cannot write %s: it is a directory", path);
        else if (S_ISFIFO(sb.st_mode) || S_ISCHR(sb.st_mode))
            op->kind = OUTPUT_DEVICE;
        else if (!S_ISREG(sb.st_mode))
            st = ctx_fail(ctx, LIMN_ERR_IO,
                           "cannot write %s: it is neither a regular file, a FIFO nor a "
                           "character device",
                           path);
        op->old_mode = sb.st_mode;
        op->old_uid = sb.st_uid;
        op->old_gid = sb.st_gid;
    }
    if (!st && op->kind == OUTPUT_FILE)
        st = split_target(ctx, path, op);
    if (st)
        output_path_free(op);
    return st;
}

/* How many bytes of BASE a temporary's name keeps. */
static size_t temp_base_len(const output_path *op)
{
    size_t fixed = 1 + strlen(TEMP_TAG) + TEMP_PID_DIGITS + 1 + strlen(TEMP_RANDOM);
    size_t room = (size_t)op->name_max > fixed ? (size_t)op->name_max - fixed : 1;
    size_t len = strlen(op->base);
    return len < room ? len : room;
}

char *output_temp_template(const output_path *op)
{
    size_t bl = temp_base_len(op);
    size_t n = strlen(op->dir) + 2 + bl + strlen(TEMP_TAG) + 24 + strlen(TEMP_RANDOM) + 1;
    char *t = malloc(n);
    if (t)
        snprintf(t, n, "%s/.%.*s" TEMP_TAG "%ld." TEMP_RANDOM, op->dir, (int)bl, op->base,
                 (long)getpid());
    return t;
}

/* The pid of a name .BASE.limn-tmp.PID.SUFFIX (prefix = ".BASE.limn-tmp."),
   or 0 when the name does not match exactly. */
static long stale_pid(const char *name, const char *prefix, size_t plen)
{
    if (strncmp(name, prefix, plen) != 0)
        return 0;
    const char *p = name + plen;
    long pid = 0;
    int digits = 0;
    for (; isdigit((unsigned char)*p) && digits < TEMP_PID_DIGITS; p++, digits++)
        pid = 10 * pid + (*p - '0');
    if (!digits || *p != '.' || !p[1])
        return 0;
    for (p++; *p; p++)
        if (!isalnum((unsigned char)*p)) /* mkstemp's alphabet */
            return 0;
    return pid;
}

void output_remove_stale(const output_path *op)
{
    size_t bl = temp_base_len(op);
    size_t plen = 1 + bl + strlen(TEMP_TAG);
    char *prefix = malloc(plen + 1);
    DIR *d = prefix ? opendir(op->dir) : NULL;
    if (!d) {
        free(prefix);
        return;
    }
    snprintf(prefix, plen + 1, ".%.*s" TEMP_TAG, (int)bl, op->base);
    struct dirent *e;
    while ((e = readdir(d))) {
        long pid = stale_pid(e->d_name, prefix, plen);
        if (pid <= 0 || pid == (long)getpid() || pid > INT_MAX)
            continue;
        /* only a process known not to exist (a live one, or one we may not
           signal, keeps its file) */
        if (kill((pid_t)pid, 0) == 0 || errno != ESRCH)
            continue;
        struct stat sb;
        if (fstatat(dirfd(d), e->d_name, &sb, AT_SYMLINK_NOFOLLOW) == 0 && S_ISREG(sb.st_mode))
            (void)unlinkat(dirfd(d), e->d_name, 0);
    }
    closedir(d);
    free(prefix);
}

limn_status output_check_rename(limn_context *ctx, const char *path, const output_path *op)
{
    struct stat ds;
    if (op->kind != OUTPUT_FILE || !op->exists || stat(op->dir, &ds) != 0)
        return LIMN_OK;
    uid_t me = geteuid();
    /* in a sticky directory only the owner of the file or of the directory
       (or root) may replace it: rename would fail with EPERM at the end */
    if ((ds.st_mode & S_ISVTX) && me != 0 && ds.st_uid != me && op->old_uid != me)
        return ctx_fail(ctx, LIMN_ERR_IO,
                         "cannot write %s: %s belongs to another user in the sticky directory "
                         "%s (not ours either), so it cannot be replaced",
                         path, op->target, op->dir);
    return LIMN_OK;
}

/* ------------------------------------------------------------------- lock */

/* The directory itself is what is locked: no lock file is left in the
   user's directory; -1 when it cannot be opened. */
static int open_lock(const char *dir, struct stat *sb)
{
    int fd = open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd >= 0 && fstat(fd, sb) != 0) {
        close(fd);
        fd = -1;
    }
    return fd;
}

void output_lock_dirs(const char *const *dirs, int n, int *fds)
{
    struct stat sb[OUTPUT_LOCK_MAX];
    int taken[OUTPUT_LOCK_MAX] = {0};
    if (n > OUTPUT_LOCK_MAX)
        n = OUTPUT_LOCK_MAX;
    for (int i = 0; i < n; i++) {
        fds[i] = open_lock(dirs[i], &sb[i]);
        for (int k = 0; k < i && fds[i] >= 0; k++)
            if (fds[k] >= 0 && sb[k].st_dev == sb[i].st_dev && sb[k].st_ino == sb[i].st_ino) {
                close(fds[i]); /* the same directory: one lock */
                fds[i] = -1;
            }
    }
    /* lock in (device, inode) order: two runs over the same directories
       always take them in the same order, so they cannot deadlock */
    for (;;) {
        int best = -1;
        for (int i = 0; i < n; i++)
            if (fds[i] >= 0 && !taken[i] &&
                (best < 0 || sb[i].st_dev < sb[best].st_dev ||
                 (sb[i].st_dev == sb[best].st_dev && sb[i].st_ino < sb[best].st_ino)))
                best = i;
        if (best < 0)
            break;
        while (flock(fds[best], LOCK_EX) != 0 && errno == EINTR)
            ;
        taken[best] = 1;
    }
}

void output_unlock(int *fds, int n)
{
    for (int i = 0; i < n; i++)
        if (fds[i] >= 0) {
            close(fds[i]); /* releases the flock */
            fds[i] = -1;
        }
}
