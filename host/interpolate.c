/*
 * Progressive interpolation (seeds 002/003): P0 = M, P_{k+1} = P_k + (M - A P_k)
 * until max |M - A P_k| <= tol * bbox diagonal. The returned P is the one
 * whose residual was measured, so the reported error is exact, not a bound.
 */
#include "context.h"
#include "device.h"
#include "mesh.h"
#include "operator.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Iterations over which a residual must shrink by STALL_FACTOR, else the
   operator is treated as singular (e.g. alpha = 0 on an all-valence-3 cube). */
#define STALL_WINDOW 25
#define STALL_FACTOR 0.99

void limn_interpolate_options_default(limn_interpolate_options *o)
{
    o->scheme = LIMN_SCHEME_AUTO;
    o->alpha = 0.0;
    o->tolerance = 1e-6;
    o->max_iterations = 1000;
    o->reorder = 1;
}

static limn_status check_options(limn_context *ctx, const limn_interpolate_options *o)
{
    if (o->scheme != LIMN_SCHEME_AUTO && o->scheme != LIMN_SCHEME_LOOP &&
        o->scheme != LIMN_SCHEME_CATMARK)
        return limn_fail(ctx, LIMN_ERR_ARGUMENT, "unknown scheme %d", (int)o->scheme);
    if (!(o->alpha >= 0.0 && o->alpha <= 1.0))
        return limn_fail(ctx, LIMN_ERR_ARGUMENT,
                         "alpha is %g; it must lie in [0, 1] (6/7 or less keeps the iteration "
                         "convergent; 0.5 is a good choice)",
                         o->alpha);
    if (!(o->tolerance > 0.0 && isfinite(o->tolerance)))
        return limn_fail(ctx, LIMN_ERR_ARGUMENT, "tolerance is %g; it must be a positive number",
                         o->tolerance);
    if (o->max_iterations < 1)
        return limn_fail(ctx, LIMN_ERR_ARGUMENT, "max iterations is %d; it must be at least 1",
                         o->max_iterations);
    return LIMN_OK;
}

typedef struct solve_state {
    struct limn_device *dev;
    device_buffer *m, *p[2];
} solve_state;

static void solve_release(solve_state *s)
{
    for (int i = 0; i < 2; i++)
        if (s->p[i])
            s->dev->ops->buffer_release(s->dev, s->p[i]);
    if (s->m)
        s->dev->ops->buffer_release(s->dev, s->m);
}

/* Runs the iteration; on success *which is the buffer holding the answer. */
static limn_status iterate(limn_context *ctx, const limn_operator *op, solve_state *s,
                           const limn_interpolate_options *o, double diag, int *which,
                           limn_report *r)
{
    double tol_abs = o->tolerance * diag;
    double history[STALL_WINDOW];
    double first = -1.0;
    int cur = 0;
    for (int k = 0;; k++) {
        device_norms nr;
        limn_status st =
            s->dev->ops->interp_step(s->dev, &op->device, s->m, s->p[cur], s->p[1 - cur], &nr);
        if (st)
            return st;
        size_t n = op->vertex_count ? op->vertex_count : 1;
        r->iterations = k;
        r->max_abs_error = nr.max;
        r->mean_abs_error = nr.sum / (double)n;
        if (!isfinite(nr.max))
            return limn_fail(ctx, LIMN_ERR_NO_CONVERGENCE,
                             "the residual became non-finite after %d iterations; the iteration "
                             "diverges for this mesh (for Catmull-Clark keep alpha <= 6/7)",
                             k);
        if (nr.max <= tol_abs) {
            *which = cur;
            return LIMN_OK;
        }
        if (first < 0.0)
            first = nr.max;
        if (k >= STALL_WINDOW && nr.max > STALL_FACTOR * history[k % STALL_WINDOW]) {
            return limn_fail(
                ctx, LIMN_ERR_SINGULAR,
                "the residual stopped shrinking: %.3g (relative %.3g) after %d iterations, "
                "%.3g %d iterations earlier. The limit operator is singular or nearly so for "
                "this mesh%s; no result was written",
                nr.max, diag > 0 ? nr.max / diag : nr.max, k,
                history[k % STALL_WINDOW], STALL_WINDOW,
                op->scheme == LIMN_SCHEME_CATMARK && op->alpha == 0.0
                    ? " (alpha = 0 with valence-3 vertices, e.g. a cube, has a zero "
                      "eigenvalue): run again with --alpha 0.5"
                    : "");
        }
        history[k % STALL_WINDOW] = nr.max;
        if (k >= o->max_iterations) {
            double rate = pow(nr.max / first, 1.0 / (double)k);
            double more = rate < 1.0 ? log(tol_abs / nr.max) / log(rate) : INFINITY;
            return limn_fail(ctx, LIMN_ERR_NO_CONVERGENCE,
                             "no convergence in %d iterations: max relative error %.3g, "
                             "tolerance %.3g; the error shrinks by %.4f per iteration, so about "
                             "%.0f more are needed: raise --max-iter or loosen --tol",
                             k, diag > 0 ? nr.max / diag : nr.max, o->tolerance, rate, more);
        }
        if ((k & 7) == 0 && first > tol_abs && nr.max < first)
            limn_progress(ctx, "solve", log(first / nr.max) / log(first / tol_abs));
        cur = 1 - cur;
    }
}

