/* SPDX-License-Identifier: MIT */
/* The mesh files' entry points beyond the public ones (dispatch.c). */
#ifndef LIMN_MESH_IO_DISPATCH_H
#define LIMN_MESH_IO_DISPATCH_H

#include "limn.h"

/* limn_mesh_write's checks of its format and options: *format (AUTO: from
   path's extension) resolved, a float precision refused but for PLY. */
limn_status mesh_write_format(limn_context *ctx, const char *path,
                              const limn_write_options *options, limn_format *format);

/* limn_mesh_write without the final rename: the mesh is complete and synced
   in af's temporary file; atomic_file_commit makes it appear, _abort drops
   it. Lets a command finish all its outputs before any of them appears.
   options and report are the library-side copies (abi.h), never NULL. */
struct atomic_file;
limn_status mesh_write_staged(limn_context *ctx, const limn_mesh *mesh, const char *path,
                              limn_format format, const limn_write_options *options,
                              limn_write_report *report, struct atomic_file *af);

#endif
