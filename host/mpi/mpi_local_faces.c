/* SPDX-License-Identifier: MIT */
/*
 * Local rows, the faces (mpi_local.h): the part of every corner of this
 * rank's face range, from part_of in its own vertex block and from the
 * block owners for the others, then each face to every other distinct part
 * among its vertices (mpi_local_sub.c builds the sub-mesh of what arrives
 * and of the range's own faces, read where they are).
 */
#include "mpi/mpi_local.h"
#include "base/large_alloc.h"

#include "base/context.h"
#include "mesh/mesh.h"
#include "topology/face_keys.h"

#include <limits.h>
#include <stdlib.h>

/* The distinct parts of a face's d corners (their parts cp) into parts. */
static size_t face_parts(const uint32_t *cp, uint32_t d, uint32_t *parts)
{
    size_t np = 0;
    for (uint32_t c = 0; c < d; c++) {
        int seen = 0;
        for (size_t k = 0; k < np; k++)
            seen |= parts[k] == cp[c];
        if (!seen)
            parts[np++] = cp[c];
    }
    return np;
}

typedef struct faces_in {
    size_t begin, count;
    const uint32_t *off, *idx;
} faces_in;

typedef struct faces_out {
    const faces_in *f;
    const uint32_t *corner_part;
    uint32_t *parts; /* scratch: a face's distinct parts */
    uint32_t **next; /* per part: where its next record goes */
    size_t nparts;
    uint32_t me;     /* this rank: its own faces are read in place, not sent */
    const uint32_t *cross; /* the faces with another part among their corners */
    size_t ncross;
} faces_out;

/* Every crossing face's record at the next place of each other distinct
   part among its corners, from to[part] on (mpi_local_alltoallv_packed): in
   face order within a part, as one send buffer in rank order had them. */
static void pack_faces(void *user, char *const *to)
{
    const faces_out *o = user;
    const faces_in *f = o->f;
    for (size_t r = 0; r < o->nparts; r++)
        o->next[r] = (uint32_t *)to[r];
    for (size_t j = 0; j < o->ncross; j++) {
        size_t i = o->cross[j];
        const uint32_t *v = f->idx + f->off[i], *cp = o->corner_part + f->off[i];
        uint32_t d = f->off[i + 1] - f->off[i];
        size_t np = face_parts(cp, d, o->parts);
        uint64_t id = f->begin + i;
        for (size_t k = 0; k < np; k++) {
            if (o->parts[k] == o->me)
                continue;
            uint32_t *w = o->next[o->parts[k]];
            w[0] = (uint32_t)id;
            w[1] = (uint32_t)(id >> 32);
            w[2] = d;
            for (uint32_t c = 0; c < d; c++) {
                w[3 + c] = v[c];
                w[3 + d + c] = cp[c];
            }
            o->next[o->parts[k]] = w + mpi_face_record_words(d);
        }
    }
}

/* Where each corner's part comes from (corner_parts): part_of for an id of
   this rank's block [lo, lo + nb), else its block owner's answer,
   ref_part[index[j]] for the j-th such corner in corner order. */
typedef struct part_source {
    size_t lo, nb;
    const uint32_t *part_of;
    uint32_t *ref_part, *index;
} part_source;

/* Every corner's part into cp, in the one walk over the range's faces: *mine
   (bits over the range: the faces with this rank among their corners'
   parts, which the sub-mesh's walks take without reading cp again) and
   each face to every other distinct part among its vertices (records
   above); *recv, *nrecv: the records this rank receives, *nlow the words of
   them from lower ranks. */
