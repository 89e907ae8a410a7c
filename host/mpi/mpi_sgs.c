/* SPDX-License-Identifier: MIT */
/*
 * The Gauss-Seidel-preconditioned conjugate gradients of solve_sgs.c over
 * MPI ranks, on the tiers of mpi_cg.c (mpi_solve_tiers).
 *
 * Colouring: the single process's, computed by the root on the global
 * operator (sgs_colour_rows, greedy in row order within each tier's block)
 * and broadcast, one colour per vertex, with each tier's colour count; so
 * every rank sweeps the same colours, and every row's entries (lower
 * colours, then higher, each in the global row's order) are summed as the
 * single process sums them. On a distributed mesh (no root operator) the
 * same greedy runs rank by rank in input order (mpi_sgs_colour.c): the
 * single process's colouring whenever it keeps the input order.
 *
 * Sweeps: colour by colour, with one halo exchange after each colour of the
 * values the next colours read at ghost columns: t after every colour of the
 * backward sweep (it reads higher colours' t), u after each colour of the
 * forward sweep (it reads lower colours' u), x once before the first sweep.
 * Each rank's table holds its rows of the block in colour order, then the
 * ghosts (sgs_table_build_coloured), and the halo reads and writes it
 * through an mpi_send_view.
 *
 * The dot products are each rank's sum of its rows, reduced in double-double
 * over the ranks: the scalars differ from the single process's by rounding,
 * so the result does too (README "MPI" gives the measured gap), with the
 * same iteration counts.
 */
#include "mpi/mpi_part.h"
#include "base/large_alloc.h"

#include "base/context.h"
#include "mesh/check.h"
#include "stencil/sgs_table.h"
#include "topology/topology.h"

#include <limits.h>
#include <stdlib.h>
#include <string.h>

typedef struct mpi_colouring {
    uint32_t *colour;        /* every local row: owned, then ghosts */
    size_t colours[3];       /* per tier, over the whole mesh */
} mpi_colouring;

/* Root: the colour of every input vertex within its tier's block (by_input,
   n_global of them) and each tier's colour count. */
static limn_status colour_on_root(mpi_part *p, uint32_t *by_input, unsigned long long count[3])
{
    const stencil_operator *op = &p->global;
    size_t n = op->host.rows;
    int8_t *tier = large_malloc(n ? n : 1);
    uint32_t *colour = large_malloc((n ? n : 1) * sizeof *colour);
    limn_status st = LIMN_OK;
    if (!tier || !colour || (n && !by_input))
        st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for the colouring");
    for (size_t r = 0; !st && r < n; r++)
        tier[r] = (int8_t)mpi_tier_of(op->topo.vertex_rule[op->order ? op->order[r] : r]);
    if (!st && n && sgs_colour_rows(&op->host, tier, colour) == 0)
        st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for the colouring");
    for (size_t r = 0; !st && r < n; r++) {
        by_input[op->order ? op->order[r] : r] = colour[r];
        if (colour[r] + 1ULL > count[tier[r]])
            count[tier[r]] = colour[r] + 1ULL;
    }
    free(tier);
    free(colour);
    return st;
}

/* Collective: the root's colouring, each rank's share of it in c (on a
   distributed mesh, no root holding the operator: mpi_sgs_colour_local). */
static limn_status colour_all(mpi_part *p, mpi_colouring *c)
{
    memset(c, 0, sizeof *c);
    int root_path = p->has_global;
    MPI_Bcast(&root_path, 1, MPI_INT, p->root, p->comm);
    if (!root_path) {
        size_t nl = p->n_owned + p->n_ghost;
        c->colour = large_malloc((nl ? nl : 1) * sizeof *c->colour);
        limn_status st = mpi_agree(p, c->colour ? LIMN_OK
                                                : ctx_fail(p->ctx, LIMN_ERR_MEMORY,
                                                           "out of memory for the colouring"));
        return st ? st : mpi_sgs_colour_local(p, c->colour, c->colours);
    }
    size_t n = p->n_global, no = p->n_owned, nl = no + p->n_ghost;
    uint32_t *by_input = large_malloc((n ? n : 1) * sizeof *by_input);
    unsigned long long count[3] = {0, 0, 0};
    limn_status st = by_input ? LIMN_OK : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory");
    if (!st && p->rank == p->root)
        st = colour_on_root(p, by_input, count);
    st = mpi_agree(p, st);
    if (!st) {
        /* one count per vertex (n < 2^32: the operator's column type) */
        MPI_Bcast(by_input, (int)n, MPI_UINT32_T, p->root, p->comm);
        MPI_Bcast(count, 3, MPI_UNSIGNED_LONG_LONG, p->root, p->comm);
        c->colour = large_malloc((nl ? nl : 1) * sizeof *c->colour);
        if (!c->colour)
            st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for the colouring");
    }
    for (size_t i = 0; !st && i < nl; i++)
        c->colour[i] = by_input[i < no ? p->owned_ids[i] : p->ghost_ids[i - no]];
    for (int t = 0; t < 3; t++)
        c->colours[t] = (size_t)count[t];
    free(by_input);
    return mpi_agree(p, st);
}

