/* SPDX-License-Identifier: MIT */
/* The convergence monitor (monitor.h): the one stop, stall, cap and
   non-finite rule and its messages, and the weighted method's omega. */
#include "solve/monitor.h"
#include "mesh/check.h"
#include "base/context.h"

#include <math.h>

void monitor_init(monitor *m, double tolerance, int cap, int window, double ratio)
{
    *m = (monitor){.tolerance = tolerance, .cap = cap, .ratio = ratio, .first = -1.0,
                   .window = window < 0 ? 0 : window > MONITOR_WINDOW_MAX ? MONITOR_WINDOW_MAX
                                                                          : window};
}

monitor_verdict monitor_step(monitor *m, double residual_max, int iteration)
{
    int k = m->steps++;
    m->k = k;
    m->residual = residual_max;
    m->iteration = iteration;
    if (!isfinite(residual_max))
        return MONITOR_NON_FINITE;
    if (residual_max <= m->tolerance)
        return MONITOR_CONVERGED;
    if (m->first < 0.0)
        m->first = residual_max;
    if (m->window > 0) {
        double *h = &m->history[k % m->window];
        if (k >= m->window && residual_max > m->ratio * *h) {
            m->earlier = *h;
            return MONITOR_STALLED;
        }
        *h = residual_max;
    }
    return iteration >= m->cap ? MONITOR_CAPPED : MONITOR_CONTINUE;
}

#define ALPHA0_HINT                                                                             \
    " (alpha = 0 with valence-3 vertices, e.g. a cube, has a zero eigenvalue): run again with " \
    "--alpha 0.5"

static limn_status fail_stalled(limn_context *ctx, const monitor *m, const monitor_words *w)
{
    int alpha0 = w->scheme == LIMN_SCHEME_CATMARK && w->alpha == 0.0;
    double rel = w->diag > 0 ? m->residual / w->diag : m->residual;
    switch (w->loop) {
    case MONITOR_LOOP_CG:
        return ctx_fail(ctx, LIMN_ERR_SINGULAR,
                         "the residual stopped shrinking under conjugate gradients: %.3g after "
                         "%d steps, %.3g %d steps earlier. The limit operator is singular or "
                         "nearly so for this mesh%s; no result was written",
                         m->residual, m->k, m->earlier, m->window,
                         w->catmark_alpha0 ? ALPHA0_HINT : "");
    case MONITOR_LOOP_TEXTURE:
        return ctx_fail(ctx, LIMN_ERR_SINGULAR,
                         "interpolating the noise of level %d stopped converging (residual "
                         "%.3g after %d iterations)%s",
                         w->level, m->residual, m->k,
                         alpha0 ? ": the operator is singular for this mesh; use --alpha 0.5"
                                : "");
    default:
        return ctx_fail(ctx, LIMN_ERR_SINGULAR,
                         "the residual stopped shrinking: %.3g (relative %.3g) after %d "
                         "iterations, %.3g %d iterations earlier. The limit operator is singular "
                         "or nearly so for this mesh%s; no result was written",
                         m->residual, rel, m->k, m->earlier, m->window, alpha0 ? ALPHA0_HINT : "");
    }
}

static limn_status fail_capped(limn_context *ctx, const monitor *m, const monitor_words *w)
{
    double rel = w->diag > 0 ? m->residual / w->diag : m->residual;
    int it = m->iteration;
    double rate = it > 0 ? pow(m->residual / m->first, 1.0 / (double)it) : 1.0;
    switch (w->loop) {
    case MONITOR_LOOP_CG:
        return ctx_fail(ctx, LIMN_ERR_NO_CONVERGENCE,
                         "no convergence in %d conjugate-gradient steps: max error %.3g, "
                         "tolerance %.3g: raise --max-iter or loosen --tol",
                         it, m->residual, m->tolerance);
    case MONITOR_LOOP_TEXTURE:
        return ctx_fail(ctx, LIMN_ERR_NO_CONVERGENCE,
                         "interpolating the noise of level %d stopped converging (residual "
                         "%.3g after %d iterations)",
                         w->level, m->residual, it);
    case MONITOR_LOOP_MIXED:
        return ctx_fail(ctx, LIMN_ERR_NO_CONVERGENCE,
                         "no convergence in %d iterations: max relative error %.3g, "
                         "tolerance %.3g; the error shrinks by %.4f per iteration: raise "
                         "--max-iter or loosen --tol",
                         it, rel, w->tolerance, rate);
    default: {
        double more = rate < 1.0 ? log(m->tolerance / m->residual) / log(rate) : INFINITY;
        return ctx_fail(ctx, LIMN_ERR_NO_CONVERGENCE,
                         "no convergence in %d iterations: max relative error %.3g, "
                         "tolerance %.3g; the error shrinks by %.4f per iteration, so about "
                         "%.0f more are needed: raise --max-iter or loosen --tol",
                         it, rel, w->tolerance, rate, more);
    }
    }
}

limn_status monitor_fail(limn_context *ctx, const monitor *m, monitor_verdict v,
                         const monitor_words *w)
{
    switch (v) {
    case MONITOR_NON_FINITE:
        return check_nonfinite_iteration(ctx, w->what,
                                         w->loop == MONITOR_LOOP_MIXED ? m->iteration : m->k,
                                         w->scheme, w->alpha, w->in_float);
    case MONITOR_STALLED:
        return fail_stalled(ctx, m, w);
    case MONITOR_CAPPED:
        return fail_capped(ctx, m, w);
    default:
        return LIMN_OK;
    }
}

double monitor_weighted_omega(double l2_probe, double l2_now)
{
    double rho = pow(l2_now / l2_probe, 1.0 / (WEIGHTED_PROBE - 2));
    double lambda = rho < 1.0 ? 1.0 - rho : 1.0;
    return 2.0 / (lambda + 1.0);
}
