/* SPDX-License-Identifier: MIT */
/*
 * limn_mpi_mesh_morph: limn_morph on distributed meshes, no rank holding
 * FROM or TO. The operator's rows are FROM's (mpi_mesh_series_open, as the
 * other filters); TO's positions are fetched into FROM's vertex blocks (the
 * two files' blocks may differ: text is cut by bytes), its faces into FROM's
 * face blocks to check the topology with limn_morph's message. Each frame
 * is a distributed mesh handed to the caller on every rank (who writes it
 * in parallel), with limn_morph's measures in its bits: the volume and area
 * of mpi_mesh_measure.c, flipped faces counted per rank (exact), the mean
 * distance to TO summed in vertex order from rank to rank. --linear blends
 * the blocks without an operator.
 */
#include "mpi/mpi_blocks.h"
#include "base/large_alloc.h"
#include "mpi/mpi_mesh.h"
#include "mpi/mpi_series.h"

#include "base/context.h"
#include "mesh/check.h"
#include "series/series.h"
#include "topology/measure.h"

#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* m's faces [begin, end) (global ids, end <= its face total) as CSR: *off
   (from 0) and *idx, fetched from their block owners. Collective, agreed. */
static limn_status fetch_faces(mpi_part *p, const limn_mpi_mesh *m, size_t begin, size_t end,
                               uint32_t **off, uint32_t **idx)
{
    const mesh_slice *s = &m->slice;
    size_t n = end - begin, nc = 0;
    size_t *cdist = large_malloc(((size_t)p->size + 1) * sizeof *cdist);
    uint64_t *rec = large_malloc((s->face_count ? s->face_count : 1) * 2 * sizeof *rec);
    uint64_t *got = large_malloc((n ? n : 1) * 2 * sizeof *got);
    uint32_t *ids = large_malloc((n ? n : 1) * sizeof *ids);
    *off = large_malloc((n + 1) * sizeof **off);
    *idx = NULL;
    limn_status st = cdist && rec && got && ids && *off
                         ? LIMN_OK
                         : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu faces", n);
    st = mpi_agree(p, st);
    if (!st) {
        mpi_blocks_dist(p, s->face_offsets[s->face_count], cdist);
        if (cdist[p->size] > UINT32_MAX) /* the same on every rank */
            st = ctx_fail(p->ctx, LIMN_ERR_ARGUMENT,
                          "comparing the faces of distributed meshes takes at most %u corners; "
                          "these have %zu",
                          UINT32_MAX, cdist[p->size]);
    }
    for (size_t i = 0; !st && i < s->face_count; i++) { /* each face's corners, globally */
        rec[2 * i] = cdist[p->rank] + s->face_offsets[i];
        rec[2 * i + 1] = s->face_offsets[i + 1] - s->face_offsets[i];
    }
    for (size_t k = 0; !st && k < n; k++)
        ids[k] = (uint32_t)(begin + k);
    if (!st)
        st = mpi_blocks_fetch(p, m->face_dist, rec, 2 * sizeof *rec, n, ids, got);
    uint32_t *cids = NULL;
    if (!st) {
        (*off)[0] = 0;
        for (size_t k = 0; k < n; k++)
            (*off)[k + 1] = (*off)[k] + (uint32_t)got[2 * k + 1];
        nc = (*off)[n];
        cids = large_malloc((nc ? nc : 1) * sizeof *cids);
        *idx = large_malloc((nc ? nc : 1) * sizeof **idx);
        if (!cids || !*idx)
            st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu corners", nc);
        for (size_t c = 0; !st && c < nc; c++)
            cids[c] = (uint32_t)(got[0] + c);
    }
    st = mpi_agree(p, st);
    if (!st)
        st = mpi_blocks_fetch(p, cdist, s->face_indices, sizeof **idx, nc, cids, *idx);
    free(cids);
    free(cdist);
    free(rec);
    free(got);
    free(ids);
    if (st) {
        free(*off);
        free(*idx);
        *off = *idx = NULL;
    }
    return st;
}

/* A face's indices as measure_same_topology writes them. */
static void face_text(const uint32_t *idx, uint32_t n, char *out, size_t cap)
{
    size_t len = 0;
    out[0] = '\0';
    for (uint32_t k = 0; k < n && len + 12 < cap; k++)
        len += (size_t)snprintf(out + len, cap - len, "%s%u", k ? " " : "", idx[k]);
}

