/* SPDX-License-Identifier: MIT */
/*
 * Uniform refinement: the levels G_0 .. G_L of a mesh as topologies plus one
 * CSR table per step (rows: vertices of level k+1, columns: vertices of level
 * k). Vertex i of level k is vertex i of level k+1 (vertex points first), then
 * face points (Catmull-Clark), then edge points, so an input vertex keeps its
 * index at every level.
 *
 * Catmull-Clark: any polygons -> quads after one step; the alpha vertex rule
 * on the first step only (DESIGN.md §1), standard after. Loop: triangles.
 * Boundary, crease, corner and non-manifold rules as in topology.h.
 */
#ifndef LIMN_REFINE_H
#define LIMN_REFINE_H

#include "limn.h"
#include "stencil/stencil.h"

typedef struct refine_plan {
    limn_scheme scheme;
    double alpha;
    int levels;
    limn_mesh **meshes;    /* levels + 1 meshes; meshes[0] is a copy of the base
                              (positions of the finer ones are undefined until
                              written: refine_plan_apply_positions, texture.c) */
    stencil_csr *steps;    /* levels tables: level k -> k + 1 */
} refine_plan;

/* Builds the topology of every level and the step tables (no positions). */
limn_status refine_plan_build(limn_context *ctx, const limn_mesh *base, limn_scheme scheme,
                              double alpha, int levels, refine_plan *out);
void refine_plan_free(refine_plan *plan);

/*
 * Carries per-vertex data of `channels` doubles (1 for a scalar, 3 for
 * positions) from level `from` to the finest level through the step tables,
 * on the context's device. in: channels * vertices(from); out: channels *
 * vertices(levels).
 */
limn_status refine_plan_apply(limn_context *ctx, const refine_plan *plan, int from,
                              int channels, const double *in, double *out);
/* refine_plan_apply of the base positions (3 doubles a vertex) into the
   finest mesh's positions, made of the device's rows in place (no fresh
   positions to fill). */
limn_status refine_plan_apply_positions(limn_context *ctx, refine_plan *plan,
                                        const double *positions);

/*
 * The finest level of refining base `levels` times (0..16; scheme resolved,
 * alpha on the first step of Catmull-Clark only), the same mesh, bytes for
 * bytes, as refine_plan_build + refine_plan_apply_positions, without their
 * step tables or device: each level's rows are used as they are made
 * (stencil_build_apply3), so a one-shot refinement moves a fraction of the
 * bytes, and a level below is freed once the next exists. *entries: the
 * nonzeros the step tables would hold; *seconds_apply: the rows' time.
 */
limn_status refine_surface(limn_context *ctx, const limn_mesh *base, limn_scheme scheme,
                           double alpha, int levels, limn_mesh **out, size_t *entries,
                           double *seconds_apply);

/* Predicted vertex, face and index counts of level `levels`, and the peak
   bytes of a whole subdivide run (plan, apply, the limit operator of the
   finest level when `limit`, the OpenCL runtime), without building anything. */
void refine_estimate(const limn_mesh *base, limn_scheme scheme, int levels, int limit,
                     size_t *vertices, size_t *faces, size_t *indices, size_t *peak_bytes);

/* The same from the base's counts: v vertices, f faces, c corners, e edges
   (an upper bound gives an upper bound), as a distributed mesh knows them. */
void refine_estimate_counts(double v, double f, double c, double e, limn_scheme scheme,
                            int levels, int limit, size_t *vertices, size_t *faces,
                            size_t *indices, size_t *peak_bytes);

/* The part of the estimate that every process pays once (the OpenCL
   runtime, the library): what does not shrink with the ranks. */
#define REFINE_RUNTIME_BYTES ((size_t)192 << 20)

#endif
