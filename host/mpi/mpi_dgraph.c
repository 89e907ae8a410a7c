/* SPDX-License-Identifier: MIT */
/*
 * Distributed vertex partition with PT-Scotch (mpi_dgraph.h): the faces'
 * edges travel to the ranks owning their ends (one MPI_Alltoallv), each rank
 * builds its block's sorted adjacency, SCOTCH_dgraphPart splits the graph
 * and a halo exchange of the parts (SCOTCH_dgraphHalo) gives the edge cut.
 * No rank ever holds more than its block's adjacency and its own faces.
 *
 * Debian's libptscotch is built with threads but without SCOTCH_PTHREAD_MPI
 * (it never calls MPI_Query_thread): only the calling thread talks to MPI,
 * so plain MPI_Init is enough (no MPI_THREAD_MULTIPLE).
 */
#include "mpi/mpi_dgraph.h"
#include "base/large_alloc.h"

#include "base/context.h"

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <mpi.h>
#include <ptscotch.h>

/* The largest SCOTCH_Num (its size is the library's build choice). */
#define DG_NUM_MAX ((size_t)(sizeof(SCOTCH_Num) == 4 ? INT32_MAX : INT64_MAX))
#define DG_NUM_MPI (sizeof(SCOTCH_Num) == 4 ? MPI_INT32_T : MPI_INT64_T)
#define DG_SEED 4321 /* the same partition on every run */

typedef struct dg_state {
    limn_context *ctx;
    MPI_Comm comm;
    int rank, size, parts;
    mpi_dgraph_strategy strategy;
    const size_t *vtxdist;
    size_t n_global, begin, n_local;
    SCOTCH_Num *xadj, *adj; /* this block's adjacency, global ids */
    size_t edges_global;
    uint32_t *part_of;
} dg_state;

/* Every rank gets the status and message of the lowest failing rank. */
static limn_status dg_agree(dg_state *g, limn_status st)
{
    int key = st == LIMN_OK ? g->size : g->rank, first;
    MPI_Allreduce(&key, &first, 1, MPI_INT, MPI_MIN, g->comm);
    if (first == g->size)
        return LIMN_OK;
    int status = (int)st;
    MPI_Bcast(&status, 1, MPI_INT, first, g->comm);
    MPI_Bcast(g->ctx->message, (int)sizeof g->ctx->message, MPI_CHAR, first, g->comm);
    g->ctx->message[sizeof g->ctx->message - 1] = '\0';
    return (limn_status)status;
}

/* The rank whose block holds global vertex v (v < n_global). */
static int dg_owner(const dg_state *g, size_t v)
{
    int lo = 0, hi = g->size - 1; /* the last r with vtxdist[r] <= v */
    while (lo < hi) {
        int mid = lo + (hi - lo + 1) / 2;
        if (g->vtxdist[mid] <= v)
            lo = mid;
        else
            hi = mid - 1;
    }
    return lo;
}

