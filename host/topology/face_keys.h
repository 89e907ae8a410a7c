/* SPDX-License-Identifier: MIT */
/*
 * What the mesh repair asks of every face, in parallel over the host
 * threads with the same result for any count: the first face that uses a
 * vertex twice, and every face's vertex-set hash sorted stably on its high
 * 32 bits (faces in increasing order among equal keys, so "earlier" is the
 * first copy of a duplicate).
 */
#ifndef LIMN_TOPOLOGY_FACE_KEYS_H
#define LIMN_TOPOLOGY_FACE_KEYS_H

#include "limn.h"

#include <stddef.h>
#include <stdint.h>

typedef struct face_key {
    uint64_t hash; /* of the sorted vertex list */
    uint32_t face;
} face_key;

/* The vertices of face f of m in increasing order, into buf (room for its
   size); *d its size. */
const uint32_t *face_sorted_vertices(const limn_mesh *m, uint32_t f, uint32_t *buf, uint32_t *d);

/* The first face using a vertex twice (*face, SIZE_MAX when none) and the
   vertex at its first repeated corner. */
limn_status face_first_repeat(limn_context *ctx, const limn_mesh *m, size_t *face,
                              uint32_t *vertex);

/* Every face's key, sorted as the file comment says, into *out (m's
   face_count of them; free() it). maxd: the largest face size. */
limn_status face_keys_sorted(limn_context *ctx, const limn_mesh *m, uint32_t maxd,
                             face_key **out);

#endif
