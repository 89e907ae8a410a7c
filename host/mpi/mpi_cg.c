/* SPDX-License-Identifier: MIT */
/*
 * The tiered, D-preconditioned conjugate gradients of solve_cg.c over MPI
 * ranks (the derivation is in README "Solvers"). A tier's block keeps every
 * owned row (rows of other tiers empty, their vector entries zero), so the
 * rows, the ghost plan and the interior / boundary split of the whole table
 * serve every block. Each step: one overlapped product with its local dot
 * product, the update with its local norms, and two reductions. The ranks'
 * sums are combined in double-double, so every rank gets the same scalars
 * whatever order MPI adds them in; each rank's own sum still runs over its own
 * rows, so the result differs from the single process's by rounding only
 * (README "MPI" gives the measured difference).
 */
#include "mpi/mpi_part.h"
#include "base/large_alloc.h"

#include "base/context.h"
#include "topology/topology.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct cg_rows {
    struct device *dev;
    device_buffer *in, *out, *dinv;
} cg_rows;

static limn_status rows_spmv(void *user, const device_csr *rows, device_norms *norms)
{
    cg_rows *a = user;
    memset(norms, 0, sizeof *norms);
    return a->dev->ops->spmv(a->dev, rows, a->in, a->out);
}

/* out = A in on the rows, and their sum of dinv_i (in_i . out_i) in norms->sum */
static limn_status rows_dot(void *user, const device_csr *rows, device_norms *norms)
{
    cg_rows *a = user;
    memset(norms, 0, sizeof *norms);
    return a->dev->ops->cg->spmv_dot(a->dev, rows, a->in, a->out, a->dinv, &norms->sum);
}

int mpi_tier_of(uint8_t rule)
{
    return rule == RULE_SMOOTH ? 2 : rule == RULE_CREASE ? 1 : 0;
}

/*
 * PCG on one block (table: this rank's rows of it on the device). b4: owned
 * rows; x4: owned and ghost rows, the start, and the answer on return; dinv:
 * one per owned row. Local failures are carried to the next reduction, so
 * every rank leaves the loop at the same step.
 */
static limn_status pcg(mpi_part *p, const device_csr *table, const double *b4, double *x4,
                       const double *dinv_host, double tol_abs, int max_iter, double share,
                       solve_stats *stats)
{
    const device_ops *ops = p->dev->ops;
    struct device *dev = p->dev;
    size_t no = p->n_owned, nl = p->n_owned + p->n_ghost, row = 4 * sizeof(double);
    device_buffer *b = NULL, *x = NULL, *z = NULL, *d = NULL, *q = NULL, *dinv = NULL;
    limn_status st = ops->buffer_create(dev, no * row, b4, &b);
    if (!st)
        st = ops->buffer_create(dev, nl * row, x4, &x);
    if (!st)
        st = ops->buffer_create(dev, no * row, NULL, &z);
    if (!st)
        st = ops->buffer_create(dev, nl * row, NULL, &d); /* the direction: ghosts too */
    if (!st)
        st = ops->buffer_create(dev, no * row, NULL, &q);
    if (!st)
        st = ops->buffer_create(dev, no * sizeof(double), dinv_host, &dinv);
    st = mpi_agree(p, st);
    device_norms loc, nz = {0, 0, 0}, glob;
    double rz = 0;
    cg_watch watch = {0};
    limn_status pending = LIMN_OK;
    if (!st) {
        /* z = b - A x0; d = z; norms of z through a zero update */
        cg_rows a = {dev, x, q, dinv};
        pending = mpi_overlapped(p, table, x, rows_spmv, &a, LIMN_OK, &loc);
        if (!pending)
            pending = ops->axpby(dev, no, 1.0, b, -1.0, q, z);
        if (!pending)
            pending = ops->axpby(dev, no, 1.0, z, 0.0, z, d);
        if (!pending)
            pending = ops->cg->pcg_update(dev, no, 0.0, d, q, x, z, dinv, &loc);
        st = mpi_reduce_norms(p, pending, &loc, &nz);
        pending = LIMN_OK;
        stats->products += share;
        rz = nz.sum;
    }
    while (!st) {
        /* every test reads reduced values: all ranks decide alike */
        int done = 0;
        st = cg_watch_step(p->ctx, &watch, nz.max, stats, tol_abs, max_iter, &done);
        if (st || done)
            break;
        cg_rows a = {dev, d, q, dinv};
        limn_status ls = mpi_overlapped(p, table, d, rows_dot, &a, pending, &loc);
        st = mpi_reduce_norms(p, ls, &loc, &glob);
        stats->products += share;
        stats->iterations++;
        if (st)
            break;
        double pq = glob.sum;
        st = cg_curvature(p->ctx, pq, stats);
        if (st)
            break;
        double alpha = rz / pq;
        ls = ops->cg->pcg_update(dev, no, alpha, d, q, x, z, dinv, &loc);
        st = mpi_reduce_norms(p, ls, &loc, &nz);
        if (st)
            break;
        double beta = nz.sum / rz;
        rz = nz.sum;
        pending = ops->axpby(dev, no, 1.0, z, beta, d, d);
    }
    if (!st)
        st = pending;
    if (!st)
        st = ops->buffer_read_at(dev, x, 0, no * row, x4);
    device_buffer *bufs[] = {b, x, z, d, q, dinv};
    for (int i = 0; i < 6; i++)
        if (bufs[i])
            ops->buffer_release(dev, bufs[i]);
    return mpi_agree(p, st);
}

