/* SPDX-License-Identifier: MIT */
/*
 * The root builds the global operator once and sends each rank its rows
 * (mpi_part.h has the local numbering). Why not build rows on each rank from
 * its faces: a row does depend only on the faces incident to its vertex, but
 * the single process sums a row's entries in the global (RCM) column order,
 * which only the global operator knows; shipping its rows keeps every
 * product bit for bit equal to the single process on any rank count. The
 * cost is a serial build on the root (measured in README "MPI").
 */
#include "mpi/mpi_part.h"
#include "base/large_alloc.h"

#include "base/context.h"
#include "mesh/mesh.h"
#include "scheme/scheme.h"
#include "topology/topology.h"

#include <limits.h>
#include <stdlib.h>
#include <string.h>

enum { TAG_HEADER = 7101, TAG_IDS, TAG_RULES, TAG_SCALES, TAG_GHOSTS, TAG_GHOST_RULES,
       TAG_OFFSETS, TAG_COLUMNS, TAG_WEIGHTS, TAG_RECV, TAG_SEND, TAG_SEND_IDX };

/* Header of a rank's rows, sent as 64-bit integers. */
enum { H_STATUS, H_N, H_FACES, H_NNZ_GLOBAL, H_CUT, H_SCHEME, H_REORDERED, H_OWNED, H_GHOST,
       H_INTERIOR, H_SEND_BEGIN, H_SEND_END, H_NNZ, H_N_RECV, H_N_SEND, H_SEND_IDX, H_WIDTH };

/* The root's view of every rank. */
typedef struct plan {
    const stencil_operator *g;
    const uint32_t *part;
    uint32_t *lidx;           /* local number of each vertex on its owner */
    uint32_t *loc;            /* scratch: local number on the rank being built */
    size_t *cls_off;          /* 4 per rank + 1: the four classes of mpi_part.h */
    size_t *ghost_off;        /* per rank + 1 */
    uint32_t *ghosts;         /* each rank's ghosts, by owner then the owner's number */
    size_t *run_off;          /* per rank + 1: runs of one owner in its ghost list */
    uint32_t *run_owner;
    size_t *run_begin, *run_cnt;
} plan;

static void plan_free(plan *pl)
{
    free(pl->lidx);
    free(pl->loc);
    free(pl->cls_off);
    free(pl->ghost_off);
    free(pl->ghosts);
    free(pl->run_off);
    free(pl->run_owner);
    free(pl->run_begin);
    free(pl->run_cnt);
}

static uint32_t vert(const stencil_operator *g, size_t row)
{
    return g->order ? g->order[row] : (uint32_t)row;
}
static uint32_t row_of(const stencil_operator *g, uint32_t v) { return g->rank ? g->rank[v] : v; }

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

/* Classes and local numbers of every vertex (root_off, root_ids, lidx). */
static limn_status plan_classes(mpi_part *p, plan *pl)
{
    const stencil_csr *a = &pl->g->host;
    size_t n = a->rows, R = (size_t)p->size;
    uint8_t *flag = calloc(n ? n : 1, 1);
    size_t *cursor = large_malloc(4 * R * sizeof *cursor);
    pl->cls_off = calloc(4 * R + 1, sizeof *pl->cls_off);
    pl->lidx = large_malloc((n ? n : 1) * sizeof *pl->lidx);
    p->root_off = large_malloc((R + 1) * sizeof *p->root_off);
    p->root_ids = large_malloc((n ? n : 1) * sizeof *p->root_ids);
    if (!flag || !cursor || !pl->cls_off || !pl->lidx || !p->root_off || !p->root_ids) {
        free(flag);
        free(cursor);
        return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory partitioning %zu rows", n);
    }
    /* bit 0: the row has a ghost column; bit 1: another rank's row needs it */
    for (size_t k = 0; k < n; k++) {
        uint32_t v = vert(pl->g, k);
        for (uint32_t e = a->row_offsets[k]; e < a->row_offsets[k + 1]; e++) {
            uint32_t u = vert(pl->g, a->columns[e]);
            if (pl->part[u] != pl->part[v]) {
                flag[v] |= 1;
                flag[u] |= 2;
            }
        }
    }
    static const int cls[4] = {0, 3, 1, 2}; /* flag -> class */
    for (size_t v = 0; v < n; v++)
        pl->cls_off[4 * pl->part[v] + (size_t)cls[flag[v]] + 1]++;
    for (size_t i = 0; i < 4 * R; i++)
        pl->cls_off[i + 1] += pl->cls_off[i];
    memcpy(cursor, pl->cls_off, 4 * R * sizeof *cursor);
    for (size_t r = 0; r <= R; r++)
        p->root_off[r] = pl->cls_off[4 * r];
    for (size_t k = 0; k < n; k++) { /* solve order within a class: locality */
        uint32_t v = vert(pl->g, k), r = pl->part[v];
        size_t at = cursor[4 * r + (size_t)cls[flag[v]]]++;
        p->root_ids[at] = v;
        pl->lidx[v] = (uint32_t)(at - p->root_off[r]);
    }
    free(flag);
    free(cursor);
    return LIMN_OK;
}