limn_status limn_interpolate(limn_context *ctx, const limn_mesh *mesh,
                             const limn_interpolate_options *options, limn_mesh **control,
                             limn_report *report)
{
    if (!ctx)
        return LIMN_ERR_ARGUMENT;
    limn_clear(ctx);
    if (!mesh || !control)
        return limn_fail(ctx, LIMN_ERR_ARGUMENT, "limn_interpolate: mesh or control is NULL");
    *control = NULL;
    limn_interpolate_options defaults;
    limn_interpolate_options_default(&defaults);
    const limn_interpolate_options *o = options ? options : &defaults;
    limn_status st = check_options(ctx, o);
    if (st)
        return st;
    limn_report local;
    limn_report *r = report ? report : &local;
    memset(r, 0, sizeof *r);
    r->vertices = mesh->vertex_count;
    r->faces = mesh->face_count;
    r->method = "paper";

    limn_operator op;
    st = operator_build_ex(ctx, mesh, o->scheme, o->alpha, o->reorder ? OPERATOR_REORDER : 0, &op);
    if (st)
        return st;
    r->scheme = op.scheme;
    r->alpha = op.alpha;
    r->seconds_topology = op.seconds_topology;
    r->seconds_stencil = op.seconds_stencil + op.seconds_reorder;
    r->stencil_nonzeros = op.host.row_offsets[op.host.rows];
    r->reordered = op.order != NULL;
    snprintf(r->device, sizeof r->device, "%s", op.dev->name);

    double diag = op.bbox_diagonal;
    r->bbox_diagonal = diag;
    size_t n = mesh->vertex_count;
    solve_state s = {.dev = op.dev};
    double *buf = calloc(n ? 4 * n : 4, sizeof *buf);
    double t0 = limn_seconds();
    if (!buf)
        st = limn_fail(ctx, LIMN_ERR_MEMORY, "out of memory for %zu vertices", n);
    else
        operator_pack(&op, mesh->positions, buf);
    if (!st)
        st = s.dev->ops->buffer_create(s.dev, 4 * n * sizeof(double), buf, &s.m);
    if (!st)
        st = s.dev->ops->buffer_create(s.dev, 4 * n * sizeof(double), buf, &s.p[0]);
    if (!st)
        st = s.dev->ops->buffer_create(s.dev, 4 * n * sizeof(double), NULL, &s.p[1]);
    int which = 0;
    if (!st)
        st = iterate(ctx, &op, &s, o, diag, &which, r);
    if (!st)
        st = s.dev->ops->buffer_read(s.dev, s.p[which], 4 * n * sizeof(double), buf);
    limn_mesh *out = NULL;
    if (!st)
        st = limn_mesh_copy(ctx, mesh, &out);
    if (!st)
        operator_unpack(&op, buf, out->positions);
    r->seconds_solve = limn_seconds() - t0;
    r->max_rel_error = diag > 0 ? r->max_abs_error / diag : r->max_abs_error;
    r->mean_rel_error = diag > 0 ? r->mean_abs_error / diag : r->mean_abs_error;
    free(buf);
    solve_release(&s);
    operator_free(&op);
    if (st) {
        limn_mesh_destroy(out);
        return st;
    }
    limn_progress(ctx, "solve", 1.0);
    *control = out;
    return LIMN_OK;
}
