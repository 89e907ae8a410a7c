/* SPDX-License-Identifier: MIT */
/*
 * Local rows, the rank side (mpi_local.h): from the sub-mesh's operator, the
 * owned rows in mpi_part.h's four classes (increasing global index within a
 * class, the order mpi_distribute gives without RCM), the ghosts (columns of
 * those rows owned elsewhere) sorted by owner and the owner's local number,
 * and the halo. Which owned vertices another rank needs is known only to
 * that rank (a row's columns are not symmetric: a boundary vertex's Loop row
 * skips its interior neighbours, whose rows read it), so every rank sends
 * each owner the ids it reads; the owner answers with the local number and
 * vertex rule of each.
 */
#include "mpi/mpi_local.h"
#include "base/large_alloc.h"

#include "base/context.h"
#include "scheme/scheme.h"

#include <limits.h>
#include <stdlib.h>
#include <string.h>

typedef struct ghost {
    uint64_t key; /* owner << 32 | id (requests), then owner << 32 | owner's local number */
    uint32_t sub; /* sub-mesh index */
    uint32_t rule;
} ghost;

static int cmp_ghost(const void *a, const void *b)
{
    uint64_t x = ((const ghost *)a)->key, y = ((const ghost *)b)->key;
    return x < y ? -1 : x > y;
}

typedef struct rows_tmp {
    uint8_t *flag;     /* per owned vertex: bit 0 ghost column, bit 1 needed elsewhere */
    uint32_t *own_of;  /* per sub-mesh vertex: owned index or UINT32_MAX */
    uint32_t *lidx;    /* per owned vertex: local number */
    uint32_t *loc;     /* per sub-mesh vertex: local column */
    ghost *g;
    size_t ng;
    int *cnt, *rcnt;   /* per rank: ghosts asked of it, ids it asks of this rank */
    uint32_t *req;     /* ids asked of this rank, by asking rank */
    size_t nreq;
} rows_tmp;

static void tmp_free(rows_tmp *t)
{
    free(t->flag);
    free(t->own_of);
    free(t->lidx);
    free(t->loc);
    free(t->g);
    free(t->cnt);
    free(t->req);
}

static const uint32_t *row_begin(const local_sub *s, uint32_t o, uint32_t *len)
{
    const stencil_csr *a = &s->op.host;
    *len = a->row_offsets[o + 1] - a->row_offsets[o];
    return a->columns + a->row_offsets[o];
}

/* Ghost columns of the owned rows (flag bit 0), listed by (owner, id): only
   the near rows' are read when s->near is there (mpi_local_counts), the
   rest have none. */
static limn_status find_ghosts(mpi_part *p, local_sub *s, rows_tmp *t)
{
    size_t n = s->n, no = s->n_owned, R = (size_t)p->size;
    uint8_t *mark = calloc(n ? n : 1, 1);
    t->flag = calloc(no ? no : 1, 1);
    t->own_of = large_malloc((n ? n : 1) * sizeof *t->own_of);
    t->cnt = calloc(2 * R, sizeof *t->cnt);
    mpi_local_note(s, n);
    if (!mark || !t->flag || !t->own_of || !t->cnt) {
        free(mark);
        return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for the ghosts");
    }
    t->rcnt = t->cnt + R;
    for (size_t i = 0; i < n; i++)
        t->own_of[i] = UINT32_MAX;
    for (size_t i = 0; i < no; i++)
        t->own_of[s->owned[i]] = (uint32_t)i;
    for (size_t i = 0; i < no; i++) {
        uint32_t len, o = s->owned[i];
        if (s->near && !(s->near[o >> 6] >> (o & 63) & 1))
            continue;
        const uint32_t *c = row_begin(s, o, &len);
        for (uint32_t e = 0; e < len; e++)
            if (s->part[c[e]] != (uint32_t)p->rank) {
                t->flag[i] |= 1;
                t->ng += !mark[c[e]];
                mark[c[e]] = 1;
            }
    }
    t->g = large_malloc((t->ng ? t->ng : 1) * sizeof *t->g);
    mpi_local_note(s, t->ng);
    if (!t->g) {
        free(mark);
        return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu ghosts", t->ng);
    }
    for (size_t i = 0, k = 0; i < n; i++)
        if (mark[i]) {
            t->g[k++] = (ghost){(uint64_t)s->part[i] << 32 | s->ids[i], (uint32_t)i, 0};
            t->cnt[s->part[i]]++;
        }
    free(mark);
    qsort(t->g, t->ng, sizeof *t->g, cmp_ghost);
    return LIMN_OK;
}

