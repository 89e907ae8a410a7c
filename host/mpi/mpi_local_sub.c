/* SPDX-License-Identifier: MIT */
/*
 * Local rows, the sub-mesh (mpi_local.h): the faces sent to every part
 * among their vertices (mpi_local_faces.c), owned vertices from their block
 * owners, and the repaired sub-mesh of every face at an owned vertex
 * (mpi_local_mesh), which mpi_local.c turns into rows and the repair's
 * census reads (mpi_local_census.c).
 */
#include "mpi/mpi_local.h"
#include "base/large_alloc.h"

#include "base/context.h"
#include "mesh/mesh.h"
#include "topology/face_keys.h"

#include <stdlib.h>
#include <string.h>

/* The owned vertices (global ids, increasing) from the block owners. */
static limn_status owned_ids(mpi_part *p, local_sub *s, const size_t *vtxdist,
                             const uint32_t *part_of, uint32_t **owned, size_t *n_owned)
{
    size_t R = (size_t)p->size, nb = vtxdist[p->rank + 1] - vtxdist[p->rank];
    int *cnt = calloc(2 * R, sizeof *cnt);
    size_t *at = calloc(R + 1, sizeof *at);
    uint32_t *buf = large_malloc((nb ? nb : 1) * sizeof *buf);
    limn_status st = cnt && at && buf ? LIMN_OK
                                      : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory");
    for (size_t i = 0; !st && i < nb; i++)
        at[part_of[i] + 1]++;
    for (size_t r = 0; !st && r < R; r++) {
        cnt[r] = (int)at[r + 1];
        at[r + 1] += at[r];
    }
    for (size_t i = 0; !st && i < nb; i++)
        buf[at[part_of[i]]++] = (uint32_t)(vtxdist[p->rank] + i);
    st = mpi_agree(p, st);
    void *got = NULL;
    if (!st)
        st = mpi_local_alltoallv(p, buf, cnt, sizeof(uint32_t), &got, cnt + R, n_owned);
    mpi_local_note(s, *n_owned);
    *owned = got;
    free(cnt);
    free(at);
    free(buf);
    return st;
}

typedef struct face_rec {
    uint64_t id;
    size_t at; /* word of its record */
} face_rec;

static int cmp_rec(const void *a, const void *b)
{
    uint64_t x = ((const face_rec *)a)->id, y = ((const face_rec *)b)->id;
    return x < y ? -1 : x > y;
}

static uint64_t record_id(const uint32_t *w, size_t at)
{
    return (uint64_t)w[at] | (uint64_t)w[at + 1] << 32;
}

/* What one walk over the received records tells: their faces, corners,
   the range of their vertex ids (lo > hi when there are none) and whether
   a face may use a vertex twice (0: none does; faces of more than 16
   corners are left to face_first_repeat). */
typedef struct records_span {
    size_t nf, nc;
    uint32_t lo, hi;
    int may_repeat;
} records_span;

/* The received face records, in increasing face id (*recs, span); *recs
   NULL when they came in that order (usually: the senders' face ranges
   follow each other), which the readers walk as they are (record_next). */
static limn_status sort_records(mpi_part *p, const uint32_t *w, size_t nw, face_rec **recs,
                                records_span *span)
{
    size_t n = 0, nc = 0;
    uint32_t lo = UINT32_MAX, hi = 0;
    int sorted = 1, repeat = 0;
    for (size_t at = 0, last = 0; at < nw; last = at, at += mpi_face_record_words(w[at + 2])) {
        sorted &= n == 0 || record_id(w, last) < record_id(w, at);
        n++;
        uint32_t d = w[at + 2];
        const uint32_t *v = w + at + 3;
        nc += d;
        for (uint32_t c = 0; c < d; c++) {
            lo = v[c] < lo ? v[c] : lo;
            hi = v[c] > hi ? v[c] : hi;
        }
        if (d == 3) /* the usual face, without a loop */
            repeat |= (v[0] == v[1]) | (v[1] == v[2]) | (v[0] == v[2]);
        else if (d > 16)
            repeat = 1;
        else
            for (uint32_t c = 0; c < d; c++)
                for (uint32_t c2 = c + 1; c2 < d; c2++)
                    repeat |= v[c] == v[c2];
    }
    *span = (records_span){n, nc, lo, hi, repeat};
    *recs = NULL;
    if (sorted)
        return LIMN_OK;
    face_rec *r = large_malloc((n ? n : 1) * sizeof *r);
    if (!r)
        return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu faces", n);
    n = 0;
    for (size_t at = 0; at < nw; at += mpi_face_record_words(w[at + 2]))
        r[n++] = (face_rec){record_id(w, at), at};
    qsort(r, n, sizeof *r, cmp_rec);
    *recs = r;
    return LIMN_OK;
}

