/* SPDX-License-Identifier: MIT */
/*
 * limn_interpolate over MPI: the iteration of solve/iterate.c (solve_iterate,
 * the same stop test, weights and messages) with each step run as an
 * overlapped product on every rank's rows and the residual norms reduced
 * over the ranks. The stop test uses the maximum, which is exact under any
 * reduction order, and every row is summed in the single process's order, so
 * the paper iteration gives the single process's bits and iteration count.
 * Precision float runs solve_mixed.c's refinement on the same rows: the
 * double residual exchanges P's ghosts in double, the float steps the
 * correction's ghosts in float, as the single process reads them.
 */
#include "mpi/mpi_part.h"
#include "base/large_alloc.h"

#include "mesh/check.h"
#include "base/context.h"
#include "mesh/mesh.h"
#include "solve/solve.h"
#include "solve/solve_mixed.h"
#include "solve/iterate.h"

#include <math.h>
#include <stdio.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

typedef struct mpi_solve {
    mpi_part *p;
    device_buffer *m, *x[2];
    double *x_host[2]; /* the iterates' host memory where the device uses it in place */
    int cur;
    solve_step step;
} mpi_solve;

static limn_status rows_step(void *user, const device_csr *rows, device_norms *norms)
{
    mpi_solve *s = user;
    struct device *dev = s->p->dev;
    if (s->step.kind == SOLVE_CHEBYSHEV)
        return dev->ops->stationary->cheb_step(dev, rows, s->m, s->x[s->cur], s->x[1 - s->cur],
                                               s->step.c1, s->step.c2, norms);
    return dev->ops->stationary->interp_step(dev, rows, s->m, s->x[s->cur], s->x[1 - s->cur],
                                             s->step.omega, norms);
}

/* solve_step_fn: one overlapped step (only P's ghosts are read: the previous
   iterate of Chebyshev is read row by row), then the global norms. */
static limn_status step(void *user, int cur, const solve_step *sp, device_norms *norms)
{
    mpi_solve *s = user;
    s->cur = cur;
    s->step = *sp;
    device_norms local;
    limn_status st = mpi_overlapped(s->p, &s->p->all, s->x[cur], rows_step, s, LIMN_OK, &local);
    return mpi_reduce_norms(s->p, st, &local, norms);
}

/* ------------------------------------------------ the float refinement */

typedef struct mpi_mixed {
    mpi_part *p;
    device_buffer *m, *x;                 /* M and P (x[0]) */
    device_buffer *b, *d, *prev, *next;   /* the step's operands, or r_f in b */
    float c1, c2;
} mpi_mixed;

static limn_status rows_residual(void *user, const device_csr *rows, device_norms *norms)
{
    mpi_mixed *mm = user;
    struct device *dev = mm->p->dev;
    return dev->ops->mixed->residual_f(dev, rows, mm->m, mm->x, mm->b, norms);
}

static limn_status mixed_residual(void *user, device_buffer *r_f, device_norms *norms)
{
    mpi_mixed *mm = user;
    device_norms local;
    mm->b = r_f;
    limn_status st = mpi_overlapped(mm->p, &mm->p->all, mm->x, rows_residual, mm, LIMN_OK, &local);
    return mpi_reduce_norms(mm->p, st, &local, norms);
}

static limn_status rows_step_f(void *user, const device_csr *rows, device_norms *norms)
{
    mpi_mixed *mm = user;
    struct device *dev = mm->p->dev;
    return dev->ops->mixed->step_f(dev, rows, mm->b, mm->d, mm->prev, mm->next, mm->c1, mm->c2,
                                   norms);
}

/* Only d's ghosts are read (b and prev row by row): one float exchange. */
static limn_status mixed_step(void *user, device_buffer *b, device_buffer *d, device_buffer *prev,
                              device_buffer *next, float c1, float c2, device_norms *norms)
{
    mpi_mixed *mm = user;
    *mm = (mpi_mixed){mm->p, mm->m, mm->x, b, d, prev, next, c1, c2};
    device_norms local;
    limn_status st = mpi_overlapped_f(mm->p, &mm->p->all, d, rows_step_f, mm, LIMN_OK, &local);
    return mpi_reduce_norms(mm->p, st, &local, norms);
}

static limn_status mixed_add(void *user, device_buffer *d)
{
    mpi_mixed *mm = user;
    struct device *dev = mm->p->dev;
    return mpi_agree(mm->p, dev->ops->mixed->add_f(dev, mm->p->n_owned, mm->x, d));
}