/* Appends the vertices rank r reads but does not own to pl->ghosts (used
   of cap entries), each once (stamp: r + 1 where already listed). */
static limn_status collect_ghosts(mpi_part *p, plan *pl, size_t r, uint32_t *stamp, size_t *cap,
                                  size_t *used)
{
    const stencil_csr *a = &pl->g->host;
    for (size_t i = p->root_off[r]; i < p->root_off[r + 1]; i++) {
        uint32_t k = row_of(pl->g, p->root_ids[i]);
        for (uint32_t e = a->row_offsets[k]; e < a->row_offsets[k + 1]; e++) {
            uint32_t u = vert(pl->g, a->columns[e]);
            if (pl->part[u] == r || stamp[u] == r + 1)
                continue;
            stamp[u] = (uint32_t)r + 1;
            if (*used == *cap) {
                uint32_t *grown = realloc(pl->ghosts, 2 * *cap * sizeof *grown);
                if (!grown)
                    return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for ghosts");
                pl->ghosts = grown;
                *cap *= 2;
            }
            pl->ghosts[(*used)++] = u;
        }
    }
    return LIMN_OK;
}

/* Doubles the room of the run lists. */
static limn_status grow_runs(mpi_part *p, plan *pl, size_t *run_cap)
{
    *run_cap *= 2;
    uint32_t *o = realloc(pl->run_owner, *run_cap * sizeof *o);
    if (o)
        pl->run_owner = o;
    size_t *b = realloc(pl->run_begin, *run_cap * sizeof *b);
    if (b)
        pl->run_begin = b;
    size_t *c = realloc(pl->run_cnt, *run_cap * sizeof *c);
    if (c)
        pl->run_cnt = c;
    if (!o || !b || !c)
        return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for ghosts");
    return LIMN_OK;
}

/* Sorts the count ghosts from `start` by (owner, owner's number), as
   vertices again, and lists their runs of one owner (keys: scratch). */
static limn_status sort_ghosts(mpi_part *p, plan *pl, size_t start, size_t count, uint64_t *keys,
                               size_t *runs, size_t *run_cap)
{
    for (size_t i = 0; i < count; i++) {
        uint32_t u = pl->ghosts[start + i];
        keys[i] = (uint64_t)pl->part[u] << 32 | pl->lidx[u];
    }
    qsort(keys, count, sizeof *keys, cmp_u64);
    for (size_t i = 0; i < count; i++) {
        uint32_t owner = (uint32_t)(keys[i] >> 32);
        pl->ghosts[start + i] = p->root_ids[p->root_off[owner] + (uint32_t)keys[i]];
        if (i == 0 || owner != (uint32_t)(keys[i - 1] >> 32)) {
            limn_status st = *runs == *run_cap ? grow_runs(p, pl, run_cap) : LIMN_OK;
            if (st)
                return st;
            pl->run_owner[*runs] = owner;
            pl->run_begin[*runs] = start + i;
            pl->run_cnt[(*runs)++] = 0;
        }
        pl->run_cnt[*runs - 1]++;
    }
    return LIMN_OK;
}

