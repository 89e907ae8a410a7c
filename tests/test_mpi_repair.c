/* SPDX-License-Identifier: MIT */
/*
 * limn_mpi_mesh_repair against limn_mesh_repair, under mpirun with 2, 3 and
 * 5 ranks, on a file every rank reads its slice of: duplicate faces whose
 * copies lie far apart in the file (so on other ranks; turned, rotated,
 * copied twice), faces that use a vertex twice, a non-manifold fin, two
 * fans meeting at a vertex, a face turned over (inconsistent edges),
 * isolated vertices, several components, n-gons. With and without
 * duplicate_faces, and counted from the sub-meshes (the default) or by
 * exchanges (sub_meshes = 0): the repaired mesh written in parallel is the single
 * process's bytes, the report's counts and first faces are its numbers,
 * and the warnings are its words, said alike on every rank.
 */
#include "mpi_check.h"
#include "mpi_meshes.h"
#include "shell.h"
#include "support.h"

#include "limn_mpi.h"
#include "mpi/mpi_mesh.h"
#include "topology/face_keys.h"
#include "topology/topology.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

MPI_CHECK_STATE;
static char dir[256];

/* mesh with extra faces: copies of faces 3 (rotated), 40 (turned) and 7
   (twice), a face repeating a vertex, a second fan at vertex 0 and face 11
   turned over; 2 vertices more. */
static limn_mesh *troubled(limn_context *ctx, const limn_mesh *m)
{
    size_t nv = limn_mesh_vertex_count(m), nf = limn_mesh_face_count(m);
    const uint32_t *off = limn_mesh_face_offsets(m), *idx = limn_mesh_face_indices(m);
    size_t ni = off[nf];
    double *pos = malloc(3 * (nv + 2) * sizeof *pos);
    uint32_t *o = malloc((nf + 8) * sizeof *o), *x = malloc((ni + 40) * sizeof *x);
    memcpy(pos, limn_mesh_positions(m), 3 * nv * sizeof *pos);
    for (int k = 0; k < 6; k++)
        pos[3 * nv + (size_t)k] = k < 3 ? -7.0 - k : -9.0 + k;
    memcpy(o, off, (nf + 1) * sizeof *o);
    memcpy(x, idx, ni * sizeof *x);
    for (uint32_t i = off[11], j = off[12] - 1; i < j; i++, j--) { /* turned over */
        uint32_t t = x[i];
        x[i] = x[j];
        x[j] = t;
    }
    size_t at = ni, f = nf;
    const size_t copies[4] = {3, 40, 7, 7};
    for (int c = 0; c < 4; c++) {
        uint32_t b = off[copies[c]], d = off[copies[c] + 1] - b;
        for (uint32_t k = 0; k < d; k++)
            x[at + k] = c == 0   ? idx[b + (k + 1) % d]
                        : c == 1 ? idx[b + d - 1 - k]
                                 : idx[b + k];
        at += d;
        o[++f] = (uint32_t)at;
    }
    const uint32_t rep[4] = {20, 20, 21, 52}; /* a vertex twice */
    memcpy(x + at, rep, sizeof rep);
    at += 4;
    o[++f] = (uint32_t)at;
    const uint32_t fan[3] = {0, (uint32_t)nv, (uint32_t)nv + 1}; /* a second fan at 0 */
    memcpy(x + at, fan, sizeof fan);
    at += 3;
    o[++f] = (uint32_t)at;
    limn_mesh *t = NULL;
    limn_mesh_create(ctx, nv + 2, pos, f, o, x, &t);
    free(pos);
    free(o);
    free(x);
    return t;
}

/* mesh and, beside it, a ring of six quads one quad wide with quad 0 copied
   in another order (0, 1, 3, 2): the copies share only the ring's boundary
   edges, so only the orientation at two vertices shows the copy (the
   distributed repair must not skip its search: mpi_local_census.c). */
static limn_mesh *with_ring_copy(limn_context *ctx, const limn_mesh *m)
{
    size_t nv = limn_mesh_vertex_count(m), nf = limn_mesh_face_count(m);
    const uint32_t *off = limn_mesh_face_offsets(m);
    size_t ni = off[nf];
    double *pos = malloc(3 * (nv + 12) * sizeof *pos);
    uint32_t *o = malloc((nf + 8) * sizeof *o), *x = malloc((ni + 28) * sizeof *x);
    memcpy(pos, limn_mesh_positions(m), 3 * nv * sizeof *pos);
    memcpy(o, off, (nf + 1) * sizeof *o);
    memcpy(x, limn_mesh_face_indices(m), ni * sizeof *x);
    uint32_t b = (uint32_t)nv;
    for (uint32_t k = 0; k < 6; k++) {
        double a = k * 3.14159265358979323846 / 3.0;
        for (uint32_t up = 0; up < 2; up++) {
            double *q = pos + 3 * (nv + k + 6 * up);
            q[0] = 40.0 + cos(a), q[1] = sin(a), q[2] = up;
        }
        uint32_t quad[4] = {b + k, b + (k + 1) % 6, b + 6 + (k + 1) % 6, b + 6 + k};
        memcpy(x + ni + 4 * k, quad, sizeof quad);
        o[nf + k + 1] = (uint32_t)(ni + 4 * k + 4);
    }
    uint32_t copy[4] = {b, b + 1, b + 6, b + 7}; /* quad 0 = (b, b+1, b+7, b+6) */
    memcpy(x + ni + 24, copy, sizeof copy);
    o[nf + 7] = (uint32_t)(ni + 28);
    limn_mesh *t = NULL;
    limn_mesh_create(ctx, nv + 12, pos, nf + 7, o, x, &t);
    free(pos);
    free(o);
    free(x);
    return t;
}

