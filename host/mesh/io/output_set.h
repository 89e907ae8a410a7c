/* SPDX-License-Identifier: MIT */
/* An output set's entry points beyond the public ones (output_set.c): for a
   writer that stages a file itself (the MPI layer's parallel write) and
   hands it to a set, to appear with the set's other outputs. */
#ifndef LIMN_MESH_IO_OUTPUT_SET_H
#define LIMN_MESH_IO_OUTPUT_SET_H

#include "limn.h"
#include "base/atomic_file.h"

/* Room in set for one more output (grown when needed), before the work of
   staging it; refuses (naming fn) a NULL set, an empty path, a set at its
   limit or no memory to grow it. */
limn_status output_set_room(limn_context *ctx, const char *fn, limn_output_set *set,
                            const char *path);
/* Takes af over (a finished, staged output: atomic_file_finish done, not
   committed); af is left empty. The set must have room (output_set_room). */
void output_set_adopt(limn_output_set *set, atomic_file *af);

#endif
