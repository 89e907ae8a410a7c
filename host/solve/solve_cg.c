/* SPDX-License-Identifier: MIT */
/*
 * Conjugate gradients for A P = M (DESIGN.md §1; derivation in README
 * "Solvers"). A is block triangular by vertex rule: pinned rows (corners,
 * non-manifold, isolated) are the identity; crease rows touch crease and
 * pinned columns only; smooth rows touch anything. So the solve runs in tiers:
 * P = M on pinned rows; then the crease block, then the smooth block, each
 * with the known tiers moved to the right-hand side. On each block
 * A_TT = D_T S_TT with S_TT symmetric (scheme_limit_row_scale), and CG on
 * S_TT x = D_T^-1 b preconditioned by D_T iterates with the spectrum of A_TT
 * itself; its preconditioned residual z = b - A_TT x is the true residual, so
 * the stop test (max |z_i| <= tol) is free. The three coordinates are one
 * stacked system (block diagonal), so one alpha and beta per step.
 */
#include "solve/solver.h"
#include "mesh/check.h"
#include "base/context.h"
#include "scheme/scheme.h"
#include "base/clock.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct block {
    stencil_csr s;          /* rows and columns of the tier, local numbering */
    uint32_t *rows;         /* operator row of each local row */
    double *b, *x0, *dinv;  /* 4 per row (b, x0), 1 per row (dinv) */
} block;

static void block_free(block *bl)
{
    stencil_free(&bl->s);
    free(bl->rows);
    free(bl->b);
    free(bl->x0);
    free(bl->dinv);
    memset(bl, 0, sizeof *bl);
}

static int tier_of(const stencil_operator *op, size_t row)
{
    uint32_t v = op->order ? op->order[row] : (uint32_t)row;
    switch ((vertex_rule)op->topo.vertex_rule[v]) {
    case RULE_SMOOTH: return 2;
    case RULE_CREASE: return 1;
    default: return 0;
    }
}

/* Extracts the tier's block and its right-hand side b = M_T - A_T,other P.
   Fails (returns 1) if a row references a column of a later tier. */
static limn_status make_block(limn_context *ctx, const stencil_operator *op, const int *tier,
                              const uint32_t *local, int t, const double *m4, const double *p4,
                              size_t count, block *bl)
{
    const stencil_csr *a = &op->host;
    memset(bl, 0, sizeof *bl);
    size_t nnz = 0;
    for (size_t r = 0; r < a->rows; r++)
        if (tier[r] == t)
            for (uint32_t k = a->row_offsets[r]; k < a->row_offsets[r + 1]; k++)
                nnz += tier[a->columns[k]] == t;
    bl->s.rows = bl->s.cols = count;
    bl->s.row_offsets = malloc((count + 1) * sizeof(uint32_t));
    bl->s.columns = malloc((nnz ? nnz : 1) * sizeof(uint32_t));
    bl->s.weights = malloc((nnz ? nnz : 1) * sizeof(double));
    bl->rows = malloc((count ? count : 1) * sizeof(uint32_t));
    bl->b = malloc((count ? count : 1) * 4 * sizeof(double));
    bl->x0 = malloc((count ? count : 1) * 4 * sizeof(double));
    bl->dinv = malloc((count ? count : 1) * sizeof(double));
    if (!bl->s.row_offsets || !bl->s.columns || !bl->s.weights || !bl->rows || !bl->b ||
        !bl->x0 || !bl->dinv) {
        block_free(bl);
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for a solver block");
    }
    size_t i = 0, k2 = 0;
    bl->s.row_offsets[0] = 0;
    for (size_t r = 0; r < a->rows; r++) {
        if (tier[r] != t)
            continue;
        double rhs[3] = {m4[4 * r], m4[4 * r + 1], m4[4 * r + 2]};
        for (uint32_t k = a->row_offsets[r]; k < a->row_offsets[r + 1]; k++) {
            uint32_t c = a->columns[k];
            if (tier[c] == t) {
                bl->s.columns[k2] = local[c];
                bl->s.weights[k2++] = a->weights[k];
            } else if (tier[c] > t) {
                block_free(bl);
                return LIMN_ERR_TOPOLOGY; /* caller falls back */
            } else {
                for (int d = 0; d < 3; d++)
                    rhs[d] -= a->weights[k] * p4[4 * c + d];
            }
        }
        bl->s.row_offsets[i + 1] = (uint32_t)k2;
        bl->rows[i] = (uint32_t)r;
        memcpy(bl->b + 4 * i, rhs, 3 * sizeof(double));
        bl->b[4 * i + 3] = 0.0;
        memcpy(bl->x0 + 4 * i, m4 + 4 * r, 4 * sizeof(double));
        uint32_t v = op->order ? op->order[r] : (uint32_t)r;
        bl->dinv[i] = 1.0 / scheme_limit_row_scale(&op->topo, op->scheme, v);
        i++;
    }
    return LIMN_OK;
}

