/* SPDX-License-Identifier: MIT */
/*
 * limn_mesh_repair: the mesh-level repair step run after reading (DESIGN.md
 * §4; README "Meshes limn accepts"). What it changes, each with a warning:
 *  - faces that use a vertex more than once: consecutive repeats (a a, also
 *    across the end of the face) are removed; a face that still visits a
 *    vertex twice (a b c a d e) is split there into loops with distinct
 *    vertices (a b c) (a d e), keeping the corner order and so the
 *    orientation; loops with fewer than 3 vertices are dropped;
 *  - duplicate faces (the vertex set of an earlier face), only on request.
 * What it leaves as it is, with a warning saying how it is treated:
 * non-manifold edges and vertices, edges of inconsistent orientation (sharp
 * and pinned, OpenSubdiv's rules), vertices used by no face (they stay put).
 * Several components and boundaries are normal and give no warning.
 */
#include "base/abi.h"
#include "base/context.h"
#include "mesh/check.h"
#include "mesh/mesh.h"
#include "topology/face_keys.h"
#include "topology/mesh_repair.h"
#include "topology/topology.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void limn_repair_options_default(limn_repair_options *o)
{
    abi_default(&abi_repair_options, o);
}

/* ---------------------------------------------------------------- repeats */

typedef struct face_out {
    uint32_t *offsets;   /* room for max_faces + 1 */
    uint32_t *indices;   /* room for the input's corner count */
    size_t faces, corners;
} face_out;

static void emit(face_out *o, const uint32_t *v, size_t n)
{
    memcpy(o->indices + o->corners, v, n * sizeof *v);
    o->corners += n;
    o->faces++;
    o->offsets[o->faces] = (uint32_t)o->corners;
}

/* Face v (d corners) into o without repeated vertices, counted in r; pos
   (zeroed, one per vertex), stack and w: scratch of room d. */
static void fix_face(face_out *o, const uint32_t *v, size_t d, uint32_t *pos, uint32_t *stack,
                     uint32_t *w, limn_repair_report *r)
{
    /* 1. consecutive repeats, cyclically */
    size_t n = 0;
    for (size_t i = 0; i < d; i++)
        if (n == 0 || w[n - 1] != v[i])
            w[n++] = v[i];
    while (n > 1 && w[n - 1] == w[0])
        n--;
    int collapsed = n != d;
    /* 2. split where a vertex comes back: the stack holds distinct vertices */
    size_t top = 0, loops = 0, dropped = 0;
    for (size_t i = 0; i < n; i++) {
        uint32_t x = w[i];
        if (pos[x]) {
            size_t p = pos[x] - 1, len = top - p;
            if (len >= 3) {
                emit(o, stack + p, len);
                loops++;
            } else {
                dropped++;
            }
            for (size_t k = p + 1; k < top; k++)
                pos[stack[k]] = 0;
            top = p + 1;
        } else {
            stack[top++] = x;
            pos[x] = (uint32_t)top;
        }
    }
    int split = loops > 0 || dropped > 0;
    if (top >= 3) {
        emit(o, stack, top);
        loops++;
    } else if (split || collapsed || top < d) {
        dropped++;
    }
    for (size_t k = 0; k < top; k++)
        pos[stack[k]] = 0;
    if (!collapsed && !split)
        return;
    r->repeat_faces++;
    if (loops == 0)
        r->degenerate_removed++;
    else if (loops > 1)
        r->faces_split++;
    else
        r->repeats_removed++;
}