/* solve_mixed over the ranks on P in x (M in m); *done as its *converged. */
static limn_status mixed_agree(void *user, limn_status st)
{
    return mpi_agree(((mpi_mixed *)user)->p, st);
}

static limn_status mixed(mpi_part *p, device_buffer *m, device_buffer *x,
                         const limn_interpolate_options *o, limn_method method, int *done,
                         limn_report *r)
{
    mpi_mixed mm = {.p = p, .m = m, .x = x};
    const mixed_ops ops = {&mm, mixed_residual, mixed_step, mixed_add, mixed_agree};
    limn_status st = mpi_agree(p, device_csr_add_float(p->dev, &p->all));
    if (!st)
        st = solve_mixed_run(p->ctx, p->dev, &ops, p->n_owned + p->n_ghost, p->n_global,
                             p->scheme, p->alpha, o, p->diag, method, done, r);
    return st;
}

static void release(mpi_solve *s)
{
    struct device *dev = s->p->dev;
    device_buffer *all[] = {s->m, s->x[0], s->x[1]};
    for (int k = 0; k < 3; k++)
        if (all[k])
            dev->ops->buffer_release(dev, all[k]);
    for (int i = 0; i < 2; i++)
        free(s->x_host[i]); /* after their buffers: the device may still use them */
}

/* Iterate i (init's rows, or zeros): host memory used in place where the
   device shares it (device_vector_create), the single process's way: its
   huge pages first touched here, not the runtime's own 4 KiB pages filled
   by a copy and a fill (measured at 2.1M on 2 ranks: ~15,000 page faults a
   rank gone); else a device buffer. */
static limn_status iterate_buffer(mpi_solve *s, int i, size_t bytes, const double *init)
{
    void *host = NULL;
    limn_status st = device_vector_create(s->p->dev, s->p->ctx, bytes, init, &host, &s->x[i]);
    s->x_host[i] = host;
    return st;
}

/* The seeds' iteration (or the weighted one, or Chebyshev) from the start
   in x[0], after the float refinement when precision is float. */
static limn_status iterate(mpi_part *p, const limn_interpolate_options *o, limn_method method,
                           limn_precision precision, const double *m4, const double *start4,
                           double *out4, limn_report *r)
{
    mpi_solve s = {.p = p};
    size_t nl = p->n_owned + p->n_ghost, row = 4 * sizeof(double);
    const device_ops *ops = p->dev->ops;
    /* M in place where the device shares host memory, when m4 has the page
       alignment of device_host_alloc (the kernels' vector loads need more
       than malloc's; mpi_local_build's rows have it): m4 outlives s.m and
       the solve only reads it (the single process's zero-copy vectors) */
    limn_status st = (uintptr_t)m4 % 4096 == 0
                         ? ops->buffer_share(p->dev, p->n_owned * row, m4, &s.m)
                         : ops->buffer_create(p->dev, p->n_owned * row, m4, &s.m);
    if (!st)
        st = iterate_buffer(&s, 0, nl * row, start4);
    if (!st)
        st = iterate_buffer(&s, 1, nl * row, NULL);
    st = mpi_agree(p, st);
    int which = 0, done = 0;
    double t0 = MPI_Wtime();
    if (!st && precision == LIMN_PRECISION_FLOAT)
        st = mixed(p, s.m, s.x[0], o, method, &done, r);
    if (!st && !done)
        st = solve_iterate(p->ctx, step, &s, p->n_global, p->scheme, p->alpha, o, p->diag,
                           solve_kind_of(method), &which, r);
    p->stats.seconds_solve += MPI_Wtime() - t0;
    if (!st)
        st = ops->buffer_read_at(p->dev, s.x[which], 0, p->n_owned * row, out4);
    release(&s);
    return mpi_agree(p, st);
}

limn_status mpi_interpolate_method(mpi_part *p, const limn_interpolate_options *o,
                                   limn_status st, limn_method *method, limn_report *r)
{
    limn_context *ctx = p->ctx;
    if (!st)
        st = solve_check_options(ctx, o);
    *method = o->method == LIMN_METHOD_AUTO ? LIMN_METHOD_CHEBYSHEV : o->method;
    limn_precision unused; /* refusals only: the choice follows the vertex count */
    if (!st)
        st = solve_precision_choose(ctx, o, *method, 0, &unused, r);
    st = mpi_agree(p, st);
    r->method = limn_method_name(*method);
    r->method_reason = o->method == LIMN_METHOD_AUTO
                           ? "auto: chebyshev, the fastest in measured time on every shared "
                             "mesh (fewest fused steps; cg uses as few products, each costlier)"
                           : "chosen by the caller";
    return st;
}