/* The word of record i in increasing face id: from recs, or (recs NULL,
   the records in order) the next one after *at. */
static size_t record_next(const uint32_t *w, const face_rec *recs, size_t i, size_t *at)
{
    if (recs)
        return recs[i].at;
    size_t here = *at;
    *at += mpi_face_record_words(w[here + 2]);
    return here;
}

/* sub_vertices by the ids' ranks (mpi_id_rank: no list of every corner,
   no sort); 0 when out of memory for the bitmap (nothing changed then). */
static int sub_vertices_ranked(mpi_part *p, local_sub *s, const uint32_t *own, size_t n_own,
                               uint32_t *w, size_t nw, uint32_t lo, uint32_t hi, uint32_t *out,
                               limn_status *st)
{
    mpi_id_rank r;
    if (!mpi_id_rank_init(&r, lo, hi))
        return 0;
    for (size_t i = 0; i < n_own; i++)
        mpi_id_rank_add(&r, own[i]);
    for (size_t at = 0; at < nw; at += mpi_face_record_words(w[at + 2]))
        for (uint32_t c = 0, d = w[at + 2]; c < d; c++)
            mpi_id_rank_add(&r, w[at + 3 + c]);
    size_t k = mpi_id_rank_finish(&r);
    s->ids = large_malloc((k ? k : 1) * sizeof *s->ids);
    s->part = large_malloc((k ? k : 1) * sizeof *s->part);
    s->owned = large_malloc((n_own ? n_own : 1) * sizeof *s->owned);
    *st = s->ids && s->part && s->owned
              ? LIMN_OK
              : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for the sub-mesh");
    if (!*st) {
        mpi_id_rank_list(&r, s->ids);
        for (size_t at = 0, n = 0; at < nw; at += mpi_face_record_words(w[at + 2]))
            for (uint32_t c = 0, d = w[at + 2]; c < d; c++, n++) {
                uint32_t i = mpi_id_rank_of(&r, w[at + 3 + c]);
                s->part[i] = w[at + 3 + d + c]; /* the same for every copy */
                if (out)
                    out[n] = i;
                else
                    w[at + 3 + d + c] = i;
            }
        /* own increases: so do their places, the owned rows' order */
        for (size_t i = 0; i < n_own; i++) {
            s->owned[i] = mpi_id_rank_of(&r, own[i]);
            s->part[s->owned[i]] = (uint32_t)p->rank;
        }
        s->n = k;
        s->n_owned = n_own;
        mpi_local_note(s, k);
    }
    mpi_id_rank_free(&r);
    return 1;
}

/* The sub-mesh's vertices: owned ones (own, increasing) and those of the
   received faces (span: sort_records'), increasing, each with its part
   (s->ids, s->part, s->owned). Each corner's vertex's sub-mesh index then
   goes to out (in the records' order), or without out over the corner's
   part word in w. By the ranks of a bitmap when the ids' range is at most
   32 times their count (mpi_local_distinct's rule), else through
   mpi_local_distinct. */
