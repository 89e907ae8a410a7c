/* SPDX-License-Identifier: MIT */
/*
 * The solver registry and the run every method shares (solver.h): the
 * method's start when it has one (with the fall-back to the paper method),
 * then the float corrections when chosen, then the stationary loop that
 * measures the residual of the P returned.
 */
#include "solve/solver.h"
#include "base/large_alloc.h"
#include "base/clock.h"
#include "base/context.h"
#include "solve/solve_mixed.h"
#include "device/device.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* The registry: one line a method. */
static const solver_ops *const registry[] = {
    &solver_paper, &solver_weighted, &solver_chebyshev, &solver_cg, &solver_sgs,
};

const solver_ops *solver_find(limn_method method)
{
    for (size_t i = 0; i < sizeof registry / sizeof registry[0]; i++)
        if (registry[i]->method == method)
            return registry[i];
    return NULL;
}

void solver_create(limn_context *ctx, limn_method method, solver *s)
{
    memset(s, 0, sizeof *s);
    s->ctx = ctx;
    s->ops = solver_find(method);
}

limn_status solver_set_from_options(solver *s, const limn_interpolate_options *o,
                                    size_t vertices, limn_report *r)
{
    s->o = o;
    return solve_precision_choose(s->ctx, o, s->ops->method, vertices, &s->precision, r);
}

void solver_destroy(solver *s)
{
    for (int i = 0; i < 2; i++)
        if (s->p[i])
            s->dev->ops->buffer_release(s->dev, s->p[i]);
    if (s->m)
        s->dev->ops->buffer_release(s->dev, s->m);
    for (int i = 0; i < 2; i++)
        free(s->p_host[i]); /* after their buffers: a device may still use them */
    memset(s, 0, sizeof *s);
}

/* Iterate i: a copy of init (from_m: init is M's rows, which the device
   holds), or zeros, in host memory used in place where the device shares it
   (device_vector_create); on a discrete device, device memory alone, a copy
   of M made there (1 M + 0 M: the same values), so no host block is written
   before the result is read back. */
static limn_status iterate_buffer(solver *s, int i, size_t n, const double *init, int from_m)
{
    if (n >= SIZE_MAX / 32)
        return ctx_fail(s->ctx, LIMN_ERR_MEMORY, "out of memory for %zu vertices", n);
    size_t bytes = 4 * n * sizeof(double);
    if (!s->dev->host_shared && from_m) {
        limn_status st = s->dev->ops->buffer_scratch(s->dev, bytes, &s->p[i]);
        return st ? st : s->dev->ops->axpby(s->dev, n, 1.0, s->m, 0.0, s->m, s->p[i]);
    }
    void *host = NULL;
    limn_status st = device_vector_create(s->dev, s->ctx, bytes, init, &host, &s->p[i]);
    s->p_host[i] = host;
    return st;
}

/* Drops iterate i: its buffer, then its host memory. */
static void iterate_drop(solver *s, int i)
{
    if (s->p[i])
        s->dev->ops->buffer_release(s->dev, s->p[i]);
    s->p[i] = NULL;
    free(s->p_host[i]);
    s->p_host[i] = NULL;
}

/* The method's start (its tiers' blocks) in host arrays: P in buf on success; on
   LIMN_ERR_TOPOLOGY the warning, and the solver becomes the paper method. */
static limn_status run_start(solver *s, const stencil_operator *op, double tol_abs, double *buf,
                             limn_report *r)
{
    size_t n = op->vertex_count;
    double *p4 = large_malloc((n ? n : 1) * 4 * sizeof *p4);
    solve_stats stats = {.catmark_alpha0 = op->scheme == LIMN_SCHEME_CATMARK && op->alpha == 0.0};
    limn_status st;
    if (!p4)
        st = ctx_fail(s->ctx, LIMN_ERR_MEMORY, "out of memory for %zu vertices", n);
    else
        st = solve_tiers(s->ctx, op, buf, tol_abs, s->o->max_iterations, p4, s->ops->block,
                         &stats);
    if (st == LIMN_ERR_TOPOLOGY) {
        ctx_warn(s->ctx, "%s needs the limit operator to be block triangular by vertex rule "
                         "with symmetric, positive blocks, which this mesh's is not: used the "
                         "seeds' iteration",
                 s->ops->long_name);
        r->method_reason = s->ops->fallback_reason;
        s->ops = &solver_paper;
        r->method = limn_method_name(s->ops->method);
        st = LIMN_OK;
    } else if (!st) {
        memcpy(buf, p4, 4 * n * sizeof *p4);
        r->products = stats.products;
        r->iterations = stats.iterations;
        r->seconds_iterations = stats.seconds_loop;
    }
    free(p4);
    return st;
}

