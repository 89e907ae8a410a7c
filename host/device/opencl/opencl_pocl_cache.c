/* SPDX-License-Identifier: MIT */
/*
 * PoCL's kernel cache directory, checked when OpenCL finds no device or a
 * build fails: PoCL 3.1 drops its devices when it cannot create the cache
 * (an unwritable HOME gives "no device", not a message about the cache).
 * PoCL's rule: POCL_CACHE_DIR, else $XDG_CACHE_HOME/pocl/kcache, else
 * $HOME/.cache/pocl/kcache.
 */
#include "device/opencl/opencl_pocl_cache.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* mkdir -p; 0 or an errno value. */
static int make_dirs(char *path)
{
    for (char *s = path + 1;; s++) {
        if (*s != '/' && *s != '\0')
            continue;
        char saved = *s;
        *s = '\0';
        int bad = mkdir(path, 0755) != 0 && errno != EEXIST;
        int err = errno;
        *s = saved;
        if (bad)
            return err;
        if (!saved)
            break;
    }
    struct stat st;
    if (stat(path, &st) != 0)
        return errno;
    return S_ISDIR(st.st_mode) ? 0 : ENOTDIR;
}

int opencl_pocl_cache_problem(char *why, size_t size)
{
    const char *env = getenv("POCL_CACHE_DIR"), *xdg = getenv("XDG_CACHE_HOME");
    const char *home = getenv("HOME");
    char dir[1024];
    if (env && *env)
        snprintf(dir, sizeof dir, "%s", env);
    else if (xdg && *xdg)
        snprintf(dir, sizeof dir, "%s/pocl/kcache", xdg);
    else if (home && *home)
        snprintf(dir, sizeof dir, "%s/.cache/pocl/kcache", home);
    else
        return 0; /* PoCL then uses no cache */
    /* create it as PoCL would, then a file in it: root passes access(W_OK)
       checks that a real write fails */
    char path[1024 + 16];
    snprintf(path, sizeof path, "%s", dir);
    int err = make_dirs(path);
    if (!err) {
        snprintf(path, sizeof path, "%s/limn_XXXXXX", dir);
        int fd = mkstemp(path);
        if (fd < 0) {
            err = errno;
        } else {
            close(fd);
            unlink(path);
        }
    }
    if (!err)
        return 0;
    snprintf(why, size,
             "PoCL's kernel cache directory %s (%s) is not writable (%s): set POCL_CACHE_DIR "
             "to a writable directory",
             dir,
             env && *env ? "POCL_CACHE_DIR" : xdg && *xdg ? "from XDG_CACHE_HOME" : "from HOME",
             strerror(err));
    return 1;
}
