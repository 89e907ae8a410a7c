/* SPDX-License-Identifier: MIT */
/*
 * What the mesh repair asks of every face, in parallel over the host
 * threads with the same result for any count: the first face that uses a
 * vertex twice, and the faces with the vertex set of an earlier face.
 */
#ifndef LIMN_TOPOLOGY_FACE_KEYS_H
#define LIMN_TOPOLOGY_FACE_KEYS_H

#include "limn.h"

#include <stddef.h>
#include <stdint.h>

/* What the duplicate search found: how many faces have the vertex set of an
   earlier face, the first of them (SIZE_MAX when none) and the earliest face
   it copies. */
typedef struct face_duplicates {
    size_t count, first, first_of;
} face_duplicates;

/* The vertices of face f of m in increasing order, into buf (room for its
   size); *d its size. */
const uint32_t *face_sorted_vertices(const limn_mesh *m, uint32_t f, uint32_t *buf, uint32_t *d);

/* The first face using a vertex twice (*face, SIZE_MAX when none) and the
   vertex at its first repeated corner. */
limn_status face_first_repeat(limn_context *ctx, const limn_mesh *m, size_t *face,
                              uint32_t *vertex);

/* Marks in dup (face_count bytes, zeroed) every face with the vertex set of
   an earlier face; maxd: the largest face size. */
limn_status face_find_duplicates(limn_context *ctx, const limn_mesh *m, uint32_t maxd,
                                 uint8_t *dup, face_duplicates *out);

/* How many searches face_find_duplicates has run in this process (for
   tests: whether a repair skipped its search). */
size_t face_duplicate_search_count(void);

/* face_find_duplicates with the marks allocated here (*dup: face_count
   bytes, caller frees; NULL when there are fewer than 2 faces). */
limn_status face_duplicates_marked(limn_context *ctx, const limn_mesh *m, uint8_t **dup,
                                   face_duplicates *out);

#endif