/* This rank's rows of tier t's block, compacted: a (rows: the tier's owned
   rows in local order; columns: those, then the ghosts), their colours
   (then the ghosts'), dinv, and row_of[i] (owned row of compact row i). */
typedef struct compact {
    stencil_csr a;
    uint32_t *colour, *row_of, *at; /* at: owned row -> compact row (or UINT32_MAX) */
    double *dinv;
} compact;

static void compact_free(compact *k)
{
    stencil_free(&k->a);
    free(k->colour);
    free(k->row_of);
    free(k->at);
    free(k->dinv);
}

static limn_status compact_block(mpi_part *p, const mpi_block *bl, const int8_t *tier, int t,
                                 const mpi_colouring *c, compact *k)
{
    size_t no = p->n_owned, ng = p->n_ghost, nt = 0, nnz = bl->s.row_offsets[no];
    memset(k, 0, sizeof *k);
    for (size_t i = 0; i < no; i++)
        nt += tier[i] == t;
    k->a.rows = nt;
    k->a.cols = nt + ng;
    k->a.row_offsets = large_malloc((nt + 1) * sizeof *k->a.row_offsets);
    k->a.columns = large_malloc((nnz ? nnz : 1) * sizeof *k->a.columns);
    k->a.weights = large_malloc((nnz ? nnz : 1) * sizeof *k->a.weights);
    k->colour = large_malloc((nt + ng ? nt + ng : 1) * sizeof *k->colour);
    k->row_of = large_malloc((nt ? nt : 1) * sizeof *k->row_of);
    k->at = large_malloc((no ? no : 1) * sizeof *k->at);
    k->dinv = large_malloc((nt ? nt : 1) * sizeof *k->dinv);
    if (!k->a.row_offsets || !k->a.columns || !k->a.weights || !k->colour || !k->row_of ||
        !k->at || !k->dinv)
        return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for a solver block");
    for (size_t i = 0, r = 0; i < no; i++) {
        k->at[i] = tier[i] == t ? (uint32_t)r : UINT32_MAX;
        if (tier[i] == t)
            k->row_of[r++] = (uint32_t)i;
    }
    size_t e = 0;
    k->a.row_offsets[0] = 0;
    for (size_t r = 0; r < nt; r++) {
        uint32_t i = k->row_of[r];
        for (uint32_t q = bl->s.row_offsets[i]; q < bl->s.row_offsets[i + 1]; q++) {
            uint32_t col = bl->s.columns[q];
            k->a.columns[e] = col < no ? k->at[col] : (uint32_t)(nt + (col - no));
            k->a.weights[e++] = bl->s.weights[q];
        }
        k->a.row_offsets[r + 1] = (uint32_t)e;
        k->colour[r] = c->colour[i];
        k->dinv[r] = bl->dinv[i];
    }
    for (size_t g = 0; g < ng; g++)
        k->colour[nt + g] = c->colour[no + g];
    return LIMN_OK;
}

enum { V_B, V_X, V_R, V_RHAT, V_PHAT, V_T, V_U, V_ST, V_COUNT };

/* The distributed run of one block: table on the device, vectors, the view
   the halo reads them through. */
typedef struct sgs_run {
    mpi_part *p;
    device_sgs da;
    device_buffer *vec[V_COUNT];
    sgs_vectors v;
    mpi_send_view view;
    uint32_t *send_idx;
} sgs_run;

/* The halo's send slots as rows of the table (a slot of another tier: row 0,
   a value no block row reads). */