/* vtxdist, the faces and the sizes Scotch's and MPI's integers can take. */
static limn_status dg_check(dg_state *g, size_t face_count, const uint32_t *off,
                            const uint32_t *idx)
{
    const size_t *d = g->vtxdist;
    if (g->parts < 1)
        return ctx_fail(g->ctx, LIMN_ERR_ARGUMENT, "distributed partition: %d parts (needs >= 1)",
                        g->parts);
    for (int r = 0; r < g->size; r++)
        if (d[r + 1] < d[r] || (r == 0 && d[0] != 0))
            return ctx_fail(g->ctx, LIMN_ERR_ARGUMENT,
                            "distributed partition: vertex blocks out of order at rank %d "
                            "(vtxdist %zu, %zu)",
                            r, d[r], d[r + 1]);
    if (g->n_global >= DG_NUM_MAX || g->n_global > UINT32_MAX)
        return ctx_fail(g->ctx, LIMN_ERR_ARGUMENT,
                        "distributed partition: %zu vertices: more than PT-Scotch's %zu-bit "
                        "indices or limn's 32-bit ones take",
                        g->n_global, 8 * sizeof(SCOTCH_Num));
    if (face_count && off[0] != 0)
        return ctx_fail(g->ctx, LIMN_ERR_ARGUMENT,
                        "distributed partition: rank %d's face offsets start at %u, not 0",
                        g->rank, off[0]);
    for (size_t f = 0; f < face_count; f++) {
        if (off[f + 1] < off[f])
            return ctx_fail(g->ctx, LIMN_ERR_ARGUMENT,
                            "distributed partition: rank %d's face %zu has offsets %u > %u",
                            g->rank, f, off[f], off[f + 1]);
        for (uint32_t c = off[f]; c < off[f + 1]; c++)
            if (idx[c] >= g->n_global)
                return ctx_fail(g->ctx, LIMN_ERR_ARGUMENT,
                                "distributed partition: rank %d's face %zu names vertex %u of %zu",
                                g->rank, f, idx[c], g->n_global);
    }
    return LIMN_OK;
}

/* Calls fn(g, user, from, to) for both directions of each edge of the faces
   (consecutive corners, the last to the first), self loops left out. */
typedef void (*dg_edge_fn)(const dg_state *g, void *user, uint32_t from, uint32_t to);
static void dg_edges(const dg_state *g, size_t face_count, const uint32_t *off,
                     const uint32_t *idx, dg_edge_fn fn, void *user)
{
    for (size_t f = 0; f < face_count; f++) {
        uint32_t b = off[f], e = off[f + 1];
        for (uint32_t c = b; c < e; c++) {
            uint32_t u = idx[c], v = idx[c + 1 < e ? c + 1 : b];
            if (u == v)
                continue;
            fn(g, user, u, v);
            fn(g, user, v, u);
        }
    }
}

typedef struct dg_send {
    int *count;   /* pairs per destination rank */
    size_t *fill; /* next pair per destination */
    uint32_t *buf;
} dg_send;

static void dg_count_edge(const dg_state *g, void *user, uint32_t from, uint32_t to)
{
    (void)to;
    ((dg_send *)user)->fill[dg_owner(g, from)]++;
}

static void dg_put_edge(const dg_state *g, void *user, uint32_t from, uint32_t to)
{
    dg_send *s = user;
    size_t k = s->fill[dg_owner(g, from)]++;
    s->buf[2 * k] = from;
    s->buf[2 * k + 1] = to;
}

/* Per-destination counts and displacements (in uint32 pairs) as MPI's ints. */
static limn_status dg_displs(dg_state *g, const size_t *n, int *count, int *displ,
                             size_t *total)
{
    size_t sum = 0;
    for (int r = 0; r < g->size; r++) {
        if (2 * n[r] > (size_t)INT_MAX || 2 * sum > (size_t)INT_MAX)
            return ctx_fail(g->ctx, LIMN_ERR_MEMORY,
                            "distributed partition: rank %d exchanges more than %d edge ends "
                            "(MPI's int counts); use more ranks",
                            g->rank, INT_MAX / 2);
        count[r] = (int)(2 * n[r]);
        displ[r] = (int)(2 * sum);
        sum += n[r];
    }
    *total = sum;
    return LIMN_OK;
}

/* Sends every directed face edge to the owner of its first end; *recv gets
   this block's directed edges (pairs from, to), *n_recv pairs. */
