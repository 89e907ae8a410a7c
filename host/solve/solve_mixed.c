/* SPDX-License-Identifier: MIT */
/*
 * Mixed-precision iterative refinement for A P = M (README "Precision").
 * In float, r = M - A P loses about three of float's seven digits to
 * cancellation (DESIGN.md §6), so a float iteration on P itself stalls near
 * 1e-7 of the coordinates. Here the residual of P is always taken in double;
 * only the correction d (A d = r, of the size of r, not of P) is iterated in
 * float, where those seven digits are relative to r. Each outer step thus
 * gains up to INNER_REDUCTION, and the stop test is the double iteration's.
 */
#include "solve/solve_mixed.h"
#include "mesh/check.h"
#include "base/context.h"
#include "solve/solver.h"
#include "base/clock.h"
#include "solve/iterate.h"

#include <math.h>

/* A float solve aims at the tolerance or at this reduction of its
   right-hand side, whichever is larger. Its floor (float weights and float
   rounding of d) measured 0.9e-7 of r on horse/Loop, so 1e-6 stays clear of
   it; then one float solve reaches 1e-8 on every shared medium mesh, and
   1e-10 takes two. Its estimate of the new residual is good to ~1e-7 of r,
   and the correction returned is one step past the one measured, so no
   margin below the tolerance is needed (none of 78 measured solves needed a
   second outer step for it). */
#define INNER_REDUCTION 1e-6
/* A float solve whose residual shrinks by less than 1% over this many steps
   has reached its floor (or A is singular): it ends there. */
#define INNER_STALL_WINDOW 10
/* An outer step that does not halve the double residual hands over to the
   double iteration, whose stall test then names a singular operator. */
#define OUTER_GAIN 0.5

const char *limn_precision_name(limn_precision p)
{
    switch (p) {
    case LIMN_PRECISION_AUTO: return "auto";
    case LIMN_PRECISION_DOUBLE: return "double";
    case LIMN_PRECISION_FLOAT: return "float";
    }
    return "unknown";
}

limn_status solve_precision_choose(limn_context *ctx, const limn_interpolate_options *o,
                                   limn_method method, size_t vertices, limn_precision *out,
                                   limn_report *r)
{
    const solver_ops *ops = solver_find(method);
    int iterative = ops && ops->floats;
    switch (o->precision) {
    case LIMN_PRECISION_DOUBLE:
        *out = LIMN_PRECISION_DOUBLE;
        r->precision_reason = "chosen by the caller";
        break;
    case LIMN_PRECISION_FLOAT:
        if (!iterative)
            return ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                             "precision float runs the chebyshev, paper or weighted iteration; "
                             "method %s runs in double: use another --method, or --precision "
                             "double or auto",
                             limn_method_name(method));
        *out = LIMN_PRECISION_FLOAT;
        r->precision_reason = "chosen by the caller";
        break;
    case LIMN_PRECISION_AUTO:
        if (!iterative) {
            *out = LIMN_PRECISION_DOUBLE;
            r->precision_reason = "auto: the method runs in double only";
        } else if (vertices < SOLVE_FLOAT_MIN_VERTICES) {
            *out = LIMN_PRECISION_DOUBLE;
            r->precision_reason = "auto: double below 200,000 vertices, where the float "
                                  "path's extra double product and set-up cost about what "
                                  "its cheaper products save";
        } else {
            *out = LIMN_PRECISION_FLOAT;
            r->precision_reason = "auto: float corrections from 200,000 vertices, measured "
                                  "9-25% faster to the same tolerance";
        }
        break;
    default:
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "limn_interpolate: unknown precision %d",
                         (int)o->precision);
    }
    r->precision = limn_precision_name(*out);
    return LIMN_OK;
}

typedef struct mixed_state {
    struct device *dev;
    const mixed_ops *ops;
    limn_method method;        /* paper, weighted or chebyshev */
    device_buffer *r, *d[2];   /* float4 rows: right-hand side, corrections */
    double omega;              /* weighted: set after the probe of the first solve */
    double probe;              /* |s|_2 at the probe's start */
    double cheb_a;             /* chebyshev: lower bound, kept across float solves */
    limn_scheme scheme;
    double alpha;
} mixed_state;