/* Rebuilds the faces without repeated vertices (see the file comment). */
limn_status repair_fix_repeats(limn_context *ctx, limn_mesh *m, limn_repair_report *r)
{
    size_t nf = m->face_count, nc = m->face_offsets[nf], nv = m->vertex_count;
    /* every output face has >= 3 corners taken from the input's corners */
    size_t max_faces = nf + nc / 3 + 1;
    face_out o = {0};
    o.offsets = malloc((max_faces + 1) * sizeof *o.offsets);
    o.indices = malloc((nc ? nc : 1) * sizeof *o.indices);
    uint32_t *pos = calloc(nv ? nv : 1, sizeof *pos);     /* stack index + 1 */
    uint32_t *stack = malloc((nc ? nc : 1) * sizeof *stack);
    uint32_t *w = malloc((nc ? nc : 1) * sizeof *w);
    if (!o.offsets || !o.indices || !pos || !stack || !w) {
        free(o.offsets);
        free(o.indices);
        free(pos);
        free(stack);
        free(w);
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory repairing faces");
    }
    o.offsets[0] = 0;
    for (size_t f = 0; f < nf; f++) {
        const uint32_t *v = m->face_indices + m->face_offsets[f];
        fix_face(&o, v, m->face_offsets[f + 1] - m->face_offsets[f], pos, stack, w, r);
    }
    free(pos);
    free(stack);
    free(w);
    topology_uncache(m);
    uint32_t *off = realloc(o.offsets, (o.faces + 1) * sizeof *off);
    uint32_t *idx = realloc(o.indices, (o.corners ? o.corners : 1) * sizeof *idx);
    mesh_faces_replace(m, o.faces, off ? off : o.offsets, idx ? idx : o.indices);
    return LIMN_OK;
}

/* ------------------------------------------------------------- duplicates */

/* Removes the faces marked in dup, keeping the order of the others. */
static limn_status remove_marked(limn_context *ctx, limn_mesh *m, const uint8_t *dup)
{
    limn_status st = mesh_faces_own(ctx, m); /* a copy's faces are another mesh's too */
    if (st)
        return st;
    topology_uncache(m);
    size_t out = 0, w = 0;
    for (size_t f = 0; f < m->face_count; f++) {
        uint32_t b = m->face_offsets[f], e = m->face_offsets[f + 1];
        if (dup[f])
            continue;
        memmove(m->face_indices + w, m->face_indices + b, (e - b) * sizeof(uint32_t));
        w += e - b;
        m->face_offsets[++out] = (uint32_t)w;
    }
    m->face_count = out;
    return LIMN_OK;
}

/* Faces with the vertex set of an earlier face (face_keys.h), removed when
   asked. */
static limn_status find_duplicates(limn_context *ctx, limn_mesh *m, int remove,
                                   limn_repair_report *r)
{
    uint8_t *dup = NULL;
    face_duplicates found;
    limn_status st = face_duplicates_marked(ctx, m, &dup, &found);
    if (!st && found.count) {
        r->duplicate_faces = found.count;
        r->first_duplicate_face = found.first;
        r->first_duplicate_of = found.first_of;
        if (remove && !(st = remove_marked(ctx, m, dup)))
            r->duplicates_removed = r->duplicate_faces;
    }
    free(dup);
    return st;
}

/* ---------------------------------------------------------------- entry */

/* The warning on the duplicate faces in r (found, and removed or kept). */
void repair_warn_duplicates(limn_context *ctx, const limn_repair_report *r)
{
    if (!r->duplicate_faces)
        return;
    if (r->duplicates_removed)
        ctx_warn(ctx,
                 "removed %zu duplicate face%s (faces with the vertices of an earlier face; "
                 "first: face %zu, a copy of face %zu)",
                 r->duplicates_removed, r->duplicates_removed == 1 ? "" : "s",
                 r->first_duplicate_face, r->first_duplicate_of);
    else
        ctx_warn(ctx,
                 "%zu duplicate face%s (the vertices of an earlier face; first: face %zu, a "
                 "copy of face %zu) kept: their edges are non-manifold, hence sharp, as in "
                 "OpenSubdiv (--drop-duplicate-faces removes them)",
                 r->duplicate_faces, r->duplicate_faces == 1 ? "" : "s",
                 r->first_duplicate_face, r->first_duplicate_of);
}