static limn_status dg_exchange(dg_state *g, size_t face_count, const uint32_t *off,
                               const uint32_t *idx, uint32_t **recv, size_t *n_recv)
{
    size_t P = (size_t)g->size, n_send = 0;
    size_t *nsend = calloc(P, sizeof *nsend), *nrecv = calloc(P, sizeof *nrecv);
    int *ci = large_malloc(4 * P * sizeof *ci);
    dg_send s = {NULL, calloc(P, sizeof(size_t)), NULL};
    limn_status st = LIMN_OK;
    if (!nsend || !nrecv || !ci || !s.fill)
        st = ctx_fail(g->ctx, LIMN_ERR_MEMORY, "distributed partition: out of memory");
    if (st == LIMN_OK) {
        dg_edges(g, face_count, off, idx, dg_count_edge, &s);
        memcpy(nsend, s.fill, P * sizeof *nsend);
        st = dg_displs(g, nsend, ci, ci + P, &n_send);
    }
    if (st == LIMN_OK && !(s.buf = large_malloc((2 * n_send + 1) * sizeof *s.buf)))
        st = ctx_fail(g->ctx, LIMN_ERR_MEMORY,
                      "distributed partition: out of memory for rank %d's %zu faces", g->rank,
                      face_count);
    if (st == LIMN_OK) {
        for (size_t r = 0, k = 0; r < P; k += nsend[r++])
            s.fill[r] = k;
        dg_edges(g, face_count, off, idx, dg_put_edge, &s);
    }
    st = dg_agree(g, st);
    if (st == LIMN_OK) {
        MPI_Alltoall(nsend, 1, MPI_UINT64_T, nrecv, 1, MPI_UINT64_T, g->comm);
        st = dg_displs(g, nrecv, ci + 2 * P, ci + 3 * P, n_recv);
        if (st == LIMN_OK && !(*recv = large_malloc((2 * *n_recv + 1) * sizeof **recv)))
            st = ctx_fail(g->ctx, LIMN_ERR_MEMORY,
                          "distributed partition: out of memory for rank %d's %zu edge ends",
                          g->rank, *n_recv);
        st = dg_agree(g, st);
    }
    if (st == LIMN_OK)
        MPI_Alltoallv(s.buf, ci, ci + P, MPI_UINT32_T, *recv, ci + 2 * P, ci + 3 * P,
                      MPI_UINT32_T, g->comm);
    free(nsend);
    free(nrecv);
    free(ci);
    free(s.fill);
    free(s.buf);
    return st;
}

static int dg_cmp(const void *a, const void *b)
{
    SCOTCH_Num x = *(const SCOTCH_Num *)a, y = *(const SCOTCH_Num *)b;
    return x < y ? -1 : x > y;
}

/* The block's CSR from its directed edges: each list sorted, no repeats
   (the graph does not depend on where the faces were). */
static limn_status dg_adjacency(dg_state *g, const uint32_t *pairs, size_t n_pairs)
{
    size_t n = g->n_local;
    g->xadj = calloc(n + 1, sizeof *g->xadj);
    g->adj = large_malloc((n_pairs + 1) * sizeof *g->adj);
    size_t *fill = calloc(n + 1, sizeof *fill);
    if (!g->xadj || !g->adj || !fill) {
        free(fill);
        return ctx_fail(g->ctx, LIMN_ERR_MEMORY,
                        "distributed partition: out of memory for rank %d's graph (%zu vertices, "
                        "%zu edge ends)",
                        g->rank, n, n_pairs);
    }
    for (size_t k = 0; k < n_pairs; k++)
        fill[pairs[2 * k] - g->begin + 1]++;
    for (size_t v = 0; v < n; v++)
        fill[v + 1] += fill[v];
    for (size_t k = 0; k < n_pairs; k++)
        g->adj[fill[pairs[2 * k] - g->begin]++] = (SCOTCH_Num)pairs[2 * k + 1];
    size_t out = 0;
    for (size_t v = 0, b = 0; v < n; v++) { /* fill[v] is now the end of list v */
        size_t e = fill[v];
        qsort(g->adj + b, e - b, sizeof *g->adj, dg_cmp);
        g->xadj[v] = (SCOTCH_Num)out;
        for (size_t k = b; k < e; k++)
            if (k == b || g->adj[k] != g->adj[k - 1])
                g->adj[out++] = g->adj[k];
        b = e;
    }
    g->xadj[n] = (SCOTCH_Num)out;
    free(fill);
    return LIMN_OK;
}