/*
 * One float solve of A d = r; *out: the buffer holding d. Its first iterate
 * d = r costs nothing (the seeds' step from d = 0), so step j here is step
 * j + 1 of the double iteration from P = M, and Chebyshev starts after that
 * step, as the double one does after its lead step. Iterates: x_0 = r,
 * x_k (k >= 1) in d[(k - 1) & 1]; step j reads x_j and x_{j-1} and writes
 * x_{j+1} over x_{j-1} (each row reads it first).
 */
static limn_status inner_solve(limn_context *ctx, mixed_state *s, double target, int probing,
                               int max_iter, device_buffer **out, limn_report *r)
{
    monitor mon;
    monitor_init(&mon, target, max_iter, INNER_STALL_WINDOW, MONITOR_STALL_RATIO);
    monitor_words words = {MONITOR_LOOP_MIXED, "the float correction", 0.0, 0.0, s->scheme,
                           s->alpha, 0, 1, 0};
    chebyshev cheb;
    chebyshev_init(&cheb, s->cheb_a, 0);
    device_buffer *cur = s->r;
    for (int j = 0;; j++) {
        device_norms ns;
        double c1 = 0.0, c2 = s->omega;
        if (s->method == LIMN_METHOD_CHEBYSHEV)
            chebyshev_coefficients(&cheb, &c1, &c2);
        /* c1 = 0 reads no previous iterate: pass cur, whose lines are loaded anyway */
        device_buffer *next = s->d[j & 1];
        device_buffer *prev = c1 == 0.0 ? cur : j == 1 ? s->r : next;
        limn_status st =
            s->ops->step(s->ops->user, s->r, cur, prev, next, (float)c1, (float)c2, &ns);
        if (st)
            return st;
        ns.max = check_norm_max(ns.max, ns.sum);
        r->products += 1.0;
        r->products_float += 1.0;
        r->iterations++;
        if (s->method == LIMN_METHOD_WEIGHTED && probing && j == 1)
            s->probe = sqrt(ns.sum_sq);
        if (s->method == LIMN_METHOD_WEIGHTED && probing && j == WEIGHTED_PROBE - 1 &&
            s->probe > 0) {
            s->omega = monitor_weighted_omega(s->probe, sqrt(ns.sum_sq));
            r->omega = s->omega;
        }
        if (s->method == LIMN_METHOD_CHEBYSHEV && ns.max > target)
            r->restarts += chebyshev_observe(&cheb, ns.max);
        /* converged, stalled or capped: the outer loop decides */
        monitor_verdict v = monitor_step(&mon, ns.max, r->iterations);
        if (v == MONITOR_NON_FINITE)
            return monitor_fail(ctx, &mon, v, &words);
        cur = next;
        if (v != MONITOR_CONTINUE)
            break;
    }
    s->cheb_a = cheb.a;
    if (s->method == LIMN_METHOD_CHEBYSHEV)
        r->spectrum_lower = cheb.a;
    *out = cur;
    return LIMN_OK;
}

/* The outer loop on open buffers: the double residual, its stop test, a
   float solve, P += d; again. */
static limn_status outer_loop(limn_context *ctx, mixed_state *s, const limn_interpolate_options *o,
                              double diag, size_t vertices, int *converged, limn_report *r)
{
    size_t n = vertices ? vertices : 1;
    double tol_abs = o->tolerance * diag;
    /* the stall test, window 1 and ratio OUTER_GAIN, is the float corrections'
       gain: a stall finishes in double */
    monitor mon;
    monitor_init(&mon, tol_abs, o->max_iterations, 1, OUTER_GAIN);
    monitor_words words = {MONITOR_LOOP_MIXED, "the residual", diag, o->tolerance, s->scheme,
                           s->alpha, 0, 1, 0};
    limn_status st = LIMN_OK;
    for (int outer = 0; !st; outer++) {
        device_norms nr;
        st = s->ops->residual(s->ops->user, s->r, &nr);
        if (st)
            break;
        nr.max = check_norm_max(nr.max, nr.sum);
        r->products += 1.0;
        r->max_abs_error = nr.max;
        r->mean_abs_error = nr.sum / (double)n;
        monitor_verdict v = monitor_step(&mon, nr.max, r->iterations);
        if (v == MONITOR_CONVERGED) {
            *converged = 1;
            break;
        }
        if (v == MONITOR_STALLED) {
            r->precision_reason = "float corrections stopped gaining; finished in double";
            break;
        }
        if (v != MONITOR_CONTINUE) {
            st = monitor_fail(ctx, &mon, v, &words);
            break;
        }
        if (mon.k > 0 && mon.first > tol_abs)
            ctx_progress(ctx, "solve", log(mon.first / nr.max) / log(mon.first / tol_abs));
        device_buffer *d = NULL;
        double target = fmax(tol_abs, INNER_REDUCTION * nr.max);
        st = inner_solve(ctx, s, target, outer == 0, o->max_iterations, &d, r);
        if (!st)
            st = s->ops->add(s->ops->user, d);
    }
    return st;
}