static limn_status send_to_parts(mpi_part *p, const faces_in *f, const part_source *ps,
                                 uint32_t *cp, uint64_t **mine, uint32_t **recv, size_t *nrecv,
                                 size_t *nlow)
{
    size_t R = (size_t)p->size, maxd = 0;
    uint32_t me = (uint32_t)p->rank;
    for (size_t i = 0; i < f->count; i++)
        maxd = f->off[i + 1] - f->off[i] > maxd ? f->off[i + 1] - f->off[i] : maxd;
    int *cnt = calloc(2 * R, sizeof *cnt), *rcnt = cnt + R;
    size_t *words = calloc(R, sizeof *words), nwords = (f->count + 63) / 64;
    /* pages past the crossing faces' count never touched */
    uint32_t *cross = large_malloc((f->count ? f->count : 1) * sizeof *cross);
    uint64_t *bits = large_malloc((nwords ? nwords : 1) * sizeof *bits);
    faces_out o = {f, cp, large_malloc((maxd ? maxd : 1) * sizeof(uint32_t)),
                   large_malloc(R * sizeof(uint32_t *)), R, me, cross, 0};
    limn_status st = LIMN_OK;
    if (!cnt || !words || !o.parts || !o.next || !cross || !bits)
        st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory sending faces");
    /* a word's 64 faces at a time: their corners' parts in a loop of their
       own (independent loads, many in flight), then the faces, cp in cache */
    for (size_t w = 0, j = 0; !st && w < nwords; w++) {
        size_t first = 64 * w, last = first + 64 < f->count ? first + 64 : f->count;
        for (uint32_t c = f->off[first]; c < f->off[last]; c++) {
            size_t v = f->idx[c] - ps->lo; /* wraps above nb below the block */
            cp[c] = v < ps->nb ? ps->part_of[v] : ps->ref_part[ps->index[j++]];
        }
        uint64_t word = 0;
        for (size_t i = first; i < last; i++) {
            uint32_t b = f->off[i], e = f->off[i + 1], other = 0;
            for (uint32_t c = b; c < e; c++)
                other |= cp[c] ^ me;
            int keep = other == 0; /* the usual face: all corners here, sent nowhere */
            if (!keep) {
                cross[o.ncross++] = (uint32_t)i;
                size_t np = face_parts(cp + b, e - b, o.parts);
                for (size_t k = 0; k < np; k++) {
                    words[o.parts[k]] += mpi_face_record_words(e - b);
                    keep |= o.parts[k] == me;
                }
            }
            word |= (uint64_t)keep << (i - first);
        }
        bits[w] = word;
    }
    if (!st)
        words[me] = 0; /* read in place (mpi_local_sub.c) */
    for (size_t r = 0; !st && r < R; r++) /* too many: the exchange's plan refuses */
        cnt[r] = words[r] > INT_MAX ? INT_MAX : (int)words[r];
    st = mpi_agree(p, st);
    void *got = NULL;
    if (!st)
        st = mpi_local_alltoallv_packed(p, cnt, sizeof(uint32_t), pack_faces, &o, &got, rcnt,
                                        nrecv);
    *nlow = 0;
    for (size_t r = 0; !st && r < me; r++)
        *nlow += (size_t)rcnt[r];
    *recv = got;
    if (st) {
        free(bits);
        bits = NULL;
    }
    *mine = bits;
    free(cross);
    free(cnt);
    free(words);
    free(o.parts);
    free(o.next);
    return st;
}

/* With repair off, limn_mesh_repair's refusal of the first face that uses a
   vertex twice, in input numbering (the lowest failing rank's message is the
   one every rank gets: with face ranges in rank order, the first face). */
static limn_status refuse_repeats(mpi_part *p, const faces_in *f, size_t vertex_total)
{
    limn_mesh view = {.vertex_count = vertex_total,
                      .face_count = f->count,
                      .face_offsets = (uint32_t *)f->off,
                      .face_indices = (uint32_t *)f->idx};
    size_t first = SIZE_MAX;
    uint32_t v = 0;
    limn_status st = face_first_repeat(p->ctx, &view, &first, &v);
    if (st || first == SIZE_MAX)
        return st;
    return ctx_fail(p->ctx, LIMN_ERR_TOPOLOGY,
                    "face %zu uses vertex %u twice (a degenerate face) and repair is off: "
                    "remove the face, or allow the repair (drop --no-repair)",
                    f->begin + first, v);
}

/* The corners' ids outside this rank's vertex block [lo, lo + nb), in
   corner order (*far, *nfar; NULL when none), after the checks of every
   face's size and ids (a message naming the face). */
static limn_status far_corners(mpi_part *p, const faces_in *f, size_t lo, size_t nb,
                               size_t vertex_total, uint32_t **far, size_t *nfar)
{
    size_t nc = f->off[f->count], n = 0;
    uint32_t *x = large_malloc((nc ? nc : 1) * sizeof *x); /* pages past n never touched */
    *far = NULL;
    *nfar = 0;
    if (!x)
        return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu face corners", nc);
    for (size_t i = 0; i < f->count; i++) {
        uint32_t b = f->off[i], e = f->off[i + 1];
        if (e < b + 3) {
            free(x);
            return ctx_fail(p->ctx, LIMN_ERR_ARGUMENT,
                            "face %zu has %ld vertices (at least 3 needed)", f->begin + i,
                            (long)e - (long)b);
        }
        uint32_t worst = 0;
        for (uint32_t c = b; c < e; c++) {
            uint32_t v = f->idx[c];
            worst = v > worst ? v : worst;
            x[n] = v;
            n += v - lo >= nb; /* unsigned: below lo wraps above nb */
        }
        if (worst >= vertex_total) {
            uint32_t c = b;
            while (f->idx[c] < vertex_total)
                c++;
            free(x);
            return ctx_fail(p->ctx, LIMN_ERR_ARGUMENT,
                            "face %zu uses vertex %u but there are %zu vertices", f->begin + i,
                            f->idx[c], vertex_total);
        }
    }
    *far = x;
    *nfar = n;
    return LIMN_OK;
}

