/* SPDX-License-Identifier: MIT */
/* Fetching and storing records by global id over a block distribution. */
#include "mpi/mpi_blocks.h"
#include "base/large_alloc.h"

#include "base/context.h"

#include <limits.h>
#include <stdlib.h>
#include <string.h>

int mpi_blocks_owner(const size_t *dist, int size, size_t id)
{
    int lo = 0, hi = size - 1; /* the last r with dist[r] <= id */
    while (lo < hi) {
        int mid = lo + (hi - lo + 1) / 2;
        if (dist[mid] <= id)
            lo = mid;
        else
            hi = mid - 1;
    }
    return lo;
}

void mpi_blocks_dist(mpi_part *p, size_t count, size_t *dist)
{
    unsigned long long mine = count, *all = (unsigned long long *)(dist + 1);
    /* size_t and unsigned long long have the same width on every target */
    _Static_assert(sizeof(size_t) == sizeof(unsigned long long), "size_t is 64-bit");
    MPI_Allgather(&mine, 1, MPI_UNSIGNED_LONG_LONG, all, 1, MPI_UNSIGNED_LONG_LONG, p->comm);
    dist[0] = 0;
    for (int r = 0; r < p->size; r++)
        dist[r + 1] += dist[r];
}

/* The plan of one exchange: ids grouped by owner (order[k]: the caller's
   index of the k-th grouped id), counts and displacements per rank. */
typedef struct blocks_plan {
    int *send_count, *send_displ, *recv_count, *recv_displ;
    size_t *order;
    uint32_t *send_ids, *recv_ids;
    size_t n_recv;
} blocks_plan;

static void plan_free(blocks_plan *b)
{
    free(b->send_count);
    free(b->send_displ);
    free(b->recv_count);
    free(b->recv_displ);
    free(b->order);
    free(b->send_ids);
    free(b->recv_ids);
    memset(b, 0, sizeof *b);
}

/* Displacements from counts; 0 when a total passes INT_MAX (MPI's counts). */
static int displacements(const int *count, int *displ, int size, size_t *total)
{
    size_t t = 0;
    for (int r = 0; r < size; r++) {
        displ[r] = (int)t;
        t += (size_t)count[r];
        if (t > INT_MAX)
            return 0;
    }
    *total = t;
    return 1;
}

/* Groups ids by owner and tells every owner which of its ids are asked for. */
static limn_status plan_open(mpi_part *p, const size_t *dist, size_t n, const uint32_t *ids,
                             blocks_plan *b)
{
    memset(b, 0, sizeof *b);
    size_t s = (size_t)p->size;
    b->send_count = calloc(s, sizeof *b->send_count);
    b->send_displ = large_malloc(s * sizeof *b->send_displ);
    b->recv_count = large_malloc(s * sizeof *b->recv_count);
    b->recv_displ = large_malloc(s * sizeof *b->recv_displ);
    b->order = large_malloc((n ? n : 1) * sizeof *b->order);
    b->send_ids = large_malloc((n ? n : 1) * sizeof *b->send_ids);
    limn_status st = LIMN_OK;
    if (!b->send_count || !b->send_displ || !b->recv_count || !b->recv_displ || !b->order ||
        !b->send_ids)
        st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory exchanging %zu records", n);
    for (size_t i = 0; !st && i < n; i++) {
        if (ids[i] >= dist[p->size]) {
            st = ctx_fail(p->ctx, LIMN_ERR_ARGUMENT, "rank %d asks for item %u of %zu", p->rank,
                           ids[i], dist[p->size]);
            break;
        }
        b->send_count[mpi_blocks_owner(dist, p->size, ids[i])]++;
    }
    size_t total = 0;
    if (!st && (n > INT_MAX || !displacements(b->send_count, b->send_displ, p->size, &total)))
        st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "rank %d: %zu records in one exchange: more than "
                      "MPI's int counts take", p->rank, n);
    st = mpi_agree(p, st);
    if (st)
        return st;
    int *fill = b->recv_count; /* cursors, before the counts arrive */
    memcpy(fill, b->send_displ, s * sizeof *fill);
    for (size_t i = 0; i < n; i++) {
        int r = mpi_blocks_owner(dist, p->size, ids[i]);
        b->order[fill[r]] = i;
        b->send_ids[fill[r]++] = ids[i];
    }
    MPI_Alltoall(b->send_count, 1, MPI_INT, b->recv_count, 1, MPI_INT, p->comm);
    if (!displacements(b->recv_count, b->recv_displ, p->size, &b->n_recv))
        st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "rank %d is asked for more records than MPI's "
                      "int counts take", p->rank);
    if (!st && !(b->recv_ids = large_malloc((b->n_recv ? b->n_recv : 1) * sizeof *b->recv_ids)))
        st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu records", b->n_recv);
    st = mpi_agree(p, st);
    if (!st)
        MPI_Alltoallv(b->send_ids, b->send_count, b->send_displ, MPI_UINT32_T, b->recv_ids,
                      b->recv_count, b->recv_displ, MPI_UINT32_T, p->comm);
    return st;
}

