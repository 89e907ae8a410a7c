/* SPDX-License-Identifier: MIT */
/*
 * The iteration every stationary method runs (iterate.h): the paper's
 * P_{k+1} = P_k + (M - A P_k), its weighted form and Chebyshev, over any way
 * of running a step (one device in interpolate.c, or MPI ranks), with the
 * stop, stall, cap and divergence rules of the monitor (monitor.c); and the checks of the options.
 */
#include "solve/iterate.h"
#include "mesh/check.h"
#include "base/context.h"
#include "solve/solve.h"
#include "solve/solver.h"
#include "solve/monitor.h"

#include <math.h>

const char *limn_method_name(limn_method m)
{
    switch (m) {
    case LIMN_METHOD_AUTO: return "auto";
    case LIMN_METHOD_PAPER: return "paper";
    case LIMN_METHOD_WEIGHTED: return "weighted";
    case LIMN_METHOD_CG: return "cg";
    case LIMN_METHOD_CHEBYSHEV: return "chebyshev";
    case LIMN_METHOD_SGS: return "sgs";
    }
    return "unknown";
}

/* The registered method's update (solver.c); the paper's for an unknown one. */
solve_kind solve_kind_of(limn_method method)
{
    const solver_ops *ops = solver_find(method);
    return ops ? ops->kind : SOLVE_PAPER;
}

int solve_reorder_wanted(const limn_interpolate_options *o, limn_method method)
{
    return o->reorder && (method == LIMN_METHOD_PAPER || method == LIMN_METHOD_WEIGHTED);
}

limn_status solve_check_options(limn_context *ctx, const limn_interpolate_options *o)
{
    limn_status st = check_scheme(ctx, "limn_interpolate", o->scheme);
    if (st)
        return st;
    if (!(o->alpha >= 0.0 && o->alpha <= 1.0))
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                         "alpha is %g; it must lie in [0, 1] (6/7 or less keeps the iteration "
                         "convergent; 0.5 is a good choice)",
                         o->alpha);
    if (!(o->tolerance > 0.0 && isfinite(o->tolerance)))
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "tolerance is %g; it must be a positive number",
                         o->tolerance);
    if (o->method < LIMN_METHOD_AUTO || o->method > LIMN_METHOD_SGS)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                         "limn_interpolate: unknown method %d (LIMN_METHOD_AUTO 0 .. "
                         "LIMN_METHOD_SGS %d)",
                         (int)o->method, (int)LIMN_METHOD_SGS);
    if (o->precision < LIMN_PRECISION_AUTO || o->precision > LIMN_PRECISION_FLOAT)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                         "limn_interpolate: unknown precision %d (LIMN_PRECISION_AUTO 0, "
                         "LIMN_PRECISION_DOUBLE 1, LIMN_PRECISION_FLOAT 2)",
                         (int)o->precision);
    if (o->max_iterations < 1)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "max iterations is %d; it must be at least 1",
                         o->max_iterations);
    return check_count(ctx, "limn_interpolate", "max_iterations", o->max_iterations, 1,
                       LIMN_MAX_ITERATIONS, "LIMN_MAX_ITERATIONS");
}

/*
 * Runs the stationary or semi-iterative update from buffer 0 through step()
 * (one device, or MPI ranks); on success *which is the buffer holding the
 * answer (always an iterate whose residual was measured). paper: P += M - A P.
 * weighted: omega starts at 1 and, after WEIGHTED_PROBE steps, becomes
 * 2 / (lambda + 1) with lambda = 1 - (contraction of |r|_2), an over-estimate
 * of lambda_min, so omega stays below the optimum and the iteration
 * convergent. chebyshev: the three-term recurrence of solve_chebyshev.c,
 * buffer 1 - cur holding the previous iterate in and the next one out. Counts
 * one stencil product per step.
 */
limn_status solve_iterate(limn_context *ctx, solve_step_fn step, void *user, size_t vertices,
                          limn_scheme scheme, double alpha, const limn_interpolate_options *o,
                          double diag, solve_kind kind, int *which, limn_report *r)
{
    double tol_abs = o->tolerance * diag;
    double omega = 1.0, l2_probe = 0.0;
    int cur = 0, start = r->iterations;
    monitor mon;
    monitor_init(&mon, tol_abs, o->max_iterations, MONITOR_STALL_WINDOW, MONITOR_STALL_RATIO);
    monitor_words words = {MONITOR_LOOP_STATIONARY, "the residual", diag, o->tolerance, scheme,
                           alpha, 0, 0, 0};
    chebyshev cheb;
    chebyshev_init(&cheb, chebyshev_prior(scheme), chebyshev_lead_steps(scheme));
    r->omega = 1.0;
    for (int k = 0;; k++) {
        device_norms nr;
        solve_step sp = {kind, omega, 0.0, 0.0};
        if (kind == SOLVE_CHEBYSHEV)
            chebyshev_coefficients(&cheb, &sp.c1, &sp.c2);
        limn_status st = step(user, cur, &sp, &nr);
        if (st)
            return st;
        nr.max = check_norm_max(nr.max, nr.sum);
        r->products += 1.0;
        size_t n = vertices ? vertices : 1;
        if (kind == SOLVE_WEIGHTED && k == 2)
            l2_probe = sqrt(nr.sum_sq);
        if (kind == SOLVE_WEIGHTED && k == WEIGHTED_PROBE && l2_probe > 0) {
            omega = monitor_weighted_omega(l2_probe, sqrt(nr.sum_sq));
            r->omega = omega;
        }
        if (kind == SOLVE_CHEBYSHEV && nr.max > tol_abs)
            chebyshev_observe(&cheb, nr.max);
        r->spectrum_lower = kind == SOLVE_CHEBYSHEV ? cheb.a : 0.0;
        r->restarts = cheb.restarts;
        r->iterations = start + k;
        r->max_abs_error = nr.max;
        r->mean_abs_error = nr.sum / (double)n;
        monitor_verdict v = monitor_step(&mon, nr.max, k);
        if (v == MONITOR_CONVERGED) {
            *which = cur;
            return LIMN_OK;
        }
        if (v != MONITOR_CONTINUE)
            return monitor_fail(ctx, &mon, v, &words);
        if ((k & 7) == 0 && mon.first > tol_abs && nr.max < mon.first)
            ctx_progress(ctx, "solve", log(mon.first / nr.max) / log(mon.first / tol_abs));
        cur = 1 - cur;
    }
}
