/* SPDX-License-Identifier: MIT */
/*
 * Geometric measures of a mesh: signed volume (divergence theorem), area,
 * Newell face normals; comparisons of two meshes of one topology (vertex
 * distances, normal angles, flipped faces). Used by the series commands'
 * reports, the tests and the benchmarks.
 */
#include "base/abi.h"
#include "topology/measure.h"
#include "mesh/check.h"
#include "base/context.h"
#include "mesh/mesh.h"
#include "topology/topology.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void measure_face_normal(const double *pos, const uint32_t *off, const uint32_t *idx, size_t f,
                         double n[3])
{
    n[0] = n[1] = n[2] = 0.0;
    uint32_t b = off[f], e = off[f + 1];
    for (uint32_t k = b; k < e; k++) {
        const double *p = pos + 3 * (size_t)idx[k];
        const double *q = pos + 3 * (size_t)idx[k + 1 < e ? k + 1 : b];
        n[0] += (p[1] - q[1]) * (p[2] + q[2]);
        n[1] += (p[2] - q[2]) * (p[0] + q[0]);
        n[2] += (p[0] - q[0]) * (p[1] + q[1]);
    }
}

void measure_volume_area(const limn_mesh *mesh, const double *pos, double *volume, double *area)
{
    /* relative to the first vertex's position: translation-invariant and
       accurate far from the origin */
    double c[3] = {0, 0, 0};
    if (mesh->vertex_count)
        memcpy(c, pos, sizeof c);
    double vol = 0.0, ar = 0.0;
    for (size_t f = 0; f < mesh->face_count; f++) {
        uint32_t b = mesh->face_offsets[f], e = mesh->face_offsets[f + 1];
        const double *p0 = pos + 3 * (size_t)mesh->face_indices[b];
        double a[3] = {p0[0] - c[0], p0[1] - c[1], p0[2] - c[2]};
        for (uint32_t k = b + 1; k + 1 < e; k++) {
            const double *p1 = pos + 3 * (size_t)mesh->face_indices[k];
            const double *p2 = pos + 3 * (size_t)mesh->face_indices[k + 1];
            double u[3] = {p1[0] - c[0], p1[1] - c[1], p1[2] - c[2]};
            double v[3] = {p2[0] - c[0], p2[1] - c[1], p2[2] - c[2]};
            double x[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                           u[0] * v[1] - u[1] * v[0]};
            vol += (a[0] * x[0] + a[1] * x[1] + a[2] * x[2]) / 6.0;
            double e1[3] = {u[0] - a[0], u[1] - a[1], u[2] - a[2]};
            double e2[3] = {v[0] - a[0], v[1] - a[1], v[2] - a[2]};
            double y[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                           e1[0] * e2[1] - e1[1] * e2[0]};
            ar += 0.5 * sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]);
        }
    }
    *volume = vol;
    *area = ar;
}

int measure_topology_closed(const topology *t)
{
    return t->face_count > 0 && t->boundary_edges == 0 && t->nonmanifold_edges == 0 &&
           t->inconsistent_edges == 0;
}

/* limn_mesh_measure into a result of this library's layout. */
static limn_status measure_sized(limn_context *ctx, const limn_mesh *mesh, limn_mesh_measures *out)
{
    limn_status begun = abi_begin(ctx, "limn_mesh_measure", "out", out);
    if (begun)
        return begun;
    memset(out, 0, sizeof *out);
    topology t;
    limn_status st = topology_get_checked(ctx, "limn_mesh_measure", mesh, &t);
    if (st)
        return st;
    out->closed = measure_topology_closed(&t);
    topology_free(&t);
    double vol;
    measure_volume_area(mesh, mesh->positions, &vol, &out->area);
    out->volume = out->closed ? vol : NAN;
    for (size_t i = 0; i < mesh->vertex_count; i++)
        for (int c = 0; c < 3; c++)
            out->centroid[c] += mesh->positions[3 * i + c];
    for (int c = 0; c < 3; c++)
        out->centroid[c] /= mesh->vertex_count ? (double)mesh->vertex_count : 1.0;
    return LIMN_OK;
}

void limn_mesh_volume_area(const limn_mesh *mesh, double *volume, double *area)
{
    double v = NAN, a = NAN;
    if (mesh)
        measure_volume_area(mesh, mesh->positions, &v, &a);
    if (volume)
        *volume = v;
    if (area)
        *area = a;
}

