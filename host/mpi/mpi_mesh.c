/* SPDX-License-Identifier: MIT */
/*
 * limn_mpi_mesh: reading every rank's slice of one file (or its own file of
 * a split input), making one from the caller's arrays, the accessors, and
 * the checks the distributed calls share (bbox, magnitude, scheme).
 */
#include "mpi/mpi_mesh.h"
#include "base/large_alloc.h"

#include "base/context.h"
#include "mesh/check.h"
#include "mpi/mpi_blocks.h"
#include "mpi/mpi_local.h"

#include <limits.h>
#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <unistd.h>
#include <string.h>

limn_status mpi_mesh_part(limn_context *ctx, const limn_mpi_mesh *mesh,
                          const limn_mpi_options *mpi, mpi_part *p)
{
    if (!mesh) {
        /* nothing to agree over: a NULL handle on one rank only is the caller's bug */
        memset(p, 0, sizeof *p);
        p->comm = MPI_COMM_NULL;
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "the distributed mesh is NULL");
    }
    return mpi_part_begin(ctx, mesh->comm, mpi, p);
}

struct mpi_local_mesh *mpi_mesh_take_sub(const limn_mpi_mesh *mesh)
{
    return atomic_exchange(&((limn_mpi_mesh *)mesh)->sub, NULL);
}

void mpi_mesh_drop_sub(const limn_mpi_mesh *mesh)
{
    mpi_local_mesh *lm = mesh ? mpi_mesh_take_sub(mesh) : NULL;
    mpi_local_mesh_free(lm);
    free(lm);
}

static void mesh_free(limn_mpi_mesh *m)
{
    if (!m)
        return;
    mpi_mesh_drop_sub(m);
    mesh_slice_free(&m->slice);
    free(m->colors);
    free(m->vertex_dist);
    free(m->face_dist);
    if (m->comm != MPI_COMM_NULL)
        MPI_Comm_free(&m->comm);
    free(m);
}

void limn_mpi_mesh_destroy(limn_mpi_mesh *mesh) { mesh_free(mesh); }

/* The largest of v[0 .. n), 0 when n is 0: four maxima side by side, as one
   chain of compares waits on the last (a cycle or two an element). */
static uint32_t largest_index(const uint32_t *v, size_t n)
{
    uint32_t m[4] = {0, 0, 0, 0};
    size_t i = 0;
    for (; i + 4 <= n; i += 4)
        for (int k = 0; k < 4; k++)
            m[k] = v[i + k] > m[k] ? v[i + k] : m[k];
    for (; i < n; i++)
        m[0] = v[i] > m[0] ? v[i] : m[0];
    m[0] = m[1] > m[0] ? m[1] : m[0];
    m[2] = m[3] > m[2] ? m[3] : m[2];
    return m[2] > m[0] ? m[2] : m[0];
}

/* Blocks in rank order without gaps: rank r's slice begins where r - 1's ends. */
static limn_status check_blocks(mpi_part *p, const limn_mpi_mesh *m)
{
    const mesh_slice *s = &m->slice;
    if (m->vertex_dist[p->rank] != s->vertex_begin || m->face_dist[p->rank] != s->face_begin)
        return ctx_fail(p->ctx, LIMN_ERR_ARGUMENT,
                         "rank %d: its blocks begin at vertex %zu and face %zu, but the ranks "
                         "before it end at vertex %zu and face %zu",
                         p->rank, s->vertex_begin, s->face_begin, m->vertex_dist[p->rank],
                         m->face_dist[p->rank]);
    size_t nv = m->vertex_dist[p->size];
    if (nv > UINT32_MAX)
        return ctx_fail(p->ctx, LIMN_ERR_ARGUMENT,
                         "the mesh has %zu vertices: more than 32-bit indices hold", nv);
    if (s->face_count == 0)
        return LIMN_OK;
    /* the largest index over the corners in one flat pass (the walk face by
       face took 2.6 ns a corner, ~55 ms a rank at 8.6M vertices), the face
       only when one is out of range */
    if (largest_index(s->face_indices + s->face_offsets[0],
                      s->face_offsets[s->face_count] - s->face_offsets[0]) < nv)
        return LIMN_OK;
    for (size_t f = 0; f < s->face_count; f++)
        for (uint32_t c = s->face_offsets[f]; c < s->face_offsets[f + 1]; c++)
            if (s->face_indices[c] >= nv)
                return ctx_fail(p->ctx, LIMN_ERR_ARGUMENT,
                                 "face %zu uses vertex %u but the mesh has %zu vertices",
                                 s->face_begin + f, s->face_indices[c], nv);
    return LIMN_OK;
}

