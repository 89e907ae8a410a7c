/* SPDX-License-Identifier: MIT */
/* Mesh container: creation from caller arrays, accessors, copies. */
#include "base/large_alloc.h"
#include "mesh/mesh.h"
#include "mesh/check.h"
#include "base/context.h"

#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

limn_status mesh_alloc(limn_context *ctx, size_t vertex_count, size_t face_count,
                       size_t index_count, limn_mesh **out)
{
    *out = NULL;
    if (vertex_count > SIZE_MAX / (3 * sizeof(double)) || face_count >= UINT32_MAX ||
        index_count > UINT32_MAX)
        return ctx_fail(ctx, LIMN_ERR_MEMORY,
                         "mesh too large: %zu vertices, %zu faces, %zu face indices",
                         vertex_count, face_count, index_count);
    limn_mesh *m = calloc(1, sizeof *m);
    if (!m)
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for a mesh");
    m->vertex_count = vertex_count;
    m->face_count = face_count;
    m->positions = large_malloc((vertex_count ? vertex_count : 1) * 3 * sizeof(double));
    m->face_offsets = large_malloc((face_count + 1) * sizeof(uint32_t));
    m->face_indices = large_malloc((index_count ? index_count : 1) * sizeof(uint32_t));
    if (!m->positions || !m->face_offsets || !m->face_indices) {
        limn_mesh_destroy(m);
        return ctx_fail(ctx, LIMN_ERR_MEMORY,
                         "out of memory for a mesh of %zu vertices and %zu faces",
                         vertex_count, face_count);
    }
    m->face_offsets[0] = 0;
    *out = m;
    return LIMN_OK;
}

limn_status limn_mesh_create(limn_context *ctx, size_t vertex_count,
                             const double *positions, size_t face_count,
                             const uint32_t *face_offsets,
                             const uint32_t *face_indices, limn_mesh **out)
{
    ctx_clear(ctx);
    if (!out)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "limn_mesh_create: out is NULL");
    *out = NULL;
    if ((vertex_count && !positions) || !face_offsets || (face_count && !face_indices))
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "limn_mesh_create: %s is NULL",
                         vertex_count && !positions ? "positions"
                         : !face_offsets            ? "face_offsets"
                                                    : "face_indices");
    if (face_offsets[0] != 0)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                         "limn_mesh_create: face_offsets[0] is %u, must be 0", face_offsets[0]);
    for (size_t f = 0; f < face_count; f++) {
        if ((uint64_t)face_offsets[f + 1] < (uint64_t)face_offsets[f] + 3)
            return ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                             "limn_mesh_create: face %zu has %ld vertices (at least 3 needed)",
                             f, (long)face_offsets[f + 1] - (long)face_offsets[f]);
    }
    size_t index_count = face_offsets[face_count];
    limn_status st =
        check_face_indices(ctx, "limn_mesh_create", face_indices, index_count, vertex_count);
    if (!st)
        st = check_positions(ctx, "limn_mesh_create", positions, vertex_count);
    if (st)
        return st;
    limn_mesh *m;
    st = mesh_alloc(ctx, vertex_count, face_count, index_count, &m);
    if (st)
        return st;
    if (vertex_count)
        memcpy(m->positions, positions, vertex_count * 3 * sizeof(double));
    memcpy(m->face_offsets, face_offsets, (face_count + 1) * sizeof(uint32_t));
    if (index_count)
        memcpy(m->face_indices, face_indices, index_count * sizeof(uint32_t));
    *out = m;
    return LIMN_OK;
}

/* Drops this mesh's hold on its faces (freed by the last holder). */
static void faces_release(limn_mesh *m)
{
    _Atomic size_t *shares = atomic_load(&m->face_shares);
    if (!shares || atomic_fetch_sub(shares, 1) == 1) {
        free(m->face_offsets);
        free(m->face_indices);
        free((void *)shares);
    }
    atomic_store(&m->face_shares, NULL);
    m->face_offsets = m->face_indices = NULL;
    m->face_count = 0;
}

/* to (holding no faces) shares from's: the count installed on from when it
   held them alone (a compare-and-swap: a loser's count is dropped). */
