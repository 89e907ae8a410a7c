/* SPDX-License-Identifier: MIT */
/*
 * limn_mpi_mesh_repair: the repair of limn_mesh_repair on every rank's face
 * block. A face that uses a vertex twice is repaired from its own corners
 * alone (mesh_repair.c), so each rank repairs its block as the single
 * process repairs those faces, in the same order; the blocks are then
 * renumbered and the counts reduced. Duplicate faces are found across the
 * ranks as the single process finds them, and what stays as it is counted
 * and said as it says it: by default from the sub-meshes of the curve
 * partition (mpi_local_census.c), which stay on the mesh for the rows built
 * next, as the single process's repair leaves its topology for the
 * operator; when duplicates are to be removed (the face blocks change) by
 * the exchanges of mpi_mesh_duplicates.c and mpi_mesh_census.c.
 */
#include "mpi/mpi_mesh.h"
#include "base/large_alloc.h"

#include "base/abi.h"
#include "base/context.h"
#include "mesh/mesh.h"
#include "mpi/mpi_blocks.h"
#include "mpi/mpi_local.h"
#include "mpi/mpi_sfc.h"
#include "topology/face_keys.h"
#include "topology/mesh_repair.h"

#include <limits.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

static int cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return x < y ? -1 : x > y;
}

/* The block's faces as a mesh of its own vertices (ids[k]: global id of
   local vertex k, sorted), positions left unset: the repair reads faces only. */
static limn_status local_mesh(limn_context *ctx, const mesh_slice *s, uint32_t **ids_out,
                              limn_mesh **out)
{
    size_t nc = s->face_offsets[s->face_count], nu = 0;
    uint32_t *ids = large_malloc((nc ? nc : 1) * sizeof *ids);
    if (!ids)
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory repairing %zu faces", s->face_count);
    memcpy(ids, s->face_indices, nc * sizeof *ids);
    qsort(ids, nc, sizeof *ids, cmp_u32);
    for (size_t c = 0; c < nc; c++)
        if (nu == 0 || ids[nu - 1] != ids[c])
            ids[nu++] = ids[c];
    limn_mesh *m = NULL;
    limn_status st = mesh_alloc(ctx, nu, s->face_count, nc, &m);
    if (st) {
        free(ids);
        return st;
    }
    memcpy(m->face_offsets, s->face_offsets, (s->face_count + 1) * sizeof *m->face_offsets);
    for (size_t c = 0; c < nc; c++) {
        const uint32_t *at = bsearch(&s->face_indices[c], ids, nu, sizeof *ids, cmp_u32);
        m->face_indices[c] = (uint32_t)(at - ids);
    }
    *ids_out = ids;
    *out = m;
    return LIMN_OK;
}

/* Moves m's repaired faces into the slice, vertices renamed back to global ids. */
static void take_faces(mesh_slice *s, limn_mesh *m, const uint32_t *ids)
{
    size_t nf = m->face_count, nc = m->face_offsets[nf];
    free(s->face_offsets);
    free(s->face_indices);
    s->face_offsets = m->face_offsets;
    s->face_indices = m->face_indices;
    s->face_count = nf;
    for (size_t c = 0; c < nc; c++)
        s->face_indices[c] = ids[s->face_indices[c]];
    m->face_offsets = NULL;
    m->face_indices = NULL;
    m->face_count = 0;
}

/* Repairs this rank's block in place (when allowed): r gets its counts and
   the block's first repeat (global face and vertex; SIZE_MAX when none).
   The repeats are looked for on the block's own arrays (a face is judged
   by its corners alone); only a block with one builds its local mesh. */
static limn_status repair_block(limn_context *ctx, mesh_slice *s, int allowed,
                                limn_repair_report *r)
{
    limn_mesh view = {.vertex_count = s->vertex_total,
                      .face_count = s->face_count,
                      .face_offsets = s->face_offsets,
                      .face_indices = s->face_indices};
    size_t first = SIZE_MAX;
    uint32_t first_v = 0;
    limn_status st = face_first_repeat(ctx, &view, &first, &first_v);
    r->first_repeat_face = SIZE_MAX;
    if (st || first == SIZE_MAX)
        return st;
    r->first_repeat_face = s->face_begin + first;
    r->first_repeat_vertex = first_v; /* a global id: the view's numbering */
    if (!allowed)
        return LIMN_OK;
    uint32_t *ids = NULL;
    limn_mesh *m = NULL;
    st = local_mesh(ctx, s, &ids, &m);
    if (!st)
        st = repair_fix_repeats(ctx, m, r);
    if (!st)
        take_faces(s, m, ids);
    limn_mesh_destroy(m);
    free(ids);
    return st;
}

/* The counts of every rank summed, the first repeat the lowest face's;
   returns whether any rank found one. */
static int reduce_report(mpi_part *p, limn_repair_report *r)
{
    unsigned long long c[4] = {r->repeat_faces, r->repeats_removed, r->faces_split,
                               r->degenerate_removed},
                       g[4];
    MPI_Allreduce(c, g, 4, MPI_UNSIGNED_LONG_LONG, MPI_SUM, p->comm);
    r->repeat_faces = g[0];
    r->repeats_removed = g[1];
    r->faces_split = g[2];
    r->degenerate_removed = g[3];
    unsigned long long f = r->first_repeat_face == SIZE_MAX ? ULLONG_MAX : r->first_repeat_face,
                       gf;
    MPI_Allreduce(&f, &gf, 1, MPI_UNSIGNED_LONG_LONG, MPI_MIN, p->comm);
    int who = p->size, me = gf != ULLONG_MAX && f == gf ? p->rank : p->size;
    MPI_Allreduce(&me, &who, 1, MPI_INT, MPI_MIN, p->comm);
    unsigned v = r->first_repeat_vertex;
    if (who < p->size)
        MPI_Bcast(&v, 1, MPI_UNSIGNED, who, p->comm);
    r->first_repeat_face = gf == ULLONG_MAX ? 0 : (size_t)gf;
    r->first_repeat_vertex = v;
    return gf != ULLONG_MAX;
}