/* Every rank's ghosts, sorted by (owner, owner's number), and their runs. */
static limn_status plan_ghosts(mpi_part *p, plan *pl)
{
    size_t n = pl->g->host.rows, R = (size_t)p->size, cap = 1024, used = 0, runs = 0,
           run_cap = 64;
    uint32_t *stamp = calloc(n ? n : 1, sizeof *stamp);
    pl->ghost_off = calloc(R + 1, sizeof *pl->ghost_off);
    pl->run_off = calloc(R + 1, sizeof *pl->run_off);
    pl->ghosts = large_malloc(cap * sizeof *pl->ghosts);
    pl->run_owner = large_malloc(run_cap * sizeof *pl->run_owner);
    pl->run_begin = large_malloc(run_cap * sizeof *pl->run_begin);
    pl->run_cnt = large_malloc(run_cap * sizeof *pl->run_cnt);
    pl->loc = large_malloc((n ? n : 1) * sizeof *pl->loc);
    uint64_t *keys = NULL;
    limn_status st = LIMN_OK;
    if (!stamp || !pl->ghost_off || !pl->run_off || !pl->ghosts || !pl->run_owner ||
        !pl->run_begin || !pl->run_cnt || !pl->loc)
        st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for the ghost lists");
    for (size_t r = 0; !st && r < R; r++) {
        size_t start = used;
        st = collect_ghosts(p, pl, r, stamp, &cap, &used);
        size_t count = used - start;
        uint64_t *grown = st ? NULL : realloc(keys, (count ? count : 1) * sizeof *keys);
        if (!st && !grown)
            st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for ghosts");
        if (st)
            break;
        keys = grown;
        st = sort_ghosts(p, pl, start, count, keys, &runs, &run_cap);
        pl->ghost_off[r + 1] = used;
        pl->run_off[r + 1] = runs;
    }
    free(keys);
    free(stamp);
    return st;
}

/* The row and halo arrays of a part (none of length 0); 1 when all are there. */
static int rows_alloc(mpi_part *d, size_t no, size_t ng, size_t nnz, int n_recv, int n_send,
                      size_t n_idx)
{
    mpi_halo *h = &d->halo;
    size_t nr = (size_t)(n_recv ? n_recv : 1), ns = (size_t)(n_send ? n_send : 1);
    int rows = mpi_part_rows_alloc(d, no, ng, nnz);
    h->recv_rank = large_malloc(nr * sizeof *h->recv_rank);
    h->recv_off = large_malloc(nr * sizeof *h->recv_off);
    h->recv_cnt = large_malloc(nr * sizeof *h->recv_cnt);
    h->send_rank = large_malloc(ns * sizeof *h->send_rank);
    h->send_off = large_malloc(ns * sizeof *h->send_off);
    h->send_cnt = large_malloc(ns * sizeof *h->send_cnt);
    h->send_idx = large_malloc((n_idx ? n_idx : 1) * sizeof *h->send_idx);
    return rows && h->recv_rank && h->recv_off && h->recv_cnt && h->send_rank && h->send_off &&
           h->send_cnt && h->send_idx;
}

static void rows_free(mpi_part *d)
{
    free(d->owned_ids);
    free(d->owned_rule);
    free(d->owned_scale);
    free(d->ghost_ids);
    free(d->ghost_rule);
    stencil_free(&d->host);
    mpi_halo_free(&d->halo);
}

/* Rank r's owned and ghost vertices (ids, rules, scales) and its rows:
   each global row as it is, entries in its order, columns renamed. */