/* The counts and numbers both routes report (components and boundary loops
   are not counted over the ranks). */
static int same_report(const limn_repair_report *a, const limn_repair_report *b)
{
    return a->faces_before == b->faces_before && a->faces_after == b->faces_after &&
           a->repeat_faces == b->repeat_faces && a->repeats_removed == b->repeats_removed &&
           a->faces_split == b->faces_split && a->degenerate_removed == b->degenerate_removed &&
           a->first_repeat_face == b->first_repeat_face &&
           a->first_repeat_vertex == b->first_repeat_vertex &&
           a->duplicate_faces == b->duplicate_faces &&
           a->duplicates_removed == b->duplicates_removed &&
           a->first_duplicate_face == b->first_duplicate_face &&
           a->first_duplicate_of == b->first_duplicate_of &&
           a->nonmanifold_edges == b->nonmanifold_edges &&
           a->nonmanifold_vertices == b->nonmanifold_vertices &&
           a->inconsistent_edges == b->inconsistent_edges &&
           a->unreferenced_vertices == b->unreferenced_vertices;
}

/* mode 0: duplicates kept, the counts from the sub-meshes (the default);
   1: duplicates removed (by exchanges); 2: kept, counted by exchanges
   (limn_repair_options.sub_meshes = 0). search: 0 or 1, whether some rank
   must have searched for duplicates (the counts rule copies out, or not);
   -1 either. */
