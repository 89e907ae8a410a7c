/* SPDX-License-Identifier: MIT */
/* Checks of the values handed to public entry points (README "Embedding
   limn"): each fails with LIMN_ERR_ARGUMENT and a message that starts with
   the function's name and names the offending value. */
#ifndef LIMN_CHECK_H
#define LIMN_CHECK_H

#include "limn.h"

/* Every coordinate finite; else names the first vertex, its axis and value. */
limn_status check_positions(limn_context *ctx, const char *fn, const double *xyz, size_t n);
/* check_positions of vertices first .. first + n - 1 of a larger mesh (the
   message names the vertex by its index there). */
limn_status check_positions_from(limn_context *ctx, const char *fn, const double *xyz, size_t n,
                                 size_t first);

/* Every one of the n face indices below vertex_count, over the context's
   host threads; else names the first one, its value and the vertex count. */
limn_status check_face_indices(limn_context *ctx, const char *fn, const uint32_t *indices,
                               size_t n, size_t vertex_count);

/* mesh non-NULL and check_positions; `name` says which mesh in messages
   ("FROM", "TO"), NULL where the function takes one ("the mesh"). */
limn_status check_mesh(limn_context *ctx, const char *fn, const char *name,
                       const limn_mesh *mesh);

/* check_mesh, then refuses coordinates so large that the sums of squares the
   solvers and filters form (norms, the bbox diagonal) overflow: the sum of
   squared coordinates and the squared bbox diagonal must stay below
   CHECK_SQUARES_MAX, DBL_MAX / 2^20, the margin leaving room for iterates
   larger than the input and for their sums. */
#define CHECK_SQUARES_MAX (1.79769313486231570815e308 / 1048576.0)
limn_status check_mesh_magnitude(limn_context *ctx, const char *fn, const char *name,
                                 const limn_mesh *mesh);

limn_status check_scheme(limn_context *ctx, const char *fn, limn_scheme scheme);

/* min <= value <= cap, else a message naming the argument, the value and the
   bound (the cap's macro in limn.h, cap_name, when the cap was hit). */
limn_status check_count(limn_context *ctx, const char *fn, const char *arg, long long value,
                        long long min, long long cap, const char *cap_name);

/* 1 <= steps <= LIMN_MAX_STEPS, and steps runs of per_step products each
   within LIMN_MAX_PRODUCTS (what names the product: "(m + 1) * steps"). */
limn_status check_steps(limn_context *ctx, const char *fn, int steps, long long per_step,
                        const char *what);

/* What limn_mesh_write can write so that limn_mesh_read reads it back:
   finite coordinates, at least one vertex, and (STL) at least one face;
   warns of what the format drops (colours but in PLY, STL's n-gons). */
limn_status check_mesh_writable(limn_context *ctx, const limn_mesh *mesh, limn_format format);
/* check_mesh_writable after its check_positions, from the whole mesh's
   counts (the MPI writer: each rank checks its own vertices); polygons: the
   faces of more than 3 corners (check_polygons). */
limn_status check_writable_counts(limn_context *ctx, limn_format format, size_t vertices,
                                  size_t faces, int colors, size_t polygons);
size_t check_polygons(const uint32_t *face_offsets, size_t face_count);

/* The max of a norm reduction, or NaN when its sum shows non-finite values:
   the reductions' max skips NaN (NaN > max is false), their sums keep it, so
   a guard testing the max alone would take a NaN iterate for converged. */
static inline double check_norm_max(double max, double sum)
{
    return sum - sum == 0.0 ? max : sum - sum; /* sum - sum: 0, or NaN for NaN and inf */
}

/* A solver's or filter's vector became non-finite: the message names the
   cause, divergence where the scheme and alpha allow it (Catmull-Clark with
   alpha > 6/7), else overflow. what: "the residual", k: iterations so far,
   in_float: the values were iterated in float. */
limn_status check_nonfinite_iteration(limn_context *ctx, const char *what, int k,
                                      limn_scheme scheme, double alpha, int in_float);

#endif
