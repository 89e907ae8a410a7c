/* SPDX-License-Identifier: MIT */
/*
 * The faces a rank's sub-mesh is built from (mpi_local_sub.c): the records
 * the other ranks sent (mpi_local_send_faces) and the faces of this rank's
 * own range with this rank among their corners' parts, read where the
 * reader left them rather than packed as records for itself (at 2 ranks
 * about 95% of a rank's faces: the copy, its pages and a walk saved, and a
 * rank's own faces no longer count against one MPI call's 2 GiB).
 *
 * The walk order is the records from lower ranks, the own faces, the records
 * from higher ranks: increasing face id when the ranks' face ranges follow
 * each other (the readers' slices), as the received records of every rank
 * were before. A face is named by a tag: a record's first word, or
 * FACE_OWN | its index in the own range.
 */
#ifndef LIMN_MPI_FACE_SOURCE_H
#define LIMN_MPI_FACE_SOURCE_H

#include "mpi/mpi_local.h"

#include <limits.h>
#include <stdint.h>

#define FACE_OWN ((size_t)1 << (sizeof(size_t) * CHAR_BIT - 1))

/* The walks call face_next once a face (millions a rank): left to itself,
   GCC made it a call, about a sixth of the sub-mesh's build. */
#if defined(__GNUC__)
#define FACE_INLINE static inline __attribute__((always_inline))
#else
#define FACE_INLINE static inline
#endif

typedef struct face_source {
    uint32_t *w;               /* received records: words [0, nlow) from lower ranks */
    size_t nlow, nw;
    size_t begin, count;       /* the own range: faces [begin, begin + count) */
    const uint32_t *off, *idx; /* its CSR (global vertex ids) */
    uint32_t *cp;              /* the part of each of its corners */
    uint64_t *mine;            /* a bit per own face: this rank among its parts */
    uint32_t me;
} face_source;

/* One face: its id, corners, global vertex ids and their parts (writable:
   mpi_local_sub.c may put the sub-mesh indices there once read). */
typedef struct face_view {
    uint64_t id;
    uint32_t d;
    const uint32_t *v;
    uint32_t *part;
} face_view;

FACE_INLINE void face_view_at(const face_source *s, size_t tag, face_view *f)
{
    if (tag & FACE_OWN) {
        size_t i = tag & ~FACE_OWN;
        f->id = s->begin + i;
        f->d = s->off[i + 1] - s->off[i];
        f->v = s->idx + s->off[i];
        f->part = s->cp + s->off[i];
    } else {
        uint32_t *r = s->w + tag;
        f->id = (uint64_t)r[0] | (uint64_t)r[1] << 32;
        f->d = r[2];
        f->v = r + 3;
        f->part = r + 3 + r[2];
    }
}

/* A walk's place: seg 0 the lower records, 1 the own faces, 2 the higher
   records; at the word or the own face next. */
typedef struct face_cursor {
    int seg;
    size_t at;
} face_cursor;

#define FACE_CURSOR_START ((face_cursor){0, 0})

/* The next face of the walk into *f (its tag in *tag); 0 after the last.
   An own face is taken when one of its corners' parts is this rank: its bit
   in mine, set before the faces' parts may be overwritten (each face's own
   slots), a word of faces skipped at once when none is left in it. */
FACE_INLINE int face_next(const face_source *s, face_cursor *c, face_view *f, size_t *tag)
{
    for (;;) {
        if (c->seg == 1) {
            while (c->at < s->count) {
                size_t i = c->at++;
                uint64_t rest = s->mine[i >> 6] >> (i & 63);
                if (rest & 1) {
                    *tag = i | FACE_OWN;
                    face_view_at(s, *tag, f);
                    return 1;
                }
                if (!rest) /* none of this word's later faces */
                    c->at = (i | 63) + 1;
            }
            c->seg = 2;
            c->at = s->nlow;
        }
        size_t end = c->seg == 0 ? s->nlow : s->nw;
        if (c->at < end) {
            *tag = c->at;
            face_view_at(s, c->at, f);
            c->at += mpi_face_record_words(f->d);
            return 1;
        }
        if (c->seg == 2)
            return 0;
        c->seg = 1;
        c->at = 0;
    }
}

#endif
