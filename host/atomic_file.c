/* Atomic file replacement with mkstemp + fsync + rename. */
#include "atomic_file.h"
#include "context.h"

#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static mode_t process_umask(void)
{
    mode_t m = umask(022);
    umask(m);
    return m;
}

limn_status atomic_file_open(limn_context *ctx, const char *path, atomic_file *af)
{
    memset(af, 0, sizeof *af);
    if (!path || !*path)
        return limn_fail(ctx, LIMN_ERR_ARGUMENT, "empty output file name");
    size_t len = strlen(path);
    const char *slash = strrchr(path, '/');
    size_t dir_len = slash ? (size_t)(slash - path + 1) : 0;
    af->path = malloc(len + 1);
    af->tmp_path = malloc(len + 32);
    if (!af->path || !af->tmp_path) {
        atomic_file_abort(af);
        return limn_fail(ctx, LIMN_ERR_MEMORY, "out of memory");
    }
    memcpy(af->path, path, len + 1);
    memcpy(af->tmp_path, path, dir_len);
    strcpy(af->tmp_path + dir_len, ".");
    strcat(af->tmp_path, path + dir_len);
    strcat(af->tmp_path, ".tmp.XXXXXX");
    int fd = mkstemp(af->tmp_path);
    if (fd < 0) {
        int e = errno;
        free(af->tmp_path);
        af->tmp_path = NULL;
        atomic_file_abort(af);
        return limn_fail(ctx, LIMN_ERR_IO, "%s: cannot create the output file: %s", path,
                         strerror(e));
    }
    fchmod(fd, 0666 & ~process_umask());
    af->f = fdopen(fd, "wb");
    if (!af->f) {
        int e = errno;
        close(fd);
        atomic_file_abort(af);
        return limn_fail(ctx, LIMN_ERR_IO, "%s: cannot open the output file: %s", path,
                         strerror(e));
    }
    return LIMN_OK;
}

limn_status atomic_file_commit(limn_context *ctx, atomic_file *af)
{
    int failed = ferror(af->f) || fflush(af->f) != 0 || fsync(fileno(af->f)) != 0;
    int e = errno;
    if (fclose(af->f) != 0 && !failed) {
        failed = 1;
        e = errno;
    }
    af->f = NULL;
    if (!failed && rename(af->tmp_path, af->path) != 0) {
        failed = 1;
        e = errno;
    }
    if (failed) {
        limn_status st = limn_fail(ctx, LIMN_ERR_IO, "%s: writing failed: %s; nothing was written",
                                   af->path, strerror(e ? e : EIO));
        atomic_file_abort(af);
        return st;
    }
    free(af->path);
    free(af->tmp_path);
    af->path = af->tmp_path = NULL;
    return LIMN_OK;
}

void atomic_file_abort(atomic_file *af)
{
    if (af->f)
        fclose(af->f);
    if (af->tmp_path)
        unlink(af->tmp_path);
    free(af->path);
    free(af->tmp_path);
    memset(af, 0, sizeof *af);
}
