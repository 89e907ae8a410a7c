/* SPDX-License-Identifier: MIT */
/*
 * limn_mpi_mesh_repair's census and duplicate search from the sub-meshes
 * (mpi_local.h "mpi_local_census"), with no exchange of their own: a rank's
 * sub-mesh holds every face at its owned vertices, so the ring of an owned
 * vertex, the faces of an edge at one and every copy of a face using one
 * (copies share all their vertices) are whole there. Each is counted by the
 * rank owning its lowest vertex: the sub-mesh numbers its vertices by
 * increasing global id, so that is the lowest local one. The topology the
 * counts come from stays on the sub-mesh for its operator (topology_cache).
 */
#include "mpi/mpi_local.h"
#include "mpi/mpi_mesh.h"

#include "base/context.h"
#include "mesh/mesh.h"
#include "topology/face_keys.h"
#include "topology/topology.h"

#include <limits.h>
#include <stdlib.h>
#include <string.h>

/* The topology's counts restricted to what this rank owns: owned vertices,
   and edges whose lower vertex is owned. k: as mpi_mesh_census's. An edge
   with a flag counted here (boundary; non-manifold; inconsistent, always
   non-manifold too) flags both its vertices, VERTEX_BOUNDARY or
   VERTEX_NONMANIFOLD (topology_rings.c: each end's ring sees the edge's
   faces alike), so only the edges of flagged owned vertices are read, not
   every edge of the sub-mesh. */
static void count_owned(const topology *t, const local_sub *s, uint64_t k[5])
{
    for (size_t i = 0; i < s->n_owned; i++) {
        uint32_t v = s->owned[i];
        uint8_t flags = t->vertex_flags[v];
        k[3] += (flags & VERTEX_NONMANIFOLD) != 0;
        k[4] += t->vertex_corner_offsets[v + 1] > t->vertex_corner_offsets[v];
        if (!(flags & (VERTEX_BOUNDARY | VERTEX_NONMANIFOLD)))
            continue;
        for (uint32_t j = t->vertex_edge_offsets[v]; j < t->vertex_edge_offsets[v + 1]; j++) {
            uint32_t e = t->vertex_edges[j];
            if (t->edge_vertices[2 * (size_t)e] != v)
                continue; /* its lower vertex counts it */
            uint8_t f = t->edge_flags[e];
            k[0] += (f & EDGE_BOUNDARY) != 0;
            k[1] += (f & EDGE_NONMANIFOLD) != 0;
            k[2] += (f & EDGE_INCONSISTENT) != 0;
        }
    }
}

/* Whether this rank's part rules copies of faces out, as
   topology_counts_no_duplicates does for a whole mesh (topology.h has the
   proof), checked where the sub-mesh holds every face: every face a triangle
   or a quad, every owned vertex one fan with 3 neighbours or more (or
   unused), no edge at one used more than twice. Two faces on one vertex set
   have a vertex some rank owns, and the proof's conditions fail at it (a
   vertex on no non-manifold edge: both faces' corners there close fans of
   their own, or it has 2 neighbours, or an edge used twice the same way ends
   two fans), so when every rank says yes there are none. */
static int owned_rule_out_copies(const topology *t, const local_sub *s)
{
    if (t->other_faces)
        return 0;
    /* a vertex on a non-manifold edge is itself VERTEX_NONMANIFOLD (as in
       count_owned): its flag says it, no walk over its edges */
    for (size_t i = 0; i < s->n_owned; i++) {
        uint32_t v = s->owned[i], b = t->vertex_edge_offsets[v], e = t->vertex_edge_offsets[v + 1];
        if (t->vertex_flags[v] & VERTEX_NONMANIFOLD ||
            (e - b < 3 && t->vertex_corner_offsets[v + 1] > t->vertex_corner_offsets[v]))
            return 0;
    }
    return 1;
}