static limn_status make_view(sgs_run *s, const sgs_table *tab, const compact *k)
{
    mpi_part *p = s->p;
    const mpi_halo *h = &p->halo;
    size_t slots = h->n_send ? h->send_off[h->n_send - 1] + h->send_cnt[h->n_send - 1] : 0;
    size_t nt = tab->rows;
    uint32_t *table_row = large_malloc((nt ? nt : 1) * sizeof *table_row);
    s->send_idx = large_malloc((slots ? slots : 1) * sizeof *s->send_idx);
    s->view.stage = calloc(4 * (nt ? nt : 1), sizeof *s->view.stage);
    if (!table_row || !s->send_idx || !s->view.stage) {
        free(table_row);
        return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for the halo");
    }
    for (size_t i = 0; i < nt; i++)
        table_row[tab->order[i]] = (uint32_t)i;
    for (size_t q = 0; q < slots; q++) {
        uint32_t r = k->at[p->send_begin + h->send_idx[q]];
        s->send_idx[q] = r == UINT32_MAX ? 0 : table_row[r];
    }
    free(table_row);
    s->view.begin = 0;
    s->view.end = nt;
    s->view.idx = s->send_idx;
    s->view.ghost_at = nt;
    return LIMN_OK;
}

/* The table and vectors on the device: b scaled to S x = dinv b, x the start,
   both in table order. */
static limn_status open_run(sgs_run *s, const sgs_table *tab, const compact *k,
                            const mpi_block *bl)
{
    mpi_part *p = s->p;
    size_t nt = tab->rows, nv = nt + p->n_ghost;
    double *bs = calloc(4 * (nv ? nv : 1), sizeof *bs), *xs = calloc(4 * (nv ? nv : 1), sizeof *xs);
    limn_status st = bs && xs ? LIMN_OK : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory");
    for (size_t i = 0; !st && i < nt; i++) {
        uint32_t o = tab->order[i], row = k->row_of[o];
        for (int c = 0; c < 3; c++)
            bs[4 * i + c] = k->dinv[o] * bl->b4[4 * (size_t)row + c];
        memcpy(xs + 4 * i, bl->x4 + 4 * (size_t)row, 3 * sizeof(double));
    }
    if (!st)
        st = make_view(s, tab, k);
    if (!st)
        st = device_sgs_upload(p->dev, tab, &s->da);
    for (int i = 0; i < V_COUNT && !st; i++)
        st = p->dev->ops->buffer_create(p->dev, 4 * (nv ? nv : 1) * sizeof(double),
                                        i == V_B ? bs : i == V_X ? xs : NULL, &s->vec[i]);
    s->v = (sgs_vectors){s->vec[V_B],    s->vec[V_X], s->vec[V_R], s->vec[V_RHAT],
                         s->vec[V_PHAT], s->vec[V_T], s->vec[V_U], s->vec[V_ST]};
    free(bs);
    free(xs);
    return st;
}

static void close_run(sgs_run *s)
{
    for (int i = 0; i < V_COUNT; i++)
        if (s->vec[i])
            s->p->dev->ops->buffer_release(s->p->dev, s->vec[i]);
    if (s->da.colour_begin)
        device_sgs_release(s->p->dev, &s->da);
    free(s->send_idx);
    free(s->view.stage);
}

/* Colour c of the table alone. */
static device_sgs colour_view(const device_sgs *a, size_t c)
{
    device_sgs one = *a;
    one.colours = 1;
    one.colour_begin = a->colour_begin + c;
    return one;
}

/* The forward sweep (start: the first one, on x), colour by colour, u's
   ghosts exchanged after each colour but the last; the reduced norms. */
static limn_status lower(sgs_run *s, int start, limn_status st, device_norms *out)
{
    mpi_part *p = s->p;
    device_norms loc = {0, 0, 0};
    if (start)
        st = mpi_exchange_view(p, &s->view, s->v.x, st);
    for (size_t c = 0; c < s->da.colours; c++) {
        device_sgs one = colour_view(&s->da, c);
        device_norms n;
        double t0 = MPI_Wtime();
        if (!st)
            st = p->dev->ops->sgs->sgs_lower(p->dev, &one, start, &s->v, &n);
        p->stats.seconds_compute += MPI_Wtime() - t0;
        if (!st) {
            loc.max = n.max > loc.max ? n.max : loc.max;
            loc.sum += n.sum;
        }
        if (c + 1 < s->da.colours)
            st = mpi_exchange_view(p, &s->view, s->v.u, st);
    }
    return mpi_reduce_norms(p, st, &loc, out);
}