static limn_status sub_vertices(mpi_part *p, local_sub *s, const uint32_t *own, size_t n_own,
                                uint32_t *w, size_t nw, const records_span *span, uint32_t *out)
{
    size_t nc = span->nc, k = 0;
    uint32_t lo = span->lo, hi = span->hi;
    if (n_own) { /* own increases */
        lo = own[0] < lo ? own[0] : lo;
        hi = own[n_own - 1] > hi ? own[n_own - 1] : hi;
    }
    limn_status ranked_st = LIMN_OK;
    if (n_own + nc > 0 && (uint64_t)hi - lo + 1 <= 32 * (uint64_t)(n_own + nc) &&
        sub_vertices_ranked(p, s, own, n_own, w, nw, lo, hi, out, &ranked_st))
        return ranked_st;
    size_t cap = n_own + nc, n = n_own;
    uint32_t *all = large_malloc((cap ? cap : 1) * sizeof *all);
    uint32_t *index = large_malloc((cap ? cap : 1) * sizeof *index);
    s->ids = large_malloc((cap ? cap : 1) * sizeof *s->ids);
    s->part = large_malloc((cap ? cap : 1) * sizeof *s->part);
    s->owned = large_malloc((n_own ? n_own : 1) * sizeof *s->owned);
    limn_status st = all && index && s->ids && s->part && s->owned
                         ? LIMN_OK
                         : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for the sub-mesh");
    if (!st) { /* the owned ids, then every corner's */
        memcpy(all, own, n_own * sizeof *all);
        for (size_t at = 0; at < nw; at += mpi_face_record_words(w[at + 2]))
            for (uint32_t c = 0, d = w[at + 2]; c < d; c++)
                all[n++] = w[at + 3 + c];
        st = mpi_local_distinct(p->ctx, all, cap, s->ids, &k, index);
    }
    free(all);
    n = n_own;
    for (size_t at = 0; !st && at < nw; at += mpi_face_record_words(w[at + 2]))
        for (uint32_t c = 0, d = w[at + 2]; c < d; c++, n++) {
            s->part[index[n]] = w[at + 3 + d + c]; /* the same for every copy */
            if (out)
                out[n - n_own] = index[n];
            else
                w[at + 3 + d + c] = index[n];
        }
    for (size_t i = 0; !st && i < n_own; i++)
        s->part[index[i]] = (uint32_t)p->rank;
    free(index);
    if (st)
        return st;
    for (size_t i = 0, o = 0; i < k && o < n_own; i++)
        if (s->part[i] == (uint32_t)p->rank)
            s->owned[o++] = (uint32_t)i;
    uint32_t *ids = realloc(s->ids, (k ? k : 1) * sizeof *ids);
    uint32_t *part = realloc(s->part, (k ? k : 1) * sizeof *part);
    s->ids = ids ? ids : s->ids; /* shrinking: the old block stays valid */
    s->part = part ? part : s->part;
    s->n = k;
    s->n_owned = n_own;
    mpi_local_note(s, k);
    return LIMN_OK;
}

/* The sub-mesh's positions (n vertices) in m, allocated with none. */
static limn_status sub_positions(limn_context *ctx, limn_mesh *m, size_t n)
{
    double *x = large_malloc((n ? n : 1) * 3 * sizeof *x);
    if (!x)
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for %zu vertices", n);
    free(m->positions);
    m->positions = x;
    m->vertex_count = n;
    return LIMN_OK;
}

/* The received records' last reader is done: freed (per-rank peak). */
static void free_records(uint32_t **words, face_rec **recs)
{
    free(*words);
    free(*recs);
    *words = NULL;
    *recs = NULL;
}

/* The sub-mesh's repair. limn_mesh_repair changes faces only where one uses
   a vertex twice or, when asked, where faces repeat; its duplicate search and
   its census, with no report asked and its warnings dropped (sub_mesh), only
   cost time, and the operator builds the topology the repair would have
   cached. So a sub-mesh without a repeated corner (every sub-mesh of a mesh
   limn_mpi_mesh_repair has seen; may_repeat 0: sort_records found none) is
   left as it is unless duplicates are to be removed: the same faces, the
   same operator. */