/* The warnings saying which topology faults the repair kept (r->nonmanifold_edges etc.). */
void repair_warn_kept(limn_context *ctx, const limn_repair_report *r)
{
    if (r->nonmanifold_edges)
        ctx_warn(ctx,
                 "%zu non-manifold edge%s (more than two faces) kept: sharp, as in OpenSubdiv",
                 r->nonmanifold_edges, r->nonmanifold_edges == 1 ? "" : "s");
    if (r->nonmanifold_vertices)
        ctx_warn(ctx,
                 "%zu non-manifold vert%s (on such edges, or where faces meet in several fans) "
                 "kept: pinned (or a crease along a fin), as in OpenSubdiv",
                 r->nonmanifold_vertices, r->nonmanifold_vertices == 1 ? "ex" : "ices");
    if (r->inconsistent_edges)
        ctx_warn(ctx,
                 "%zu edge%s where two faces disagree on orientation kept (faces are not "
                 "re-oriented): %s sharp, as in OpenSubdiv",
                 r->inconsistent_edges, r->inconsistent_edges == 1 ? "" : "s",
                 r->inconsistent_edges == 1 ? "it is" : "they are");
    if (r->unreferenced_vertices)
        ctx_warn(ctx, "%zu vert%s used by no face kept: %s unchanged in the output",
                 r->unreferenced_vertices, r->unreferenced_vertices == 1 ? "ex" : "ices",
                 r->unreferenced_vertices == 1 ? "it stays" : "they stay");
}

/* The warning saying what repair_fix_repeats changed. */
void repair_warn_repeats(limn_context *ctx, const limn_repair_report *r, size_t faces_left)
{
    char parts[3][96];
    size_t np = 0;
    if (r->repeats_removed)
        snprintf(parts[np++], sizeof parts[0], "%zu lost a repeated corner",
                 r->repeats_removed);
    if (r->faces_split)
        snprintf(parts[np++], sizeof parts[0], "%zu %s split where a vertex comes back",
                 r->faces_split, r->faces_split == 1 ? "was" : "were");
    if (r->degenerate_removed)
        snprintf(parts[np++], sizeof parts[0],
                 "%zu with fewer than 3 distinct vertices %s removed", r->degenerate_removed,
                 r->degenerate_removed == 1 ? "was" : "were");
    ctx_warn(ctx,
              "repaired %zu face%s that use%s a vertex more than once (first: face %zu, "
              "vertex %u): %s%s%s%s%s; %zu faces remain (later messages number the faces "
              "of the repaired mesh)",
              r->repeat_faces, r->repeat_faces == 1 ? "" : "s",
              r->repeat_faces == 1 ? "s" : "", r->first_repeat_face, r->first_repeat_vertex,
              np > 0 ? parts[0] : "", np > 1 ? ", " : "", np > 1 ? parts[1] : "",
              np > 2 ? ", " : "", np > 2 ? parts[2] : "", faces_left);
}

/* Faces that use a vertex twice: refused when repair is off, else rebuilt. */
static limn_status repair_repeats(limn_context *ctx, limn_mesh *mesh, const limn_repair_options *o,
                                  limn_repair_report *r)
{
    size_t first = SIZE_MAX;
    uint32_t first_v = 0;
    limn_status st = face_first_repeat(ctx, mesh, &first, &first_v);
    if (st || first == SIZE_MAX)
        return st;
    if (!o->repeated_vertices)
        return ctx_fail(ctx, LIMN_ERR_TOPOLOGY,
                         "face %zu uses vertex %u twice (a degenerate face) and repair is off: "
                         "remove the face, or allow the repair (drop --no-repair)",
                         first, first_v);
    r->first_repeat_face = first;
    r->first_repeat_vertex = first_v;
    st = repair_fix_repeats(ctx, mesh, r);
    if (st)
        return st;
    repair_warn_repeats(ctx, r, mesh->face_count);
    return LIMN_OK;
}