/* Sends each owner the ids this rank reads; marks the owned vertices other
   ranks read (flag bit 1). */
static limn_status exchange_requests(mpi_part *p, local_sub *s, rows_tmp *t)
{
    uint32_t *ids = large_malloc((t->ng ? t->ng : 1) * sizeof *ids);
    limn_status st = ids ? LIMN_OK : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory");
    for (size_t i = 0; ids && i < t->ng; i++)
        ids[i] = (uint32_t)t->g[i].key;
    st = mpi_agree(p, st);
    void *got = NULL;
    if (!st)
        st = mpi_local_alltoallv(p, ids, t->cnt, sizeof *ids, &got, t->rcnt, &t->nreq);
    free(ids);
    t->req = got;
    mpi_local_note(s, t->nreq);
    for (size_t i = 0; !st && i < t->nreq; i++) {
        size_t k = 0, lo = 0, hi = s->n;
        while (lo < hi) { /* the sub-mesh index of the id asked */
            k = lo + (hi - lo) / 2;
            if (s->ids[k] < t->req[i])
                lo = k + 1;
            else
                hi = k;
        }
        if (lo == s->n || s->ids[lo] != t->req[i] || t->own_of[lo] == UINT32_MAX)
            st = ctx_fail(p->ctx, LIMN_ERR_ARGUMENT,
                          "another rank reads vertex %u from rank %d, which does not own it "
                          "(the ranks disagree on the partition)",
                          t->req[i], p->rank);
        else
            t->flag[t->own_of[lo]] |= 2;
        if (!st)
            t->req[i] = t->own_of[lo]; /* from now on: the owned index */
    }
    return mpi_agree(p, st);
}

/* The four classes and every owned vertex's local number (owned_ids too). */
static limn_status classes(mpi_part *p, local_sub *s, rows_tmp *t)
{
    static const int cls[4] = {0, 3, 1, 2}; /* flag -> class */
    size_t no = s->n_owned, off[5] = {0, 0, 0, 0, 0};
    t->lidx = large_malloc((no ? no : 1) * sizeof *t->lidx);
    if (!t->lidx)
        return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu rows", no);
    for (size_t i = 0; i < no; i++)
        off[cls[t->flag[i]] + 1]++;
    for (int c = 0; c < 4; c++)
        off[c + 1] += off[c];
    p->send_begin = off[1];
    p->n_interior = off[2];
    p->send_end = off[3];
    for (size_t i = 0; i < no; i++) /* increasing id within a class */
        t->lidx[i] = (uint32_t)off[cls[t->flag[i]]]++;
    return LIMN_OK;
}

/* Answers the requests with (local number, rule); sorts the ghosts by
   (owner, owner's local number) with their rules. */
static limn_status exchange_answers(mpi_part *p, local_sub *s, rows_tmp *t)
{
    uint32_t *ans = large_malloc((t->nreq ? 2 * t->nreq : 1) * sizeof *ans);
    limn_status st = ans ? LIMN_OK : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory");
    for (size_t i = 0; ans && i < t->nreq; i++) {
        ans[2 * i] = t->lidx[t->req[i]];
        ans[2 * i + 1] = s->op.topo.vertex_rule[s->owned[t->req[i]]];
    }
    st = mpi_agree(p, st);
    void *got = NULL;
    size_t n = 0;
    int *back = large_malloc((size_t)p->size * sizeof *back);
    if (!st && !back)
        st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory");
    st = mpi_agree(p, st);
    if (!st)
        st = mpi_local_alltoallv(p, ans, t->rcnt, 2 * sizeof *ans, &got, back, &n);
    const uint32_t *w = got;
    for (size_t i = 0; !st && i < t->ng; i++) {
        t->g[i].key = (t->g[i].key >> 32) << 32 | w[2 * i];
        t->g[i].rule = w[2 * i + 1];
    }
    if (!st)
        qsort(t->g, t->ng, sizeof *t->g, cmp_ghost);
    free(ans);
    free(back);
    free(got);
    return st;
}

