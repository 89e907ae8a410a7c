/* SPDX-License-Identifier: MIT */
/*
 * Local rows, the mesh side (mpi_local.h): parts of the vertices the faces
 * use, faces to every part among their vertices, owned vertices from their
 * block owners, the repaired sub-mesh, its operator and the global numbers
 * (vertex and face counts, stencil entries, bounding box, edge cut).
 */
#include "mpi/mpi_local.h"
#include "base/large_alloc.h"

#include "base/context.h"
#include "mesh/mesh.h"
#include "topology/face_keys.h"

#include <limits.h>
#include <stdlib.h>
#include <string.h>

/* The distinct vertices of this rank's faces, increasing (*ref, *nref), and
   for each face corner the index of its vertex in that list (*corner_ref). */
static limn_status referenced(mpi_part *p, size_t nf, const uint32_t *off, const uint32_t *idx,
                              uint32_t **ref, size_t *nref, uint32_t **corner_ref)
{
    size_t nc = off[nf];
    uint32_t *r = large_malloc((nc ? nc : 1) * sizeof *r);
    uint32_t *cr = large_malloc((nc ? nc : 1) * sizeof *cr);
    limn_status st = r && cr ? mpi_local_distinct(p->ctx, idx, nc, r, nref, cr)
                             : ctx_fail(p->ctx, LIMN_ERR_MEMORY,
                                        "out of memory for %zu face corners", nc);
    if (st) {
        free(r);
        free(cr);
        return st;
    }
    *ref = r;
    *corner_ref = cr;
    return LIMN_OK;
}

