/* SPDX-License-Identifier: MIT */
/*
 * Local rows, the sub-mesh (mpi_local.h): the faces sent to every other
 * part among their vertices (mpi_local_faces.c) and this rank's own faces
 * read in place (mpi_face_source.h), owned vertices from their block
 * owners, and the repaired sub-mesh of every face at an owned vertex
 * (mpi_local_mesh), which mpi_local.c turns into rows and the repair's
 * census reads (mpi_local_census.c).
 */
#include "mpi/mpi_local.h"
#include "mpi/mpi_face_source.h"
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
    size_t tag; /* face_source's */
} face_rec;

static int cmp_rec(const void *a, const void *b)
{
    uint64_t x = ((const face_rec *)a)->id, y = ((const face_rec *)b)->id;
    return x < y ? -1 : x > y;
}

/* What one walk over the faces tells: their number, corners, the range of
   their vertex ids (lo > hi when there are none) and whether a face may use
   a vertex twice (0: none does; faces of more than 16 corners are left to
   face_first_repeat). */
typedef struct records_span {
    size_t nf, nc;
    uint32_t lo, hi;
    int may_repeat;
} records_span;

/* The sub-mesh's faces in increasing face id (*recs, span); *recs NULL when
   the walk order is that order (usually: the ranks' face ranges follow each
   other), which the readers walk as it is (face_next). */
static limn_status sort_faces(mpi_part *p, const face_source *src, face_rec **recs,
                              records_span *span)
{
    size_t n = 0, nc = 0, tag;
    uint64_t last = 0;
    uint32_t lo = UINT32_MAX, hi = 0;
    int sorted = 1, repeat = 0;
    face_view f;
    for (face_cursor c = FACE_CURSOR_START; face_next(src, &c, &f, &tag);) {
        sorted &= n == 0 || last < f.id;
        last = f.id;
        n++;
        uint32_t d = f.d;
        const uint32_t *v = f.v;
        nc += d;
        for (uint32_t k = 0; k < d; k++) {
            lo = v[k] < lo ? v[k] : lo;
            hi = v[k] > hi ? v[k] : hi;
        }
        if (d == 3) /* the usual face, without a loop */
            repeat |= (v[0] == v[1]) | (v[1] == v[2]) | (v[0] == v[2]);
        else if (d > 16)
            repeat = 1;
        else
            for (uint32_t k = 0; k < d; k++)
                for (uint32_t k2 = k + 1; k2 < d; k2++)
                    repeat |= v[k] == v[k2];
    }
    *span = (records_span){n, nc, lo, hi, repeat};
    *recs = NULL;
    if (sorted)
        return LIMN_OK;
    face_rec *r = large_malloc((n ? n : 1) * sizeof *r);
    if (!r)
        return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu faces", n);
    n = 0;
    for (face_cursor c = FACE_CURSOR_START; face_next(src, &c, &f, &tag);)
        r[n++] = (face_rec){f.id, tag};
    qsort(r, n, sizeof *r, cmp_rec);
    *recs = r;
    return LIMN_OK;
}

/* The sub-mesh's faces as the walk writes them when it is in face id
   order: corners' sub-mesh indices, offsets (from 0) and, when asked, ids. */
typedef struct sub_faces {
    uint32_t *idx, *off;
    uint64_t *ids;
} sub_faces;

/* Face fi of the walk ends at corner n: its offset and id (out's). */
static void sub_face_end(const sub_faces *out, size_t fi, size_t n, uint64_t id)
{
    out->off[fi + 1] = (uint32_t)n;
    if (out->ids)
        out->ids[fi] = id;
}

/* Every corner's vertex's sub-mesh index (its rank in r) to out, or over
   the corner's part without out, and the part of each vertex not owned
   (part other than me) to s->part: the owned ones' the caller sets, and a
   store per corner, at a scattered place, cost more than the ranking. */
MPI_POPCNT_CLONES static void rank_corners(const mpi_id_rank *r, local_sub *s, uint32_t me,
                                           const face_source *src, const sub_faces *out)
{
    face_view f;
    size_t n = 0, fi = 0, tag;
    for (face_cursor c = FACE_CURSOR_START; face_next(src, &c, &f, &tag); fi++) {
        for (uint32_t j = 0; j < f.d; j++, n++) {
            uint32_t i = mpi_id_rank_of(r, f.v[j]);
            if (f.part[j] != me) /* the same for every copy */
                s->part[i] = f.part[j];
            if (out)
                out->idx[n] = i;
            else
                f.part[j] = i;
        }
        if (out)
            sub_face_end(out, fi, n, f.id);
    }
}

