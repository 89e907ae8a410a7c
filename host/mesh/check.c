/* SPDX-License-Identifier: MIT */
/*
 * Checks of the values handed to public entry points: a bad value is refused
 * at the door with a message naming it, rather than surfacing later as a
 * non-finite result or a misleading convergence failure.
 */
#include "mesh/check.h"
#include "base/context.h"
#include "base/parallel.h"
#include "mesh/mesh.h"

#include <math.h>

static limn_status finite(limn_context *ctx, const char *fn, const char *name, const double *xyz,
                          size_t n, size_t first)
{
    for (size_t i = 0; i < 3 * n; i++)
        if (!isfinite(xyz[i]))
            return ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                             "%s: %s%svertex %zu has a non-finite coordinate (%c = %g); nothing "
                             "was computed or written",
                             fn, name ? name : "", name ? ": " : "", first + i / 3,
                             "xyz"[i % 3], xyz[i]);
    return LIMN_OK;
}

/* The first index at or past the vertex count in each range of indices
   (SIZE_MAX when none). */
typedef struct index_job {
    const uint32_t *indices;
    size_t n, vertex_count;
    unsigned parts;
    size_t bad[PARALLEL_MAX];
} index_job;

static int index_range(void *arg, size_t begin, size_t end)
{
    index_job *j = arg;
    size_t i = begin;
    while (i < end && j->indices[i] < j->vertex_count)
        i++;
    j->bad[parallel_part(j->n, j->parts, begin)] = i < end ? i : SIZE_MAX;
    return 0;
}

limn_status check_face_indices(limn_context *ctx, const char *fn, const uint32_t *indices,
                               size_t n, size_t vertex_count)
{
    index_job j = {.indices = indices, .n = n, .vertex_count = vertex_count};
    j.parts = parallel_threads(ctx, (uint64_t)n * 4);
    for (unsigned i = 0; i < PARALLEL_MAX; i++)
        j.bad[i] = SIZE_MAX;
    parallel_run(n, j.parts, index_range, &j);
    for (unsigned i = 0; i < PARALLEL_MAX; i++) /* ranges in index order: the first */
        if (j.bad[i] != SIZE_MAX)
            return ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                            "%s: face index %zu is %u but there are %zu vertices", fn, j.bad[i],
                            indices[j.bad[i]], vertex_count);
    return LIMN_OK;
}

limn_status check_positions(limn_context *ctx, const char *fn, const double *xyz, size_t n)
{
    return finite(ctx, fn, NULL, xyz, n, 0);
}

limn_status check_positions_from(limn_context *ctx, const char *fn, const double *xyz, size_t n,
                                 size_t first)
{
    return finite(ctx, fn, NULL, xyz, n, first);
}

limn_status check_mesh(limn_context *ctx, const char *fn, const char *name, const limn_mesh *mesh)
{
    if (!mesh)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "%s: %s is NULL", fn, name ? name : "the mesh");
    return finite(ctx, fn, name, mesh->positions, mesh->vertex_count, 0);
}

limn_status check_mesh_magnitude(limn_context *ctx, const char *fn, const char *name,
                                 const limn_mesh *mesh)
{
    limn_status st = check_mesh(ctx, fn, name, mesh);
    if (st || mesh->vertex_count == 0)
        return st;
    const double *p = mesh->positions;
    double sum = 0.0, big = 0.0, lo[3], hi[3];
    size_t at = 0;
    for (size_t i = 0; i < 3 * mesh->vertex_count; i++) {
        sum += p[i] * p[i]; /* +inf once a square overflows: refused below */
        if (fabs(p[i]) > big) {
            big = fabs(p[i]);
            at = i;
        }
    }
    double diag = mesh_bbox_diagonal(mesh, lo, hi), diag2 = diag * diag;
    if (sum <= CHECK_SQUARES_MAX && diag2 <= CHECK_SQUARES_MAX)
        return LIMN_OK;
    int by_sum = !(sum <= CHECK_SQUARES_MAX);
    return ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                     "%s: coordinates too large (overflow): the %s is %.3g, over the %.3g "
                     "that sums of squares can hold here (largest coordinate: vertex %zu, "
                     "%c = %.3g); scale %s down; nothing was computed",
                     fn, by_sum ? "sum of squared coordinates" : "squared bbox diagonal",
                     by_sum ? sum : diag2, CHECK_SQUARES_MAX, at / 3, "xyz"[at % 3], p[at],
                     name ? name : "the mesh");
}