static void fill_rows(mpi_part *p, plan *pl, int r, mpi_part *dst)
{
    const stencil_operator *g = pl->g;
    const stencil_csr *a = &g->host;
    size_t o0 = p->root_off[r], no = dst->n_owned, g0 = pl->ghost_off[r], ng = dst->n_ghost;
    for (size_t i = 0; i < no; i++) {
        uint32_t v = p->root_ids[o0 + i];
        dst->owned_ids[i] = v;
        dst->owned_rule[i] = g->topo.vertex_rule[v];
        dst->owned_scale[i] = scheme_limit_row_scale(&g->topo, g->scheme, v);
        pl->loc[v] = (uint32_t)i;
    }
    for (size_t i = 0; i < ng; i++) {
        dst->ghost_ids[i] = pl->ghosts[g0 + i];
        dst->ghost_rule[i] = g->topo.vertex_rule[pl->ghosts[g0 + i]];
        pl->loc[pl->ghosts[g0 + i]] = (uint32_t)(no + i);
    }
    size_t e2 = 0;
    dst->host.rows = no;
    dst->host.cols = no + ng;
    dst->host.row_offsets[0] = 0;
    for (size_t i = 0; i < no; i++) {
        uint32_t k = row_of(g, dst->owned_ids[i]);
        for (uint32_t e = a->row_offsets[k]; e < a->row_offsets[k + 1]; e++, e2++) {
            dst->host.columns[e2] = pl->loc[vert(g, a->columns[e])];
            dst->host.weights[e2] = a->weights[e];
        }
        dst->host.row_offsets[i + 1] = (uint32_t)e2;
    }
}

/* Rank r's halo plan: a receive per run of its ghost list, a send per run
   of another rank's list that r owns. */
static void fill_halo(mpi_part *p, plan *pl, int r, mpi_part *dst)
{
    mpi_halo *h = &dst->halo;
    size_t off = 0;
    for (int q = 0; q < h->n_recv; q++) {
        size_t run = pl->run_off[r] + (size_t)q;
        h->recv_rank[q] = (int)pl->run_owner[run];
        h->recv_off[q] = off;
        h->recv_cnt[q] = pl->run_cnt[run];
        off += pl->run_cnt[run];
    }
    int q = 0;
    size_t n_idx = 0;
    for (int s = 0; s < p->size; s++)
        for (size_t run = pl->run_off[s]; run < pl->run_off[s + 1]; run++) {
            if (pl->run_owner[run] != (uint32_t)r)
                continue;
            h->send_rank[q] = s;
            h->send_off[q] = n_idx;
            h->send_cnt[q++] = pl->run_cnt[run];
            for (size_t i = 0; i < pl->run_cnt[run]; i++) {
                /* a vertex another rank needs sits in [send_begin, send_end) */
                uint32_t l = pl->lidx[pl->ghosts[pl->run_begin[run] + i]];
                h->send_idx[n_idx++] = (uint32_t)(l - dst->send_begin);
            }
        }
}

/* Rank r's rows and halo plan, into dst (the root's own part, or a scratch
   part that is sent and freed). */
static limn_status build_rows(mpi_part *p, plan *pl, int r, mpi_part *dst)
{
    const stencil_operator *g = pl->g;
    const stencil_csr *a = &g->host;
    size_t o0 = p->root_off[r], no = p->root_off[r + 1] - o0;
    size_t g0 = pl->ghost_off[r], ng = pl->ghost_off[r + 1] - g0;
    dst->n_owned = no;
    dst->n_ghost = ng;
    dst->send_begin = pl->cls_off[4 * (size_t)r + 1] - o0;
    dst->n_interior = pl->cls_off[4 * (size_t)r + 2] - o0;
    dst->send_end = pl->cls_off[4 * (size_t)r + 3] - o0;
    size_t nnz = 0;
    for (size_t i = 0; i < no; i++) {
        uint32_t k = row_of(g, p->root_ids[o0 + i]);
        nnz += a->row_offsets[k + 1] - a->row_offsets[k];
    }
    /* the senders: ranks s whose ghost lists hold a run owned by r */
    int n_send = 0;
    size_t n_idx = 0;
    for (int s = 0; s < p->size; s++)
        for (size_t q = pl->run_off[s]; q < pl->run_off[s + 1]; q++)
            if (pl->run_owner[q] == (uint32_t)r) {
                n_send++;
                n_idx += pl->run_cnt[q];
            }
    int n_recv = (int)(pl->run_off[r + 1] - pl->run_off[r]);
    if (!rows_alloc(dst, no, ng, nnz, n_recv, n_send, n_idx))
        return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for the rows of rank %d", r);
    if (nnz > INT_MAX || 3 * no > INT_MAX || 3 * ng > INT_MAX || 3 * n_idx > INT_MAX)
        return ctx_fail(p->ctx, LIMN_ERR_MEMORY,
                         "rank %d would hold %zu rows and %zu entries: too many for one MPI "
                         "message; use more ranks",
                         r, no, nnz);
    dst->halo.n_recv = n_recv;
    dst->halo.n_send = n_send;
    fill_rows(p, pl, r, dst);
    fill_halo(p, pl, r, dst);
    return LIMN_OK;
}

