/* SPDX-License-Identifier: MIT */
/*
 * limn_interpolate_estimate: the peak memory of limn_interpolate, predicted
 * before anything is allocated, so that a batch job refuses a mesh it cannot
 * hold instead of being killed half way.
 *
 * Model, from the peak RSS of `limn interpolate` measured 2026-11-23 on both
 * backends (README "Memory"): per vertex and per face corner, plus 96 MiB for
 * the OpenCL runtime (measured 78-80 MiB):
 *   cg: 1000 B/vertex + 8 B/corner; measured 2.15M-vertex Loop
 *     mesh (igea, 2 levels) 1.95 GiB (OpenCL), 1.37M-vertex Catmull-Clark
 *     (bob_quad, 4 levels) 1.32 GiB; the model says 2.19 and 1.40 GiB;
 *   paper (auto), weighted: 600 B/vertex + 16 B/corner; measured 1.27 and 0.81 GiB;
 *     the model says 1.50 and 0.94 GiB.
 *   precision float (and auto from SOLVE_FLOAT_MIN_VERTICES): + 80 B/vertex for its
 *     float right-hand side, two float corrections and float weights; measured
 *     +60 MB at both sizes (1.36 -> 1.42 and 0.87 -> 0.93 GiB).
 * A solver that keeps more vectors must update these figures.
 */
#include "base/abi.h"
#include "mesh/check.h"
#include "base/context.h"
#include "mesh/mesh.h"
#include "solve/solve.h"
#include "solve/solve_mixed.h"
#include "solve/iterate.h"

#include <unistd.h>

#define RUNTIME_BYTES ((size_t)96 << 20)

static size_t physical_memory(void)
{
    long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGE_SIZE);
    return pages > 0 && size > 0 ? (size_t)pages * (size_t)size : (size_t)8 << 30;
}

limn_status limn_interpolate_estimate(limn_context *ctx, const limn_mesh *mesh,
                                      const limn_interpolate_options *options,
                                      size_t max_memory, size_t *peak_bytes)
{
    limn_status begun = abi_begin(ctx, "limn_interpolate_estimate", "mesh", mesh);
    if (begun)
        return begun;
    limn_interpolate_options sized;
    limn_interpolate_options_default(&sized);
    limn_status checked = abi_options_in(ctx, "limn_interpolate_estimate", "options",
                                         &abi_interpolate_options, options, &sized);
    if (checked)
        return checked;
    if (options)
        options = &sized;
    checked = options ? solve_check_options(ctx, options) : LIMN_OK;
    if (checked)
        return checked;
    /* paper, weighted, chebyshev (and so auto) hold the same buffers; cg more;
       sgs most (its colour-ordered table copy and eight vectors: measured
       1,171-1,230 B a vertex at 0.5-2.1M, README "Solvers") */
    limn_method method = options ? options->method : LIMN_METHOD_AUTO;
    int cg = method == LIMN_METHOD_CG || method == LIMN_METHOD_SGS;
    double per_vertex = method == LIMN_METHOD_SGS ? 1350.0 : cg ? 1000.0 : 600.0;
    double per_corner = cg ? 8.0 : 16.0;
    limn_precision precision = options ? options->precision : LIMN_PRECISION_AUTO;
    if (!cg && (precision == LIMN_PRECISION_FLOAT ||
                (precision == LIMN_PRECISION_AUTO &&
                 mesh->vertex_count >= SOLVE_FLOAT_MIN_VERTICES)))
        per_vertex += 80.0;
    size_t corners = mesh->face_offsets[mesh->face_count];
    double peak = (double)mesh->vertex_count * per_vertex + (double)corners * per_corner +
                  (double)RUNTIME_BYTES;
    size_t bytes = peak >= (double)SIZE_MAX ? SIZE_MAX : (size_t)peak;
    if (peak_bytes)
        *peak_bytes = bytes;
    size_t budget = max_memory ? max_memory : physical_memory() / 4 * 3;
    if (bytes > budget)
        return ctx_fail(ctx, LIMN_ERR_MEMORY,
                         "interpolating %zu vertices and %zu faces needs about %.2f GiB, over the "
                         "limit of %.2f GiB: raise --max-memory or use a machine with more "
                         "memory; nothing was written",
                         mesh->vertex_count, mesh->face_count, peak / (1 << 30),
                         (double)budget / (1 << 30));
    return LIMN_OK;
}