static size_t find_u32(const uint32_t *a, size_t n, uint32_t v)
{
    size_t lo = 0, hi = n;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (a[mid] < v)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

/* Face record: face id (2 words), corner count d, d vertices, d parts. */
static size_t record_words(uint32_t d) { return 3 + 2 * (size_t)d; }

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

/* Each face to every distinct part among its vertices (records above);
   *recv, *nrecv: the records this rank receives. */
static limn_status send_faces(mpi_part *p, const faces_in *f, const uint32_t *corner_part,
                              uint32_t **recv, size_t *nrecv)
{
    size_t R = (size_t)p->size, maxd = 0;
    for (size_t i = 0; i < f->count; i++)
        maxd = f->off[i + 1] - f->off[i] > maxd ? f->off[i + 1] - f->off[i] : maxd;
    int *cnt = calloc(2 * R, sizeof *cnt), *rcnt = cnt + R;
    size_t *at = calloc(R + 1, sizeof *at);
    uint32_t *parts = large_malloc((maxd ? maxd : 1) * sizeof *parts), *buf = NULL;
    limn_status st = LIMN_OK;
    if (!cnt || !at || !parts)
        st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory sending faces");
    for (int pass = 0; !st && pass < 2; pass++) {
        for (size_t i = 0; i < f->count; i++) {
            const uint32_t *v = f->idx + f->off[i], *cp = corner_part + f->off[i];
            uint32_t d = f->off[i + 1] - f->off[i];
            size_t np = face_parts(cp, d, parts);
            for (size_t k = 0; k < np; k++) {
                if (pass == 0) {
                    at[parts[k] + 1] += record_words(d);
                    continue;
                }
                uint32_t *w = buf + at[parts[k]];
                uint64_t id = f->begin + i;
                w[0] = (uint32_t)id;
                w[1] = (uint32_t)(id >> 32);
                w[2] = d;
                for (uint32_t c = 0; c < d; c++) {
                    w[3 + c] = v[c];
                    w[3 + d + c] = cp[c];
                }
                at[parts[k]] += record_words(d);
            }
        }
        if (pass == 1)
            break;
        for (size_t r = 0; r < R; r++) {
            cnt[r] = at[r + 1] > INT_MAX ? INT_MAX : (int)at[r + 1];
            at[r + 1] += at[r];
        }
        if (!(buf = large_malloc((at[R] ? at[R] : 1) * sizeof *buf)))
            st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory sending faces");
    }
    st = mpi_agree(p, st);
    void *got = NULL;
    if (!st)
        st = mpi_local_alltoallv(p, buf, cnt, sizeof(uint32_t), &got, rcnt, nrecv);
    *recv = got;
    free(cnt);
    free(at);
    free(parts);
    free(buf);
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

/* The parts of the vertices this rank's faces use, from their block owners
   (checked: each part is a rank), and the part of every face corner. */
static limn_status ref_parts(mpi_part *p, local_sub *s, const size_t *vtxdist,
                             const uint32_t *part_of, const faces_in *f, uint32_t **ref,
                             const limn_repair_options *repair, size_t *nref,
                             uint32_t **ref_part, uint32_t **corner_part)
{
    limn_status st = referenced(p, f->count, f->off, f->idx, ref, nref, corner_part);
    size_t bad = SIZE_MAX, nb = vtxdist[p->rank + 1] - vtxdist[p->rank];
    for (size_t i = 0; !st && i < nb && bad == SIZE_MAX; i++)
        if (part_of[i] >= (uint32_t)p->size)
            bad = i;
    if (!st && bad != SIZE_MAX)
        st = ctx_fail(p->ctx, LIMN_ERR_ARGUMENT,
                      "vertex %zu is given to part %u but there are %d ranks",
                      vtxdist[p->rank] + bad, part_of[bad], p->size);
    for (size_t i = 0; !st && i < f->count; i++) {
        if (f->off[i + 1] < f->off[i] + 3) {
            st = ctx_fail(p->ctx, LIMN_ERR_ARGUMENT,
                          "face %zu has %ld vertices (at least 3 needed)", f->begin + i,
                          (long)f->off[i + 1] - (long)f->off[i]);
            break;
        }
        for (uint32_t c = f->off[i]; c < f->off[i + 1] && !st; c++)
            if (f->idx[c] >= vtxdist[p->size])
                st = ctx_fail(p->ctx, LIMN_ERR_ARGUMENT,
                              "face %zu uses vertex %u but there are %zu vertices", f->begin + i,
                              f->idx[c], vtxdist[p->size]);
    }
    if (!st && repair && !repair->repeated_vertices)
        st = refuse_repeats(p, f, vtxdist[p->size]);
    *ref_part = st ? NULL : large_malloc((*nref ? *nref : 1) * sizeof **ref_part);
    if (!st && !*ref_part)
        st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu vertices", *nref);
    mpi_local_note(s, *nref);
    st = mpi_agree(p, st);
    if (!st)
        st = mpi_local_fetch(p, s, vtxdist, *ref, *nref, part_of, sizeof(uint32_t), *ref_part);
    for (size_t c = 0; !st && c < f->off[f->count]; c++)
        (*corner_part)[c] = (*ref_part)[(*corner_part)[c]];
    return st;
}

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

/* The received face records, in increasing face id (*recs, *nf). */
static limn_status sort_records(mpi_part *p, const uint32_t *w, size_t nw, face_rec **recs,
                                size_t *nf)
{
    size_t n = 0;
    for (size_t at = 0; at < nw; at += record_words(w[at + 2]))
        n++;
    face_rec *r = large_malloc((n ? n : 1) * sizeof *r);
    if (!r)
        return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu faces", n);
    n = 0;
    for (size_t at = 0; at < nw; at += record_words(w[at + 2]))
        r[n++] = (face_rec){(uint64_t)w[at] | (uint64_t)w[at + 1] << 32, at};
    int sorted = 1; /* usually: senders' ranges follow each other */
    for (size_t i = 1; i < n && sorted; i++)
        sorted = r[i - 1].id < r[i].id;
    if (!sorted)
        qsort(r, n, sizeof *r, cmp_rec);
    *recs = r;
    *nf = n;
    return LIMN_OK;
}

/* The sub-mesh's vertices: owned ones and those of the received faces,
   increasing, each with its part (s->ids, s->part, s->owned). Each corner's
   part word in w is then overwritten with its vertex's sub-mesh index. */
static limn_status sub_vertices(mpi_part *p, local_sub *s, const uint32_t *own, size_t n_own,
                                uint32_t *w, size_t nw)
{
    size_t nc = 0, k = 0;
    for (size_t at = 0; at < nw; at += record_words(w[at + 2]))
        nc += w[at + 2];
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
        for (size_t at = 0; at < nw; at += record_words(w[at + 2]))
            for (uint32_t c = 0, d = w[at + 2]; c < d; c++)
                all[n++] = w[at + 3 + c];
        st = mpi_local_distinct(p->ctx, all, cap, s->ids, &k, index);
    }
    free(all);
    n = n_own;
    for (size_t at = 0; !st && at < nw; at += record_words(w[at + 2]))
        for (uint32_t c = 0, d = w[at + 2]; c < d; c++, n++) {
            s->part[index[n]] = w[at + 3 + d + c]; /* the same for every copy */
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
   limn_mpi_mesh_repair has seen) is left as it is unless duplicates are to
   be removed: the same faces, the same operator. */
static limn_status sub_repair(limn_context *ctx, limn_mesh *m, const limn_repair_options *repair)
{
    if (!repair || !repair->duplicate_faces) {
        size_t first = SIZE_MAX;
        uint32_t v = 0;
        limn_status st = face_first_repeat(ctx, m, &first, &v);
        if (st || first == SIZE_MAX)
            return st;
    }
    return limn_mesh_repair(ctx, m, repair, NULL);
}

/* The sub-mesh (faces by increasing id, local vertex numbers), repaired; the
   records (*words, *recs) are freed once the faces are out of them. */
static limn_status sub_mesh(mpi_part *p, local_sub *s, uint32_t **words, face_rec **recs_in,
                            size_t nf, const double *pos, const limn_repair_options *repair,
                            limn_mesh **out)
{
    const uint32_t *w = *words;
    const face_rec *recs = *recs_in;
    size_t nc = 0;
    for (size_t i = 0; i < nf; i++)
        nc += w[recs[i].at + 2];
    uint32_t *off = large_malloc((nf + 1) * sizeof *off);
    uint32_t *idx = large_malloc((nc ? nc : 1) * sizeof *idx);
    limn_status st = off && idx ? LIMN_OK
                                : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for faces");
    if (!st)
        off[0] = 0;
    for (size_t i = 0, k = 0; !st && i < nf; i++) {
        const uint32_t *r = w + recs[i].at;
        for (uint32_t c = 0; c < r[2]; c++)
            idx[k++] = r[3 + r[2] + c]; /* sub_vertices left the local index there */
        off[i + 1] = (uint32_t)k;
    }
    free_records(words, recs_in);
    /* the caller's warnings are kept; the sub-mesh's repair warnings are
       dropped: they number its own faces and see only its part of the mesh */
    limn_context *ctx = p->ctx;
    char *warnings = ctx->warnings;
    size_t warnings_len = ctx->warnings_len;
    ctx->warnings = NULL;
    ctx->warnings_len = 0;
    if (!st)
        st = limn_mesh_create(ctx, s->n, pos, nf, off, idx, out);
    free(off); /* the mesh holds its own copies */
    free(idx);
    if (!st)
        st = sub_repair(ctx, *out, repair);
    free(ctx->warnings);
    ctx->warnings = warnings;
    ctx->warnings_len = warnings_len;
    return st;
}

/* The scheme over all ranks (AUTO: Loop when every face is a triangle), and
   a refusal naming a face Loop cannot take. */
static limn_status resolve_scheme(mpi_part *p, const local_sub *s, const limn_mesh *m,
                                  limn_scheme want, limn_scheme *out)
{
    size_t other = SIZE_MAX;
    for (size_t f = 0; f < m->face_count && other == SIZE_MAX; f++)
        if (m->face_offsets[f + 1] - m->face_offsets[f] != 3)
            other = f;
    int all_tri = other == SIZE_MAX, every = 0;
    MPI_Allreduce(&all_tri, &every, 1, MPI_INT, MPI_MIN, p->comm);
    if (want == LIMN_SCHEME_AUTO)
        want = every && p->faces_global > 0 ? LIMN_SCHEME_LOOP : LIMN_SCHEME_CATMARK;
    limn_status st = LIMN_OK;
    if (want == LIMN_SCHEME_LOOP && other != SIZE_MAX) {
        const uint32_t *v = m->face_indices + m->face_offsets[other];
        st = ctx_fail(p->ctx, LIMN_ERR_TOPOLOGY,
                      "a face with %u vertices (vertices %u, %u, %u, %u, ...) but Loop "
                      "subdivision needs triangles only: use --scheme catmark (or auto), or "
                      "triangulate the mesh",
                      m->face_offsets[other + 1] - m->face_offsets[other], s->ids[v[0]],
                      s->ids[v[1]], s->ids[v[2]], s->ids[v[3]]);
    }
    *out = want;
    return mpi_agree(p, st);
}

/* Global numbers, the scheme and the sub-mesh's operator (input order). */
static limn_status sub_operator(mpi_part *p, local_sub *s, const limn_mesh *m, limn_scheme want,
                                double alpha)
{
    limn_status st = mpi_local_counts(p, s, m);
    if (st)
        return st;
    st = resolve_scheme(p, s, m, want, &p->scheme);
    if (!st && s->n) /* a rank without vertices has no rows */
        st = operator_build_ex(p->ctx, m, p->scheme, alpha, OPERATOR_HOST_ONLY, &s->op);
    st = mpi_agree(p, st);
    if (st)
        return st;
    p->alpha = p->scheme == LIMN_SCHEME_CATMARK ? alpha : 0.0;
    uint64_t nnz = 0;
    for (size_t i = 0; i < s->n_owned; i++)
        nnz += s->op.host.row_offsets[s->owned[i] + 1] - s->op.host.row_offsets[s->owned[i]];
    MPI_Allreduce(MPI_IN_PLACE, &nnz, 1, MPI_UINT64_T, MPI_SUM, p->comm);
    p->nnz_global = nnz;
    return LIMN_OK;
}

typedef struct local_tmp {
    uint32_t *ref, *ref_part, *corner_part, *own, *words;
    face_rec *recs;
    double *pos;
    limn_mesh *mesh;
    size_t nref, ncorner, nown, nw, nf; /* entries of the arrays above (held_bytes) */
} local_tmp;

/* Bytes of the build's own arrays alive now (mpi_local_stats), counted
   from the live pointers; the sub-mesh, the operator's input, aside. */
static size_t held_bytes(const local_tmp *t, const local_sub *s)
{
    size_t w = sizeof(uint32_t);
    return (t->ref ? t->nref * w : 0) + (t->ref_part ? t->nref * w : 0) +
           (t->corner_part ? t->ncorner * w : 0) + (t->own ? t->nown * w : 0) +
           (t->words ? t->nw * w : 0) + (t->recs ? t->nf * sizeof *t->recs : 0) +
           (t->pos ? 3 * s->n * sizeof *t->pos : 0) + (s->ids ? s->n * w : 0) +
           (s->part ? s->n * w : 0) + (s->owned ? s->n_owned * w : 0);
}

static void tmp_free(local_tmp *t)
{
    free(t->ref);
    free(t->ref_part);
    free(t->corner_part);
    free(t->own);
    free(t->words);
    free(t->recs);
    free(t->pos);
    limn_mesh_destroy(t->mesh);
}

/* The referenced vertices' lists, done with once the faces are sent. */
static void free_lists(uint32_t **ref, uint32_t **ref_part, uint32_t **corner_part)
{
    free(*ref);
    free(*ref_part);
    free(*corner_part);
    *ref = *ref_part = *corner_part = NULL;
}

/* Everything up to the sub-mesh's operator (s filled). */
static limn_status build_sub(mpi_part *p, local_sub *s, local_tmp *t, const size_t *vtxdist,
                             const double *positions, const uint32_t *part_of, const faces_in *f,
                             const limn_repair_options *repair)
{
    t->ncorner = f->off[f->count];
    limn_status st =
        ref_parts(p, s, vtxdist, part_of, f, &t->ref, repair, &t->nref, &t->ref_part,
                  &t->corner_part);
    if (!st)
        st = send_faces(p, f, t->corner_part, &t->words, &t->nw);
    free_lists(&t->ref, &t->ref_part, &t->corner_part); /* their last reader */
    if (!st)
        st = owned_ids(p, s, vtxdist, part_of, &t->own, &t->nown);
    if (!st)
        st = sort_records(p, t->words, t->nw, &t->recs, &t->nf);
    if (!st)
        st = sub_vertices(p, s, t->own, t->nown, t->words, t->nw);
    free(t->own);
    t->own = NULL;
    if (!st && !(t->pos = large_malloc((s->n ? 3 * s->n : 1) * sizeof *t->pos)))
        st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu positions", s->n);
    st = mpi_agree(p, st);
    if (!st)
        st = mpi_local_fetch(p, s, vtxdist, s->ids, s->n, positions, 3 * sizeof(double), t->pos);
    if (!st)
        st = sub_mesh(p, s, &t->words, &t->recs, t->nf, t->pos, repair, &t->mesh);
    st = mpi_agree(p, st);
    if (s->stats) {
        s->stats->faces_received = t->nf;
        s->stats->sub_vertices = s->n;
        s->stats->sub_faces = t->mesh ? t->mesh->face_count : 0;
    }
    return st;
}

/* The positions of the owned rows, 4 doubles a row (w = 0), local order. */
static limn_status owned_positions(mpi_part *p, const local_sub *s, const double *pos,
                                   double **rows4)
{
    size_t no = p->n_owned;
    /* page aligned: the solve's device buffer of M uses it in place */
    double *r = device_host_alloc((no ? 4 * no : 4) * sizeof *r);
    if (!r)
        return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu rows", no);
    memset(r, 0, (no ? 4 * no : 4) * sizeof *r);
    for (size_t l = 0; l < no; l++)
        memcpy(r + 4 * l, pos + 3 * find_u32(s->ids, s->n, p->owned_ids[l]), 3 * sizeof *r);
    *rows4 = r;
    return LIMN_OK;
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

limn_status mpi_local_build(mpi_part *p, const size_t *vtxdist, const double *positions,
                            const uint32_t *part_of, size_t face_begin, size_t face_count,
                            const uint32_t *face_offsets, const uint32_t *face_indices,
                            limn_scheme scheme, double alpha, const limn_repair_options *repair,
                            double **owned_rows4, mpi_local_stats *stats)
{
    double t0 = MPI_Wtime();
    local_sub s;
    local_tmp t;
    memset(&s, 0, sizeof s);
    memset(&t, 0, sizeof t);
    if (stats)
        memset(stats, 0, sizeof *stats);
    if (owned_rows4)
        *owned_rows4 = NULL;
    s.stats = stats;
    faces_in f = {face_begin, face_count, face_offsets, face_indices};
    limn_status st = check_blocks(p, vtxdist, face_offsets);
    if (st)
        return st;
    size_t nb = vtxdist[p->rank + 1] - vtxdist[p->rank];
    p->n_global = vtxdist[p->size];
    p->diag = mpi_local_diagonal(p, positions, nb);
    p->reordered = 0;
    st = build_sub(p, &s, &t, vtxdist, positions, part_of, &f, repair);
    if (stats)
        stats->bytes_held_at_operator = held_bytes(&t, &s);
    if (!st)
        st = sub_operator(p, &s, t.mesh, scheme, alpha);
    limn_mesh_destroy(t.mesh); /* the rows are built: its last reader is done */
    t.mesh = NULL;
    if (!st)
        st = mpi_local_rows(p, &s);
    if (!st && owned_rows4)
        st = owned_positions(p, &s, t.pos, owned_rows4);
    st = mpi_agree(p, st);
    tmp_free(&t);
    operator_free(&s.op);
    free(s.ids);
    free(s.part);
    free(s.owned);
    if (!st)
        st = mpi_open_rows(p);
    p->stats.seconds_distribute = MPI_Wtime() - t0;
    if (stats)
        stats->seconds = p->stats.seconds_distribute;
    st = mpi_agree(p, st);
    if (st && owned_rows4) {
        free(*owned_rows4);
        *owned_rows4 = NULL;
    }
    return st;
}