/* Where the part of every face corner comes from (*ps, its arrays the
   caller's to free with part_source_free): part_of for a vertex of this
   rank's block, the block owner's answer for the distinct others (fetched
   once each); checked first: each part is a rank, each face has 3 or more
   vertices below the total, and, with repair off, none repeats a vertex. */
static limn_status corner_parts(mpi_part *p, local_sub *s, const size_t *vtxdist,
                                const uint32_t *part_of, const faces_in *f,
                                const limn_repair_options *repair, part_source *ps)
{
    size_t lo = vtxdist[p->rank], nb = vtxdist[p->rank + 1] - lo;
    size_t bad = SIZE_MAX, nfar = 0, nref = 0;
    *ps = (part_source){lo, nb, part_of, NULL, NULL};
    for (size_t i = 0; i < nb && bad == SIZE_MAX; i++)
        if (part_of[i] >= (uint32_t)p->size)
            bad = i;
    limn_status st = bad == SIZE_MAX
                         ? LIMN_OK
                         : ctx_fail(p->ctx, LIMN_ERR_ARGUMENT,
                                    "vertex %zu is given to part %u but there are %d ranks",
                                    lo + bad, part_of[bad], p->size);
    uint32_t *far = NULL, *ref = NULL;
    if (!st)
        st = far_corners(p, f, lo, nb, vtxdist[p->size], &far, &nfar);
    if (!st && repair && !repair->repeated_vertices)
        st = refuse_repeats(p, f, vtxdist[p->size]);
    if (!st) {
        ps->index = large_malloc((nfar ? nfar : 1) * sizeof *ps->index);
        ref = large_malloc((nfar ? nfar : 1) * sizeof *ref);
        st = ps->index && ref ? mpi_local_distinct(p->ctx, far, nfar, ref, &nref, ps->index)
                              : ctx_fail(p->ctx, LIMN_ERR_MEMORY,
                                         "out of memory for %zu face corners", nfar);
    }
    free(far);
    if (!st && !(ps->ref_part = large_malloc((nref ? nref : 1) * sizeof *ps->ref_part)))
        st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu vertices", nref);
    mpi_local_note(s, nref);
    st = mpi_agree(p, st);
    if (!st)
        st = mpi_local_fetch(p, s, vtxdist, ref, nref, part_of, sizeof(uint32_t), ps->ref_part);
    free(ref);
    return st;
}

static void part_source_free(part_source *ps)
{
    free(ps->index);
    free(ps->ref_part);
    ps->index = ps->ref_part = NULL;
}

limn_status mpi_local_send_faces(mpi_part *p, local_sub *s, const size_t *vtxdist,
                                 const uint32_t *part_of, size_t face_begin, size_t face_count,
                                 const uint32_t *face_offsets, const uint32_t *face_indices,
                                 const limn_repair_options *repair, uint32_t **corner_part,
                                 uint64_t **mine, uint32_t **recv, size_t *nrecv, size_t *nlow)
{
    faces_in f = {face_begin, face_count, face_offsets, face_indices};
    size_t nc = face_offsets[face_count];
    part_source ps;
    *recv = NULL;
    *nrecv = *nlow = 0;
    *mine = NULL;
    *corner_part = NULL;
    limn_status st = corner_parts(p, s, vtxdist, part_of, &f, repair, &ps);
    uint32_t *cp = NULL;
    if (!st && !(cp = large_malloc((nc ? nc : 1) * sizeof *cp)))
        st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu face corners", nc);
    st = mpi_agree(p, st);
    if (!st)
        st = send_to_parts(p, &f, &ps, cp, mine, recv, nrecv, nlow);
    part_source_free(&ps);
    if (st) {
        free(cp);
        cp = NULL;
    }
    *corner_part = cp;
    return st;
}