/* fill_rows' second half: the rows of classes 1-3 (from p->send_begin in
   local order) set aside, then every owned row moved down into local order
   (order: local index -> owned index) with its columns renumbered by t->loc;
   offsets (no + 1) filled; the table becomes p->host. */
static limn_status move_rows(mpi_part *p, local_sub *s, const rows_tmp *t,
                             const uint32_t *order, uint32_t *offsets)
{
    stencil_csr *a = &s->op.host;
    size_t no = s->n_owned, aside = 0, first = p->send_begin;
    for (size_t l = first; l < no; l++) {
        uint32_t len;
        row_begin(s, s->owned[order[l]], &len);
        aside += len;
    }
    uint32_t *cols_aside = large_malloc((aside ? aside : 1) * sizeof *cols_aside);
    double *w_aside = large_malloc((aside ? aside : 1) * sizeof *w_aside);
    if (!cols_aside || !w_aside) {
        free(cols_aside);
        free(w_aside);
        return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for the rows of rank %d",
                        p->rank);
    }
    uint32_t *cols = a->columns;
    double *w = a->weights;
    for (size_t l = first, k = 0; l < no; l++) {
        uint32_t o = s->owned[order[l]];
        for (uint32_t e = a->row_offsets[o]; e < a->row_offsets[o + 1]; e++, k++) {
            cols_aside[k] = t->loc[cols[e]];
            w_aside[k] = w[e];
        }
    }
    size_t e2 = 0; /* never past e: the rows before are class 0 ones, a subset */
    offsets[0] = 0;
    for (size_t l = 0; l < no; l++) {
        uint32_t o = s->owned[order[l]];
        p->owned_ids[l] = s->ids[o];
        p->owned_rule[l] = s->op.topo.vertex_rule[o];
        p->owned_scale[l] = scheme_limit_row_scale(&s->op.topo, p->scheme, o);
        if (l < first) {
            for (uint32_t e = a->row_offsets[o]; e < a->row_offsets[o + 1]; e++, e2++) {
                cols[e2] = t->loc[cols[e]];
                w[e2] = w[e];
            }
        } else {
            uint32_t len = a->row_offsets[o + 1] - a->row_offsets[o];
            memcpy(cols + e2, cols_aside + (e2 - offsets[first]), len * sizeof *cols);
            memcpy(w + e2, w_aside + (e2 - offsets[first]), len * sizeof *w);
            e2 += len;
        }
        offsets[l + 1] = (uint32_t)e2;
    }
    free(cols_aside);
    free(w_aside);
    /* the table is p's now; shrunk to its rows (the old block kept if not) */
    uint32_t *c = realloc(cols, (e2 ? e2 : 1) * sizeof *c);
    double *wr = realloc(w, (e2 ? e2 : 1) * sizeof *wr);
    p->host.columns = c ? c : cols;
    p->host.weights = wr ? wr : w;
    a->columns = NULL;
    a->weights = NULL;
    p->host.row_offsets = offsets;
    p->host.rows = no;
    p->host.cols = no + t->ng;
    return LIMN_OK;
}

/* Rows, ids, rules and scales into p. The sub-mesh operator's table becomes
   p's: the owned rows move down into local order in place, their columns
   renumbered on the way, so a rank never holds its rows twice. Class 0 (no
   ghost column, read by no other rank: nearly every row) comes first in
   increasing id, as the sub-mesh's rows are, so each of its rows lands at or
   before where it was; the other classes are set aside first. */
