/* SPDX-License-Identifier: MIT */
/* Test-only minimal Wavefront OBJ reader: `v x y z` and `f a b c ...` lines
 * (index forms a, a/b, a/b/c, a//c; negative = relative indices). Every other
 * line (vt, vn, g, s, o, usemtl, mtllib, t, comments, ...) is skipped.
 * Independent of limn's own reader. */
#ifndef LIMN_TEST_OBJ_MINI_H
#define LIMN_TEST_OBJ_MINI_H

#include <stddef.h>

typedef struct obj_mini_mesh {
    int nverts;
    double *pos;        /* 3*nverts */
    int nfaces;
    int *face_sizes;    /* nfaces */
    int *face_indices;  /* sum(face_sizes), 0-based */
} obj_mini_mesh;

/* Returns 0 on success (free with obj_mini_free), non-zero with a message. */
int obj_mini_read(const char *path, obj_mini_mesh *m, char *err, size_t errlen);
void obj_mini_free(obj_mini_mesh *m);

#endif