/* mesh_repair.c's report_kept: what stays as it is (the counts k over the
   ranks) said in the same words. components and boundary_loops stay 0:
   they need a walk over the whole mesh. */
static void report_kept(mpi_part *p, const limn_mpi_mesh *mesh, const mpi_mesh_counts *k,
                        limn_repair_report *r)
{
    r->nonmanifold_edges = k->nonmanifold_edges - k->inconsistent_edges;
    r->nonmanifold_vertices = k->nonmanifold_vertices;
    r->inconsistent_edges = k->inconsistent_edges;
    r->unreferenced_vertices = mesh->vertex_dist[p->size] - k->referenced_vertices;
    repair_warn_kept(p->ctx, r);
}

/* The duplicates and the counts from the sub-meshes of the curve partition
   (mpi_local_census), which stay on the mesh for the next rows. */
static limn_status census_by_sub(mpi_part *p, limn_mpi_mesh *mesh, mpi_mesh_counts *k,
                                 limn_repair_report *r)
{
    const mesh_slice *s = &mesh->slice;
    uint32_t *part_of = NULL;
    mpi_local_mesh *lm = calloc(1, sizeof *lm);
    limn_status st = lm ? LIMN_OK : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory");
    st = mpi_agree(p, st);
    if (!st)
        st = mpi_sfc_partition(p, mesh->vertex_dist, s->positions, p->size, &part_of, NULL);
    if (!st)
        st = mpi_local_mesh_build(p, mesh->vertex_dist, s->positions, part_of, s->face_begin,
                                  s->face_count, s->face_offsets, s->face_indices, NULL, 1, lm,
                                  NULL);
    free(part_of);
    if (!st)
        st = mpi_local_census(p, lm, k, r);
    if (!st) {
        atomic_store(&mesh->sub, lm);
        return LIMN_OK;
    }
    mpi_local_mesh_free(lm);
    free(lm);
    return st;
}

/* Duplicates (found, removed when asked) and the counts by the exchanges of
   mpi_mesh_duplicates.c and mpi_mesh_census.c: the faces' blocks change. */
static limn_status census_by_exchange(mpi_part *p, limn_mpi_mesh *mesh, int remove,
                                      mpi_mesh_counts *k, limn_repair_report *r)
{
    limn_status st = mpi_mesh_duplicates(p, mesh, remove, r);
    return st ? st : mpi_mesh_census(p, mesh, k);
}

/* The whole repair on structs of this library's layout (c from abi_enter). */
static limn_status repair_sized(mpi_part *p, limn_mpi_mesh *mesh, const limn_repair_options *o,
                                limn_repair_report *r)
{
    memset(r, 0, sizeof *r);
    mpi_mesh_drop_sub(mesh); /* made from faces this repair may change */
    mesh->has_counts = 0;
    r->faces_before = mesh->slice.face_total;
    limn_status st = repair_block(p->ctx, &mesh->slice, o->repeated_vertices, r);
    st = mpi_agree(p, st);
    if (st)
        return st;
    int found = reduce_report(p, r);
    if (found && !o->repeated_vertices)
        return ctx_fail(p->ctx, LIMN_ERR_TOPOLOGY,
                         "face %zu uses vertex %u twice (a degenerate face) and repair is off: "
                         "remove the face, or allow the repair (drop --no-repair)",
                         r->first_repeat_face, r->first_repeat_vertex);
    if (r->repeat_faces) {
        /* new face blocks: the counts changed, the order did not */
        unsigned long long c = mesh->slice.face_count, b = 0;
        MPI_Exscan(&c, &b, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, p->comm);
        mesh->slice.face_begin = p->rank ? (size_t)b : 0;
        mpi_blocks_dist(p, mesh->slice.face_count, mesh->face_dist);
        mesh->slice.face_total = mesh->face_dist[p->size];
        repair_warn_repeats(p->ctx, r, mesh->slice.face_total);
    }
    mpi_mesh_counts k;
    /* the sub-meshes are the curve's: under PT-Scotch (LIMN_MPI_PARTITION)
       the rows will not come from them */
    st = o->duplicate_faces || !o->sub_meshes || p->partition == LIMN_MPI_PARTITION_SCOTCH
             ? census_by_exchange(p, mesh, o->duplicate_faces, &k, r)
             : census_by_sub(p, mesh, &k, r);
    if (st)
        return st;
    repair_warn_duplicates(p->ctx, r);
    r->faces_after = mesh->slice.face_total;
    if (r->first_duplicate_face == SIZE_MAX)
        r->first_duplicate_face = 0;
    report_kept(p, mesh, &k, r);
    mesh->counts = k;
    mesh->has_counts = 1;
    return LIMN_OK;
}

limn_status limn_mpi_mesh_repair(limn_context *ctx, limn_mpi_mesh *mesh,
                                 const limn_repair_options *options, limn_repair_report *report)
{
    mpi_part p;
    limn_status st = mpi_mesh_part(ctx, mesh, NULL, &p);
    if (p.comm == MPI_COMM_NULL)
        return st;
    abi_call c;
    if (!st)
        st = abi_enter(&c, ctx, "limn_mpi_mesh_repair", &abi_repair_options, options,
                       &abi_repair_report, report, NULL);
    int entered = !st;
    st = mpi_agree(&p, st);
    if (!st)
        st = repair_sized(&p, mesh, c.options, c.report);
    if (entered)
        st = abi_leave(&c, st);
    mpi_part_end(&p);
    return st;
}