/* The ghost rows of x4 (owned rows current) made current. */
static limn_status exchange_host(mpi_part *p, double *x4)
{
    size_t no = p->n_owned, nl = no + p->n_ghost, row = 4 * sizeof(double);
    device_buffer *x = NULL;
    limn_status st = p->dev->ops->buffer_create(p->dev, nl * row, x4, &x);
    st = mpi_exchange(p, x, st);
    if (!st)
        st = p->dev->ops->buffer_read_at(p->dev, x, no * row, p->n_ghost * row, x4 + 4 * no);
    if (x)
        p->dev->ops->buffer_release(p->dev, x);
    return mpi_agree(p, st);
}

static void block_free(mpi_block *bl)
{
    stencil_free(&bl->s);
    free(bl->b4);
    free(bl->x4);
    free(bl->dinv);
}

/* Tier t's block and right-hand side b = M_t - A_t,lower P (entries in the
   rows' order, as solve_cg.c's make_block). LIMN_ERR_TOPOLOGY, without a
   message, when a row of tier t reads a later tier. */
static limn_status make_block(mpi_part *p, const int8_t *tier, int t, const double *m4,
                              const double *p4, mpi_block *bl)
{
    const stencil_csr *a = &p->host;
    size_t no = p->n_owned, nl = no + p->n_ghost, nnz = 0;
    memset(bl, 0, sizeof *bl);
    for (size_t i = 0; i < no; i++)
        if (tier[i] == t)
            for (uint32_t e = a->row_offsets[i]; e < a->row_offsets[i + 1]; e++)
                nnz += tier[a->columns[e]] == t;
    bl->s.rows = no;
    bl->s.cols = nl;
    bl->s.row_offsets = large_malloc((no + 1) * sizeof *bl->s.row_offsets);
    bl->s.columns = large_malloc((nnz ? nnz : 1) * sizeof *bl->s.columns);
    bl->s.weights = large_malloc((nnz ? nnz : 1) * sizeof *bl->s.weights);
    bl->b4 = calloc(no ? 4 * no : 4, sizeof *bl->b4);
    bl->x4 = calloc(nl ? 4 * nl : 4, sizeof *bl->x4);
    bl->dinv = calloc(no ? no : 1, sizeof *bl->dinv);
    if (!bl->s.row_offsets || !bl->s.columns || !bl->s.weights || !bl->b4 || !bl->x4 || !bl->dinv)
        return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for a solver block");
    size_t k2 = 0;
    bl->s.row_offsets[0] = 0;
    for (size_t i = 0; i < no; i++) {
        if (tier[i] == t) {
            double rhs[3] = {m4[4 * i], m4[4 * i + 1], m4[4 * i + 2]};
            for (uint32_t e = a->row_offsets[i]; e < a->row_offsets[i + 1]; e++) {
                uint32_t c = a->columns[e];
                if (tier[c] == t) {
                    bl->s.columns[k2] = c;
                    bl->s.weights[k2++] = a->weights[e];
                } else if (tier[c] > t) {
                    return LIMN_ERR_TOPOLOGY;
                } else {
                    for (int d = 0; d < 3; d++)
                        rhs[d] -= a->weights[e] * p4[4 * (size_t)c + d];
                }
            }
            memcpy(bl->b4 + 4 * i, rhs, sizeof rhs);
            memcpy(bl->x4 + 4 * i, m4 + 4 * i, 3 * sizeof(double));
            bl->dinv[i] = 1.0 / p->owned_scale[i];
        }
        bl->s.row_offsets[i + 1] = (uint32_t)k2;
    }
    return LIMN_OK;
}

