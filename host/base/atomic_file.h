/* SPDX-License-Identifier: MIT */
/* Files that appear whole or not at all: a regular output is written under a
   temporary name beside its target (".NAME.limn-tmp.PID.XXXXXX", the target
   being the file a symlink chain names), synced, then renamed over it; on
   any failure the temporary file is removed and the target is untouched.
   Standard output ("-"), a FIFO or a character device cannot be replaced:
   their bytes are kept in an unlinked buffer file and written straight
   through only at commit, after every regular output of the set is in
   place. Used for every output limn writes (meshes, reports, pictures). */
#ifndef LIMN_ATOMIC_FILE_H
#define LIMN_ATOMIC_FILE_H

#include "limn.h"
#include "base/output_path.h"
#include <stdio.h>

typedef struct atomic_file {
    FILE *f;
    char *path;     /* as given (messages) */
    char *tmp_path; /* the temporary beside the target (regular outputs) */
    char *iobuf;
    output_path out;
} atomic_file;

/* Before any work: refuses an output that atomic_file_open or the final
   rename would refuse (see output_path_resolve, output_check_rename, a
   directory where no temporary file can be made; a closed standard output). */
limn_status atomic_file_check(limn_context *ctx, const char *path);
limn_status atomic_file_open(limn_context *ctx, const char *path, atomic_file *af);
/* Flushes, syncs and closes the temporary file but does not rename it, so
   that several outputs of one run can all be complete before any appears
   (then atomic_file_commit_all); on failure removes the temporary file. */
limn_status atomic_file_finish(limn_context *ctx, atomic_file *af);
/* Makes n staged outputs appear: finishes them, renames the regular ones in
   order (under a flock of their directories when there are several, so that
   concurrent runs never interleave their sets), then writes the
   straight-through ones. Drops the rest after a failure; returns the first. */
limn_status atomic_file_commit_all(limn_context *ctx, atomic_file *af, int n);
/* atomic_file_commit_all of one file. */
limn_status atomic_file_commit(limn_context *ctx, atomic_file *af);
/* Closes and removes the temporary file; the target is untouched. */
void atomic_file_abort(atomic_file *af);

#endif
