/* Files that appear whole or not at all: written under a temporary name in
   the target's directory (".NAME.tmp.XXXXXX"), synced, then renamed over the
   target; on any failure the temporary file is removed and the target is
   untouched. Used for every output limn writes (meshes, reports). */
#ifndef LIMN_ATOMIC_FILE_H
#define LIMN_ATOMIC_FILE_H

#include "limn.h"
#include <stdio.h>

typedef struct atomic_file {
    FILE *f;
    char *path;
    char *tmp_path;
    char *iobuf;
} atomic_file;

limn_status atomic_file_open(limn_context *ctx, const char *path, atomic_file *af);
/* Flushes, syncs and closes the temporary file but does not rename it, so
   that several outputs of one run can all be complete before any appears
   (then atomic_file_commit each); on failure removes the temporary file. */
limn_status atomic_file_finish(limn_context *ctx, atomic_file *af);
/* Flushes, syncs, closes (unless finished) and renames; on failure removes
   the temporary file. */
limn_status atomic_file_commit(limn_context *ctx, atomic_file *af);
/* Closes and removes the temporary file; the target is untouched. */
void atomic_file_abort(atomic_file *af);

#endif