limn_status mpi_mesh_adopt(mpi_part *p, mesh_slice *slice, limn_mpi_mesh **out)
{
    limn_mpi_mesh *m = calloc(1, sizeof *m);
    limn_status st = LIMN_OK;
    if (m) {
        m->comm = MPI_COMM_NULL;
        m->vertex_dist = large_malloc(((size_t)p->size + 1) * sizeof *m->vertex_dist);
        m->face_dist = large_malloc(((size_t)p->size + 1) * sizeof *m->face_dist);
    }
    if (!m || !m->vertex_dist || !m->face_dist)
        st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for a distributed mesh");
    st = mpi_agree(p, st);
    if (!st) {
        m->slice = *slice;
        memset(slice, 0, sizeof *slice);
        MPI_Comm_dup(p->comm, &m->comm);
        m->rank = p->rank;
        m->size = p->size;
        mpi_blocks_dist(p, m->slice.vertex_count, m->vertex_dist);
        mpi_blocks_dist(p, m->slice.face_count, m->face_dist);
        m->slice.vertex_total = m->vertex_dist[p->size];
        m->slice.face_total = m->face_dist[p->size];
        st = mpi_agree(p, check_blocks(p, m));
    }
    if (st) {
        mesh_free(m);
        return st;
    }
    *out = m;
    return LIMN_OK;
}

/* The counts of the ranks before this one and of all (phase 2 of mesh_slice.h). */
static void slice_sums(mpi_part *p, const mesh_slice_counts *mine, mesh_slice_counts *before,
                       mesh_slice_counts *total)
{
    _Static_assert(sizeof(mesh_slice_counts) == MESH_SLICE_COUNT_FIELDS * sizeof(uint64_t),
                   "counts are uint64_t fields");
    memset(before, 0, sizeof *before);
    MPI_Exscan(mine, before, MESH_SLICE_COUNT_FIELDS, MPI_UINT64_T, MPI_SUM, p->comm);
    if (p->rank == 0)
        memset(before, 0, sizeof *before); /* Exscan leaves rank 0's undefined */
    MPI_Allreduce(mine, total, MESH_SLICE_COUNT_FIELDS, MPI_UINT64_T, MPI_SUM, p->comm);
}

limn_status limn_mpi_mesh_read(limn_context *ctx, MPI_Comm comm, const char *path,
                               limn_format format, limn_mpi_mesh **out)
{
    mpi_part p;
    limn_status st = mpi_part_begin(ctx, comm, NULL, &p);
    if (!st && (!path || !out))
        st = ctx_fail(ctx, LIMN_ERR_ARGUMENT, "limn_mpi_mesh_read: %s is NULL",
                       path ? "out" : "path");
    st = p.comm == MPI_COMM_NULL ? st : mpi_agree(&p, st);
    mesh_slice_counts mine = {0}, before, total;
    if (!st)
        st = mpi_agree(&p, mesh_slice_count(ctx, path, format, (unsigned)p.rank,
                                            (unsigned)p.size, &mine));
    mesh_slice s = {0};
    if (!st) {
        ctx_clear(ctx); /* the read phase says the header's warnings again: once is enough */
        slice_sums(&p, &mine, &before, &total);
        st = mpi_agree(&p, mesh_slice_read(ctx, path, format, (unsigned)p.rank,
                                           (unsigned)p.size, &before, &total, &s));
    }
    if (!st)
        st = mpi_mesh_adopt(&p, &s, out);
    mesh_slice_free(&s);
    mpi_part_end(&p);
    return st;
}

limn_status limn_mpi_mesh_read_split(limn_context *ctx, MPI_Comm comm, const char *name,
                                     limn_mpi_mesh **out)
{
    mpi_part p;
    limn_status st = mpi_part_begin(ctx, comm, NULL, &p);
    if (!st && (!name || !out))
        st = ctx_fail(ctx, LIMN_ERR_ARGUMENT, "limn_mpi_mesh_read_split: %s is NULL",
                       name ? "out" : "name");
    st = p.comm == MPI_COMM_NULL ? st : mpi_agree(&p, st);
    mesh_slice s = {0};
    if (!st)
        st = mpi_agree(&p, mesh_slice_read_split(ctx, name, (unsigned)p.rank, (unsigned)p.size,
                                                 &s));
    if (!st)
        st = mpi_mesh_adopt(&p, &s, out);
    mesh_slice_free(&s);
    mpi_part_end(&p);
    return st;
}