/* The root's checks of limn_interpolate_mpi, then the options' (agreed):
   auto as in limn_interpolate, so that both give the same answer. */
static limn_status check_interpolate(mpi_part *p, const limn_mesh *mesh,
                                     const limn_interpolate_options *o, limn_mesh **control,
                                     limn_method *method, limn_report *r)
{
    limn_status st = LIMN_OK;
    if (p->rank == p->root && (!mesh || !control))
        st = ctx_fail(p->ctx, LIMN_ERR_ARGUMENT,
                       "limn_interpolate_mpi: the root rank needs the mesh and control");
    if (!st && p->rank == p->root)
        st = check_mesh_magnitude(p->ctx, "limn_interpolate_mpi", NULL, mesh);
    return mpi_interpolate_method(p, o, st, method, r);
}

/* The distributed operator's part of the report, and the vectors: m4 and
   p4 (owned and ghost rows, 4 doubles), xyz (root: 3 per vertex). */
static limn_status open_vectors(mpi_part *p, limn_report *r, double **m4, double **p4,
                                double **xyz)
{
    MPI_REPORT_OPERATOR(r, p);
    r->reordered = p->reordered;
    r->omega = 1.0;
    size_t nl = p->n_owned + p->n_ghost;
    *m4 = device_host_alloc((nl ? 4 * nl : 4) * sizeof **m4); /* page aligned: iterate */
    if (*m4)
        memset(*m4, 0, (nl ? 4 * nl : 4) * sizeof **m4);
    *p4 = calloc(nl ? 4 * nl : 4, sizeof **p4);
    if (p->rank == p->root)
        *xyz = large_malloc((p->n_global ? 3 * p->n_global : 1) * sizeof **xyz);
    limn_status st = LIMN_OK;
    if (!*m4 || !*p4 || (p->rank == p->root && !*xyz))
        st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu vertices", nl);
    return mpi_agree(p, st);
}

/* CG (or SGS-preconditioned CG) gives the start p4; the seeds' step
   measures its residual on the whole system (and polishes, should rounding
   leave it short). Where it cannot run, the seeds' iteration from M (the
   method changed to it), with the single process's warning and reason. */
static limn_status cg_start(mpi_part *p, const limn_interpolate_options *o, const double *m4,
                            double *p4, limn_method *method, limn_report *r)
{
    solve_stats stats = {.catmark_alpha0 = p->scheme == LIMN_SCHEME_CATMARK && p->alpha == 0.0};
    int sgs = *method == LIMN_METHOD_SGS;
    double tol_abs = o->tolerance * p->diag;
    limn_status st = sgs ? mpi_solve_sgs(p, m4, tol_abs, o->max_iterations, p4, &stats)
                         : mpi_solve_cg(p, m4, tol_abs, o->max_iterations, p4, &stats);
    if (st == LIMN_ERR_TOPOLOGY && sgs) {
        ctx_warn(p->ctx, "sgs (Gauss-Seidel-preconditioned CG) needs the limit operator to be "
                         "block triangular by vertex rule with symmetric, positive blocks, "
                         "which this mesh's is not: used the seeds' iteration");
        *method = LIMN_METHOD_PAPER;
        r->method = limn_method_name(*method);
        r->method_reason = "sgs cannot run on this operator (see the warning)";
        memcpy(p4, m4, 4 * p->n_owned * sizeof *p4);
        st = LIMN_OK;
    } else if (st == LIMN_ERR_TOPOLOGY) {
        ctx_warn(p->ctx, "conjugate gradients need the limit operator to be block triangular "
                         "by vertex rule, which this mesh's is not: used the seeds' iteration");
        *method = LIMN_METHOD_PAPER;
        r->method = limn_method_name(*method);
        r->method_reason = "cg cannot run on this operator (not block triangular)";
        memcpy(p4, m4, 4 * p->n_owned * sizeof *p4);
        st = LIMN_OK;
    } else if (!st) {
        r->products = stats.products;
        r->iterations = stats.iterations;
    }
    return st;
}

/* Hands the root's control mesh out after a success; else frees it and the pieces. */
static limn_status hand_out(limn_context *ctx, limn_status st, limn_mesh *out,
                            limn_mesh **control, limn_mpi_result *result)
{
    if (st) {
        limn_mesh_destroy(out);
        if (result)
            limn_mpi_result_free(result);
        return st;
    }
    if (control && out)
        *control = out;
    else
        limn_mesh_destroy(out);
    ctx_progress(ctx, "solve", 1.0);
    return LIMN_OK;
}