limn_status solve_mixed_run(limn_context *ctx, struct device *dev, const mixed_ops *ops,
                            size_t rows, size_t vertices, limn_scheme scheme, double alpha,
                            const limn_interpolate_options *o, double diag, limn_method method,
                            int *converged, limn_report *r)
{
    mixed_state s = {.dev = dev, .ops = ops, .method = method, .omega = 1.0,
                     .cheb_a = chebyshev_prior(scheme), .scheme = scheme, .alpha = alpha};
    *converged = 0;
    r->omega = 1.0;
    size_t nb = rows ? rows : 1;
    /* no zero fill: residual writes every row of r (w = 0) before a step
       reads it, and step j writes d[j & 1] whole before step j + 2 reads it */
    limn_status st = dev->ops->buffer_scratch(dev, 4 * nb * sizeof(float), &s.r);
    for (int i = 0; i < 2 && !st; i++)
        st = dev->ops->buffer_scratch(dev, 4 * nb * sizeof(float), &s.d[i]);
    if (ops->agree)
        st = ops->agree(ops->user, st);
    double t_loop = clock_seconds(), compiles = dev->setup.kernels; /* first launches */
    if (!st)
        st = outer_loop(ctx, &s, o, diag, vertices, converged, r);
    r->seconds_iterations += clock_seconds() - t_loop - (dev->setup.kernels - compiles);
    for (int i = 0; i < 2; i++)
        if (s.d[i])
            dev->ops->buffer_release(dev, s.d[i]);
    if (s.r)
        dev->ops->buffer_release(dev, s.r);
    return st;
}

/* ------------------------------------------------ the single process's ops */

typedef struct local_mixed {
    stencil_operator *op;
    device_buffer *m, *p;
} local_mixed;

static limn_status local_residual(void *user, device_buffer *r_f, device_norms *norms)
{
    local_mixed *l = user;
    struct device *dev = l->op->dev;
    return dev->ops->mixed->residual_f(dev, &l->op->device, l->m, l->p, r_f, norms);
}

static limn_status local_step(void *user, device_buffer *b, device_buffer *d, device_buffer *prev,
                              device_buffer *next, float c1, float c2, device_norms *norms)
{
    local_mixed *l = user;
    struct device *dev = l->op->dev;
    return dev->ops->mixed->step_f(dev, &l->op->device, b, d, prev, next, c1, c2, norms);
}

static limn_status local_add(void *user, device_buffer *d)
{
    local_mixed *l = user;
    struct device *dev = l->op->dev;
    return dev->ops->mixed->add_f(dev, l->op->vertex_count, l->p, d);
}

limn_status solve_mixed(limn_context *ctx, stencil_operator *op, device_buffer *m, device_buffer *p,
                        const limn_interpolate_options *o, double diag, limn_method method,
                        int *converged, limn_report *r)
{
    *converged = 0;
    limn_status st = device_csr_add_float(op->dev, &op->device);
    if (st)
        return st;
    local_mixed l = {op, m, p};
    const mixed_ops ops = {&l, local_residual, local_step, local_add, NULL};
    return solve_mixed_run(ctx, op->dev, &ops, op->vertex_count, op->vertex_count, op->scheme,
                           op->alpha, o, diag, method, converged, r);
}