limn_status cg_watch_step(limn_context *ctx, cg_watch *w, double residual, solve_stats *stats,
                          double tol_abs, int max_iter, int *done)
{
    if (w->mon.steps == 0)
        monitor_init(&w->mon, tol_abs, max_iter, MONITOR_STALL_WINDOW, MONITOR_STALL_RATIO);
    monitor_verdict v = monitor_step(&w->mon, residual, stats->iterations);
    /* CG does not diverge on these operators: a non-finite residual is overflow */
    monitor_words words = {MONITOR_LOOP_CG, "the conjugate-gradient residual", 0.0, 0.0,
                           LIMN_SCHEME_AUTO, 0.0, stats->catmark_alpha0, 0, 0};
    *done = v == MONITOR_CONVERGED;
    return monitor_fail(ctx, &w->mon, v, &words);
}

limn_status cg_curvature(limn_context *ctx, double pq, solve_stats *stats)
{
    if (pq > 0.0 && isfinite(pq))
        return LIMN_OK;
    if (!isfinite(pq)) /* overflow, not a property of the operator */
        return check_nonfinite_iteration(ctx, "p.Ap in conjugate gradients", stats->iterations,
                                         LIMN_SCHEME_AUTO, 0.0, 0);
    return ctx_fail(ctx, LIMN_ERR_SINGULAR,
                     "conjugate gradients broke down (p.Ap = %.3g): the limit operator is "
                     "not positive definite for this mesh%s; no result was written",
                     pq,
                     stats->catmark_alpha0 ? ": run again with --alpha 0.5 or --method paper"
                                           : ": try --method paper");
}

/* PCG on one block whose matrix is on the device (s, n rows): b and x0 are
   4 doubles a row, dinv one; the answer returns in x0. */
static limn_status pcg(limn_context *ctx, struct device *dev, const device_csr *sp,
                       size_t n, const double *b_host, double *x0, const double *dinv_host,
                       double tol_abs, int max_iter, double n_total, solve_stats *stats)
{
    if (n == 0)
        return LIMN_OK;
    const device_ops *ops = dev->ops;
    const device_csr s = *sp;
    device_buffer *b = NULL, *x = NULL, *z = NULL, *p = NULL, *q = NULL, *dinv = NULL;
    size_t bytes = 4 * n * sizeof(double);
    limn_status st = ops->buffer_create(dev, bytes, b_host, &b);
    if (!st)
        st = ops->buffer_create(dev, bytes, x0, &x);
    if (!st)
        st = ops->buffer_create(dev, bytes, NULL, &z);
    if (!st)
        st = ops->buffer_create(dev, bytes, NULL, &p);
    if (!st)
        st = ops->buffer_create(dev, bytes, NULL, &q);
    if (!st)
        st = ops->buffer_create(dev, n * sizeof(double), dinv_host, &dinv);
    double share = (double)n / n_total, rz = 0;
    device_norms nz;
    double t_loop = clock_seconds(), compiles = dev->setup.kernels;
    /* z = b - S x0 (one product); p = z; norms of z through a zero update */
    if (!st)
        st = ops->spmv(dev, &s, x, q);
    if (!st)
        st = ops->axpby(dev, n, 1.0, b, -1.0, q, z);
    if (!st)
        st = ops->axpby(dev, n, 1.0, z, 0.0, z, p);
    if (!st)
        st = ops->cg->pcg_update(dev, n, 0.0, p, q, x, z, dinv, &nz);
    stats->products += share;
    rz = nz.sum;
    cg_watch watch = {0};
    while (!st) {
        int done = 0;
        st = cg_watch_step(ctx, &watch, check_norm_max(nz.max, nz.sum), stats, tol_abs,
                           max_iter, &done);
        if (st || done)
            break;
        double pq;
        st = ops->cg->spmv_dot(dev, &s, p, q, dinv, &pq);
        stats->products += share;
        stats->iterations++;
        if (st)
            break;
        st = cg_curvature(ctx, pq, stats);
        if (st)
            break;
        double alpha = rz / pq;
        st = ops->cg->pcg_update(dev, n, alpha, p, q, x, z, dinv, &nz);
        if (st)
            break;
        double beta = nz.sum / rz;
        rz = nz.sum;
        st = ops->axpby(dev, n, 1.0, z, beta, p, p);
    }
    stats->seconds_loop += clock_seconds() - t_loop - (dev->setup.kernels - compiles);
    if (!st)
        st = ops->buffer_read(dev, x, bytes, x0);
    device_buffer *bufs[] = {b, x, z, p, q, dinv};
    for (int i = 0; i < 6; i++)
        if (bufs[i])
            ops->buffer_release(dev, bufs[i]);
    return st;
}

