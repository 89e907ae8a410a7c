/* SPDX-License-Identifier: MIT */
/*
 * limn_interpolate_estimate: the peak memory of limn_interpolate, predicted
 * before anything is allocated, so that a batch job refuses a mesh it cannot
 * hold instead of being killed half way.
 *
 * Model: bytes per vertex + bytes per stencil entry + 96 MiB (the OpenCL
 * runtime, measured 78-80 MiB), the entries counted from the faces before any
 * table exists: a limit row holds its vertex and the other corners of its
 * faces, an edge's far end shared by two faces, V + sum over faces of
 * d (d - 2) on a closed mesh (Loop and Catmull-Clark alike: 7 a vertex on a
 * regular triangle mesh, 9 on a quad mesh; fewer at a boundary). Refitted
 * 2026-12-06 (docs/robustness.md "Memory") from the peak RSS of `limn
 * interpolate` on both backends, seven meshes of 1.4-8.6M vertices (Loop and
 * Catmull-Clark, closed and with holes, binary and text input), each method
 * and precision: the least coefficients above every measured peak (entries at
 * 12 B or more: a column and a double weight), plus 10% for meshes not
 * measured. The memory work since halved the peaks the first model
 * (2026-11-23: 600 B a vertex + 16 a corner) was fitted to, so it refused
 * meshes that fitted: 34M vertices predicted at 22 GiB.
 * A solver that keeps more vectors must update these figures: perf/memory_fit.py
 * remeasures the peaks and prints the coefficients they give.
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
    limn_method method = options ? options->method : LIMN_METHOD_AUTO;
    limn_precision precision = options ? options->precision : LIMN_PRECISION_AUTO;
    int krylov = method == LIMN_METHOD_CG || method == LIMN_METHOD_SGS;
    int single = !krylov && (precision == LIMN_PRECISION_FLOAT ||
                             (precision == LIMN_PRECISION_AUTO &&
                              mesh->vertex_count >= SOLVE_FLOAT_MIN_VERTICES));
    int reordered = (!options || options->reorder) &&
                    (method == LIMN_METHOD_PAPER || method == LIMN_METHOD_WEIGHTED);
    /* {B a vertex, B an entry} as fitted; cg's and sgs's from a mesh with
       holes, whose unsymmetric boundary rows cost them the most (bunny,
       refined: 1.5x a closed mesh's) */
    static const double fitted[6][2] = {
        {202.0, 12.0}, /* chebyshev (auto), double */
        {213.0, 12.0}, /* chebyshev, float corrections */
        {10.0, 40.0},  /* paper, weighted in RCM order, double */
        {134.0, 22.0}, /* the same, float */
        {583.0, 12.0}, /* cg */
        {878.0, 12.0}, /* sgs */
    };
    int k = method == LIMN_METHOD_SGS ? 5 : method == LIMN_METHOD_CG ? 4
                                                                     : 2 * reordered + single;
    double entries = (double)mesh->vertex_count;
    for (size_t f = 0; f < mesh->face_count; f++) {
        double d = (double)(mesh->face_offsets[f + 1] - mesh->face_offsets[f]);
        entries += d > 2.0 ? d * (d - 2.0) : 0.0;
    }
    double peak = 1.1 * ((double)mesh->vertex_count * fitted[k][0] + entries * fitted[k][1]) +
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