/* measure_same_topology(FROM, TO) on distributed meshes, the same messages
   (the lowest differing face: the lowest failing rank's). Agreed. */
static limn_status same_topology(mpi_part *p, const limn_mpi_mesh *a, const limn_mpi_mesh *b)
{
    size_t nva = a->vertex_dist[p->size], nvb = b->vertex_dist[p->size];
    if (nva != nvb)
        return ctx_fail(p->ctx, LIMN_ERR_TOPOLOGY,
                        "FROM and TO differ in topology: FROM has %zu vertices, TO has %zu", nva,
                        nvb);
    size_t fa = a->face_dist[p->size], fb = b->face_dist[p->size], nf = fa < fb ? fa : fb;
    const mesh_slice *s = &a->slice;
    size_t lo = s->face_begin < nf ? s->face_begin : nf;
    size_t hi = s->face_begin + s->face_count < nf ? s->face_begin + s->face_count : nf;
    uint32_t *off = NULL, *idx = NULL;
    limn_status st = fetch_faces(p, b, lo, hi, &off, &idx);
    for (size_t f = lo; !st && f < hi; f++) {
        const uint32_t *ia = s->face_indices + s->face_offsets[f - s->face_begin];
        const uint32_t *ib = idx + off[f - lo];
        uint32_t sa = s->face_offsets[f - s->face_begin + 1] - s->face_offsets[f - s->face_begin];
        uint32_t sb = off[f - lo + 1] - off[f - lo];
        int differ = sa != sb;
        for (uint32_t k = 0; !differ && k < sa; k++)
            differ = ia[k] != ib[k];
        if (differ) {
            char ta[96], tb[96];
            face_text(ia, sa, ta, sizeof ta);
            face_text(ib, sb, tb, sizeof tb);
            st = ctx_fail(p->ctx, LIMN_ERR_TOPOLOGY,
                          "FROM and TO differ in topology: face %zu is (%s) in FROM but (%s) in "
                          "TO (0-based vertex indices); both meshes need the same faces",
                          f, ta, tb);
        }
    }
    free(off);
    free(idx);
    st = mpi_agree(p, st);
    if (!st && fa != fb)
        st = ctx_fail(p->ctx, LIMN_ERR_TOPOLOGY,
                      "FROM and TO differ in topology: FROM has %zu faces, TO has %zu (face %zu "
                      "is the first one only one of them has)",
                      fa, fb, nf);
    return st;
}

/* limn_morph's checks in its order (fn, FROM, TO, options, the counts and
   the topology, empty meshes), over the ranks. Agreed. */
static limn_status check_morph(mpi_part *p, const limn_mpi_mesh *from, const limn_mpi_mesh *to,
                               const limn_morph_options *o, limn_mpi_morph_frame_fn fn)
{
    const char *name = "limn_mpi_mesh_morph";
    limn_status st = LIMN_OK;
    if (!fn)
        st = ctx_fail(p->ctx, LIMN_ERR_ARGUMENT, "%s: the frame callback is NULL", name);
    else if (to->size != from->size)
        st = ctx_fail(p->ctx, LIMN_ERR_ARGUMENT, "%s: FROM is on %d ranks, TO on %d", name,
                      from->size, to->size);
    st = mpi_agree(p, st);
    if (!st)
        st = mpi_mesh_check(p, name, from);
    if (!st)
        st = mpi_mesh_check(p, name, to);
    if (!st)
        st = check_scheme(p->ctx, name, o->series.scheme);
    if (!st)
        st = series_check_options(p->ctx, &o->series);
    if (!st)
        st = series_check_morph_counts(p->ctx, name, o);
    st = mpi_agree(p, st);
    if (!st)
        st = same_topology(p, from, to);
    if (!st && (from->vertex_dist[p->size] == 0 || from->face_dist[p->size] == 0))
        st = ctx_fail(p->ctx, LIMN_ERR_TOPOLOGY, "the meshes have no %s",
                      from->vertex_dist[p->size] ? "faces" : "vertices");
    return st;
}

/* One morph's state on this rank. */
typedef struct morph_run {
    mpi_part *p;
    const limn_mpi_mesh *from, *to;
    limn_mpi_morph_frame_fn fn;
    void *user;
    double *to_block;     /* TO's positions in FROM's vertex blocks */
    double *from_corners; /* FROM's position at each corner of this rank's faces */
    double *corners;      /* a frame's, the same */
    uint32_t *iota;       /* 0, 1, ...: corner c is corner c (measure_face_normal) */
    limn_mpi_mesh *frame; /* FROM's blocks with the frame's positions */
    int closed;
    double diag;          /* TO's bbox diagonal */
} morph_run;

