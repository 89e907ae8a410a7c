/* SPDX-License-Identifier: MIT */
/*
 * The mesh file formats, called by the dispatcher (dispatch.c): the readers
 * (mesh_obj.c, mesh_ply.c, mesh_off.c, mesh_stl.c) and the writers
 * (mesh_text_write.c: OBJ, OFF; mesh_ply_write.c; mesh_stl_write.c).
 *
 * Readers get an open FILE* positioned at the start and the path (for
 * messages only). They return LIMN_OK and a new mesh, or a status with a
 * message "PATH:LINE: ..." (text) / "PATH: byte N: ..." (binary).
 * Writers get an open FILE* and the target path (for messages); every
 * stdio return value is checked.
 */
#ifndef LIMN_MESH_IO_FORMATS_H
#define LIMN_MESH_IO_FORMATS_H

#include "limn.h"

#include <stdio.h>

limn_status obj_read(limn_context *ctx, const char *path, FILE *f, limn_mesh **out);
limn_status ply_read(limn_context *ctx, const char *path, FILE *f, limn_mesh **out);
limn_status off_read(limn_context *ctx, const char *path, FILE *f, limn_mesh **out);
limn_status stl_read(limn_context *ctx, const char *path, FILE *f, limn_mesh **out);

limn_status obj_write(limn_context *ctx, const limn_mesh *mesh, const char *path, FILE *f);
/* format: LIMN_FORMAT_PLY (binary little endian), _PLY_ASCII or _PLY_BINARY_BE;
   single: binary positions as float32 (else double). */
limn_status ply_write(limn_context *ctx, const limn_mesh *mesh, const char *path, FILE *f,
                      limn_format format, int single);
/* The error of positions written as float32: the largest and the mean
   distance between a vertex and its float32 rounding. */
void ply_float_error(const limn_mesh *mesh, double *max_error, double *mean_error);
limn_status off_write(limn_context *ctx, const limn_mesh *mesh, const char *path, FILE *f);
/* Binary STL: faces fan-triangulated, coordinates rounded to float. */
limn_status stl_write(limn_context *ctx, const limn_mesh *mesh, const char *path, FILE *f);

#endif