static void header_of(const mpi_part *p, const mpi_part *d, limn_status st, uint64_t *h,
                      double *dh)
{
    memset(h, 0, H_WIDTH * sizeof *h);
    h[H_STATUS] = (uint64_t)st;
    h[H_N] = p->n_global;
    h[H_FACES] = p->faces_global;
    h[H_NNZ_GLOBAL] = p->nnz_global;
    h[H_CUT] = p->edge_cut;
    h[H_SCHEME] = (uint64_t)p->scheme;
    h[H_REORDERED] = (uint64_t)p->reordered;
    if (!st) {
        h[H_OWNED] = d->n_owned;
        h[H_GHOST] = d->n_ghost;
        h[H_INTERIOR] = d->n_interior;
        h[H_SEND_BEGIN] = d->send_begin;
        h[H_SEND_END] = d->send_end;
        h[H_NNZ] = d->host.row_offsets[d->n_owned];
        h[H_N_RECV] = (uint64_t)d->halo.n_recv;
        h[H_N_SEND] = (uint64_t)d->halo.n_send;
        h[H_SEND_IDX] = d->halo.n_send ? d->halo.send_off[d->halo.n_send - 1] +
                                             d->halo.send_cnt[d->halo.n_send - 1]
                                       : 0;
    }
    dh[0] = p->alpha;
    dh[1] = p->diag;
}

/* size_t arrays travel as 64-bit integers */
static MPI_Datatype size_type(void)
{
    return sizeof(size_t) == 8 ? MPI_UINT64_T : MPI_UINT32_T;
}

/* The arrays of a part's rows and halo plan as they travel, in this order
   (send_rows, recv_rows): where each is, its length and type. */
enum { ROW_MSGS = 13 };
typedef struct row_msgs {
    void *ptr[ROW_MSGS];
    int count[ROW_MSGS];
    MPI_Datatype type[ROW_MSGS];
} row_msgs;
static const int row_tags[ROW_MSGS] = {
    TAG_IDS,     TAG_RULES,   TAG_SCALES,  TAG_GHOSTS, TAG_GHOST_RULES, TAG_OFFSETS, TAG_COLUMNS,
    TAG_WEIGHTS, TAG_RECV,    TAG_RECV,    TAG_SEND,   TAG_SEND,        TAG_SEND_IDX};

static row_msgs row_msgs_of(const mpi_part *d, size_t nnz, int n_recv, int n_send, size_t nidx)
{
    const mpi_halo *h = &d->halo;
    int no = (int)d->n_owned, ng = (int)d->n_ghost;
    return (row_msgs){{d->owned_ids, d->owned_rule, d->owned_scale, d->ghost_ids, d->ghost_rule,
                       d->host.row_offsets, d->host.columns, d->host.weights, h->recv_rank,
                       h->recv_cnt, h->send_rank, h->send_cnt, h->send_idx},
                      {no, no, no, ng, ng, no + 1, (int)nnz, (int)nnz, n_recv, n_recv, n_send,
                       n_send, (int)nidx},
                      {MPI_UINT32_T, MPI_UINT8_T, MPI_DOUBLE, MPI_UINT32_T, MPI_UINT8_T,
                       MPI_UINT32_T, MPI_UINT32_T, MPI_DOUBLE, MPI_INT, size_type(), MPI_INT,
                       size_type(), MPI_UINT32_T}};
}