limn_status check_scheme(limn_context *ctx, const char *fn, limn_scheme scheme)
{
    if (scheme == LIMN_SCHEME_AUTO || scheme == LIMN_SCHEME_LOOP ||
        scheme == LIMN_SCHEME_CATMARK)
        return LIMN_OK;
    return ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                     "%s: unknown scheme %d (LIMN_SCHEME_AUTO 0, LIMN_SCHEME_LOOP 1, "
                     "LIMN_SCHEME_CATMARK 2)",
                     fn, (int)scheme);
}

limn_status check_count(limn_context *ctx, const char *fn, const char *arg, long long value,
                        long long min, long long cap, const char *cap_name)
{
    if (value < min)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "%s: %s is %lld; it must be at least %lld", fn,
                         arg, value, min);
    if (value > cap)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                         "%s: %s is %lld, over the cap of %lld (%s): no use needs more, and "
                         "it would run for hours",
                         fn, arg, value, cap, cap_name);
    return LIMN_OK;
}

limn_status check_steps(limn_context *ctx, const char *fn, int steps, long long per_step,
                        const char *what)
{
    limn_status st = check_count(ctx, fn, "steps", steps, 1, LIMN_MAX_STEPS, "LIMN_MAX_STEPS");
    return st ? st
              : check_count(ctx, fn, what, per_step * steps, 0, LIMN_MAX_PRODUCTS,
                            "LIMN_MAX_PRODUCTS");
}

limn_status check_nonfinite_iteration(limn_context *ctx, const char *what, int k,
                                      limn_scheme scheme, double alpha, int in_float)
{
    if (scheme == LIMN_SCHEME_CATMARK && alpha > 6.0 / 7.0)
        return ctx_fail(ctx, LIMN_ERR_NO_CONVERGENCE,
                         "%s became non-finite after %d iteration(s): with alpha %g over 6/7 "
                         "the iteration diverges for Catmull-Clark; keep alpha <= 6/7 (0.5 is "
                         "a good choice)",
                         what, k, alpha);
    return ctx_fail(ctx, LIMN_ERR_NO_CONVERGENCE,
                     "non-finite values in the iteration (overflow?): %s became non-finite "
                     "after %d iteration%s%s; nothing was written",
                     what, k, k == 1 ? "" : "s",
                     in_float ? "; corrections are iterated in float (largest value 3.4e38): "
                                "run with --precision double (LIMN_PRECISION_DOUBLE) or scale "
                                "the mesh down"
                              : "; scale the mesh down");
}

limn_status check_writable_counts(limn_context *ctx, limn_format format, size_t vertices,
                                  size_t faces, int colors, size_t polygons)
{
    /* limn_mesh_read refuses a file without vertices, so none is written */
    if (vertices == 0)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                         "limn_mesh_write: the mesh has no vertices, and a mesh file without "
                         "vertices is not read back; nothing was written");
    /* what the format drops, said rather than done silently (the file still
       reads back, as a mesh with less in it) */
    if (colors && format != LIMN_FORMAT_PLY && format != LIMN_FORMAT_PLY_ASCII &&
        format != LIMN_FORMAT_PLY_BINARY_BE)
        ctx_warn(ctx, "limn_mesh_write: %s holds no vertex colours: the mesh's are not "
                       "written (PLY holds them)",
                  format == LIMN_FORMAT_OBJ ? "OBJ" : format == LIMN_FORMAT_OFF ? "OFF" : "STL");
    if (format == LIMN_FORMAT_STL && polygons)
        ctx_warn(ctx, "limn_mesh_write: STL holds triangles only: %zu faces with more than 3 "
                       "vertices are written fan-triangulated",
                  polygons);
    if (format == LIMN_FORMAT_STL && faces == 0)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                         "limn_mesh_write: STL holds triangles only, and the mesh has %zu "
                         "vertices but no faces: write OBJ, PLY or OFF instead; nothing was "
                         "written",
                         vertices);
    return LIMN_OK;
}

size_t check_polygons(const uint32_t *face_offsets, size_t face_count)
{
    size_t polygons = 0;
    for (size_t f = 0; f < face_count; f++)
        polygons += face_offsets[f + 1] - face_offsets[f] > 3;
    return polygons;
}

limn_status check_mesh_writable(limn_context *ctx, const limn_mesh *mesh, limn_format format)
{
    limn_status st = check_positions(ctx, "limn_mesh_write", mesh->positions, mesh->vertex_count);
    if (st)
        return st;
    size_t polygons =
        format == LIMN_FORMAT_STL ? check_polygons(mesh->face_offsets, mesh->face_count) : 0;
    return check_writable_counts(ctx, format, mesh->vertex_count, mesh->face_count,
                                 mesh->colors != NULL, polygons);
}