/* Parts that need no Scotch (the same rules as mpi_partition.c). */
static void dg_trivial(dg_state *g)
{
    size_t n = g->n_global, P = (size_t)g->parts;
    for (size_t i = 0; i < g->n_local; i++) {
        size_t v = g->begin + i;
        g->part_of[i] = P <= 1 ? 0 : (uint32_t)(n <= P ? v : v * P / n);
    }
}

static SCOTCH_Num dg_flags(mpi_dgraph_strategy s)
{
    return s == MPI_DGRAPH_SPEED     ? SCOTCH_STRATSPEED
           : s == MPI_DGRAPH_DEFAULT ? SCOTCH_STRATDEFAULT
                                     : SCOTCH_STRATQUALITY;
}

/* A Scotch context that is deterministic with a fixed random seed and one
   thread (with Scotch's default of a thread per core, oversubscribed ranks
   were seen spinning for minutes): the same parts on every run for the same
   graph and rank count. Local: returns nonzero on failure. */
static int dg_context(SCOTCH_Context *cont)
{
    if (SCOTCH_contextInit(cont))
        return 1;
    int rc = SCOTCH_contextOptionSetNum(cont, SCOTCH_OPTIONNUMDETERMINISTIC, 1) ||
             SCOTCH_contextOptionSetNum(cont, SCOTCH_OPTIONNUMRANDOMFIXEDSEED, 1) ||
             SCOTCH_contextThreadSpawn(cont, 1, NULL);
    if (!rc)
        SCOTCH_contextRandomSeed(cont, DG_SEED);
    else
        SCOTCH_contextExit(cont);
    return rc;
}

/* Collective: the fixed strategy (imbalance bound 3%, METIS's default
   ufactor 30) and context made and agreed on, the graph into d, then the
   partition in a copy bound to the context. */
static limn_status dg_scotch_part(dg_state *g, SCOTCH_Dgraph *d, SCOTCH_Num *part)
{
    SCOTCH_Strat strat;
    SCOTCH_Context cont;
    SCOTCH_Dgraph bound;
    SCOTCH_Num n = (SCOTCH_Num)g->n_local, edges = g->xadj[g->n_local];
    int strat_made = SCOTCH_stratInit(&strat) == 0, cont_made = strat_made && !dg_context(&cont);
    int ready = cont_made && !SCOTCH_stratDgraphMapBuild(&strat, dg_flags(g->strategy),
                                                         (SCOTCH_Num)g->size,
                                                         (SCOTCH_Num)g->parts, 0.03);
    limn_status st = ready ? LIMN_OK
                               : ctx_fail(g->ctx, LIMN_ERR_MEMORY,
                                          "PT-Scotch: could not set up on rank %d", g->rank);
    st = dg_agree(g, st); /* every rank has the failing rank's message */
    int rc = st != LIMN_OK, bound_made = 0;
    if (!rc)
        rc = SCOTCH_dgraphBuild(d, 0, n, n, g->xadj, g->xadj + 1, NULL, NULL, edges, edges,
                                g->adj, NULL, NULL);
    if (!rc)
        bound_made = !(rc = SCOTCH_contextBindDgraph(&cont, d, &bound));
    if (!rc)
        rc = SCOTCH_dgraphPart(&bound, (SCOTCH_Num)g->parts, &strat, part);
    if (bound_made)
        SCOTCH_dgraphExit(&bound);
    if (cont_made)
        SCOTCH_contextExit(&cont);
    if (strat_made)
        SCOTCH_stratExit(&strat);
    if (st == LIMN_OK && rc)
        st = ctx_fail(g->ctx, LIMN_ERR_MEMORY,
                      "PT-Scotch could not partition %zu vertices (%zu edges) into %d parts "
                      "(rank %d; its message is on standard error)",
                      g->n_global, g->edges_global, g->parts, g->rank);
    return st;
}