static limn_status faces_share(limn_context *ctx, const limn_mesh *from, limn_mesh *to)
{
    limn_mesh *f = (limn_mesh *)from; /* only its atomic count changes */
    _Atomic size_t *shares = atomic_load(&f->face_shares);
    if (!shares) {
        _Atomic size_t *mine = malloc(sizeof *mine);
        if (!mine)
            return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory copying a mesh");
        atomic_init(mine, 1);
        if (atomic_compare_exchange_strong(&f->face_shares, &shares, mine))
            shares = mine;
        else
            free((void *)mine); /* another copy installed one: shares is it */
    }
    atomic_fetch_add(shares, 1);
    atomic_store(&to->face_shares, shares);
    to->face_offsets = from->face_offsets;
    to->face_indices = from->face_indices;
    to->face_count = from->face_count;
    return LIMN_OK;
}

limn_status mesh_faces_own(limn_context *ctx, limn_mesh *m)
{
    _Atomic size_t *shares = atomic_load(&m->face_shares);
    if (!shares)
        return LIMN_OK;
    if (atomic_load(shares) == 1) { /* the other holders are gone: no copy */
        free((void *)shares);
        atomic_store(&m->face_shares, NULL);
        return LIMN_OK;
    }
    size_t nf = m->face_count, nc = m->face_offsets[nf];
    uint32_t *off = large_malloc((nf + 1) * sizeof *off);
    uint32_t *idx = large_malloc((nc ? nc : 1) * sizeof *idx);
    if (!off || !idx) {
        free(off);
        free(idx);
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for the faces of a mesh");
    }
    memcpy(off, m->face_offsets, (nf + 1) * sizeof *off);
    memcpy(idx, m->face_indices, nc * sizeof *idx);
    mesh_faces_replace(m, nf, off, idx);
    return LIMN_OK;
}

void mesh_faces_replace(limn_mesh *m, size_t face_count, uint32_t *face_offsets,
                        uint32_t *face_indices)
{
    faces_release(m);
    m->face_offsets = face_offsets;
    m->face_indices = face_indices;
    m->face_count = face_count;
}

/* A mesh with mesh's vertex count, sharing its faces, with a copy of its
   colours; its positions are `positions` (taken over, freed on failure
   too), or room for them when NULL. */
static limn_status alloc_sharing(limn_context *ctx, const limn_mesh *mesh, double *positions,
                                 limn_mesh **out)
{
    limn_status st = mesh_alloc(ctx, positions ? 0 : mesh->vertex_count, 0, 0, out);
    if (st) {
        free(positions);
        return st;
    }
    limn_mesh *m = *out;
    if (positions) {
        free(m->positions);
        m->positions = positions;
    }
    m->vertex_count = mesh->vertex_count;
    faces_release(m);
    st = faces_share(ctx, mesh, m);
    if (!st && mesh->colors)
        st = limn_mesh_set_colors(ctx, m, mesh->colors);
    if (st) {
        limn_mesh_destroy(m);
        *out = NULL;
    }
    return st;
}

limn_status limn_mesh_copy(limn_context *ctx, const limn_mesh *mesh, limn_mesh **out)
{
    /* no ctx_clear: operations call this for their results, keeping their warnings */
    if (out)
        *out = NULL;
    if (!mesh || !out)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "limn_mesh_copy: %s is NULL",
                         !mesh ? "mesh" : "out");
    limn_status st = alloc_sharing(ctx, mesh, NULL, out);
    if (!st)
        memcpy((*out)->positions, mesh->positions, mesh->vertex_count * 3 * sizeof(double));
    return st;
}

double *mesh_rows4_to_xyz(double *rows4, size_t vertices)
{
    /* row k's source 4k.. lies at or past everything rows before it wrote,
       and each value is read before the forward copy writes over it: no
       memmove call per row */
    for (size_t k = 1; k < vertices; k++) {
        double x = rows4[4 * k], y = rows4[4 * k + 1], z = rows4[4 * k + 2];
        rows4[3 * k] = x;
        rows4[3 * k + 1] = y;
        rows4[3 * k + 2] = z;
    }
    double *shrunk = realloc(rows4, (vertices ? 3 * vertices : 1) * sizeof *rows4);
    return shrunk ? shrunk : rows4;
}

limn_status mesh_copy_with_positions(limn_context *ctx, const limn_mesh *mesh, double *positions,
                                     limn_mesh **out)
{
    *out = NULL;
    return alloc_sharing(ctx, mesh, positions, out);
}