/* sub_vertices by the ids' ranks (mpi_id_rank: no list of every corner,
   no sort); 0 when out of memory for the bitmap (nothing changed then). */
static int sub_vertices_ranked(mpi_part *p, local_sub *s, const uint32_t *own, size_t n_own,
                               const face_source *src, uint32_t lo, uint32_t hi,
                               const sub_faces *out, limn_status *st)
{
    mpi_id_rank r;
    if (!mpi_id_rank_init(&r, lo, hi))
        return 0;
    for (size_t i = 0; i < n_own; i++)
        mpi_id_rank_add(&r, own[i]);
    face_view f;
    size_t tag;
    for (face_cursor c = FACE_CURSOR_START; face_next(src, &c, &f, &tag);)
        for (uint32_t k = 0; k < f.d; k++)
            mpi_id_rank_add(&r, f.v[k]);
    size_t k = mpi_id_rank_finish(&r);
    s->ids = large_malloc((k ? k : 1) * sizeof *s->ids);
    s->part = large_malloc((k ? k : 1) * sizeof *s->part);
    s->owned = large_malloc((n_own ? n_own : 1) * sizeof *s->owned);
    *st = s->ids && s->part && s->owned
              ? LIMN_OK
              : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for the sub-mesh");
    if (!*st) {
        mpi_id_rank_list(&r, s->ids);
        rank_corners(&r, s, (uint32_t)p->rank, src, out);
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

/* The sub-mesh's vertices: owned ones (own, increasing) and those of its
   faces (span: sort_faces'), increasing, each with its part (s->ids,
   s->part, s->owned). Each corner's vertex's sub-mesh index then goes to
   out with the faces' offsets and ids (the walk in face id order), or
   without out over the corner's part. By the
   ranks of a bitmap when the ids' range is at most 32 times their count
   (mpi_local_distinct's rule), else through mpi_local_distinct. */
static limn_status sub_vertices(mpi_part *p, local_sub *s, const uint32_t *own, size_t n_own,
                                const face_source *src, const records_span *span,
                                const sub_faces *out)
{
    size_t nc = span->nc, k = 0, tag;
    uint32_t lo = span->lo, hi = span->hi;
    if (n_own) { /* own increases */
        lo = own[0] < lo ? own[0] : lo;
        hi = own[n_own - 1] > hi ? own[n_own - 1] : hi;
    }
    limn_status ranked_st = LIMN_OK;
    if (n_own + nc > 0 && (uint64_t)hi - lo + 1 <= 32 * (uint64_t)(n_own + nc) &&
        sub_vertices_ranked(p, s, own, n_own, src, lo, hi, out, &ranked_st))
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
    face_view f;
    if (!st) { /* the owned ids, then every corner's */
        memcpy(all, own, n_own * sizeof *all);
        for (face_cursor c = FACE_CURSOR_START; face_next(src, &c, &f, &tag);)
            for (uint32_t j = 0; j < f.d; j++)
                all[n++] = f.v[j];
        st = mpi_local_distinct(p->ctx, all, cap, s->ids, &k, index);
    }
    free(all);
    n = n_own;
    size_t fi = 0;
    for (face_cursor c = FACE_CURSOR_START; !st && face_next(src, &c, &f, &tag); fi++) {
        for (uint32_t j = 0; j < f.d; j++, n++) {
            s->part[index[n]] = f.part[j]; /* the same for every copy */
            if (out)
                out->idx[n - n_own] = index[n];
            else
                f.part[j] = index[n];
        }
        if (out)
            sub_face_end(out, fi, n - n_own, f.id);
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

/* The faces' last reader is done: the received records, the own corners'
   parts and the sorted order freed (per-rank peak). */
static void free_faces(face_source *src, face_rec **recs)
{
    free(src->w);
    free(src->cp);
    free(src->mine);
    free(*recs);
    src->w = src->cp = NULL;
    src->mine = NULL;
    src->nw = src->nlow = src->count = 0;
    *recs = NULL;
}

/* The sub-mesh's repair. limn_mesh_repair changes faces only where one uses
   a vertex twice or, when asked, where faces repeat; its duplicate search and
   its census, with no report asked and its warnings dropped (sub_mesh), only
   cost time, and the operator builds the topology the repair would have
   cached. So a sub-mesh without a repeated corner (every sub-mesh of a mesh
   limn_mpi_mesh_repair has seen; may_repeat 0: sort_faces found none) is
   left as it is unless duplicates are to be removed: the same faces, the
   same operator. */
static limn_status sub_repair(limn_context *ctx, limn_mesh *m, const limn_repair_options *repair,
                              int may_repeat)
{
    if (!repair || !repair->duplicate_faces) {
        if (!may_repeat) /* sort_faces saw every face */
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
   into m (allocated for them: no copy; already there when indexed,
   sub_vertices having written them) with their ids (ids, when asked), then
   repaired; the faces' sources (src, *recs) are freed once the faces are
   out of them. Its indices are below its vertex count by construction and
   its positions are the input's, checked by the callers with global names
   (mpi_mesh_check): none of limn_mesh_create's checks and copies. */
static limn_status sub_mesh(mpi_part *p, face_source *src, face_rec **recs_in,
                            const records_span *span, int indexed,
                            const limn_repair_options *repair, limn_mesh *m, uint64_t *ids)
{
    const face_rec *recs = *recs_in;
    uint32_t *off = m->face_offsets, *idx = m->face_indices;
    face_view f;
    off[0] = 0;
    for (size_t i = 0, k = 0; !indexed && i < span->nf; i++) {
        face_view_at(src, recs[i].tag, &f);
        for (uint32_t j = 0; j < f.d; j++)
            idx[k + j] = f.part[j]; /* sub_vertices left the local index there */
        k += f.d;
        off[i + 1] = (uint32_t)k;
        if (ids)
            ids[i] = f.id;
    }
    free_faces(src, recs_in);
    /* the caller's warnings are kept; the sub-mesh's repair warnings are
       dropped: they number its own faces and see only its part of the mesh */
    limn_context *ctx = p->ctx;
    char *warnings = ctx->warnings;
    size_t warnings_len = ctx->warnings_len;
    ctx->warnings = NULL;
    ctx->warnings_len = 0;
    limn_status st = sub_repair(ctx, m, repair, span->may_repeat);
    free(ctx->warnings);
    ctx->warnings = warnings;
    ctx->warnings_len = warnings_len;
    return st;
}

typedef struct local_tmp {
    uint32_t *own;
    face_source src;
    face_rec *recs;
    limn_mesh *mesh;
    size_t nown; /* entries of own */
    records_span span;
} local_tmp;

static void tmp_free(local_tmp *t)
{
    free(t->own);
    free_faces(&t->src, &t->recs);
    limn_mesh_destroy(t->mesh);
}

/* Everything up to the sub-mesh's operator (s filled). */
static limn_status build_sub(mpi_part *p, local_sub *s, local_tmp *t, const size_t *vtxdist,
                             const double *positions, const uint32_t *part_of, size_t face_begin,
                             size_t face_count, const uint32_t *face_offsets,
                             const uint32_t *face_indices, const limn_repair_options *repair,
                             uint64_t **face_ids)
{
    face_source *src = &t->src;
    *src = (face_source){.begin = face_begin, .count = face_count, .off = face_offsets,
                         .idx = face_indices, .me = (uint32_t)p->rank};
    limn_status st =
        mpi_local_send_faces(p, s, vtxdist, part_of, face_begin, face_count, face_offsets,
                             face_indices, repair, &src->cp, &src->mine, &src->w, &src->nw,
                             &src->nlow);
    if (!st)
        st = owned_ids(p, s, vtxdist, part_of, &t->own, &t->nown);
    if (!st)
        st = sort_faces(p, src, &t->recs, &t->span);
    /* faces in id order (the usual case): each corner's sub-mesh index goes
       straight to the mesh's faces, allocated first, the positions once the
       vertices are counted; else over the corners' parts (sub_mesh) */
    int indexed = !st && !t->recs;
    size_t nf = t->span.nf;
    if (!st && face_ids && !(*face_ids = large_malloc((nf ? nf : 1) * sizeof **face_ids)))
        st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu faces", nf);
    if (!st && indexed)
        st = mesh_alloc(p->ctx, 0, nf, t->span.nc, &t->mesh);
    sub_faces out = {NULL, NULL, NULL};
    if (!st && indexed) /* t->mesh allocated */
        out = (sub_faces){t->mesh->face_indices, t->mesh->face_offsets,
                          face_ids ? *face_ids : NULL};
    if (!st)
        st = sub_vertices(p, s, t->own, t->nown, src, &t->span, indexed ? &out : NULL);
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
        st = sub_mesh(p, src, &t->recs, &t->span, indexed, repair, t->mesh,
                      face_ids ? *face_ids : NULL);
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
    free(lm->s.near);
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
