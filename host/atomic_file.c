/* Atomic file replacement: mkstemp + fsync + rename (+ fsync of the directory). */
#include "atomic_file.h"
#include "context.h"

#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
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
    return limn_fail(ctx, LIMN_ERR_IO, "cannot write %s: %s", path, e ? strerror(e) : "write error");
}

limn_status atomic_file_open(limn_context *ctx, const char *path, atomic_file *af)
{
    memset(af, 0, sizeof *af);
    if (!path || !*path)
        return limn_fail(ctx, LIMN_ERR_ARGUMENT, "empty output file name");
    const char *slash = strrchr(path, '/');
    const char *base = slash ? slash + 1 : path;
    if (!*base || strcmp(base, ".") == 0 || strcmp(base, "..") == 0)
        return limn_fail(ctx, LIMN_ERR_ARGUMENT, "cannot write %s: it names a directory", path);
    size_t dirlen = slash ? (size_t)(slash - path) + 1 : 0; /* keeps the '/' */
    size_t baselen = strlen(base);
    if (baselen > 200)
        baselen = 200; /* keep the temporary name within NAME_MAX */
    const char suffix[] = ".tmp.XXXXXX";
    af->path = strdup(path);
    af->tmp_path = malloc(dirlen + 1 + baselen + sizeof suffix);
    if (!af->path || !af->tmp_path) {
        atomic_file_abort(af);
        return limn_fail(ctx, LIMN_ERR_MEMORY, "out of memory");
    }
    memcpy(af->tmp_path, path, dirlen);
    af->tmp_path[dirlen] = '.';
    memcpy(af->tmp_path + dirlen + 1, base, baselen);
    memcpy(af->tmp_path + dirlen + 1 + baselen, suffix, sizeof suffix);
    int fd = mkstemp(af->tmp_path);
    if (fd < 0) {
        int e = errno;
        free(af->tmp_path);
        af->tmp_path = NULL; /* nothing to remove */
        atomic_file_abort(af);
        if (dirlen)
            return limn_fail(ctx, LIMN_ERR_IO,
                             "cannot write %s: cannot create a temporary file in %.*s: %s", path,
                             (int)dirlen, path, strerror(e));
        return limn_fail(ctx, LIMN_ERR_IO,
                         "cannot write %s: cannot create a temporary file in the current "
                         "directory: %s",
                         path, strerror(e));
    }
    if (fchmod(fd, 0666 & ~current_umask()) != 0 || !(af->f = fdopen(fd, "wb"))) {
        int e = errno;
        if (!af->f)
            close(fd);
        atomic_file_abort(af);
        return write_failed(ctx, path, e);
    }
    af->iobuf = malloc(ATOMIC_FILE_BUFFER);
    if (af->iobuf)
        setvbuf(af->f, af->iobuf, _IOFBF, ATOMIC_FILE_BUFFER);
    return LIMN_OK;
}

limn_status atomic_file_finish(limn_context *ctx, atomic_file *af)
{
    if (!af->f)
        return LIMN_OK;
    limn_status st = LIMN_OK;
    if (fflush(af->f) != 0 || ferror(af->f) || fsync(fileno(af->f)) != 0)
        st = write_failed(ctx, af->path, errno);
    FILE *closing = af->f;
    af->f = NULL;
    if (fclose(closing) != 0 && !st)
        st = write_failed(ctx, af->path, errno);
    if (st)
        atomic_file_abort(af);
    return st;
}

limn_status atomic_file_commit(limn_context *ctx, atomic_file *af)
{
    limn_status st = atomic_file_finish(ctx, af);
    if (st)
        return st;
    if (rename(af->tmp_path, af->path) != 0)
        st = limn_fail(ctx, LIMN_ERR_IO, "cannot write %s: cannot rename %s over it: %s",
                       af->path, af->tmp_path, strerror(errno));
    if (st) {
        atomic_file_abort(af);
        return st;
    }
    /* make the rename durable; a failure here does not undo the write */
    const char *slash = strrchr(af->path, '/');
    if (slash)
        af->path[slash - af->path + 1] = '\0';
    int dfd = open(slash ? af->path : ".", O_RDONLY);
    if (dfd >= 0) {
        (void)fsync(dfd);
        close(dfd);
    }
    free(af->tmp_path);
    af->tmp_path = NULL; /* renamed: nothing to remove */
    atomic_file_abort(af);
    return LIMN_OK;
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
    memset(af, 0, sizeof *af);
}