/* The lowest (local) vertex of face f. */
static uint32_t face_lowest(const limn_mesh *m, size_t f)
{
    uint32_t lo = UINT32_MAX;
    for (uint32_t c = m->face_offsets[f]; c < m->face_offsets[f + 1]; c++)
        lo = m->face_indices[c] < lo ? m->face_indices[c] : lo;
    return lo;
}

/* This rank's duplicates: count (faces judged here), and the lowest
   duplicate face of the sub-mesh with the face it copies (global ids;
   ULLONG_MAX when none): any rank holding a copy sees the whole set. */
static limn_status local_duplicates(limn_context *ctx, const mpi_local_mesh *lm, uint32_t me,
                                    unsigned long long d[3])
{
    const limn_mesh *m = lm->mesh;
    d[0] = 0;
    d[1] = d[2] = ULLONG_MAX;
    uint8_t *dup = NULL;
    face_duplicates found;
    limn_status st = face_duplicates_marked(ctx, m, &dup, &found);
    if (!st && found.count) {
        d[1] = lm->face_ids[found.first];
        d[2] = lm->face_ids[found.first_of];
        for (size_t f = 0; f < m->face_count; f++)
            d[0] += dup[f] && lm->s.part[face_lowest(m, f)] == me;
    }
    free(dup);
    return st;
}

limn_status mpi_local_census(mpi_part *p, mpi_local_mesh *lm, mpi_mesh_counts *out,
                             limn_repair_report *r)
{
    memset(out, 0, sizeof *out);
    uint64_t k[5] = {0, 0, 0, 0, 0};
    unsigned long long d[3] = {0, ULLONG_MAX, ULLONG_MAX};
    limn_status st = lm->face_ids ? LIMN_OK
                                  : ctx_fail(p->ctx, LIMN_ERR_ARGUMENT,
                                             "mpi_local_census: the sub-mesh lacks face ids");
    int no_copies = 1; /* a rank owning nothing rules nothing in */
    if (!st && lm->s.n) {
        topology t;
        st = topology_cache(p->ctx, lm->mesh, &t);
        if (!st) {
            count_owned(&t, &lm->s, k);
            no_copies = owned_rule_out_copies(&t, &lm->s);
            topology_free(&t); /* back to the sub-mesh, for the operator */
        }
    }
    st = mpi_agree(p, st);
    if (st)
        return st;
    /* the search only where some rank's counts leave room for a copy (as the
       single process's repair skips it: mesh_repair.c) */
    MPI_Allreduce(MPI_IN_PLACE, &no_copies, 1, MPI_INT, MPI_MIN, p->comm);
    if (!no_copies && lm->s.n)
        st = local_duplicates(p->ctx, lm, (uint32_t)p->rank, d);
    st = mpi_agree(p, st);
    if (st)
        return st;
    MPI_Allreduce(MPI_IN_PLACE, k, 5, MPI_UINT64_T, MPI_SUM, p->comm);
    unsigned long long first = d[1], of = d[2];
    MPI_Allreduce(MPI_IN_PLACE, &d[0], 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, p->comm);
    MPI_Allreduce(MPI_IN_PLACE, &first, 1, MPI_UNSIGNED_LONG_LONG, MPI_MIN, p->comm);
    if (d[1] != first) /* every rank holding that face names the same original */
        of = ULLONG_MAX;
    MPI_Allreduce(MPI_IN_PLACE, &of, 1, MPI_UNSIGNED_LONG_LONG, MPI_MIN, p->comm);
    out->boundary_edges = (size_t)k[0];
    out->nonmanifold_edges = (size_t)k[1];
    out->inconsistent_edges = (size_t)k[2];
    out->nonmanifold_vertices = (size_t)k[3];
    out->referenced_vertices = (size_t)k[4];
    r->duplicate_faces = (size_t)d[0];
    r->first_duplicate_face = first == ULLONG_MAX ? SIZE_MAX : (size_t)first;
    r->first_duplicate_of = first == ULLONG_MAX ? 0 : (size_t)of;
    return LIMN_OK;
}