limn_status limn_mpi_mesh_write_split(limn_context *ctx, const limn_mpi_mesh *mesh,
                                      const char *name)
{
    mpi_part p;
    limn_status st = mpi_mesh_part(ctx, mesh, NULL, &p);
    if (p.comm == MPI_COMM_NULL)
        return st;
    if (!st && !name)
        st = ctx_fail(ctx, LIMN_ERR_ARGUMENT, "limn_mpi_mesh_write_split: name is NULL");
    st = mpi_agree(&p, st);
    /* every part staged before any appears: a rank that fails leaves no part anywhere */
    atomic_file af;
    memset(&af, 0, sizeof af);
    if (!st)
        st = mpi_agree(&p, mesh_slice_stage_split(ctx, name, (unsigned)p.rank,
                                                  (unsigned)p.size, &mesh->slice, &af));
    if (!st) {
        limn_status mine = atomic_file_commit(ctx, &af);
        char path[4096];
        /* a rename that failed on another rank: no set of parts from two writes */
        if ((st = mpi_agree(&p, mine)) && !mine &&
            mesh_slice_split_name(name, (unsigned)p.rank, path, sizeof path))
            unlink(path);
    } else {
        atomic_file_abort(&af);
    }
    mpi_part_end(&p);
    return st;
}

/* A slice holding copies of the caller's arrays (global numbering unknown yet). */
static limn_status slice_copy(limn_context *ctx, size_t nv, const double *pos, size_t nf,
                              const uint32_t *off, const uint32_t *idx, mesh_slice *s)
{
    memset(s, 0, sizeof *s);
    if ((nv && !pos) || !off || (nf && off[nf] && !idx))
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "limn_mpi_mesh_create: an array is NULL");
    if (off[0] != 0)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                         "limn_mpi_mesh_create: face_offsets[0] is %u, not 0", off[0]);
    for (size_t f = 0; f < nf; f++)
        if (off[f + 1] < off[f] + 3)
            return ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                             "limn_mpi_mesh_create: this rank's face %zu has %d corners "
                             "(offsets %u, %u): a face needs at least 3",
                             f, (int)off[f + 1] - (int)off[f], off[f], off[f + 1]);
    size_t nc = off[nf];
    s->positions = large_malloc((nv ? 3 * nv : 1) * sizeof *s->positions);
    s->face_offsets = large_malloc((nf + 1) * sizeof *s->face_offsets);
    s->face_indices = large_malloc((nc ? nc : 1) * sizeof *s->face_indices);
    if (!s->positions || !s->face_offsets || !s->face_indices) {
        mesh_slice_free(s);
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for %zu vertices", nv);
    }
    if (nv)
        memcpy(s->positions, pos, 3 * nv * sizeof *pos);
    memcpy(s->face_offsets, off, (nf + 1) * sizeof *off);
    if (nc)
        memcpy(s->face_indices, idx, nc * sizeof *idx);
    s->vertex_count = nv;
    s->face_count = nf;
    return LIMN_OK;
}

limn_status limn_mpi_mesh_create(limn_context *ctx, MPI_Comm comm, size_t vertex_count,
                                 const double *positions, size_t face_count,
                                 const uint32_t *face_offsets, const uint32_t *face_indices,
                                 limn_mpi_mesh **out)
{
    mpi_part p;
    limn_status st = mpi_part_begin(ctx, comm, NULL, &p);
    if (p.comm == MPI_COMM_NULL)
        return st;
    mesh_slice s = {0};
    if (!st && !out)
        st = ctx_fail(ctx, LIMN_ERR_ARGUMENT, "limn_mpi_mesh_create: out is NULL");
    if (!st)
        st = slice_copy(ctx, vertex_count, positions, face_count, face_offsets, face_indices, &s);
    if (!st)
        st = check_positions(ctx, "limn_mpi_mesh_create", s.positions, s.vertex_count);
    st = mpi_agree(&p, st);
    if (!st) {
        /* the beginnings follow from the counts: what adopt checks holds */
        unsigned long long c[2] = {s.vertex_count, s.face_count}, b[2] = {0, 0};
        MPI_Exscan(c, b, 2, MPI_UNSIGNED_LONG_LONG, MPI_SUM, p.comm);
        s.vertex_begin = p.rank ? b[0] : 0;
        s.face_begin = p.rank ? b[1] : 0;
        st = mpi_mesh_adopt(&p, &s, out);
    }
    mesh_slice_free(&s);
    mpi_part_end(&p);
    return st;
}

