/* SPDX-License-Identifier: MIT */
/*
 * The Gauss-Seidel colouring on a distributed mesh, no rank holding the
 * operator: sgs_colour_rows's greedy in input order (the single process's
 * rows when it keeps the input order), computed rank by rank. The greedy
 * gives row i the smallest colour not taken by its columns j < i of its
 * tier; that depends only on those lower columns' colours, so a row can be
 * coloured as soon as they are known, whoever owns them (Jones-Plassmann
 * with the global id as priority gives the sequential greedy exactly). Each
 * round, every rank colours in id order each owned row whose lower columns
 * are known (chains among its own rows resolve in the same pass), then the
 * halo carries the new colours to the ranks that read them; the lowest
 * uncoloured row of the whole mesh can always go, so the rounds end. The
 * rounds are the number of times an increasing chain of ids crosses
 * between ranks, small for partitions into compact parts.
 */
#include "mpi/mpi_local.h"
#include "base/large_alloc.h"
#include "mpi/mpi_part.h"

#include "base/context.h"

#include <stdlib.h>
#include <string.h>

#define UNSET UINT32_MAX

/* Colours the owned rows (in id order) whose lower columns of their tier
   are all coloured; returns how many stay uncoloured. stamp: scratch. */
static size_t colour_pass(const mpi_part *p, const uint32_t *order, const int8_t *tier,
                          uint32_t *colour, size_t *stamp, size_t *pass)
{
    size_t left = 0, no = p->n_owned;
    const stencil_csr *a = &p->host;
    for (size_t k = 0; k < no; k++) {
        uint32_t i = order[k], gi = p->owned_ids[i];
        if (colour[i] != UNSET)
            continue;
        ++*pass;
        int ready = 1;
        for (uint32_t e = a->row_offsets[i]; ready && e < a->row_offsets[i + 1]; e++) {
            uint32_t j = a->columns[e];
            uint32_t gj = j < no ? p->owned_ids[j] : p->ghost_ids[j - no];
            if (gj >= gi || tier[j] != tier[i])
                continue;
            if (colour[j] == UNSET)
                ready = 0;
            else
                stamp[colour[j]] = *pass;
        }
        if (!ready) {
            left++;
            continue;
        }
        uint32_t c = 0;
        while (stamp[c] == *pass)
            c++;
        colour[i] = c;
    }
    return left;
}

/* The colours of the rows other ranks read, into their ghosts (p->halo). */
static void exchange(const mpi_part *p, uint32_t *colour, uint32_t *sendbuf, MPI_Request *req)
{
    const mpi_halo *h = &p->halo;
    for (int k = 0; k < h->n_recv; k++)
        MPI_Irecv(colour + p->n_owned + h->recv_off[k], (int)h->recv_cnt[k], MPI_UINT32_T,
                  h->recv_rank[k], 7, p->comm, &req[k]);
    for (int k = 0; k < h->n_send; k++) {
        uint32_t *b = sendbuf + h->send_off[k];
        for (size_t i = 0; i < h->send_cnt[k]; i++)
            b[i] = colour[p->send_begin + h->send_idx[h->send_off[k] + i]];
        MPI_Isend(b, (int)h->send_cnt[k], MPI_UINT32_T, h->send_rank[k], 7, p->comm,
                  &req[h->n_recv + k]);
    }
    MPI_Waitall(h->n_recv + h->n_send, req, MPI_STATUSES_IGNORE);
}

limn_status mpi_sgs_colour_local(mpi_part *p, uint32_t *colour, size_t colours[3])
{
    size_t no = p->n_owned, nl = no + p->n_ghost, longest = 0, nsend = 0;
    const mpi_halo *h = &p->halo;
    for (int k = 0; k < h->n_send; k++)
        nsend += h->send_cnt[k];
    for (size_t i = 0; p->host.row_offsets && i < no; i++) {
        size_t len = p->host.row_offsets[i + 1] - p->host.row_offsets[i];
        longest = len > longest ? len : longest;
    }
    int8_t *tier = large_malloc(nl ? nl : 1);
    uint32_t *order = large_malloc((no ? no : 1) * sizeof *order);
    uint64_t *key = large_malloc((no ? no : 1) * sizeof *key);
    uint32_t *sendbuf = large_malloc((nsend ? nsend : 1) * sizeof *sendbuf);
    size_t *stamp = calloc(longest + 2, sizeof *stamp), pass = 0;
    MPI_Request *req = large_malloc(((size_t)h->n_recv + (size_t)h->n_send + 1) * sizeof *req);
    limn_status st = tier && order && key && sendbuf && stamp && req && (no == 0 || p->host.row_offsets)
                         ? LIMN_OK
                         : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for the colouring");
    for (size_t i = 0; !st && i < nl; i++) {
        tier[i] = (int8_t)mpi_tier_of(i < no ? p->owned_rule[i] : p->ghost_rule[i - no]);
        colour[i] = UNSET;
    }
    for (size_t i = 0; !st && i < no; i++) /* the owned rows in id order */
        key[i] = (uint64_t)p->owned_ids[i] << 32 | i;
    if (!st)
        mpi_local_sort(key, no);
    for (size_t i = 0; !st && i < no; i++)
        order[i] = (uint32_t)key[i];
    free(key);
    st = mpi_agree(p, st);
    for (unsigned long long left = 1; !st && left;) {
        left = colour_pass(p, order, tier, colour, stamp, &pass);
        exchange(p, colour, sendbuf, req);
        MPI_Allreduce(MPI_IN_PLACE, &left, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, p->comm);
    }
    unsigned long long count[3] = {0, 0, 0};
    for (size_t i = 0; !st && i < no; i++)
        if (colour[i] + 1ULL > count[tier[i]])
            count[tier[i]] = colour[i] + 1ULL;
    if (!st)
        MPI_Allreduce(MPI_IN_PLACE, count, 3, MPI_UNSIGNED_LONG_LONG, MPI_MAX, p->comm);
    for (int t = 0; t < 3; t++)
        colours[t] = (size_t)count[t];
    free(tier);
    free(order);
    free(sendbuf);
    free(stamp);
    free(req);
    return st;
}