/* Scotch's parts, and the edges cut (counted from this block's lists, the
   neighbours' parts from a halo exchange): *cut_twice counts both ends. */
static limn_status dg_scotch(dg_state *g, uint64_t *cut_twice)
{
    SCOTCH_Dgraph d;
    int made = SCOTCH_dgraphInit(&d, g->comm) == 0;
    SCOTCH_Num *part = large_malloc((g->n_local + 1) * sizeof *part);
    limn_status st = made && part ? LIMN_OK
                                  : ctx_fail(g->ctx, LIMN_ERR_MEMORY,
                                             "PT-Scotch: out of memory for a graph on rank %d",
                                             g->rank);
    st = dg_agree(g, st);
    if (st == LIMN_OK) /* agrees itself before its collective calls */
        st = dg_agree(g, dg_scotch_part(g, &d, part));
    SCOTCH_Num local_and_ghosts = 0, *gst = NULL, *halo = NULL;
    if (st == LIMN_OK && SCOTCH_dgraphGhst(&d))
        st = ctx_fail(g->ctx, LIMN_ERR_MEMORY, "PT-Scotch: could not find the ghosts");
    if (st == LIMN_OK) {
        SCOTCH_dgraphData(&d, NULL, NULL, NULL, NULL, &local_and_ghosts, NULL, NULL, NULL, NULL,
                          NULL, NULL, NULL, NULL, &gst, NULL, NULL);
        if (!(halo = large_malloc(((size_t)local_and_ghosts + 1) * sizeof *halo)))
            st = ctx_fail(g->ctx, LIMN_ERR_MEMORY, "distributed partition: out of memory");
    }
    st = dg_agree(g, st);
    if (st == LIMN_OK) { /* local parts first, the ghosts' arrive after them */
        memcpy(halo, part, g->n_local * sizeof *halo);
        if (SCOTCH_dgraphHalo(&d, halo, DG_NUM_MPI))
            st = ctx_fail(g->ctx, LIMN_ERR_MEMORY, "PT-Scotch: the halo exchange failed");
        st = dg_agree(g, st);
    }
    for (size_t v = 0; st == LIMN_OK && v < g->n_local; v++) {
        g->part_of[v] = (uint32_t)part[v];
        for (SCOTCH_Num e = g->xadj[v]; e < g->xadj[v + 1]; e++)
            *cut_twice += halo[gst[e]] != part[v];
    }
    free(halo);
    free(part);
    if (made)
        SCOTCH_dgraphExit(&d);
    return st;
}

/* Part sizes and edge cut over all ranks. */
static limn_status dg_stats(dg_state *g, uint64_t cut_twice, mpi_dgraph_stats *s)
{
    size_t P = (size_t)g->parts;
    uint64_t *cnt = calloc(2 * P + 2, sizeof *cnt);
    limn_status st = cnt ? LIMN_OK
                         : ctx_fail(g->ctx, LIMN_ERR_MEMORY,
                                    "distributed partition: out of memory for %d part sizes",
                                    g->parts);
    st = dg_agree(g, st);
    if (st)
        return st;
    for (size_t v = 0; v < g->n_local; v++)
        cnt[g->part_of[v]]++;
    cnt[P] = cut_twice;
    MPI_Allreduce(cnt, cnt + P + 1, (int)P + 1, MPI_UINT64_T, MPI_SUM, g->comm);
    const uint64_t *all = cnt + P + 1;
    s->vertices = g->n_global;
    s->edges = g->edges_global;
    s->edge_cut = (size_t)(all[P] / 2);
    s->part_max = 0;
    s->part_min = SIZE_MAX;
    for (size_t p = 0; p < P; p++) {
        s->part_max = all[p] > s->part_max ? (size_t)all[p] : s->part_max;
        s->part_min = all[p] < s->part_min ? (size_t)all[p] : s->part_min;
    }
    s->imbalance = g->n_global ? (double)s->part_max * (double)P / (double)g->n_global : 1.0;
    free(cnt);
    return LIMN_OK;
}