/* Duplicate faces: found, removed when asked, and said. */
static limn_status repair_duplicates(limn_context *ctx, limn_mesh *mesh, int remove,
                                     limn_repair_report *r)
{
    limn_status st = find_duplicates(ctx, mesh, remove, r);
    if (st)
        return st;
    repair_warn_duplicates(ctx, r);
    return LIMN_OK;
}

/* The mesh's counts: from its topology, built and left on the mesh for the
   calls after the repair (topology_get) with keep_topology; else from a
   census. */
static limn_status count_mesh(limn_context *ctx, limn_mesh *mesh, int keep_topology,
                              topology_counts *k)
{
    if (!keep_topology)
        return topology_counts_get(ctx, mesh, k);
    topology t;
    limn_status st = topology_cache(ctx, mesh, &t);
    if (!st) {
        topology_counts_of(&t, k);
        topology_free(&t);
    }
    return st;
}

/* What stays as it is: counted into r, each with a warning. */
static void report_kept(limn_context *ctx, const limn_mesh *mesh, const topology_counts *k,
                        limn_repair_report *r)
{
    r->nonmanifold_edges = k->nonmanifold_edges - k->inconsistent_edges;
    r->nonmanifold_vertices = k->nonmanifold_vertices;
    r->inconsistent_edges = k->inconsistent_edges;
    r->unreferenced_vertices = mesh->vertex_count - k->referenced_vertices;
    r->components = k->components;
    r->boundary_loops = k->boundary_loops;
    repair_warn_kept(ctx, r);
}

/* Duplicate faces searched for unless the counts k rule them out (the
   search hashes every face; most closed scans need none), removed when
   asked (and k counted again). */
static limn_status repair_duplicates_counted(limn_context *ctx, limn_mesh *mesh,
                                             const limn_repair_options *o, topology_counts *k,
                                             limn_repair_report *r)
{
    if (topology_counts_no_duplicates(k))
        return LIMN_OK;
    limn_status st = repair_duplicates(ctx, mesh, o->duplicate_faces, r);
    if (!st && r->duplicates_removed)
        st = count_mesh(ctx, mesh, o->keep_topology, k); /* the faces changed */
    return st;
}

/* limn_mesh_repair on options and report of this library's layout, both never NULL. */
static limn_status repair_sized(limn_context *ctx, limn_mesh *mesh,
                                const limn_repair_options *options, limn_repair_report *report)
{
    limn_status begun = abi_begin(ctx, "limn_mesh_repair", "mesh", mesh);
    if (begun)
        return begun;
    const limn_repair_options *o = options; /* never NULL: abi_enter's copies */
    limn_repair_report *r = report;
    memset(r, 0, sizeof *r);
    r->first_duplicate_face = SIZE_MAX;
    r->faces_before = mesh->face_count;
    limn_status st = check_face_indices(ctx, "limn_mesh_repair", mesh->face_indices,
                                        mesh->face_offsets[mesh->face_count],
                                        mesh->vertex_count);
    if (st)
        return st;
    st = repair_repeats(ctx, mesh, o, r);
    ctx_progress(ctx, "repair", 0.2);
    topology_counts k;
    if (!st)
        st = count_mesh(ctx, mesh, o->keep_topology, &k);
    if (!st)
        st = repair_duplicates_counted(ctx, mesh, o, &k, r);
    if (st)
        return st;
    ctx_progress(ctx, "repair", 1.0);
    r->faces_after = mesh->face_count;
    if (r->first_duplicate_face == SIZE_MAX)
        r->first_duplicate_face = 0;
    report_kept(ctx, mesh, &k, r);
    return LIMN_OK;
}

limn_status limn_mesh_repair(limn_context *ctx, limn_mesh *mesh, const limn_repair_options *options,
                             limn_repair_report *report)
{
    abi_call c;
    limn_status st = abi_enter(&c, ctx, "limn_mesh_repair", &abi_repair_options, options,
                               &abi_repair_report, report, NULL);
    return st ? st : abi_leave(&c, repair_sized(ctx, mesh, c.options, c.report));
}