static void send_rows(mpi_part *p, int r, const mpi_part *d, limn_status st)
{
    uint64_t h[H_WIDTH];
    double dh[2];
    header_of(p, d, st, h, dh);
    MPI_Send(h, H_WIDTH, MPI_UINT64_T, r, TAG_HEADER, p->comm);
    MPI_Send(dh, 2, MPI_DOUBLE, r, TAG_HEADER, p->comm);
    if (st)
        return;
    row_msgs m = row_msgs_of(d, h[H_NNZ], d->halo.n_recv, d->halo.n_send, h[H_SEND_IDX]);
    for (int k = 0; k < ROW_MSGS; k++)
        MPI_Send(m.ptr[k], m.count[k], m.type[k], r, row_tags[k], p->comm);
}

/* Receives one message into scratch and drops it. */
static void drop_message(mpi_part *p, int tag)
{
    MPI_Status status;
    int bytes = 0;
    MPI_Probe(p->root, tag, p->comm, &status);
    MPI_Get_count(&status, MPI_BYTE, &bytes);
    void *scratch = large_malloc(bytes > 0 ? (size_t)bytes : 1);
    MPI_Recv(scratch, bytes, MPI_BYTE, p->root, tag, p->comm, MPI_STATUS_IGNORE);
    free(scratch);
}

/* A non-root rank: the header, then (unless the root failed) the arrays. */
static limn_status recv_rows(mpi_part *p)
{
    uint64_t h[H_WIDTH];
    double dh[2];
    MPI_Recv(h, H_WIDTH, MPI_UINT64_T, p->root, TAG_HEADER, p->comm, MPI_STATUS_IGNORE);
    MPI_Recv(dh, 2, MPI_DOUBLE, p->root, TAG_HEADER, p->comm, MPI_STATUS_IGNORE);
    if (h[H_STATUS]) {
        p->echo = 1;
        return ctx_fail(p->ctx, (limn_status)h[H_STATUS], "the root failed");
    }
    p->n_global = h[H_N];
    p->faces_global = h[H_FACES];
    p->nnz_global = h[H_NNZ_GLOBAL];
    p->edge_cut = h[H_CUT];
    p->scheme = (limn_scheme)h[H_SCHEME];
    p->reordered = (int)h[H_REORDERED];
    p->alpha = dh[0];
    p->diag = dh[1];
    size_t no = h[H_OWNED], ng = h[H_GHOST], nnz = h[H_NNZ], nidx = h[H_SEND_IDX];
    int n_recv = (int)h[H_N_RECV], n_send = (int)h[H_N_SEND];
    mpi_halo *hl = &p->halo;
    p->n_owned = no;
    p->n_ghost = ng;
    p->n_interior = h[H_INTERIOR];
    p->send_begin = h[H_SEND_BEGIN];
    p->send_end = h[H_SEND_END];
    /* the messages are on their way: receive them even when memory ran out
       (into a scratch buffer), so that the root's sends complete */
    int ok = rows_alloc(p, no, ng, nnz, n_recv, n_send, nidx);
    row_msgs m = row_msgs_of(p, nnz, n_recv, n_send, nidx);
    for (int k = 0; k < ROW_MSGS; k++) {
        if (ok)
            MPI_Recv(m.ptr[k], m.count[k], m.type[k], p->root, row_tags[k], p->comm,
                     MPI_STATUS_IGNORE);
        else
            drop_message(p, row_tags[k]);
    }
    if (!ok)
        return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu rows", no);
    p->host.rows = no;
    p->host.cols = no + ng;
    hl->n_recv = n_recv;
    hl->n_send = n_send;
    for (int q = 0, off = 0; q < n_recv; off += (int)hl->recv_cnt[q], q++)
        hl->recv_off[q] = (size_t)off;
    for (int q = 0, off = 0; q < n_send; off += (int)hl->send_cnt[q], q++)
        hl->send_off[q] = (size_t)off;
    return LIMN_OK;
}