static void repair_case(limn_context *ctx, const char *name, const limn_mesh *mesh, int mode,
                        int search)
{
    int drop = mode == 1;
    char in[320], ref[320], out[320];
    snprintf(in, sizeof in, "%s/in.obj", dir);
    snprintf(ref, sizeof ref, "%s/ref.ply", dir);
    snprintf(out, sizeof out, "%s/out.ply", dir);
    limn_repair_options o;
    limn_repair_options_default(&o);
    o.duplicate_faces = drop;
    o.sub_meshes = mode != 2;
    limn_repair_report rs = {.size = sizeof rs}, rd = {.size = sizeof rd};
    mpi_mesh_counts counts; /* the single process's topology of its repaired mesh */
    memset(&counts, 0, sizeof counts);
    char warned[4096] = "";
    int ok = 1;
    if (rank == 0) {
        limn_mesh *m = NULL;
        ok = limn_mesh_write(ctx, mesh, in, LIMN_FORMAT_AUTO) == LIMN_OK &&
             limn_mesh_read(ctx, in, LIMN_FORMAT_AUTO, &m) == LIMN_OK &&
             limn_mesh_repair(ctx, m, &o, &rs) == LIMN_OK;
        snprintf(warned, sizeof warned, "%s", limn_context_warnings(ctx));
        ok = ok && limn_mesh_write(ctx, m, ref, LIMN_FORMAT_AUTO) == LIMN_OK;
        topology_counts tc;
        ok = ok && topology_counts_get(ctx, m, &tc) == LIMN_OK;
        if (ok)
            counts = (mpi_mesh_counts){tc.boundary_edges, tc.nonmanifold_edges,
                                       tc.inconsistent_edges, tc.nonmanifold_vertices,
                                       tc.referenced_vertices};
        CHECK(ok, "%s: single process: %s", name, limn_context_message(ctx));
        limn_mesh_destroy(m);
    }
    MPI_Bcast(&counts, (int)sizeof counts, MPI_BYTE, 0, MPI_COMM_WORLD);
    MPI_Bcast(&ok, 1, MPI_INT, 0, MPI_COMM_WORLD);
    MPI_Bcast(&rs, (int)sizeof rs, MPI_BYTE, 0, MPI_COMM_WORLD);
    MPI_Bcast(warned, sizeof warned, MPI_CHAR, 0, MPI_COMM_WORLD);
    limn_mpi_mesh *m = NULL;
    limn_status st =
        ok ? limn_mpi_mesh_read(ctx, MPI_COMM_WORLD, in, LIMN_FORMAT_AUTO, &m) : LIMN_ERR_IO;
    size_t searches = face_duplicate_search_count();
    if (!st)
        st = limn_mpi_mesh_repair(ctx, m, &o, &rd);
    int searched = face_duplicate_search_count() != searches;
    MPI_Allreduce(MPI_IN_PLACE, &searched, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    CHECK(search < 0 || searched == search, "%s (mode %d, %d ranks): duplicates %s", name, mode,
          size, searched ? "searched where the counts rule copies out" : "not searched");
    CHECK(!ok || st == LIMN_OK, "%s: limn_mpi_mesh_repair: %s", name, limn_context_message(ctx));
    if (ok && !st) {
        CHECK(same_report(&rs, &rd),
              "%s (mode %d, %d ranks): %zu duplicates (first %zu of %zu), %zu/%zu/%zu/%zu kept; "
              "one process %zu (first %zu of %zu), %zu/%zu/%zu/%zu",
              name, mode, size, rd.duplicate_faces, rd.first_duplicate_face,
              rd.first_duplicate_of, rd.nonmanifold_edges, rd.nonmanifold_vertices,
              rd.inconsistent_edges, rd.unreferenced_vertices, rs.duplicate_faces,
              rs.first_duplicate_face, rs.first_duplicate_of, rs.nonmanifold_edges,
              rs.nonmanifold_vertices, rs.inconsistent_edges, rs.unreferenced_vertices);
        /* the census the repair keeps for later calls (subdivide's estimate):
           boundary edges and used vertices too, which the report leaves out */
        const mpi_mesh_counts *k = &m->counts;
        CHECK(m->has_counts && k->boundary_edges == counts.boundary_edges &&
                  k->nonmanifold_edges == counts.nonmanifold_edges &&
                  k->inconsistent_edges == counts.inconsistent_edges &&
                  k->nonmanifold_vertices == counts.nonmanifold_vertices &&
                  k->referenced_vertices == counts.referenced_vertices,
              "%s (mode %d, %d ranks): counts %zu/%zu/%zu/%zu/%zu (boundary, non-manifold and "
              "inconsistent edges, non-manifold and used vertices), one process "
              "%zu/%zu/%zu/%zu/%zu",
              name, mode, size, k->boundary_edges, k->nonmanifold_edges, k->inconsistent_edges,
              k->nonmanifold_vertices, k->referenced_vertices, counts.boundary_edges,
              counts.nonmanifold_edges, counts.inconsistent_edges, counts.nonmanifold_vertices,
              counts.referenced_vertices);
        CHECK(strcmp(limn_context_warnings(ctx), warned) == 0,
              "%s (mode %d, %d ranks): warnings\n'%s'\none process\n'%s'", name, mode, size,
              limn_context_warnings(ctx), warned);
        if (rank == 0)
            printf("  %-22s mode %d: %zu repeats, %zu duplicates (first %zu of %zu), "
                   "%zu/%zu/%zu/%zu non-manifold edges/vertices, inconsistent, unused\n",
                   name, mode, rd.repeat_faces, rd.duplicate_faces, rd.first_duplicate_face,
                   rd.first_duplicate_of, rd.nonmanifold_edges, rd.nonmanifold_vertices,
                   rd.inconsistent_edges, rd.unreferenced_vertices);
        st = limn_mpi_mesh_write(ctx, m, out, LIMN_FORMAT_AUTO, NULL, NULL);
        CHECK(st == LIMN_OK, "%s: writing: %s", name, limn_context_message(ctx));
        if (rank == 0 && !st)
            CHECK(test_same_bytes(ref, out), "%s (mode %d, %d ranks): repaired mesh differs", name,
                  mode, size);
    }
    limn_mpi_mesh_destroy(m);
    MPI_Barrier(MPI_COMM_WORLD);
    if (rank == 0) {
        unlink(in);
        unlink(ref);
        unlink(out);
    }
}

int main(int argc, char **argv)
{
    MPI_Init(&argc, &argv);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    mpi_test_scratch_dir(dir, sizeof dir, "test_mpi_repair");
    limn_context *ctx = limn_context_create();
    limn_mesh *tri = mpi_test_composite(ctx, 1), *quad = mpi_test_composite(ctx, 0);
    limn_mesh *closed = mpi_test_closed(ctx, 0);
    limn_mesh *bad_tri = troubled(ctx, tri), *bad_quad = troubled(ctx, quad);
    limn_mesh *closed_tri = mpi_test_closed(ctx, 1), *ring = with_ring_copy(ctx, closed_tri);
    for (int mode = 0; mode <= 2; mode++) {
        repair_case(ctx, "composite tri", bad_tri, mode, mode == 0 ? 1 : -1);
        repair_case(ctx, "composite quad", bad_quad, mode, mode == 0 ? 1 : -1);
    }
    repair_case(ctx, "closed", closed, 0, 1); /* its prism's caps are n-gons: no skip */
    repair_case(ctx, "closed triangles", closed_tri, 0, 0);
    repair_case(ctx, "closed triangles + ring copy", ring, 0, 1);
    repair_case(ctx, "composite tri, clean", tri, 1, -1);
    limn_mesh_destroy(ring);
    limn_mesh_destroy(closed_tri);
    limn_mesh_destroy(tri);
    limn_mesh_destroy(quad);
    limn_mesh_destroy(closed);
    limn_mesh_destroy(bad_tri);
    limn_mesh_destroy(bad_quad);
    limn_context_destroy(ctx);
    return mpi_check_finish("test_mpi_repair", dir, checks, failures);
}