/* The D-preconditioned block solve (mpi_block_fn): the block's table uploaded. */
static limn_status block_jacobi(mpi_part *p, void *user, const mpi_block *bl, const int8_t *tier,
                                int t, double tol_abs, int max_iter, double share,
                                solve_stats *stats)
{
    (void)user, (void)tier, (void)t;
    device_csr sd;
    limn_status st = mpi_agree(p, device_csr_upload(p->dev, &bl->s, &sd));
    if (!st) {
        st = pcg(p, &sd, bl->b4, bl->x4, bl->dinv, tol_abs, max_iter, share, stats);
        device_csr_release(p->dev, &sd);
    }
    return st;
}

limn_status mpi_solve_tiers(mpi_part *p, const double *m4, double tol_abs, int max_iter,
                            double *p4, mpi_block_fn solve_block, void *user, solve_stats *stats)
{
    size_t no = p->n_owned, nl = no + p->n_ghost;
    int8_t *tier = large_malloc(nl ? nl : 1);
    limn_status st = tier ? LIMN_OK : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory");
    double count[3] = {0, 0, 0};
    for (size_t i = 0; !st && i < nl; i++) {
        tier[i] = (int8_t)mpi_tier_of(i < no ? p->owned_rule[i] : p->ghost_rule[i - no]);
        count[tier[i]] += i < no;
    }
    st = mpi_agree(p, st);
    for (int t = 0; !st && t < 3; t++)
        count[t] = mpi_sum(p, count[t]); /* integers: exact */
    double n = (double)(p->n_global ? p->n_global : 1);
    memcpy(p4, m4, 4 * no * sizeof *p4); /* pinned rows: P = M */
    for (int t = 1; !st && t <= 2; t++) {
        if (count[t] == 0)
            continue;
        mpi_block bl;
        memset(&bl, 0, sizeof bl);
        st = exchange_host(p, p4); /* the lower tiers' values at ghost columns */
        if (!st) {
            st = make_block(p, tier, t, m4, p4, &bl);
            st = mpi_agree(p, st);
        }
        if (st) {
            block_free(&bl);
            break;
        }
        /* forming b reads the block's rows once (nothing when it is all of A) */
        if (count[t] < n)
            stats->products += count[t] / n;
        st = solve_block(p, user, &bl, tier, t, tol_abs, max_iter, count[t] / n, stats);
        for (size_t i = 0; !st && i < no; i++)
            if (tier[i] == t)
                memcpy(p4 + 4 * i, bl.x4 + 4 * i, 3 * sizeof(double));
        block_free(&bl);
    }
    free(tier);
    return st;
}

limn_status mpi_solve_cg(mpi_part *p, const double *m4, double tol_abs, int max_iter, double *p4,
                         solve_stats *stats)
{
    return mpi_solve_tiers(p, m4, tol_abs, max_iter, p4, block_jacobi, NULL, stats);
}
