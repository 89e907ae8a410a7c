/* SPDX-License-Identifier: MIT */
/*
 * Ghost exchange for one stencil product. The values other ranks need are
 * one contiguous device range (mpi_part.h), read in one transfer, packed
 * per neighbour as 3 doubles a vertex and sent with MPI_Isend; each
 * neighbour's values arrive as one block (ghosts are sorted by owner) and
 * go to the device in one write. Rows free of ghost columns run between
 * posting and waiting.
 */
#include "mpi/mpi_part.h"

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

/* Posts the receives and the sends of x's values. Every call is made even
   when reading x failed (what is sent is then meaningless, and the failure
   is returned), so that no neighbour waits for a message that never comes. */
static limn_status post(mpi_part *p, device_buffer *x, limn_status st)
{
    mpi_halo *h = &p->halo;
    for (int q = 0; q < h->n_recv; q++)
        MPI_Irecv(h->recv3 + 3 * h->recv_off[q], (int)(3 * h->recv_cnt[q]), MPI_DOUBLE,
                  h->recv_rank[q], TAG_HALO, p->comm, &h->req[q]);
    size_t span = p->send_end - p->send_begin;
    if (!st && h->n_send && span)
        st = p->dev->ops->buffer_read_at(p->dev, x, 4 * sizeof(double) * p->send_begin,
                                         4 * sizeof(double) * span, h->stage4);
    for (int q = 0; q < h->n_send; q++) {
        double *out = h->send3 + 3 * h->send_off[q];
        const uint32_t *idx = h->send_idx + h->send_off[q];
        for (size_t k = 0; k < h->send_cnt[q]; k++)
            memcpy(out + 3 * k, h->stage4 + 4 * (size_t)idx[k], 3 * sizeof(double));
        MPI_Isend(out, (int)(3 * h->send_cnt[q]), MPI_DOUBLE, h->send_rank[q], TAG_HALO, p->comm,
                  &h->req[h->n_recv + q]);
    }
    return st;
}

/* Waits for every receive and send, then writes the ghosts into x. */
static limn_status finish(mpi_part *p, device_buffer *x, limn_status st)
{
    mpi_halo *h = &p->halo;
    double t0 = MPI_Wtime();
    MPI_Waitall(h->n_recv + h->n_send, h->req, MPI_STATUSES_IGNORE);
    p->stats.seconds_wait += MPI_Wtime() - t0;
    if (st || p->n_ghost == 0)
        return st;
    for (size_t i = 0; i < p->n_ghost; i++) {
        memcpy(h->ghost4 + 4 * i, h->recv3 + 3 * i, 3 * sizeof(double));
        h->ghost4[4 * i + 3] = 0.0;
    }
    return p->dev->ops->buffer_write_at(p->dev, x, 4 * sizeof(double) * p->n_owned,
                                        4 * sizeof(double) * p->n_ghost, h->ghost4);
}

static void add_norms(device_norms *acc, const device_norms *n)
{
    acc->max = n->max > acc->max ? n->max : acc->max;
    acc->sum += n->sum;
    acc->sum_sq += n->sum_sq;
}

limn_status mpi_overlapped(mpi_part *p, const device_csr *table, device_buffer *x,
                           mpi_rows_fn fn, void *user, limn_status prior, device_norms *norms)
{
    memset(norms, 0, sizeof *norms);
    device_csr inner = *table, outer = *table;
    inner.rows = p->n_split;
    outer.row_begin = p->n_split;
    outer.rows = p->n_owned - p->n_split;
    double t0 = MPI_Wtime();
    limn_status st = post(p, x, prior);
    double t1 = MPI_Wtime();
    device_norms part;
    if (!st && inner.rows) {
        st = fn(user, &inner, &part);
        add_norms(norms, &part);
    }
    double t2 = MPI_Wtime();
    st = finish(p, x, st);
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
    h->req = malloc((size_t)(h->n_recv + h->n_send + 1) * sizeof *h->req);
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
    if (!st)
        st = device_csr_upload(p->dev, &p->host, &p->all);
    return st;
}