/* The D-preconditioned block solve (solve_block_fn): the block's table is
   uploaded unless it is the operator's own. */
static limn_status solve_block_jacobi(limn_context *ctx, struct device *dev,
                                      const stencil_csr *a, const device_csr *on_device,
                                      const double *b, double *x0, const double *dinv,
                                      double tol_abs, int max_iter, double n_total,
                                      solve_stats *stats)
{
    if (on_device)
        return pcg(ctx, dev, on_device, a->rows, b, x0, dinv, tol_abs, max_iter, n_total, stats);
    device_csr sd;
    limn_status st = device_csr_upload(dev, a, &sd);
    if (!st) {
        st = pcg(ctx, dev, &sd, a->rows, b, x0, dinv, tol_abs, max_iter, n_total, stats);
        device_csr_release(dev, &sd);
    }
    return st;
}

/* Every row smooth (closed manifold meshes): the operator's own table is the
   block, already on the device; b = x0 = M. */
static limn_status solve_single_block(limn_context *ctx, const stencil_operator *op,
                                      const double *m4, double tol_abs, int max_iter, double *p4,
                                      solve_block_fn solve_block, solve_stats *stats)
{
    size_t n = op->host.rows;
    double *dinv = malloc((n ? n : 1) * sizeof *dinv);
    if (!dinv)
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for the solver");
    for (size_t r = 0; r < n; r++)
        dinv[r] = 1.0 / scheme_limit_row_scale(&op->topo, op->scheme,
                                               op->order ? op->order[r] : (uint32_t)r);
    memcpy(p4, m4, 4 * n * sizeof(double));
    limn_status st = solve_block(ctx, op->dev, &op->host, &op->device, m4, p4, dinv, tol_abs,
                                 max_iter, (double)(n ? n : 1), stats);
    free(dinv);
    return st;
}

limn_status solve_tiers(limn_context *ctx, const stencil_operator *op, const double *m4,
                        double tol_abs, int max_iter, double *p4, solve_block_fn solve_block,
                        solve_stats *stats)
{
    size_t n = op->host.rows;
    int *tier = malloc((n ? n : 1) * sizeof *tier);
    uint32_t *local = malloc((n ? n : 1) * sizeof *local);
    if (!tier || !local) {
        free(tier);
        free(local);
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for the solver");
    }
    size_t count[3] = {0, 0, 0};
    for (size_t r = 0; r < n; r++) {
        tier[r] = tier_of(op, r);
        local[r] = (uint32_t)count[tier[r]]++;
    }
    if (count[2] == n) {
        free(tier);
        free(local);
        return solve_single_block(ctx, op, m4, tol_abs, max_iter, p4, solve_block, stats);
    }
    /* pinned rows: P = M */
    memcpy(p4, m4, 4 * n * sizeof(double));
    limn_status st = LIMN_OK;
    for (int t = 1; t <= 2 && !st; t++) {
        if (count[t] == 0)
            continue;
        block bl;
        st = make_block(ctx, op, tier, local, t, m4, p4, count[t], &bl);
        if (st)
            break; /* LIMN_ERR_TOPOLOGY: not block triangular, the caller falls back */
        /* forming b reads the block's rows once: a fraction of a product,
           and nothing when no other tier exists (b = M) */
        if (count[t] < n)
            stats->products += (double)count[t] / (double)(n ? n : 1);
        st = solve_block(ctx, op->dev, &bl.s, NULL, bl.b, bl.x0, bl.dinv, tol_abs, max_iter,
                         (double)(n ? n : 1), stats);
        for (size_t i = 0; !st && i < count[t]; i++)
            memcpy(p4 + 4 * (size_t)bl.rows[i], bl.x0 + 4 * i, 3 * sizeof(double));
        block_free(&bl);
    }
    free(tier);
    free(local);
    return st;
}

/* CG gives the start; the seeds' step measures its residual. */
const solver_ops solver_cg = {
    .method = LIMN_METHOD_CG,
    .kind = SOLVE_PAPER,
    .block = solve_block_jacobi,
    .long_name = "conjugate gradients",
    .fallback_reason = "cg cannot run on this operator (not block triangular)",
};