limn_status measure_same_topology(limn_context *ctx, const limn_mesh *a, const limn_mesh *b,
                                  const char *name_a, const char *name_b)
{
    if (a->vertex_count != b->vertex_count)
        return ctx_fail(ctx, LIMN_ERR_TOPOLOGY,
                         "%s and %s differ in topology: %s has %zu vertices, %s has %zu",
                         name_a, name_b, name_a, a->vertex_count, name_b, b->vertex_count);
    size_t nf = a->face_count < b->face_count ? a->face_count : b->face_count;
    for (size_t f = 0; f < nf; f++) {
        uint32_t sa = a->face_offsets[f + 1] - a->face_offsets[f];
        uint32_t sb = b->face_offsets[f + 1] - b->face_offsets[f];
        int differ = sa != sb;
        for (uint32_t k = 0; !differ && k < sa; k++)
            differ = a->face_indices[a->face_offsets[f] + k] !=
                     b->face_indices[b->face_offsets[f] + k];
        if (differ) {
            char fa[96], fb[96];
            size_t la = 0, lb = 0;
            for (uint32_t k = 0; k < sa && la + 12 < sizeof fa; k++)
                la += (size_t)snprintf(fa + la, sizeof fa - la, "%s%u", k ? " " : "",
                                       a->face_indices[a->face_offsets[f] + k]);
            for (uint32_t k = 0; k < sb && lb + 12 < sizeof fb; k++)
                lb += (size_t)snprintf(fb + lb, sizeof fb - lb, "%s%u", k ? " " : "",
                                       b->face_indices[b->face_offsets[f] + k]);
            return ctx_fail(ctx, LIMN_ERR_TOPOLOGY,
                             "%s and %s differ in topology: face %zu is (%s) in %s but (%s) in "
                             "%s (0-based vertex indices); both meshes need the same faces",
                             name_a, name_b, f, fa, name_a, fb, name_b);
        }
    }
    if (a->face_count != b->face_count)
        return ctx_fail(ctx, LIMN_ERR_TOPOLOGY,
                         "%s and %s differ in topology: %s has %zu faces, %s has %zu (face %zu "
                         "is the first one only one of them has)",
                         name_a, name_b, name_a, a->face_count, name_b, b->face_count, nf);
    return LIMN_OK;
}

limn_status limn_mesh_same_topology(limn_context *ctx, const limn_mesh *a, const limn_mesh *b)
{
    if (!ctx)
        return LIMN_ERR_ARGUMENT;
    ctx_clear(ctx);
    if (!a || !b)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "limn_mesh_same_topology: the %s mesh is NULL",
                         !a ? "first" : "second");
    return measure_same_topology(ctx, a, b, "the first mesh", "the second mesh");
}

size_t measure_flipped(const limn_mesh *ref, const double *ref_pos, const double *pos)
{
    size_t flipped = 0;
    for (size_t f = 0; f < ref->face_count; f++) {
        double n0[3], n1[3];
        measure_face_normal(ref_pos, ref->face_offsets, ref->face_indices, f, n0);
        measure_face_normal(pos, ref->face_offsets, ref->face_indices, f, n1);
        flipped += n0[0] * n1[0] + n0[1] * n1[1] + n0[2] * n1[2] < 0.0;
    }
    return flipped;
}

/* limn_mesh_compare into a result of this library's layout. */
static limn_status compare_sized(limn_context *ctx, const limn_mesh *a, const limn_mesh *b,
                                 limn_mesh_comparison *out)
{
    limn_status begun = abi_begin(ctx, "limn_mesh_compare", "out", out);
    if (begun)
        return begun;
    memset(out, 0, sizeof *out);
    limn_status st = check_mesh(ctx, "limn_mesh_compare", "the first mesh", a);
    if (!st)
        st = check_mesh(ctx, "limn_mesh_compare", "the second mesh", b);
    if (!st)
        st = measure_same_topology(ctx, a, b, "the first mesh", "the second mesh");
    if (st)
        return st;
    double sum = 0.0;
    for (size_t i = 0; i < a->vertex_count; i++) {
        const double *p = a->positions + 3 * i, *q = b->positions + 3 * i;
        double d = sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
                        (p[2] - q[2]) * (p[2] - q[2]));
        sum += d;
        out->max_distance = d > out->max_distance ? d : out->max_distance;
    }
    out->mean_distance = a->vertex_count ? sum / (double)a->vertex_count : 0.0;
    double angles = 0.0;
    size_t counted = 0;
    for (size_t f = 0; f < a->face_count; f++) {
        double n0[3], n1[3];
        measure_face_normal(a->positions, a->face_offsets, a->face_indices, f, n0);
        measure_face_normal(b->positions, a->face_offsets, a->face_indices, f, n1);
        double l0 = sqrt(n0[0] * n0[0] + n0[1] * n0[1] + n0[2] * n0[2]);
        double l1 = sqrt(n1[0] * n1[0] + n1[1] * n1[1] + n1[2] * n1[2]);
        double dot = n0[0] * n1[0] + n0[1] * n1[1] + n0[2] * n1[2];
        out->flipped_faces += dot < 0.0;
        if (l0 > 0.0 && l1 > 0.0) {
            /* atan2 of |n0 x n1| and n0 . n1: accurate for small angles too */
            double x[3] = {n0[1] * n1[2] - n0[2] * n1[1], n0[2] * n1[0] - n0[0] * n1[2],
                           n0[0] * n1[1] - n0[1] * n1[0]};
            angles += atan2(sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]), dot);
            counted++;
        }
    }
    out->mean_normal_angle = counted ? angles / (double)counted * (180.0 / 3.14159265358979323846)
                                     : 0.0;
    return LIMN_OK;
}

limn_status limn_mesh_measure(limn_context *ctx, const limn_mesh *mesh, limn_mesh_measures *out)
{
    abi_call c;
    limn_status st = abi_enter_result(&c, ctx, "limn_mesh_measure", "out", &abi_mesh_measures, out);
    return st ? st : abi_leave(&c, measure_sized(ctx, mesh, c.report));
}

limn_status limn_mesh_compare(limn_context *ctx, const limn_mesh *a, const limn_mesh *b,
                              limn_mesh_comparison *out)
{
    abi_call c;
    limn_status st =
        abi_enter_result(&c, ctx, "limn_mesh_compare", "out", &abi_mesh_comparison, out);
    return st ? st : abi_leave(&c, compare_sized(ctx, a, b, c.report));
}