/* Root: the global operator, the partition and every rank's plan. */
static limn_status root_prepare(mpi_part *p, const limn_mesh *mesh, limn_scheme scheme,
                                double alpha, int reorder, const uint32_t *given, plan *pl)
{
    double t0 = MPI_Wtime();
    limn_status st = operator_build_ex(p->ctx, mesh, scheme, alpha,
                                       OPERATOR_HOST_ONLY | (reorder ? OPERATOR_REORDER : 0),
                                       &p->global);
    if (st)
        return st;
    p->has_global = 1;
    const stencil_operator *g = &p->global;
    p->scheme = g->scheme;
    p->alpha = g->alpha;
    p->diag = g->bbox_diagonal;
    p->n_global = mesh->vertex_count;
    p->faces_global = mesh->face_count;
    p->nnz_global = g->host.row_offsets[g->host.rows];
    p->reordered = g->order != NULL;
    if (3 * p->n_global > INT_MAX) /* MPI_Scatterv's displacements are ints */
        return ctx_fail(p->ctx, LIMN_ERR_MEMORY,
                         "%zu vertices are more than the MPI layer can scatter (%d at most)",
                         p->n_global, INT_MAX / 3);
    p->part_of = large_malloc((p->n_global ? p->n_global : 1) * sizeof *p->part_of);
    p->root_buf = large_malloc((p->n_global ? 3 * p->n_global : 1) * sizeof *p->root_buf);
    if (!p->part_of || !p->root_buf)
        return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu vertices", p->n_global);
    if (given) {
        memcpy(p->part_of, given, p->n_global * sizeof *p->part_of);
        st = mpi_edge_cut(p->ctx, mesh, p->size, p->part_of, &p->edge_cut);
    } else {
        st = mpi_partition(p->ctx, mesh, p->size, p->part_of, &p->edge_cut);
    }
    pl->g = g;
    pl->part = p->part_of;
    if (!st)
        st = plan_classes(p, pl);
    if (!st)
        st = plan_ghosts(p, pl);
    p->stats.seconds_partition = MPI_Wtime() - t0;
    return st;
}

limn_status mpi_distribute(mpi_part *p, const limn_mesh *mesh, limn_scheme scheme, double alpha,
                           int reorder)
{
    return mpi_distribute_part(p, mesh, scheme, alpha, reorder, NULL);
}

limn_status mpi_distribute_part(mpi_part *p, const limn_mesh *mesh, limn_scheme scheme,
                                double alpha, int reorder, const uint32_t *part_of)
{
    plan pl;
    memset(&pl, 0, sizeof pl);
    limn_status st = LIMN_OK;
    if (p->rank == p->root)
        st = root_prepare(p, mesh, scheme, alpha, reorder, part_of, &pl);
    st = mpi_agree(p, st);
    if (st) {
        plan_free(&pl);
        return st;
    }
    double t0 = MPI_Wtime();
    if (p->rank == p->root) {
        for (int r = 0; r < p->size; r++) {
            if (r == p->root) {
                limn_status mine = build_rows(p, &pl, r, p);
                st = st ? st : mine;
                continue;
            }
            mpi_part scratch;
            memset(&scratch, 0, sizeof scratch);
            limn_status built = st ? st : build_rows(p, &pl, r, &scratch);
            st = st ? st : built;
            send_rows(p, r, &scratch, built); /* a failure still tells r, so it never waits */
            rows_free(&scratch);
        }
    } else {
        st = recv_rows(p);
    }
    plan_free(&pl);
    if (!st)
        st = mpi_open_rows(p);
    p->stats.seconds_distribute = MPI_Wtime() - t0;
    return mpi_agree(p, st);
}