limn_status mpi_interpolate_rows(mpi_part *p, const limn_interpolate_options *o,
                                 limn_method *method, const double *m4, double *p4,
                                 limn_report *r)
{
    /* as limn_interpolate decides it, on the vertex count */
    limn_precision precision = LIMN_PRECISION_DOUBLE;
    limn_status st =
        mpi_agree(p, solve_precision_choose(p->ctx, o, *method, p->n_global, &precision, r));
    if (!st)
        memcpy(p4, m4, 4 * p->n_owned * sizeof *p4);
    if (!st && (*method == LIMN_METHOD_CG || *method == LIMN_METHOD_SGS))
        st = cg_start(p, o, m4, p4, method, r);
    if (!st)
        st = iterate(p, o, *method, precision, m4, p4, p4, r);
    return st;
}

limn_status mpi_interpolate_part(mpi_part *p, const limn_interpolate_options *o,
                                 const double *m4, double *p4, limn_report *r)
{
    memset(r, 0, sizeof *r);
    limn_method method;
    limn_status st = mpi_interpolate_method(p, o, LIMN_OK, &method, r);
    MPI_REPORT_OPERATOR(r, p);
    r->reordered = p->reordered;
    r->omega = 1.0;
    if (!st)
        st = mpi_interpolate_rows(p, o, &method, m4, p4, r);
    return mpi_agree(p, st);
}

/* limn_interpolate_mpi on structs of this library's layout. */
static limn_status interpolate_mpi_sized(limn_context *ctx, MPI_Comm comm, const limn_mesh *mesh,
                                         const limn_interpolate_options *o,
                                         limn_mesh **control, limn_report *r,
                                         const limn_mpi_options *mpi, limn_mpi_result *result)
{
    if (result)
        memset(result, 0, sizeof *result);
    memset(r, 0, sizeof *r);
    mpi_part p;
    limn_status st = mpi_part_begin(ctx, comm, mpi, &p);
    if (st) {
        mpi_part_end(&p);
        return st;
    }
    limn_method method;
    st = check_interpolate(&p, mesh, o, control, &method, r);
    if (!st)
        st = mpi_distribute(&p, mesh, o->scheme, o->alpha, solve_reorder_wanted(o, method));
    double t0 = MPI_Wtime();
    double *m4 = NULL, *p4 = NULL, *xyz = NULL;
    if (!st)
        st = open_vectors(&p, r, &m4, &p4, &xyz);
    if (!st)
        st = mpi_scatter_rows(&p, p.rank == p.root ? mesh->positions : NULL, m4);
    if (!st)
        st = mpi_interpolate_rows(&p, o, &method, m4, p4, r);
    if (!st)
        st = mpi_gather_rows(&p, p4, xyz);
    limn_mesh *out = NULL;
    if (!st && p.rank == p.root) {
        st = limn_mesh_copy(ctx, mesh, &out);
        if (!st)
            memcpy(out->positions, xyz, 3 * p.n_global * sizeof *xyz);
    }
    st = mpi_agree(&p, st);
    r->seconds_solve = MPI_Wtime() - t0;
    r->max_rel_error = p.diag > 0 ? r->max_abs_error / p.diag : r->max_abs_error;
    r->mean_rel_error = p.diag > 0 ? r->mean_abs_error / p.diag : r->mean_abs_error;
    if (!st && mpi && mpi->keep_piece)
        st = mpi_pieces(&p, mesh, xyz, result);
    if (result)
        result->stats = p.stats;
    free(m4);
    free(p4);
    free(xyz);
    mpi_part_end(&p);
    return hand_out(ctx, st, out, control, result);
}

limn_status limn_interpolate_mpi(limn_context *ctx, MPI_Comm comm, const limn_mesh *mesh,
                                 const limn_interpolate_options *options, limn_mesh **control,
                                 limn_report *report, const limn_mpi_options *mpi,
                                 limn_mpi_result *result)
{
    mpi_call c;
    limn_status st = mpi_enter(&c, ctx, comm, "limn_interpolate_mpi", &abi_interpolate_options,
                               options, &abi_report, report, mpi, result, control);
    return st ? st
              : mpi_leave(&c, interpolate_mpi_sized(ctx, comm, mesh, c.abi.options, control,
                                                    c.abi.report, c.mpi, c.result));
}