limn_status mpi_dgraph_partition(limn_context *ctx, MPI_Comm comm, const size_t *vtxdist,
                                 size_t face_count, const uint32_t *face_offsets,
                                 const uint32_t *face_indices, int parts, uint32_t **part_of,
                                 mpi_dgraph_stats *stats)
{
    return mpi_dgraph_partition_with(ctx, comm, vtxdist, face_count, face_offsets, face_indices,
                                     parts, MPI_DGRAPH_QUALITY, part_of, stats);
}

limn_status mpi_dgraph_partition_with(limn_context *ctx, MPI_Comm comm, const size_t *vtxdist,
                                      size_t face_count, const uint32_t *face_offsets,
                                      const uint32_t *face_indices, int parts,
                                      mpi_dgraph_strategy strategy, uint32_t **part_of,
                                      mpi_dgraph_stats *stats)
{
    double t0 = MPI_Wtime();
    dg_state g = {.ctx = ctx, .comm = comm, .parts = parts, .strategy = strategy,
                  .vtxdist = vtxdist};
    MPI_Comm_rank(comm, &g.rank);
    MPI_Comm_size(comm, &g.size);
    g.n_global = vtxdist[g.size];
    g.begin = vtxdist[g.rank];
    g.n_local = vtxdist[g.rank + 1] - vtxdist[g.rank];
    *part_of = NULL;
    limn_status st = dg_check(&g, face_count, face_offsets, face_indices);
    if (st == LIMN_OK && !(g.part_of = large_malloc((g.n_local + 1) * sizeof *g.part_of)))
        st = ctx_fail(ctx, LIMN_ERR_MEMORY, "distributed partition: out of memory");
    st = dg_agree(&g, st);
    uint32_t *pairs = NULL;
    size_t n_pairs = 0;
    if (st == LIMN_OK)
        st = dg_exchange(&g, face_count, face_offsets, face_indices, &pairs, &n_pairs);
    if (st == LIMN_OK)
        st = dg_agree(&g, dg_adjacency(&g, pairs, n_pairs));
    free(pairs);
    if (st == LIMN_OK) { /* every edge is in the lists of both ends */
        uint64_t mine = (uint64_t)g.xadj[g.n_local], all = 0;
        MPI_Allreduce(&mine, &all, 1, MPI_UINT64_T, MPI_SUM, comm);
        g.edges_global = (size_t)(all / 2);
        if (all >= DG_NUM_MAX) /* the same on every rank */
            st = ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                          "distributed partition: %zu edges: more than PT-Scotch's %zu-bit "
                          "indices take (a 64-bit build of PT-Scotch would)",
                          g.edges_global, 8 * sizeof(SCOTCH_Num));
    }
    double t_graph = MPI_Wtime() - t0;
    uint64_t cut_twice = 0;
    if (st == LIMN_OK) {
        if (parts <= 1 || g.n_global <= (size_t)parts || g.edges_global == 0) {
            dg_trivial(&g);
            cut_twice = parts > 1 && g.n_global <= (size_t)parts ? (uint64_t)g.xadj[g.n_local] : 0;
        } else {
            st = dg_scotch(&g, &cut_twice);
        }
    }
    mpi_dgraph_stats s = {0};
    if (st == LIMN_OK)
        st = dg_stats(&g, cut_twice, &s);
    double dt[2] = {MPI_Wtime() - t0, t_graph}, dmax[2];
    MPI_Allreduce(dt, dmax, 2, MPI_DOUBLE, MPI_MAX, comm);
    s.seconds = dmax[0];
    s.seconds_graph = dmax[1];
    free(g.xadj);
    free(g.adj);
    if (st == LIMN_OK) {
        *part_of = g.part_of;
        if (stats)
            *stats = s;
    } else {
        free(g.part_of);
    }
    return st;
}
