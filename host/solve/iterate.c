/* SPDX-License-Identifier: MIT */
/*
 * The iteration every stationary method runs (iterate.h): the paper's
 * P_{k+1} = P_k + (M - A P_k), its weighted form and Chebyshev, over any way
 * of running a step (one device in interpolate.c, or MPI ranks), with the
 * stop, stall, cap and divergence rules; and the checks of the options.
 */
#include "solve/iterate.h"
#include "mesh/check.h"
#include "base/context.h"
#include "solve/solve.h"

#include <math.h>

/* Iterations over which a residual must shrink by STALL_FACTOR, else the
   operator is treated as singular (e.g. alpha = 0 on an all-valence-3 cube). */
#define STALL_WINDOW 25
#define STALL_FACTOR 0.99

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

solve_kind solve_kind_of(limn_method method)
{
    return method == LIMN_METHOD_WEIGHTED    ? SOLVE_WEIGHTED
           : method == LIMN_METHOD_CHEBYSHEV ? SOLVE_CHEBYSHEV
                                             : SOLVE_PAPER;
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

/* Iterations of the weighted method spent estimating lambda_min from the
   contraction of the seeds' iteration (power iteration on E - A). */
#define WEIGHTED_PROBE 8

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
    double history[STALL_WINDOW];
    double first = -1.0, omega = 1.0, l2_probe = 0.0;
    int cur = 0, start = r->iterations;
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
            double rho = pow(sqrt(nr.sum_sq) / l2_probe, 1.0 / (WEIGHTED_PROBE - 2));
            double lambda = rho < 1.0 ? 1.0 - rho : 1.0;
            omega = 2.0 / (lambda + 1.0);
            r->omega = omega;
        }
        if (kind == SOLVE_CHEBYSHEV && nr.max > tol_abs)
            chebyshev_observe(&cheb, nr.max);
        r->spectrum_lower = kind == SOLVE_CHEBYSHEV ? cheb.a : 0.0;
        r->restarts = cheb.restarts;
        r->iterations = start + k;
        r->max_abs_error = nr.max;
        r->mean_abs_error = nr.sum / (double)n;
        if (!isfinite(nr.max))
            return check_nonfinite_iteration(ctx, "the residual", k, scheme, alpha, 0);
        if (nr.max <= tol_abs) {
            *which = cur;
            return LIMN_OK;
        }
        if (first < 0.0)
            first = nr.max;
        if (k >= STALL_WINDOW && nr.max > STALL_FACTOR * history[k % STALL_WINDOW]) {
            return ctx_fail(
                ctx, LIMN_ERR_SINGULAR,
                "the residual stopped shrinking: %.3g (relative %.3g) after %d iterations, "
                "%.3g %d iterations earlier. The limit operator is singular or nearly so for "
                "this mesh%s; no result was written",
                nr.max, diag > 0 ? nr.max / diag : nr.max, k,
                history[k % STALL_WINDOW], STALL_WINDOW,
                scheme == LIMN_SCHEME_CATMARK && alpha == 0.0
                    ? " (alpha = 0 with valence-3 vertices, e.g. a cube, has a zero "
                      "eigenvalue): run again with --alpha 0.5"
                    : "");
        }
        history[k % STALL_WINDOW] = nr.max;
        if (k >= o->max_iterations) {
            double rate = pow(nr.max / first, 1.0 / (double)k);
            double more = rate < 1.0 ? log(tol_abs / nr.max) / log(rate) : INFINITY;
            return ctx_fail(ctx, LIMN_ERR_NO_CONVERGENCE,
                             "no convergence in %d iterations: max relative error %.3g, "
                             "tolerance %.3g; the error shrinks by %.4f per iteration, so about "
                             "%.0f more are needed: raise --max-iter or loosen --tol",
                             k, diag > 0 ? nr.max / diag : nr.max, o->tolerance, rate, more);
        }
        if ((k & 7) == 0 && first > tol_abs && nr.max < first)
            ctx_progress(ctx, "solve", log(first / nr.max) / log(first / tol_abs));
        cur = 1 - cur;
    }
}