static void morph_free(morph_run *m)
{
    free(m->to_block);
    free(m->from_corners);
    free(m->corners);
    free(m->iota);
    limn_mpi_mesh_destroy(m->frame);
}

/* TO's positions, FROM's corners, the frame mesh, closedness and TO's
   diagonal. Collective, agreed. */
static limn_status morph_prepare(morph_run *m)
{
    mpi_part *p = m->p;
    const mesh_slice *s = &m->from->slice;
    size_t nb = s->vertex_count, nc = s->face_offsets[s->face_count];
    uint32_t *ids = large_malloc((nb ? nb : 1) * sizeof *ids);
    double *copy = large_malloc((nb ? 3 * nb : 1) * sizeof *copy);
    m->to_block = large_malloc((nb ? 3 * nb : 1) * sizeof *m->to_block);
    m->from_corners = large_malloc((nc ? 3 * nc : 1) * sizeof *m->from_corners);
    m->corners = large_malloc((nc ? 3 * nc : 1) * sizeof *m->corners);
    m->iota = large_malloc((nc ? nc : 1) * sizeof *m->iota);
    limn_status st = ids && copy && m->to_block && m->from_corners && m->corners && m->iota
                         ? LIMN_OK
                         : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for the morph");
    for (size_t i = 0; !st && i < nb; i++)
        ids[i] = (uint32_t)(s->vertex_begin + i);
    for (size_t c = 0; !st && c < nc; c++)
        m->iota[c] = (uint32_t)c;
    st = mpi_agree(p, st);
    if (!st)
        st = mpi_blocks_fetch(p, m->to->vertex_dist, m->to->slice.positions, 3 * sizeof(double),
                              nb, ids, m->to_block);
    if (!st)
        st = mpi_blocks_fetch(p, m->from->vertex_dist, s->positions, 3 * sizeof(double), nc,
                              s->face_indices, m->from_corners);
    free(ids);
    if (!st) {
        memcpy(copy, s->positions, 3 * nb * sizeof *copy);
        st = mpi_mesh_control_of(p, m->from, copy, &m->frame); /* takes copy */
        copy = NULL;
    }
    free(copy);
    mpi_mesh_counts k;
    if (!st)
        st = mpi_mesh_census(p, m->from, &k);
    if (!st) {
        m->closed = k.boundary_edges == 0 && k.nonmanifold_edges == 0 &&
                    k.inconsistent_edges == 0;
        m->diag = mpi_mesh_bbox_diagonal(p, m->to);
    }
    return st;
}

/* series_emit_frame over the ranks: frame k's measures with positions pos
   (FROM's blocks; copied into the frame mesh), then the callback. */
static limn_status emit(morph_run *m, int k, const double *pos)
{
    mpi_part *p = m->p;
    const mesh_slice *s = &m->from->slice;
    size_t nb = s->vertex_count, nc = s->face_offsets[s->face_count];
    double *q = m->frame->slice.positions;
    if (q != pos)
        memcpy(q, pos, 3 * nb * sizeof *q);
    limn_morph_frame fr = {.index = k, .positions = q};
    double vol = 0.0;
    limn_status st = mpi_mesh_volume_area(p, m->from, q, &vol, &fr.area);
    if (!st)
        st = mpi_blocks_fetch(p, m->from->vertex_dist, q, 3 * sizeof *q, nc, s->face_indices,
                              m->corners);
    if (st)
        return st;
    fr.volume = m->closed ? vol : NAN;
    unsigned long long flipped = 0;
    for (size_t f = 0; f < s->face_count; f++) {
        double n0[3], n1[3];
        measure_face_normal(m->from_corners, s->face_offsets, m->iota, f, n0);
        measure_face_normal(m->corners, s->face_offsets, m->iota, f, n1);
        flipped += n0[0] * n1[0] + n0[1] * n1[1] + n0[2] * n1[2] < 0.0;
    }
    MPI_Allreduce(MPI_IN_PLACE, &flipped, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, p->comm);
    fr.flipped_faces = (size_t)flipped;
    double *dist = large_malloc((nb ? nb : 1) * sizeof *dist), sum = 0.0;
    st = mpi_agree(p, dist ? LIMN_OK : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory"));
    if (st) {
        free(dist);
        return st;
    }
    for (size_t i = 0; i < nb; i++) {
        const double *a = q + 3 * i, *b = m->to_block + 3 * i;
        dist[i] = sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                       (a[2] - b[2]) * (a[2] - b[2]));
    }
    mpi_mesh_chained_sums(p, dist, nb, 1, &sum);
    free(dist);
    fr.mean_distance_to_target = sum / (double)m->from->vertex_dist[p->size] /
                                 (m->diag > 0 ? m->diag : 1.0);
    return mpi_agree(p, m->fn(m->user, m->frame, &fr));
}

