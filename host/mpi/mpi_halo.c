/* SPDX-License-Identifier: MIT */
/*
 * Ghost exchange for one stencil product. The values other ranks need are
 * one contiguous device range (mpi_part.h), read in one transfer, packed
 * per neighbour as 3 doubles (or floats, for the float path) a vertex and
 * sent with MPI_Isend; each
 * neighbour's values arrive as one block (ghosts are sorted by owner) and
 * go to the device in one write. Rows free of ghost columns run between
 * posting and waiting.
 */
#include "mpi/mpi_part.h"
#include "base/large_alloc.h"

#include "base/context.h"

#include <stdlib.h>
#include <string.h>

enum { TAG_HALO = 7201 };

void mpi_halo_free(mpi_halo *h)
{
    free(h->recv_rank);
    free(h->recv_off);
    free(h->recv_cnt);
    free(h->send_rank);
    free(h->send_off);
    free(h->send_cnt);
    free(h->send_idx);
    free(h->stage4);
    free(h->send3);
    free(h->recv3);
    free(h->ghost4);
    free(h->req);
    memset(h, 0, sizeof *h);
}

/* The values of a vector on the wire: doubles, or floats (the float path's
   corrections, solve_mixed.c), 4 to a device row, 3 to a vertex sent. */
typedef struct width {
    size_t bytes;
    MPI_Datatype type;
} width;

/* Posts the receives and the sends of x's values. Every call is made even
   when reading x failed (what is sent is then meaningless, and the failure
   is returned), so that no neighbour waits for a message that never comes. */
static limn_status post(mpi_part *p, const mpi_send_view *v, device_buffer *x, width w,
                        limn_status st)
{
    mpi_halo *h = &p->halo;
    char *recv = (char *)h->recv3, *send = (char *)h->send3, *stage = (char *)v->stage;
    for (int q = 0; q < h->n_recv; q++)
        MPI_Irecv(recv + 3 * w.bytes * h->recv_off[q], (int)(3 * h->recv_cnt[q]), w.type,
                  h->recv_rank[q], TAG_HALO, p->comm, &h->req[q]);
    size_t span = v->end - v->begin;
    if (!st && h->n_send && span)
        st = p->dev->ops->buffer_read_at(p->dev, x, 4 * w.bytes * v->begin, 4 * w.bytes * span,
                                         stage);
    for (int q = 0; q < h->n_send; q++) {
        char *out = send + 3 * w.bytes * h->send_off[q];
        const uint32_t *idx = v->idx + h->send_off[q];
        for (size_t k = 0; k < h->send_cnt[q]; k++)
            memcpy(out + 3 * w.bytes * k, stage + 4 * w.bytes * idx[k], 3 * w.bytes);
        MPI_Isend(out, (int)(3 * h->send_cnt[q]), w.type, h->send_rank[q], TAG_HALO, p->comm,
                  &h->req[h->n_recv + q]);
    }
    return st;
}

/* Waits for every receive and send, then writes the ghosts into x (the
   fourth value of a row zero bits: 0.0 in either width). */
static limn_status finish(mpi_part *p, size_t ghost_at, device_buffer *x, width w,
                          limn_status st)
{
    mpi_halo *h = &p->halo;
    double t0 = MPI_Wtime();
    MPI_Waitall(h->n_recv + h->n_send, h->req, MPI_STATUSES_IGNORE);
    p->stats.seconds_wait += MPI_Wtime() - t0;
    if (st || p->n_ghost == 0)
        return st;
    char *ghost = (char *)h->ghost4;
    const char *recv = (const char *)h->recv3;
    for (size_t i = 0; i < p->n_ghost; i++) {
        memcpy(ghost + 4 * w.bytes * i, recv + 3 * w.bytes * i, 3 * w.bytes);
        memset(ghost + 4 * w.bytes * i + 3 * w.bytes, 0, w.bytes);
    }
    return p->dev->ops->buffer_write_at(p->dev, x, 4 * w.bytes * ghost_at,
                                        4 * w.bytes * p->n_ghost, ghost);
}

static void add_norms(device_norms *acc, const device_norms *n)
{
    acc->max = n->max > acc->max ? n->max : acc->max;
    acc->sum += n->sum;
    acc->sum_sq += n->sum_sq;
}