/* A contiguous MPI type of width bytes (counts stay in records). */
static MPI_Datatype record_type(size_t width)
{
    MPI_Datatype t;
    MPI_Type_contiguous((int)width, MPI_BYTE, &t);
    MPI_Type_commit(&t);
    return t;
}

limn_status mpi_blocks_fetch(mpi_part *p, const size_t *dist, const void *block, size_t width,
                             size_t n, const uint32_t *ids, void *out)
{
    blocks_plan b;
    limn_status st = plan_open(p, dist, n, ids, &b);
    char *answer = NULL, *got = NULL;
    if (!st) {
        answer = large_malloc((b.n_recv ? b.n_recv : 1) * width);
        got = large_malloc((n ? n : 1) * width);
        if (!answer || !got)
            st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu records", n + b.n_recv);
        st = mpi_agree(p, st);
    }
    if (!st) {
        size_t begin = dist[p->rank];
        for (size_t k = 0; k < b.n_recv; k++)
            memcpy(answer + k * width, (const char *)block + (b.recv_ids[k] - begin) * width,
                   width);
        MPI_Datatype t = record_type(width);
        /* the answers travel back along the requests' counts */
        MPI_Alltoallv(answer, b.recv_count, b.recv_displ, t, got, b.send_count, b.send_displ, t,
                      p->comm);
        MPI_Type_free(&t);
        for (size_t k = 0; k < n; k++)
            memcpy((char *)out + b.order[k] * width, got + k * width, width);
    }
    free(answer);
    free(got);
    plan_free(&b);
    return st;
}

limn_status mpi_blocks_store(mpi_part *p, const size_t *dist, size_t n, const uint32_t *ids,
                             const void *values, size_t width, void *block)
{
    blocks_plan b;
    limn_status st = plan_open(p, dist, n, ids, &b);
    char *sent = NULL, *got = NULL;
    if (!st) {
        sent = large_malloc((n ? n : 1) * width);
        got = large_malloc((b.n_recv ? b.n_recv : 1) * width);
        if (!sent || !got)
            st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu records", n + b.n_recv);
        st = mpi_agree(p, st);
    }
    if (!st) {
        for (size_t k = 0; k < n; k++)
            memcpy(sent + k * width, (const char *)values + b.order[k] * width, width);
        MPI_Datatype t = record_type(width);
        MPI_Alltoallv(sent, b.send_count, b.send_displ, t, got, b.recv_count, b.recv_displ, t,
                      p->comm);
        MPI_Type_free(&t);
        size_t begin = dist[p->rank];
        for (size_t k = 0; k < b.n_recv; k++)
            memcpy((char *)block + (b.recv_ids[k] - begin) * width, got + k * width, width);
    }
    free(sent);
    free(got);
    plan_free(&b);
    return st;
}