/* The lowest vertex of any rank with a non-finite coordinate in q (nb of
   FROM's block), refused as series_check_finite refuses it. Agreed. */
static limn_status check_finite(mpi_part *p, const limn_mpi_mesh *from, const double *q)
{
    unsigned long long bad = ULLONG_MAX;
    for (size_t i = 0; i < 3 * from->slice.vertex_count && bad == ULLONG_MAX; i++)
        if (!isfinite(q[i]))
            bad = from->slice.vertex_begin + i / 3;
    MPI_Allreduce(MPI_IN_PLACE, &bad, 1, MPI_UNSIGNED_LONG_LONG, MPI_MIN, p->comm);
    if (bad == ULLONG_MAX)
        return LIMN_OK;
    return ctx_fail(p->ctx, LIMN_ERR_NO_CONVERGENCE,
                    "the morph produced a non-finite coordinate at vertex %llu; nothing was "
                    "written (use fewer steps or terms)",
                    bad);
}

/* series_morph_run's frames on the ranks (D_0 = FROM - TO in s->m4). */
static limn_status morph_series(morph_run *m, series_mpi *s, const series_engine *e,
                                const limn_morph_options *o)
{
    mpi_part *p = m->p;
    device_buffer **b = e->buf;
    size_t nb = m->from->slice.vertex_count;
    double *q = large_malloc((nb ? 3 * nb : 1) * sizeof *q);
    limn_status st =
        mpi_agree(p, q ? LIMN_OK : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory"));
    if (!st)
        st = e->ops->upload(e, NULL, b[0]);
    if (!st)
        st = emit(m, 0, m->from->slice.positions);
    for (int k = 1; !st && k < o->frames; k++) {
        /* D_k = p sum_{i=0..m} (E - A)^i A D_{k-1}; Q_k = TO + D_k */
        st = series_terms(e, b[0], b[1], b[2], b[3], o->m);
        if (!st)
            st = e->ops->axpby(e, o->p, b[1], 0.0, b[1], b[0]);
        if (!st)
            st = mpi_agree(p, p->dev->ops->buffer_read_at(p->dev, b[0], 0,
                                                          4 * p->n_owned * sizeof(double),
                                                          s->rows4));
        double *d = NULL;
        if (!st)
            st = mpi_mesh_results_to_blocks(p, m->from, s->rows4, &d);
        for (size_t i = 0; !st && i < 3 * nb; i++)
            q[i] = m->to_block[i] + d[i];
        free(d);
        if (!st)
            st = check_finite(p, m->from, q);
        if (!st)
            st = emit(m, k, q);
        ctx_progress(p->ctx, "morph", (double)k / (double)(o->frames - 1));
    }
    free(q);
    return st;
}

/* D_0 = FROM - TO on the owned rows (s->m4 holds FROM's), as limn_morph
   forms it. */
static limn_status difference(mpi_part *p, series_mpi *s, const limn_mpi_mesh *to)
{
    size_t no = p->n_owned;
    double *t = large_malloc((no ? 3 * no : 1) * sizeof *t);
    limn_status st =
        mpi_agree(p, t ? LIMN_OK : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory"));
    if (!st)
        st = mpi_blocks_fetch(p, to->vertex_dist, to->slice.positions, 3 * sizeof *t, no,
                              p->owned_ids, t);
    for (size_t i = 0; !st && i < no; i++)
        for (int c = 0; c < 3; c++)
            s->m4[4 * i + c] = s->m4[4 * i + c] - t[3 * i + c];
    free(t);
    return st;
}

/* The operator path (o->linear 0). */
static limn_status run_series(morph_run *m, limn_context *ctx, const limn_morph_options *o,
                              limn_series_report *r, const limn_mpi_options *mpi,
                              limn_mpi_result *result)
{
    series_mpi s;
    series_engine e;
    limn_mpi_mesh *unused = NULL;
    limn_status st = mpi_mesh_series_open(ctx, "limn_mpi_mesh_morph", m->from, &o->series, mpi,
                                          LIMN_OK, &unused, &s, &e, r);
    if (s.p.comm == MPI_COMM_NULL)
        return st;
    m->p = &s.p;
    if (!st)
        st = morph_prepare(m);
    if (!st)
        st = difference(&s.p, &s, m->to);
    if (!st)
        st = morph_series(m, &s, &e, o);
    morph_free(m);
    return mpi_mesh_series_close(&s, st, result, r);
}

/* The linear blend (o->linear): no operator, the blocks blended. */
static limn_status run_linear(morph_run *m, const limn_morph_options *o, limn_series_report *r)
{
    mpi_part *p = m->p;
    size_t nb = m->from->slice.vertex_count;
    limn_scheme scheme = LIMN_SCHEME_AUTO;
    limn_status st = mpi_mesh_scheme(p, m->from, o->series.scheme, &scheme);
    double *q = NULL;
    if (!st)
        st = morph_prepare(m);
    if (!st) {
        r->vertices = m->from->vertex_dist[p->size];
        r->faces = m->from->face_dist[p->size];
        r->scheme = scheme;
        r->alpha = scheme == LIMN_SCHEME_CATMARK ? o->series.alpha : 0.0;
        r->bbox_diagonal = mpi_mesh_bbox_diagonal(p, m->from);
        snprintf(r->device, sizeof r->device, "none (linear blend on the host)");
        q = large_malloc((nb ? 3 * nb : 1) * sizeof *q);
        st = mpi_agree(p, q ? LIMN_OK : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory"));
    }
    double t0 = MPI_Wtime();
    const double *a = m->from->slice.positions, *b = m->to_block;
    for (int k = 0; !st && k < o->frames; k++) {
        double u = (double)k / (double)(o->frames - 1);
        for (size_t i = 0; i < 3 * nb; i++)
            q[i] = (1.0 - u) * a[i] + u * b[i];
        st = emit(m, k, q);
    }
    r->seconds_compute = MPI_Wtime() - t0;
    free(q);
    morph_free(m);
    return st;
}

/* limn_mpi_mesh_morph on structs of this library's layout. */
static limn_status morph_sized(limn_context *ctx, const limn_mpi_mesh *from,
                               const limn_mpi_mesh *to, const limn_morph_options *o,
                               limn_mpi_morph_frame_fn fn, void *user, limn_series_report *r,
                               const limn_mpi_options *mpi, limn_mpi_result *result)
{
    if (result)
        memset(result, 0, sizeof *result);
    memset(r, 0, sizeof *r);
    mpi_part probe;
    limn_status st = mpi_mesh_part(ctx, from, mpi, &probe);
    if (probe.comm == MPI_COMM_NULL)
        return st;
    if (to != from)
        mpi_mesh_drop_sub(to); /* the rows are FROM's: TO's sub-mesh is never read */
    st = mpi_agree(&probe, st);
    if (!st)
        st = check_morph(&probe, from, to, o, fn);
    morph_run m = {.p = &probe, .from = from, .to = to, .fn = fn, .user = user};
    if (!st && o->linear)
        st = run_linear(&m, o, r);
    int linear = o->linear;
    mpi_part_end(&probe);
    if (st || linear)
        return st;
    return run_series(&m, ctx, o, r, mpi, result);
}

limn_status limn_mpi_mesh_morph(limn_context *ctx, const limn_mpi_mesh *from,
                                const limn_mpi_mesh *to, const limn_morph_options *options,
                                limn_mpi_morph_frame_fn fn, void *user,
                                limn_series_report *report, const limn_mpi_options *mpi,
                                limn_mpi_result *result)
{
    if (!ctx)
        return LIMN_ERR_ARGUMENT;
    if (!from || !to)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "limn_mpi_mesh_morph: %s is NULL",
                        from ? "TO" : "FROM");
    mpi_call c;
    limn_status st = mpi_enter(&c, ctx, from->comm, "limn_mpi_mesh_morph", &abi_morph_options,
                               options, &abi_series_report, report, mpi, result, NULL);
    return st ? st
              : mpi_leave(&c, morph_sized(ctx, from, to, c.abi.options, fn, user, c.abi.report,
                                          c.mpi, c.result));
}