static limn_status overlapped(mpi_part *p, const device_csr *table, device_buffer *x, width w,
                              mpi_rows_fn fn, void *user, limn_status prior, device_norms *norms)
{
    memset(norms, 0, sizeof *norms);
    device_csr inner = *table, outer = *table;
    inner.rows = p->n_split;
    outer.row_begin = p->n_split;
    outer.rows = p->n_owned - p->n_split;
    double t0 = MPI_Wtime();
    const mpi_send_view v = {p->send_begin, p->send_end, p->halo.send_idx, p->n_owned,
                             p->halo.stage4};
    limn_status st = post(p, &v, x, w, prior);
    double t1 = MPI_Wtime();
    device_norms part;
    if (!st && inner.rows) {
        st = fn(user, &inner, &part);
        add_norms(norms, &part);
    }
    double t2 = MPI_Wtime();
    st = finish(p, p->n_owned, x, w, st);
    double t3 = MPI_Wtime();
    if (!st && outer.rows) {
        st = fn(user, &outer, &part);
        add_norms(norms, &part);
    }
    double t4 = MPI_Wtime();
    p->stats.seconds_halo += (t1 - t0) + (t3 - t2);
    p->stats.seconds_compute += (t2 - t1) + (t4 - t3);
    p->stats.exchanges++;
    return st;
}

limn_status mpi_overlapped(mpi_part *p, const device_csr *table, device_buffer *x,
                           mpi_rows_fn fn, void *user, limn_status prior, device_norms *norms)
{
    const width doubles = {sizeof(double), MPI_DOUBLE};
    return overlapped(p, table, x, doubles, fn, user, prior, norms);
}

limn_status mpi_overlapped_f(mpi_part *p, const device_csr *table, device_buffer *x_f,
                             mpi_rows_fn fn, void *user, limn_status prior, device_norms *norms)
{
    const width floats = {sizeof(float), MPI_FLOAT};
    return overlapped(p, table, x_f, floats, fn, user, prior, norms);
}

static limn_status no_rows(void *user, const device_csr *rows, device_norms *norms)
{
    (void)user;
    (void)rows;
    memset(norms, 0, sizeof *norms);
    return LIMN_OK;
}

limn_status mpi_exchange(mpi_part *p, device_buffer *x, limn_status prior)
{
    device_norms unused;
    return mpi_overlapped(p, &p->all, x, no_rows, NULL, prior, &unused);
}

/* Every rank: device views of its rows, halo buffers, statistics. */
limn_status mpi_open_rows(mpi_part *p)
{
    mpi_halo *h = &p->halo;
    size_t nidx = h->n_send ? h->send_off[h->n_send - 1] + h->send_cnt[h->n_send - 1] : 0;
    size_t span = p->send_end - p->send_begin;
    h->stage4 = calloc(span ? 4 * span : 1, sizeof *h->stage4);
    h->send3 = calloc(nidx ? 3 * nidx : 1, sizeof *h->send3);
    h->recv3 = calloc(p->n_ghost ? 3 * p->n_ghost : 1, sizeof *h->recv3);
    h->ghost4 = calloc(p->n_ghost ? 4 * p->n_ghost : 1, sizeof *h->ghost4);
    h->req = large_malloc((size_t)(h->n_recv + h->n_send + 1) * sizeof *h->req);
    if (!h->stage4 || !h->send3 || !h->recv3 || !h->ghost4 || !h->req)
        return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for the halo buffers");
    p->n_split = p->n_interior / DEVICE_ROWS_PER_ITEM * DEVICE_ROWS_PER_ITEM;
    p->stats.owned = p->n_owned;
    p->stats.ghosts = p->n_ghost;
    p->stats.interior_rows = p->n_interior;
    p->stats.edge_cut = p->edge_cut;
    p->stats.halo_bytes_sent = 3 * sizeof(double) * nidx;
    p->stats.halo_bytes_received = 3 * sizeof(double) * p->n_ghost;
    int neighbours = h->n_recv;
    for (int s = 0; s < h->n_send; s++) {
        int known = 0;
        for (int q = 0; q < h->n_recv; q++)
            known |= h->recv_rank[q] == h->send_rank[s];
        neighbours += !known;
    }
    p->stats.neighbours = neighbours;
    limn_status st = mpi_open_device(p);
    /* in place where the device shares host memory (PoCL's CPU device), as
       the single process's operator: p->host outlives p->all (mpi_part_end
       releases it first) and nothing writes it while the rows are open */
    if (!st)
        st = device_csr_share(p->dev, &p->host, &p->all);
    return st;
}

limn_status mpi_exchange_view(mpi_part *p, const mpi_send_view *v, device_buffer *x,
                              limn_status prior)
{
    const width doubles = {sizeof(double), MPI_DOUBLE};
    double t0 = MPI_Wtime();
    limn_status st = post(p, v, x, doubles, prior);
    st = finish(p, v->ghost_at, x, doubles, st);
    p->stats.seconds_halo += MPI_Wtime() - t0;
    p->stats.exchanges++;
    return st;
}