static limn_status sub_repair(limn_context *ctx, limn_mesh *m, const limn_repair_options *repair,
                              int may_repeat)
{
    if (!repair || !repair->duplicate_faces) {
        if (!may_repeat) /* sort_records saw every face */
            return LIMN_OK;
        size_t first = SIZE_MAX;
        uint32_t v = 0;
        limn_status st = face_first_repeat(ctx, m, &first, &v);
        if (st || first == SIZE_MAX)
            return st;
    }
    return limn_mesh_repair(ctx, m, repair, NULL);
}

/* The sub-mesh's faces (by increasing id, local vertex numbers) written
   into m (allocated for them: no copy; its indices there already when
   indexed, sub_vertices having written them), then repaired; the records
   (*words, *recs) are freed once the faces are out of them. Its indices are
   below its vertex count by construction and its positions are the
   input's, checked by the callers with global names (mpi_mesh_check): none
   of limn_mesh_create's checks and copies. */
static limn_status sub_mesh(mpi_part *p, uint32_t **words, face_rec **recs_in,
                            const records_span *span, int indexed,
                            const limn_repair_options *repair, limn_mesh *m, uint64_t **face_ids)
{
    size_t nf = span->nf;
    const uint32_t *w = *words;
    const face_rec *recs = *recs_in;
    uint32_t *off = m->face_offsets, *idx = m->face_indices;
    uint64_t *ids = face_ids ? large_malloc((nf ? nf : 1) * sizeof *ids) : NULL;
    limn_status st = ids || !face_ids
                         ? LIMN_OK
                         : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu faces", nf);
    off[0] = 0;
    for (size_t i = 0, k = 0, at = 0; !st && i < nf; i++) {
        size_t here = record_next(w, recs, i, &at);
        const uint32_t *r = w + here;
        for (uint32_t c = 0; c < r[2] && !indexed; c++)
            idx[k + c] = r[3 + r[2] + c]; /* sub_vertices left the local index there */
        k += r[2];
        off[i + 1] = (uint32_t)k;
        if (ids)
            ids[i] = record_id(w, here);
    }
    if (face_ids)
        *face_ids = ids;
    free_records(words, recs_in);
    /* the caller's warnings are kept; the sub-mesh's repair warnings are
       dropped: they number its own faces and see only its part of the mesh */
    limn_context *ctx = p->ctx;
    char *warnings = ctx->warnings;
    size_t warnings_len = ctx->warnings_len;
    ctx->warnings = NULL;
    ctx->warnings_len = 0;
    if (!st)
        st = sub_repair(ctx, m, repair, span->may_repeat);
    free(ctx->warnings);
    ctx->warnings = warnings;
    ctx->warnings_len = warnings_len;
    return st;
}

typedef struct local_tmp {
    uint32_t *own, *words;
    face_rec *recs;
    limn_mesh *mesh;
    size_t nown, nw; /* entries of the arrays above */
    records_span span;
} local_tmp;

static void tmp_free(local_tmp *t)
{
    free(t->own);
    free(t->words);
    free(t->recs);
    limn_mesh_destroy(t->mesh);
}

