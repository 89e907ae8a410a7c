/* SPDX-License-Identifier: MIT */
/* The lines of the text formats (OBJ, OFF, ascii PLY): mesh_text_write.c. */
#ifndef LIMN_MESH_IO_TEXT_WRITE_H
#define LIMN_MESH_IO_TEXT_WRITE_H

#include "limn.h"

#include <stdint.h>
#include <stdio.h>

/* The text writers' lines. One line per vertex: lead, x y z (%.17g; single:
   of the float32 rounding, which reads back as that float exactly), and
   " r g b" when colors is not NULL (3 bytes per vertex). */
limn_status mio_write_vertices(limn_context *ctx, const limn_mesh *m, const char *path, FILE *f,
                               const char *lead, const uint8_t *colors, int single);
/* One line per face: lead, or the corner count when lead is NULL (OFF, PLY),
   then " v" for each corner, numbered from base (OBJ counts from 1). */
limn_status mio_write_faces(limn_context *ctx, const limn_mesh *m, const char *path, FILE *f,
                            const char *lead, unsigned base);

#endif
