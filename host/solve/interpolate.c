/* SPDX-License-Identifier: MIT */
/*
 * Progressive interpolation (seeds 002/003): P0 = M, P_{k+1} = P_k + (M - A P_k)
 * until max |M - A P_k| <= tol * bbox diagonal. The returned P is the one
 * whose residual was measured, so the reported error is exact, not a bound.
 */
#include "base/abi.h"
#include "mesh/check.h"
#include "base/context.h"
#include "device/device.h"
#include "mesh/mesh.h"
#include "solve/operator.h"
#include "solve/solver.h"
#include "base/clock.h"
#include "solve/iterate.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void limn_interpolate_options_default(limn_interpolate_options *o)
{
    abi_default(&abi_interpolate_options, o);
}

/* The report's fields that describe the operator and its device. */
static void report_operator(const stencil_operator *op, limn_report *r)
{
    r->scheme = op->scheme;
    r->alpha = op->alpha;
    r->seconds_topology = op->seconds_topology;
    r->seconds_stencil = op->seconds_stencil + op->seconds_reorder;
    r->stencil_nonzeros = op->host.row_offsets[op->host.rows];
    r->reordered = op->order != NULL;
    snprintf(r->device, sizeof r->device, "%s", op->dev->name);
    r->bbox_diagonal = op->bbox_diagonal;
}

/* The control mesh from P (4 doubles a row in the operator's order, taken
   over): in the mesh's order P's rows become its positions in place (the
   first 3 of every 4 doubles moved down, the block shrunk: no fresh memory
   to touch); a renumbered operator's go through its order into a copy. */
static limn_status control_mesh(limn_context *ctx, const stencil_operator *op,
                                const limn_mesh *mesh, double *p, limn_mesh **out)
{
    if (op->order) {
        limn_status st = limn_mesh_copy(ctx, mesh, out);
        if (!st)
            operator_unpack(op, p, (*out)->positions);
        free(p);
        return st;
    }
    return mesh_copy_with_positions(ctx, mesh, mesh_rows4_to_xyz(p, op->vertex_count), out);
}

/* limn_interpolate on options and report of this library's layout, both never NULL. */
static limn_status interpolate_sized(limn_context *ctx, const limn_mesh *mesh,
                                     const limn_interpolate_options *options, limn_mesh **control,
                                     limn_report *report)
{
    limn_status begun = abi_begin(ctx, "limn_interpolate", "control", control);
    if (begun)
        return begun;
    *control = NULL;
    const limn_interpolate_options *o = options; /* never NULL: abi_enter's copies */
    limn_status st = check_mesh_magnitude(ctx, "limn_interpolate", NULL, mesh);
    if (!st)
        st = solve_check_options(ctx, o);
    if (st)
        return st;
    limn_report *r = report;
    memset(r, 0, sizeof *r);
    r->vertices = mesh->vertex_count;
    r->faces = mesh->face_count;
    /* auto: Chebyshev. It needs 2.6-4.3x fewer products than the seeds'
       iteration on the shared medium meshes and its fused step moves one
       vector more (~16% per product), so it was the fastest in measured
       solve time from 4k to 8.6M vertices; CG needs about as few products
       but each costs 2-3 fused steps here (README "Solvers"). */
    limn_method method = o->method == LIMN_METHOD_AUTO ? LIMN_METHOD_CHEBYSHEV : o->method;
    r->method = limn_method_name(method);
    r->method_reason = o->method == LIMN_METHOD_AUTO
                           ? "auto: chebyshev, the fastest in measured time on every shared "
                             "mesh (fewest fused steps; cg uses as few products, each costlier)"
                           : "chosen by the caller";
    solver sv;
    solver_create(ctx, method, &sv);
    st = solver_set_from_options(&sv, o, mesh->vertex_count, r);
    if (st)
        return st;
    device_setup_times setup = device_setup_of(ctx);

    stencil_operator op;
    int flags = solve_reorder_wanted(o, method) ? OPERATOR_REORDER : 0;
    st = operator_build_ex(ctx, mesh, o->scheme, o->alpha, flags, &op);
    if (st)
        return st;
    report_operator(&op, r);
    double diag = op.bbox_diagonal;
    size_t n = mesh->vertex_count;
    /* every entry is written by operator_pack (padding included) */
    double *buf = n < SIZE_MAX / 32 ? device_host_alloc(4 * n * sizeof *buf) : NULL;
    double t0 = clock_seconds();
    if (!buf)
        st = ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for %zu vertices", n);
    else
        operator_pack(&op, mesh->positions, buf);
    double *p = NULL;
    if (!st)
        st = solver_solve(&sv, &op, diag, buf, &p, r);
    free(buf); /* M: before the control mesh is made, which lowers the peak */
    buf = NULL;
    limn_mesh *out = NULL;
    if (!st)
        st = control_mesh(ctx, &op, mesh, p, &out);
    /* the last line of defence: no non-finite control point is ever returned */
    if (!st && check_positions(NULL, "", out->positions, n))
        st = check_nonfinite_iteration(ctx, "the control mesh", r->iterations, op.scheme,
                                       op.alpha, sv.precision == LIMN_PRECISION_FLOAT);
    double t_end = clock_seconds();
    r->seconds_solve = t_end - t0;
    if (sv.finish_begin > 0)
        r->seconds_solve_finish = t_end - sv.finish_begin;
    device_setup_report(ctx, &setup, r);
    r->max_rel_error = diag > 0 ? r->max_abs_error / diag : r->max_abs_error;
    r->mean_rel_error = diag > 0 ? r->mean_abs_error / diag : r->mean_abs_error;
    free(buf);
    solver_destroy(&sv);
    operator_free(&op);
    if (!st)
        ctx_progress(ctx, "solve", 1.0);
    return mesh_hand_over(st, out, control);
}

limn_status limn_interpolate(limn_context *ctx, const limn_mesh *mesh,
                             const limn_interpolate_options *options, limn_mesh **control,
                             limn_report *report)
{
    abi_call c;
    limn_status st = abi_enter(&c, ctx, "limn_interpolate", &abi_interpolate_options, options,
                               &abi_report, report, control);
    return st ? st : abi_leave(&c, interpolate_sized(ctx, mesh, c.options, control, c.report));
}