/* The backward sweep, colour by colour from the last, t's ghosts exchanged
   after each (the forward sweep reads them all). */
static limn_status upper(sgs_run *s, double beta)
{
    mpi_part *p = s->p;
    limn_status st = LIMN_OK;
    for (size_t c = s->da.colours; c-- > 0;) {
        device_sgs one = colour_view(&s->da, c);
        double t0 = MPI_Wtime();
        if (!st)
            st = p->dev->ops->sgs->sgs_upper(p->dev, &one, beta, &s->v);
        p->stats.seconds_compute += MPI_Wtime() - t0;
        st = mpi_exchange_view(p, &s->view, s->v.t, st);
    }
    return st;
}

/* solve_sgs.c's loop; every decision on reduced values. */
static limn_status iterate(sgs_run *s, const sgs_table *tab, double tol_abs, int max_iter,
                           double share, solve_stats *stats)
{
    mpi_part *p = s->p;
    double entries = mpi_sum(p, (double)(tab->lower + tab->upper + tab->rows));
    double twice = mpi_sum(p, (double)(tab->lower + tab->upper + 2 * tab->rows));
    double step_pass = entries > 0 ? twice / entries : 1.0;
    device_norms norms;
    limn_status st = lower(s, 1, LIMN_OK, &norms);
    stats->products += share;
    double gamma = norms.sum, beta = 0.0;
    cg_watch watch = {0};
    while (!st) {
        int done = 0;
        st = cg_watch_step(p->ctx, &watch, check_norm_max(norms.max, norms.sum), stats, tol_abs,
                           max_iter, &done);
        if (st || done)
            break;
        device_norms dot;
        st = lower(s, 0, upper(s, beta), &dot);
        double pq = dot.sum;
        stats->products += share * step_pass;
        stats->iterations++;
        if (st)
            break;
        st = cg_curvature(p->ctx, pq, stats);
        if (st)
            break;
        device_norms loc;
        st = p->dev->ops->sgs->sgs_update(p->dev, &s->da, gamma / pq, &s->v, &loc);
        st = mpi_reduce_norms(p, st, &loc, &norms);
        beta = norms.sum / gamma;
        gamma = norms.sum;
    }
    return st;
}

/* mpi_block_fn: SGS-preconditioned CG on tier t's block. */
static limn_status block_sgs(mpi_part *p, void *user, const mpi_block *bl, const int8_t *tier,
                             int t, double tol_abs, int max_iter, double share,
                             solve_stats *stats)
{
    const mpi_colouring *c = user;
    compact k;
    sgs_table tab;
    memset(&tab, 0, sizeof tab);
    limn_status st = compact_block(p, bl, tier, t, c, &k);
    if (!st) /* LIMN_ERR_TOPOLOGY (no message) on a row the sweeps cannot take */
        st = sgs_table_build_coloured(p->ctx, &k.a, k.dinv, k.colour, c->colours[t], &tab);
    sgs_run s = {.p = p};
    if (!st)
        st = open_run(&s, &tab, &k, bl);
    st = mpi_agree(p, st);
    if (!st)
        st = iterate(&s, &tab, tol_abs, max_iter, share, stats);
    size_t nt = tab.rows;
    double *xs = large_malloc(4 * (nt ? nt : 1) * sizeof *xs);
    if (!st && !xs)
        st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory");
    if (!st && nt)
        st = p->dev->ops->buffer_read_at(p->dev, s.v.x, 0, 4 * nt * sizeof(double), xs);
    for (size_t i = 0; !st && i < nt; i++)
        memcpy(bl->x4 + 4 * (size_t)k.row_of[tab.order[i]], xs + 4 * i, 3 * sizeof(double));
    free(xs);
    close_run(&s);
    sgs_table_free(&tab);
    compact_free(&k);
    return mpi_agree(p, st);
}

limn_status mpi_solve_sgs(mpi_part *p, const double *m4, double tol_abs, int max_iter,
                          double *p4, solve_stats *stats)
{
    mpi_colouring c;
    limn_status st = colour_all(p, &c);
    if (!st)
        st = mpi_solve_tiers(p, m4, tol_abs, max_iter, p4, block_sgs, &c, stats);
    free(c.colour);
    return st;
}