/* Everything up to the sub-mesh's operator (s filled). */
static limn_status build_sub(mpi_part *p, local_sub *s, local_tmp *t, const size_t *vtxdist,
                             const double *positions, const uint32_t *part_of, size_t face_begin,
                             size_t face_count, const uint32_t *face_offsets,
                             const uint32_t *face_indices, const limn_repair_options *repair,
                             uint64_t **face_ids)
{
    limn_status st = mpi_local_send_faces(p, s, vtxdist, part_of, face_begin, face_count,
                                          face_offsets, face_indices, repair, &t->words, &t->nw);
    if (!st)
        st = owned_ids(p, s, vtxdist, part_of, &t->own, &t->nown);
    if (!st)
        st = sort_records(p, t->words, t->nw, &t->recs, &t->span);
    /* records in face order (the usual case): each corner's sub-mesh index
       goes straight to the mesh's faces, allocated first, the positions once
       the vertices are counted; else through the records (sub_mesh) */
    int indexed = !st && !t->recs;
    if (indexed)
        st = mesh_alloc(p->ctx, 0, t->span.nf, t->span.nc, &t->mesh);
    if (!st)
        st = sub_vertices(p, s, t->own, t->nown, t->words, t->nw, &t->span,
                          indexed ? t->mesh->face_indices : NULL);
    free(t->own);
    t->own = NULL;
    if (!st && indexed)
        st = sub_positions(p->ctx, t->mesh, s->n);
    else if (!st) /* the positions are fetched into it, the faces written into it */
        st = mesh_alloc(p->ctx, s->n, t->span.nf, t->span.nc, &t->mesh);
    st = mpi_agree(p, st);
    if (!st)
        st = mpi_local_fetch(p, s, vtxdist, s->ids, s->n, positions, 3 * sizeof(double),
                             t->mesh->positions);
    if (!st)
        st = sub_mesh(p, &t->words, &t->recs, &t->span, indexed, repair, t->mesh, face_ids);
    st = mpi_agree(p, st);
    if (s->stats) {
        s->stats->faces_received = t->span.nf;
        s->stats->sub_vertices = s->n;
        s->stats->sub_faces = t->mesh ? t->mesh->face_count : 0;
    }
    return st;
}

/* vtxdist: from 0, never decreasing, global ids within 32 bits; the face
   offsets from 0 (agreed over the ranks). */
static limn_status check_blocks(mpi_part *p, const size_t *vtxdist, const uint32_t *off)
{
    limn_status st = LIMN_OK;
    for (int r = 0; r < p->size && !st; r++)
        if (vtxdist[r + 1] < vtxdist[r])
            st = ctx_fail(p->ctx, LIMN_ERR_ARGUMENT,
                          "vtxdist[%d] = %zu is below vtxdist[%d] = %zu: the vertex blocks "
                          "must follow each other",
                          r + 1, vtxdist[r + 1], r, vtxdist[r]);
    if (!st && (vtxdist[0] != 0 || vtxdist[p->size] > (size_t)UINT32_MAX + 1))
        st = ctx_fail(p->ctx, LIMN_ERR_ARGUMENT,
                      "vtxdist runs from %zu to %zu: it must start at 0 and hold at most 2^32 "
                      "vertices",
                      vtxdist[0], vtxdist[p->size]);
    if (!st && off[0] != 0)
        st = ctx_fail(p->ctx, LIMN_ERR_ARGUMENT,
                      "rank %d: face_offsets[0] is %u, must be 0", p->rank, off[0]);
    return mpi_agree(p, st);
}

void mpi_local_mesh_free(mpi_local_mesh *lm)
{
    if (!lm)
        return;
    operator_free(&lm->s.op);
    free(lm->s.ids);
    free(lm->s.part);
    free(lm->s.owned);
    free(lm->pos);
    free(lm->face_ids);
    limn_mesh_destroy(lm->mesh);
    memset(lm, 0, sizeof *lm);
}

limn_status mpi_local_mesh_build(mpi_part *p, const size_t *vtxdist, const double *positions,
                                 const uint32_t *part_of, size_t face_begin, size_t face_count,
                                 const uint32_t *face_offsets, const uint32_t *face_indices,
                                 const limn_repair_options *repair, int face_ids,
                                 mpi_local_mesh *lm, mpi_local_stats *stats)
{
    local_tmp t;
    memset(&t, 0, sizeof t);
    memset(lm, 0, sizeof *lm);
    lm->s.stats = stats;
    limn_status st = check_blocks(p, vtxdist, face_offsets);
    if (!st)
        st = build_sub(p, &lm->s, &t, vtxdist, positions, part_of, face_begin, face_count,
                       face_offsets, face_indices, repair, face_ids ? &lm->face_ids : NULL);
    lm->mesh = t.mesh; /* the build's lists are freed: the sub-mesh is what is left */
    t.mesh = NULL;
    tmp_free(&t);
    if (st)
        mpi_local_mesh_free(lm);
    return st;
}