static limn_status fill_rows(mpi_part *p, local_sub *s, rows_tmp *t)
{
    size_t no = s->n_owned, ng = t->ng, nnz = 0;
    for (size_t i = 0; i < no; i++) {
        uint32_t len;
        row_begin(s, s->owned[i], &len);
        nnz += len;
    }
    if (nnz > INT_MAX || 3 * no > INT_MAX || 3 * ng > INT_MAX)
        return ctx_fail(p->ctx, LIMN_ERR_MEMORY,
                        "rank %d would hold %zu rows and %zu entries: too many for one MPI "
                        "message; use more ranks",
                        p->rank, no, nnz);
    int ids = mpi_part_ids_alloc(p, no, ng);
    t->loc = large_malloc((s->n ? s->n : 1) * sizeof *t->loc);
    uint32_t *order = large_malloc((no ? no : 1) * sizeof *order);
    uint32_t *offsets = large_malloc((no + 1) * sizeof *offsets);
    mpi_local_note(s, s->n);
    if (!ids || !t->loc || !order || !offsets) {
        free(order);
        free(offsets);
        return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for the rows of rank %d",
                        p->rank);
    }
    p->n_owned = no;
    p->n_ghost = ng;
    for (size_t i = 0; i < no; i++) {
        uint32_t o = s->owned[i];
        order[t->lidx[i]] = (uint32_t)i;
        t->loc[o] = t->lidx[i];
    }
    for (size_t k = 0; k < ng; k++) {
        p->ghost_ids[k] = s->ids[t->g[k].sub];
        p->ghost_rule[k] = (uint8_t)t->g[k].rule;
        t->loc[t->g[k].sub] = (uint32_t)(no + k);
    }
    limn_status st = move_rows(p, s, t, order, offsets);
    free(order);
    if (st)
        free(offsets);
    return st;
}

static int cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return x < y ? -1 : x > y;
}

/* A receive per owner among the ghosts, a send per rank that reads this
   rank's values (in the asking rank's order: the owner's local numbers). */
static limn_status fill_halo(mpi_part *p, rows_tmp *t)
{
    mpi_halo *h = &p->halo;
    size_t R = (size_t)p->size, nr = 0, ns = 0;
    for (size_t r = 0; r < R; r++) {
        nr += t->cnt[r] > 0;
        ns += t->rcnt[r] > 0;
    }
    h->recv_rank = large_malloc((nr ? nr : 1) * sizeof *h->recv_rank);
    h->recv_off = large_malloc((nr ? nr : 1) * sizeof *h->recv_off);
    h->recv_cnt = large_malloc((nr ? nr : 1) * sizeof *h->recv_cnt);
    h->send_rank = large_malloc((ns ? ns : 1) * sizeof *h->send_rank);
    h->send_off = large_malloc((ns ? ns : 1) * sizeof *h->send_off);
    h->send_cnt = large_malloc((ns ? ns : 1) * sizeof *h->send_cnt);
    h->send_idx = large_malloc((t->nreq ? t->nreq : 1) * sizeof *h->send_idx);
    if (!h->recv_rank || !h->recv_off || !h->recv_cnt || !h->send_rank || !h->send_off ||
        !h->send_cnt || !h->send_idx)
        return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for the halo plan");
    h->n_recv = (int)nr;
    h->n_send = (int)ns;
    size_t off = 0, q = 0, sq = 0;
    for (size_t r = 0; r < R; r++) {
        if (t->cnt[r] > 0) {
            h->recv_rank[q] = (int)r;
            h->recv_off[q] = off;
            h->recv_cnt[q++] = (size_t)t->cnt[r];
            off += (size_t)t->cnt[r];
        }
    }
    for (size_t r = 0, at = 0; r < R; r++) {
        if (t->rcnt[r] <= 0)
            continue;
        for (int i = 0; i < t->rcnt[r]; i++)
            h->send_idx[at + (size_t)i] = t->lidx[t->req[at + (size_t)i]];
        qsort(h->send_idx + at, (size_t)t->rcnt[r], sizeof *h->send_idx, cmp_u32);
        for (int i = 0; i < t->rcnt[r]; i++)
            h->send_idx[at + (size_t)i] -= (uint32_t)p->send_begin;
        h->send_rank[sq] = (int)r;
        h->send_off[sq] = at;
        h->send_cnt[sq++] = (size_t)t->rcnt[r];
        at += (size_t)t->rcnt[r];
    }
    return LIMN_OK;
}

limn_status mpi_local_rows(mpi_part *p, local_sub *s)
{
    rows_tmp t;
    memset(&t, 0, sizeof t);
    limn_status st = find_ghosts(p, s, &t);
    free(s->near);
    s->near = NULL;
    st = mpi_agree(p, st);
    if (!st)
        st = exchange_requests(p, s, &t);
    if (!st)
        st = classes(p, s, &t);
    st = mpi_agree(p, st);
    if (!st)
        st = exchange_answers(p, s, &t);
    if (!st)
        st = fill_rows(p, s, &t);
    if (!st)
        st = fill_halo(p, &t);
    tmp_free(&t);
    return mpi_agree(p, st);
}