limn_status mesh_hand_over(limn_status st, limn_mesh *made, limn_mesh **out)
{
    if (st)
        limn_mesh_destroy(made);
    else
        *out = made;
    return st;
}

void limn_mesh_destroy(limn_mesh *mesh)
{
    if (!mesh)
        return;
    if (mesh->topology)
        mesh->topology_drop(mesh->topology);
    free(mesh->counts);
    free(mesh->positions);
    faces_release(mesh);
    free(mesh->colors);
    free(mesh);
}

size_t limn_mesh_vertex_count(const limn_mesh *mesh) { return mesh ? mesh->vertex_count : 0; }
size_t limn_mesh_face_count(const limn_mesh *mesh) { return mesh ? mesh->face_count : 0; }
const double *limn_mesh_positions(const limn_mesh *mesh) { return mesh ? mesh->positions : NULL; }
double *limn_mesh_positions_mutable(limn_mesh *mesh) { return mesh ? mesh->positions : NULL; }
const uint32_t *limn_mesh_face_offsets(const limn_mesh *mesh) { return mesh ? mesh->face_offsets : NULL; }
const uint32_t *limn_mesh_face_indices(const limn_mesh *mesh) { return mesh ? mesh->face_indices : NULL; }
const uint8_t *limn_mesh_colors(const limn_mesh *mesh) { return mesh ? mesh->colors : NULL; }

limn_status limn_mesh_set_colors(limn_context *ctx, limn_mesh *mesh, const uint8_t *rgb)
{
    if (!mesh)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "limn_mesh_set_colors: mesh is NULL");
    if (!rgb) {
        free(mesh->colors);
        mesh->colors = NULL;
        return LIMN_OK;
    }
    uint8_t *c = malloc(mesh->vertex_count ? mesh->vertex_count * 3 : 1);
    if (!c)
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for vertex colours");
    memcpy(c, rgb, mesh->vertex_count * 3);
    free(mesh->colors);
    mesh->colors = c;
    return LIMN_OK;
}

/* Coordinate c's extremes as one walk in vertex order with strict
   comparisons: the first vertex's value unless another is strictly beyond
   it (so a NaN only from the first vertex, and of equal zeros the first). */
static void bbox_walk(const double *p, size_t n, int c, double *lo, double *hi)
{
    *lo = *hi = n ? p[c] : 0.0;
    for (size_t i = 0; i < n; i++) {
        double x = p[3 * i + c];
        *lo = x < *lo ? x : *lo;
        *hi = x > *hi ? x : *hi;
    }
}

double mesh_bbox_diagonal(const limn_mesh *mesh, double lo[3], double hi[3])
{
    /* four walks over interleaved vertices, merged: four chains of compares
       side by side instead of one, the same numbers as bbox_walk's (values
       that compare equal have the same bits) except the sign of a zero
       extreme, which is then walked again */
    const double *p = mesh->positions;
    size_t n = mesh->vertex_count, i = 0;
    double l[4][3], h[4][3];
    for (int k = 0; k < 4; k++)
        for (int c = 0; c < 3; c++)
            l[k][c] = h[k][c] = n ? p[c] : 0.0;
    for (; i + 4 <= n; i += 4)
        for (int k = 0; k < 4; k++)
            for (int c = 0; c < 3; c++) {
                double x = p[3 * (i + k) + c];
                l[k][c] = x < l[k][c] ? x : l[k][c];
                h[k][c] = x > h[k][c] ? x : h[k][c];
            }
    for (; i < n; i++)
        for (int c = 0; c < 3; c++) {
            double x = p[3 * i + c];
            l[0][c] = x < l[0][c] ? x : l[0][c];
            h[0][c] = x > h[0][c] ? x : h[0][c];
        }
    for (int c = 0; c < 3; c++) {
        lo[c] = l[0][c];
        hi[c] = h[0][c];
        for (int k = 1; k < 4; k++) {
            lo[c] = l[k][c] < lo[c] ? l[k][c] : lo[c];
            hi[c] = h[k][c] > hi[c] ? h[k][c] : hi[c];
        }
        if (lo[c] == 0.0 || hi[c] == 0.0)
            bbox_walk(p, n, c, &lo[c], &hi[c]);
    }
    return sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                (hi[2] - lo[2]) * (hi[2] - lo[2]));
}
