/* SPDX-License-Identifier: MIT */
/* Where an output really goes (README "Command line", output rules): "-" is
   standard output; a FIFO or a character device is written straight through;
   a symlink chain is followed to the file it names, which is the one
   replaced; a directory or another kind of file is refused. Also the names
   of temporary files (".NAME.limn-tmp.PID.XXXXXX"), the removal of stale
   ones, and the lock that serialises the renames of a set of outputs. */
#ifndef LIMN_OUTPUT_PATH_H
#define LIMN_OUTPUT_PATH_H

#include "limn.h"

#include <sys/types.h>

typedef enum output_kind {
    OUTPUT_FILE,   /* a regular file (existing or not): replaced by rename */
    OUTPUT_STDOUT, /* "-" or /dev/stdout: file descriptor 1 */
    OUTPUT_DEVICE  /* a FIFO or a character device: opened and written */
} output_kind;

typedef struct output_path {
    output_kind kind;
    char *target;   /* OUTPUT_FILE / _DEVICE: path with its symlinks resolved */
    char *dir;      /* OUTPUT_FILE: target's directory ("." when none), no trailing '/' */
    const char *base; /* OUTPUT_FILE: target's last component (inside target) */
    long name_max;  /* OUTPUT_FILE: NAME_MAX of dir */
    int exists;     /* OUTPUT_FILE: target exists; then the file replaced has: */
    mode_t old_mode;
    uid_t old_uid;
    gid_t old_gid;
} output_path;

/* Is this path standard output ("-", /dev/stdout, /dev/fd/1, /proc/self/fd/1)? */
int output_is_stdout(const char *path);
/* Classifies path and resolves its symlinks; refuses a directory, another
   kind of special file, a link loop, a name over the directory's NAME_MAX.
   Messages name path. On success free with output_path_free. */
limn_status output_path_resolve(limn_context *ctx, const char *path, output_path *op);
void output_path_free(output_path *op);
/* The mkstemp template for a temporary beside op's target:
   DIR/.BASE.limn-tmp.PID.XXXXXX, BASE cut so that the name fits NAME_MAX.
   Returns NULL when out of memory; caller frees. */
char *output_temp_template(const output_path *op);
/* Removes the temporary files of op's target left by processes that no
   longer exist (.BASE.limn-tmp.PID.SUFFIX, SUFFIX letters and digits, a
   regular file, PID dead); never one of a live process or another name. */
void output_remove_stale(const output_path *op);
/* Refuses (before any work) a replacement that the final rename would not
   be allowed to make: a sticky directory owned by someone else holding a
   target owned by someone else. */
limn_status output_check_rename(limn_context *ctx, const char *path, const output_path *op);

/* flock(LOCK_EX) on each distinct directory (the directory itself: no lock
   file is created), in (device, inode) order so that two runs cannot
   deadlock. fds gets n descriptors (-1 unused; n at most OUTPUT_LOCK_MAX);
   output_unlock closes them. Best effort: a directory that cannot be opened
   or locked is skipped. */
#define OUTPUT_LOCK_MAX 16
void output_lock_dirs(const char *const *dirs, int n, int *fds);
void output_unlock(int *fds, int n);

#endif
