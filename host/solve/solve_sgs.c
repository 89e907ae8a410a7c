/* SPDX-License-Identifier: MIT */
/*
 * Conjugate gradients preconditioned by symmetric Gauss-Seidel, for A P = M
 * (README "Solvers"). On each tier's block (solve_tiers), S = dinv A is
 * symmetric positive definite; with S = L + D + U and C = (D + L) D^-1/2,
 * CG runs on C^-1 S C^-T (Eisenstat's form): one step is a backward sweep
 * t = (D + U)^-1 D^1/2 phat and a forward sweep u = (D + L)^-1 (D^1/2 phat -
 * D t), since C^-1 S C^-T phat = D^1/2 (t + u). The two sweeps read each
 * entry once, so a step costs about one product, against one product plus a
 * separate preconditioner for plain PCG. The iterate x (x += alpha t) and the
 * residual r = b - S x (r -= alpha S t, with S t = D^1/2 phat + L t summed in
 * the forward sweep) are kept in the block's own terms, so the stop test
 * max scale_i |r_i| <= tol is on A's residual, as every method's.
 * Sweeps run colour by colour (sgs_table.c). Measured on the shared medium
 * meshes: 4-6 steps to 1e-6 where the seeds' iteration takes 23-82.
 */
#include "mesh/check.h"
#include "base/context.h"
#include "stencil/sgs_table.h"
#include "solve/solver.h"
#include "base/clock.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { V_B, V_X, V_R, V_RHAT, V_PHAT, V_T, V_U, V_ST, V_COUNT };

static limn_status run(limn_context *ctx, struct device *dev, const device_sgs *a,
                       const sgs_vectors *v, double tol_abs, int max_iter, double share,
                       const sgs_table *t, solve_stats *stats)
{
    const device_ops *ops = dev->ops;
    /* entries read, as a fraction of the block's table (diagonal included):
       the start sweep reads each once, a step's two sweeps the diagonal twice */
    double entries = (double)(t->lower + t->upper + t->rows);
    double step_pass = (double)(t->lower + t->upper + 2 * t->rows) / entries;
    device_norms norms;
    limn_status st = ops->sgs->sgs_lower(dev, a, 1, v, &norms);
    stats->products += share;
    double gamma = norms.sum, beta = 0.0;
    cg_watch watch = {0};
    while (!st) {
        int done = 0;
        st = cg_watch_step(ctx, &watch, check_norm_max(norms.max, norms.sum), stats, tol_abs,
                           max_iter, &done);
        if (st || done)
            break;
        device_norms dot = {0, 0, 0};
        st = ops->sgs->sgs_upper(dev, a, beta, v);
        if (!st)
            st = ops->sgs->sgs_lower(dev, a, 0, v, &dot);
        double pq = dot.sum;
        stats->products += share * step_pass;
        stats->iterations++;
        if (st)
            break;
        st = cg_curvature(ctx, pq, stats);
        if (!st)
            st = ops->sgs->sgs_update(dev, a, gamma / pq, v, &norms);
        beta = norms.sum / gamma;
        gamma = norms.sum;
    }
    return st;
}

static limn_status solve_block_sgs(limn_context *ctx, struct device *dev, const stencil_csr *a,
                                   const device_csr *on_device, const double *b, double *x0,
                                   const double *dinv, double tol_abs, int max_iter, double n_total,
                                   solve_stats *stats)
{
    (void)on_device; /* the sweeps need their own layout */
    size_t n = a->rows;
    if (n == 0)
        return LIMN_OK;
    sgs_table t;
    limn_status st = sgs_table_build(ctx, a, dinv, &t);
    if (st)
        return st;
    /* b scaled to S x = dinv b; both in the table's row order */
    double *bs = malloc(4 * n * sizeof *bs), *xs = malloc(4 * n * sizeof *xs);
    if (!bs || !xs) {
        free(bs);
        free(xs);
        sgs_table_free(&t);
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for the solver");
    }
    for (size_t i = 0; i < n; i++) {
        uint32_t o = t.order[i];
        for (int c = 0; c < 3; c++)
            bs[4 * i + c] = dinv[o] * b[4 * (size_t)o + c];
        bs[4 * i + 3] = 0.0;
        memcpy(xs + 4 * i, x0 + 4 * (size_t)o, 3 * sizeof(double));
        xs[4 * i + 3] = 0.0;
    }
    device_sgs da;
    device_buffer *vec[V_COUNT] = {0};
    const device_ops *ops = dev->ops;
    st = device_sgs_upload(dev, &t, &da);
    for (int i = 0; i < V_COUNT && !st; i++)
        st = ops->buffer_create(dev, 4 * n * sizeof(double),
                                i == V_B ? bs : i == V_X ? xs : NULL, &vec[i]);
    if (!st) {
        sgs_vectors v = {vec[V_B], vec[V_X], vec[V_R], vec[V_RHAT],
                         vec[V_PHAT], vec[V_T], vec[V_U], vec[V_ST]};
        double t_loop = clock_seconds(), compiles = dev->setup.kernels;
        st = run(ctx, dev, &da, &v, tol_abs, max_iter, (double)n / n_total, &t, stats);
        stats->seconds_loop += clock_seconds() - t_loop - (dev->setup.kernels - compiles);
        if (!st)
            st = ops->buffer_read(dev, vec[V_X], 4 * n * sizeof(double), xs);
        for (size_t i = 0; !st && i < n; i++)
            memcpy(x0 + 4 * (size_t)t.order[i], xs + 4 * i, 3 * sizeof(double));
    }
    for (int i = 0; i < V_COUNT; i++)
        if (vec[i])
            ops->buffer_release(dev, vec[i]);
    if (da.colour_begin || da.info)
        device_sgs_release(dev, &da);
    free(bs);
    free(xs);
    sgs_table_free(&t);
    return st;
}

/* SGS-preconditioned CG gives the start; the seeds' step measures its residual. */
const solver_ops solver_sgs = {
    .method = LIMN_METHOD_SGS,
    .kind = SOLVE_PAPER,
    .block = solve_block_sgs,
    .long_name = "sgs (Gauss-Seidel-preconditioned CG)",
    .fallback_reason = "sgs cannot run on this operator (see the warning)",
};