size_t limn_mpi_mesh_vertex_begin(const limn_mpi_mesh *m) { return m ? m->slice.vertex_begin : 0; }
size_t limn_mpi_mesh_vertex_count(const limn_mpi_mesh *m) { return m ? m->slice.vertex_count : 0; }
size_t limn_mpi_mesh_vertex_total(const limn_mpi_mesh *m) { return m ? m->slice.vertex_total : 0; }
size_t limn_mpi_mesh_face_begin(const limn_mpi_mesh *m) { return m ? m->slice.face_begin : 0; }
size_t limn_mpi_mesh_face_count(const limn_mpi_mesh *m) { return m ? m->slice.face_count : 0; }
size_t limn_mpi_mesh_face_total(const limn_mpi_mesh *m) { return m ? m->slice.face_total : 0; }
const double *limn_mpi_mesh_positions(const limn_mpi_mesh *m)
{
    return m ? m->slice.positions : NULL;
}
const uint32_t *limn_mpi_mesh_face_offsets(const limn_mpi_mesh *m)
{
    return m ? m->slice.face_offsets : NULL;
}
const uint32_t *limn_mpi_mesh_face_indices(const limn_mpi_mesh *m)
{
    return m ? m->slice.face_indices : NULL;
}

/* ----------------------------------------------------------------- checks */

double mpi_mesh_bbox_diagonal(mpi_part *p, const limn_mpi_mesh *mesh)
{
    return mpi_local_diagonal(p, mesh->slice.positions, mesh->slice.vertex_count);
}

limn_status mpi_mesh_check(mpi_part *p, const char *fn, const limn_mpi_mesh *mesh)
{
    const mesh_slice *s = &mesh->slice;
    limn_status st = LIMN_OK;
    for (size_t i = 0; i < 3 * s->vertex_count && !st; i++)
        if (!isfinite(s->positions[i]))
            st = ctx_fail(p->ctx, LIMN_ERR_ARGUMENT,
                           "%s: vertex %zu has a non-finite coordinate (%c = %g); nothing was "
                           "computed or written",
                           fn, s->vertex_begin + i / 3, "xyz"[i % 3], s->positions[i]);
    st = mpi_agree(p, st);
    if (st)
        return st;
    /* the sum of squares in double-double: the same on every rank count */
    double sum = 0.0;
    for (size_t i = 0; i < 3 * s->vertex_count; i++)
        sum += s->positions[i] * s->positions[i];
    double total = mpi_sum(p, sum), diag = mpi_mesh_bbox_diagonal(p, mesh);
    if (total <= CHECK_SQUARES_MAX && diag * diag <= CHECK_SQUARES_MAX)
        return LIMN_OK;
    return ctx_fail(p->ctx, LIMN_ERR_ARGUMENT,
                     "%s: coordinates too large (overflow): the sum of squared coordinates "
                     "is %.3g and the squared bbox diagonal %.3g, over the %.3g that sums of "
                     "squares can hold here; scale the mesh down; nothing was computed",
                     fn, total, diag * diag, CHECK_SQUARES_MAX);
}

limn_status mpi_mesh_scheme(mpi_part *p, const limn_mpi_mesh *mesh, limn_scheme want,
                            limn_scheme *out)
{
    limn_status st = check_scheme(p->ctx, "limn_mpi_mesh_interpolate", want);
    st = mpi_agree(p, st);
    if (st)
        return st;
    const mesh_slice *s = &mesh->slice;
    unsigned long long first = ULLONG_MAX; /* the first face that is not a triangle */
    for (size_t f = 0; f < s->face_count; f++)
        if (s->face_offsets[f + 1] - s->face_offsets[f] != 3) {
            first = s->face_begin + f;
            break;
        }
    unsigned long long gfirst;
    MPI_Allreduce(&first, &gfirst, 1, MPI_UNSIGNED_LONG_LONG, MPI_MIN, p->comm);
    if (want == LIMN_SCHEME_AUTO)
        want = gfirst == ULLONG_MAX && s->face_total > 0 ? LIMN_SCHEME_LOOP : LIMN_SCHEME_CATMARK;
    if (want == LIMN_SCHEME_LOOP && gfirst != ULLONG_MAX) {
        int who = mpi_blocks_owner(mesh->face_dist, p->size, (size_t)gfirst);
        unsigned corners = 0;
        if (who == p->rank)
            corners = s->face_offsets[gfirst - s->face_begin + 1] -
                      s->face_offsets[gfirst - s->face_begin];
        MPI_Bcast(&corners, 1, MPI_UNSIGNED, who, p->comm);
        return ctx_fail(p->ctx, LIMN_ERR_TOPOLOGY,
                         "face %llu has %u vertices but Loop subdivision needs triangles only: "
                         "use --scheme catmark (or auto), or triangulate the mesh",
                         gfirst, corners);
    }
    *out = want;
    return LIMN_OK;
}