/* One step of the single process: the whole table in one launch. */
typedef struct local_step {
    const stencil_operator *op;
    solver *s;
} local_step;

static limn_status step_local(void *user, int cur, const solve_step *sp, device_norms *norms)
{
    const stencil_operator *op = ((local_step *)user)->op;
    solver *s = ((local_step *)user)->s;
    if (sp->kind == SOLVE_CHEBYSHEV)
        return s->dev->ops->stationary->cheb_step(s->dev, &op->device, s->m, s->p[cur],
                                                  s->p[1 - cur], sp->c1, sp->c2, norms);
    return s->dev->ops->stationary->interp_step(s->dev, &op->device, s->m, s->p[cur],
                                                s->p[1 - cur], sp->omega, norms);
}

limn_status solver_solve(solver *s, stencil_operator *op, double diag, double *buf,
                         double **p_out, limn_report *r)
{
    *p_out = NULL;
    const limn_interpolate_options *o = s->o;
    size_t n = op->vertex_count;
    s->dev = op->dev;
    /* a start (CG) gives P; the stationary loop below measures its residual on
       the whole system (and polishes, should rounding leave it short) */
    /* M in place where the device shares host memory, unless a start (CG)
       overwrites buf with its P while M is still needed */
    limn_status st =
        s->ops->block ? s->dev->ops->buffer_create(s->dev, 4 * n * sizeof(double), buf, &s->m)
                      : s->dev->ops->buffer_share(s->dev, 4 * n * sizeof(double), buf, &s->m);
    if (!st && s->ops->block)
        st = run_start(s, op, o->tolerance * diag, buf, r);
    if (!st) /* P starts as M, or as the method's start (now in buf) */
        st = iterate_buffer(s, 0, n, buf, !s->ops->block);
    int done = 0;
    if (!st && s->precision == LIMN_PRECISION_FLOAT)
        st = solve_mixed(s->ctx, op, s->m, s->p[0], o, diag, s->ops->method, &done, r);
    if (!st && !done)
        st = iterate_buffer(s, 1, n, NULL, 0); /* defined: Chebyshev's first step reads it */
    double t_loop = clock_seconds(), compiles = s->dev->setup.kernels; /* first launches */
    local_step ls = {op, s};
    if (!st && !done)
        st = solve_iterate(s->ctx, step_local, &ls, op->vertex_count, op->scheme,
                           op->alpha, o, diag, s->ops->kind, &s->which, r);
    s->finish_begin = clock_seconds();
    r->seconds_iterations += s->finish_begin - t_loop - (s->dev->setup.kernels - compiles);
    /* M (perhaps buf itself) and the other iterate are done with: released
       before P lands in buf, which also lowers the peak */
    if (s->m)
        s->dev->ops->buffer_release(s->dev, s->m);
    s->m = NULL;
    iterate_drop(s, 1 - s->which);
    /* into the iterate's own memory: in place where the device shares it; a
       discrete device's into host memory made for it now */
    if (!st && !s->p_host[s->which] &&
        !(s->p_host[s->which] = n < SIZE_MAX / 32 ? device_host_alloc(4 * n * sizeof(double))
                                                  : NULL))
        st = ctx_fail(s->ctx, LIMN_ERR_MEMORY, "out of memory for %zu vertices", n);
    if (!st)
        st = s->dev->ops->buffer_read(s->dev, s->p[s->which], 4 * n * sizeof(double),
                                      s->p_host[s->which]);
    if (!st) {
        s->dev->ops->buffer_release(s->dev, s->p[s->which]);
        s->p[s->which] = NULL;
        *p_out = s->p_host[s->which];
        s->p_host[s->which] = NULL;
    }
    return st;
}
