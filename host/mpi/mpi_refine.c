/* SPDX-License-Identifier: MIT */
/*
 * One refinement step over ranks (mpi_refine.h): each rank refines its star
 * with refine/'s plan (the single process's step rows, here for the patch),
 * keeps the vertex points of its own vertices, the face points of its face
 * block and the edge points of the edges whose lower vertex it owns, and
 * numbers them as one process does: old vertices keep their ids, the face
 * point of face f is nv + f (Catmull-Clark), the edge points follow in edge
 * order. topology.c numbers the edges by (lower vertex, upper vertex), a
 * function of the vertex ids alone, so the edges of the lower vertices of one
 * segment are one range: in a split segment a rank's run starts after the
 * earlier ranks' (an Allgather of the counts), in a directory segment each
 * vertex's first edge id is a prefix sum of the counts in the directory's
 * blocks (a store, an Exscan, a fetch). The child faces of the face block
 * take the ids of their edges' points from the ranks that own them (one
 * request and one answer exchange). Each rank keeps what it computed.
 */
#include "mpi/mpi_refine.h"
#include "base/large_alloc.h"

#include "base/context.h"
#include "mesh/mesh.h"
#include "mpi/mpi_blocks.h"
#include "mpi/mpi_local.h"
#include "refine/refine.h"
#include "topology/topology.h"

#include <stdlib.h>
#include <string.h>

/* A level's work on this rank. */
typedef struct level {
    mpi_part *p;
    mpi_rmesh *in;
    limn_scheme scheme;
    mpi_star star;
    refine_plan plan;
    topology topo;
    int have_plan, have_topo;
    uint32_t *edge_id;     /* global id of each patch edge's point (UINT32_MAX: unknown) */
    size_t nv, nf;         /* the whole level's vertices and faces */
    size_t n_new, new_total, owned_edges;
    mpi_rseg *edge_seg;    /* in->segments: the edge points' segments */
    uint32_t *next_id;     /* per owned vertex: the id of its next edge's point */
    double *new_xyz;       /* this rank's new vertices: its old ones, face points, edge points */
} level;

static size_t edge_point_base(const level *l)
{
    return l->nv + (l->scheme == LIMN_SCHEME_CATMARK ? l->nf : 0);
}

/* The patch's points: rows of plan step 0 (vertex, face, then edge points). */
static size_t patch_face_row(const level *l, size_t pf)
{
    return l->star.mesh->vertex_count + pf;
}
static size_t patch_edge_row(const level *l, size_t e)
{
    return l->star.mesh->vertex_count +
           (l->scheme == LIMN_SCHEME_CATMARK ? l->star.mesh->face_count : 0) + e;
}

/* The first edge ids of split segment s's owned vertices: the rank's run
   starts after the earlier ranks' edges of the segment (counts of all). */
static limn_status split_ids(level *l, int s, size_t start, const uint64_t *all, size_t at,
                             const uint32_t *count)
{
    size_t S = (size_t)l->in->segments, R = (size_t)l->p->size;
    mpi_rseg *g = &l->edge_seg[s];
    g->dist = large_malloc((R + 1) * sizeof *g->dist);
    if (!g->dist)
        return ctx_fail(l->p->ctx, LIMN_ERR_MEMORY, "out of memory");
    g->dist[0] = start;
    for (size_t r = 0; r < R; r++)
        g->dist[r + 1] = g->dist[r] + (size_t)all[r * S + (size_t)s];
    g->start = start;
    g->end = g->dist[R];
    size_t next = g->dist[l->p->rank], n = mpi_rseg_count(&l->in->seg[s], l->p->rank);
    for (size_t i = 0; i < n; i++) {
        l->next_id[at + i] = (uint32_t)next;
        next += count[at + i];
    }
    return LIMN_OK;
}

/* The first edge ids of directory segment s's owned vertices: each
   vertex's count to the directory's blocks, summed there in id order (after
   the earlier blocks', an Exscan), the first ids fetched back. Collective. */
static limn_status directory_ids(level *l, int s, size_t start, size_t at, const uint32_t *count)
{
    mpi_part *p = l->p;
    const mpi_rseg *g = &l->in->seg[s];
    size_t nb = g->dist[p->rank + 1] - g->dist[p->rank];
    uint32_t *block = calloc(nb ? nb : 1, sizeof *block);
    limn_status st = mpi_agree(p, block ? LIMN_OK
                                        : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory"));
    if (!st)
        st = mpi_blocks_store(p, g->dist, g->n_own, g->own, count + at, sizeof *block, block);
    if (!st) {
        uint64_t mine = 0, before = 0;
        for (size_t i = 0; i < nb; i++)
            mine += block[i];
        MPI_Exscan(&mine, &before, 1, MPI_UINT64_T, MPI_SUM, p->comm);
        size_t next = start + (p->rank ? (size_t)before : 0);
        for (size_t i = 0; i < nb; i++) {
            uint32_t c = block[i];
            block[i] = (uint32_t)next;
            next += c;
        }
        st = mpi_blocks_fetch(p, g->dist, block, sizeof *block, g->n_own, g->own,
                              l->next_id + at);
    }
    free(block);
    return st;
}

/* The new directory segment of the points of the edges this rank owns in
   directory segment s (their ids increasing in edge order). Collective. */
static limn_status directory_segment(level *l, int s, size_t start, size_t end)
{
    size_t ne = l->topo.edge_count, n = 0;
    uint32_t *own = large_malloc((l->owned_edges ? l->owned_edges : 1) * sizeof *own);
    limn_status st = mpi_agree(l->p, own ? LIMN_OK
                                         : ctx_fail(l->p->ctx, LIMN_ERR_MEMORY, "out of memory"));
    for (size_t e = 0; !st && e < ne; e++)
        if (l->edge_id[e] != UINT32_MAX && l->edge_id[e] >= start && l->edge_id[e] < end)
            own[n++] = l->edge_id[e];
    if (st) {
        free(own);
        return st;
    }
    return mpi_rseg_directory(l->p, start, end, own, n, &l->edge_seg[s]);
}

/* The ids of the owned edges' points (edge order: by lower vertex, then
   upper), and the new level's edge segments; l->owned_edges their count. */
static limn_status number_edges(level *l)
{
    mpi_part *p = l->p;
    size_t ne = l->topo.edge_count, S = (size_t)l->in->segments, R = (size_t)p->size;
    size_t no = l->in->n_owned;
    l->edge_id = large_malloc((ne ? ne : 1) * sizeof *l->edge_id);
    l->edge_seg = calloc(S, sizeof *l->edge_seg);
    l->next_id = large_malloc((no ? no : 1) * sizeof *l->next_id);
    uint32_t *count = calloc(no ? no : 1, sizeof *count);
    uint64_t *mine = calloc(S, sizeof *mine), *all = large_malloc(S * R * sizeof *all);
    limn_status st = l->edge_id && l->edge_seg && l->next_id && count && mine && all
                         ? LIMN_OK
                         : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory");
    for (size_t e = 0; !st && e < ne; e++) {
        uint32_t lo = l->star.ids[l->topo.edge_vertices[2 * e]];
        size_t i = mpi_rmesh_local(l->in, p->rank, lo);
        l->edge_id[e] = UINT32_MAX;
        if (i != SIZE_MAX) {
            mine[mpi_rmesh_segment(l->in, lo)]++;
            count[i]++;
            l->owned_edges++;
        }
    }
    st = mpi_agree(p, st);
    if (!st)
        MPI_Allgather(mine, (int)S, MPI_UINT64_T, all, (int)S, MPI_UINT64_T, p->comm);
    size_t start = edge_point_base(l), at = 0;
    for (size_t s = 0; !st && s < S; s++) {
        size_t total = 0;
        for (size_t r = 0; r < R; r++)
            total += (size_t)all[r * S + s];
        mine[s] = start; /* now each segment's first id */
        st = l->in->seg[s].directory ? directory_ids(l, (int)s, start, at, count)
                                     : mpi_agree(p, split_ids(l, (int)s, start, all, at, count));
        at += mpi_rseg_count(&l->in->seg[s], p->rank);
        start += total;
    }
    l->new_total = start;
    if (!st && l->new_total > UINT32_MAX)
        st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "the next level would have %zu vertices (over 2^32)",
                      l->new_total);
    for (size_t e = 0; !st && e < ne; e++) {
        uint32_t lo = l->star.ids[l->topo.edge_vertices[2 * e]];
        size_t i = mpi_rmesh_local(l->in, p->rank, lo);
        if (i != SIZE_MAX)
            l->edge_id[e] = l->next_id[i]++;
    }
    st = mpi_agree(p, st);
    for (size_t s = 0; !st && s < S; s++)
        if (l->in->seg[s].directory)
            st = directory_segment(l, (int)s, mine[s], s + 1 < S ? mine[s + 1] : l->new_total);
    free(count);
    free(mine);
    free(all);
    return st;
}

/* This rank's new vertices: vertex points of its vertices, face points of
   its face block, points of its edges (the new level's segments' order). */
static limn_status gather_points(level *l, mpi_refine_stats *stats)
{
    const mpi_rmesh *s = l->in;
    int cc = l->scheme == LIMN_SCHEME_CATMARK;
    size_t n = s->n_owned + (cc ? s->face_count : 0) + l->owned_edges;
    l->new_xyz = large_malloc((n ? 3 * n : 1) * sizeof *l->new_xyz);
    if (!l->new_xyz)
        return ctx_fail(l->p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu new vertices", n);
    const double *fine = l->plan.meshes[1]->positions;
    const uint32_t *ro = l->plan.steps[0].row_offsets;
    size_t k = 0;
    for (size_t i = 0; i < s->n_owned; i++, k++) {
        size_t v = mpi_star_local(&l->star, (uint32_t)mpi_rmesh_id(s, l->p->rank, i));
        memcpy(l->new_xyz + 3 * k, fine + 3 * v, 3 * sizeof(double));
        stats->stencil_nonzeros += ro[v + 1] - ro[v];
    }
    for (size_t i = 0; cc && i < s->face_count; i++, k++) {
        size_t row = patch_face_row(l, l->star.block_face[i]);
        memcpy(l->new_xyz + 3 * k, fine + 3 * row, 3 * sizeof(double));
        stats->stencil_nonzeros += ro[row + 1] - ro[row];
    }
    for (size_t e = 0; e < l->topo.edge_count; e++) {
        if (l->edge_id[e] == UINT32_MAX)
            continue;
        size_t row = patch_edge_row(l, e);
        memcpy(l->new_xyz + 3 * k, fine + 3 * row, 3 * sizeof(double));
        stats->stencil_nonzeros += ro[row + 1] - ro[row];
        k++;
    }
    l->n_new = k;
    return LIMN_OK;
}

/* The point of the edge (lo, hi) of this rank's star, asked by another rank. */
static uint32_t answer_edge(const level *l, uint32_t lo, uint32_t hi)
{
    size_t a = mpi_star_local(&l->star, lo), b = mpi_star_local(&l->star, hi);
    if (a == SIZE_MAX || b == SIZE_MAX)
        return UINT32_MAX;
    const topology *t = &l->topo;
    for (uint32_t k = t->vertex_edge_offsets[a]; k < t->vertex_edge_offsets[a + 1]; k++)
        if (topology_edge_other(t, t->vertex_edges[k], (uint32_t)a) == b)
            return l->edge_id[t->vertex_edges[k]];
    return UINT32_MAX;
}

/* The patch edges of the block faces this rank does not own (each once),
   their lower vertices in lo. */
static limn_status asked_edges(level *l, uint32_t **edges, uint32_t **lo, size_t *n)
{
    const limn_mesh *pm = l->star.mesh;
    size_t ne = l->topo.edge_count, k = 0;
    uint8_t *asked = calloc(ne ? ne : 1, 1);
    *edges = large_malloc((ne ? ne : 1) * sizeof **edges);
    *lo = large_malloc((ne ? ne : 1) * sizeof **lo);
    limn_status st = asked && *edges && *lo ? LIMN_OK
                                            : ctx_fail(l->p->ctx, LIMN_ERR_MEMORY,
                                                       "out of memory for the edge requests");
    for (size_t i = 0; !st && i < l->in->face_count; i++) {
        size_t pf = l->star.block_face[i];
        for (uint32_t c = pm->face_offsets[pf]; c < pm->face_offsets[pf + 1]; c++) {
            uint32_t e = l->topo.corner_edge[c];
            if (l->edge_id[e] != UINT32_MAX || asked[e])
                continue;
            asked[e] = 1;
            (*edges)[k] = e;
            (*lo)[k++] = l->star.ids[l->topo.edge_vertices[2 * e]];
        }
    }
    free(asked);
    *n = k;
    return st;
}

/* Those edges grouped by the rank that owns their lower vertex: (lo, hi)
   pairs in req, their patch edges in which. Collective (the owners). */
static limn_status pack_requests(level *l, int *cnt, uint32_t **req, uint32_t **which)
{
    mpi_part *p = l->p;
    uint32_t *edges = NULL, *lo = NULL;
    size_t n = 0;
    size_t *at = calloc((size_t)p->size + 1, sizeof *at);
    limn_status st = at ? asked_edges(l, &edges, &lo, &n)
                        : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory");
    int *owner = large_malloc((n ? n : 1) * sizeof *owner);
    *req = large_malloc((n ? 2 * n : 1) * sizeof **req);
    *which = large_malloc((n ? n : 1) * sizeof **which);
    if (!st && (!owner || !*req || !*which || n > INT32_MAX / 2))
        st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu requests", n);
    st = mpi_agree(p, st);
    if (!st)
        st = mpi_rmesh_owners(p, l->in, n, lo, owner);
    for (size_t k = 0; !st && k < n; k++)
        at[owner[k] + 1]++;
    for (int r = 0; !st && r < p->size; r++) {
        cnt[r] = (int)(2 * at[r + 1]);
        at[r + 1] += at[r];
    }
    for (size_t k = 0; !st && k < n; k++) {
        size_t j = at[owner[k]]++;
        (*req)[2 * j] = lo[k];
        (*req)[2 * j + 1] = l->star.ids[l->topo.edge_vertices[2 * edges[k] + 1]];
        (*which)[j] = edges[k];
    }
    free(edges);
    free(lo);
    free(owner);
    free(at);
    return st;
}

/* The ids of the points of the block faces' edges owned elsewhere. */
static limn_status fetch_edges(level *l)
{
    mpi_part *p = l->p;
    int *cnt = large_malloc(4 * (size_t)p->size * sizeof *cnt);
    uint32_t *req = NULL, *which = NULL, *got = NULL, *ans = NULL, *back = NULL;
    size_t words = 0, n_back = 0;
    limn_status st = cnt ? LIMN_OK : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory");
    st = mpi_agree(p, st);
    if (!st)
        st = pack_requests(l, cnt, &req, &which);
    st = mpi_agree(p, st);
    if (!st)
        st = mpi_local_alltoallv(p, req, cnt, sizeof *req, (void **)&got, cnt + p->size, &words);
    if (!st && !(ans = large_malloc((words ? words / 2 : 1) * sizeof *ans)))
        st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu answers", words / 2);
    for (size_t k = 0; !st && k < words / 2; k++)
        if ((ans[k] = answer_edge(l, got[2 * k], got[2 * k + 1])) == UINT32_MAX)
            st = ctx_fail(p->ctx, LIMN_ERR_ARGUMENT,
                          "rank %d: edge (%u, %u) asked of it is not in its star", p->rank,
                          got[2 * k], got[2 * k + 1]);
    for (int r = 0; !st && r < p->size; r++)
        cnt[2 * p->size + r] = cnt[p->size + r] / 2;
    st = mpi_agree(p, st);
    if (!st)
        st = mpi_local_alltoallv(p, ans, cnt + 2 * p->size, sizeof *ans, (void **)&back,
                                 cnt + 3 * p->size, &n_back);
    for (size_t k = 0; !st && k < n_back; k++)
        l->edge_id[which[k]] = back[k];
    free(cnt);
    free(req);
    free(which);
    free(got);
    free(ans);
    free(back);
    return st;
}

/* The children of the block's faces, in the single process's order and ids. */
static limn_status child_faces(level *l, mpi_rmesh *out)
{
    const limn_mesh *pm = l->star.mesh;
    const mpi_rmesh *s = l->in;
    int loop = l->scheme == LIMN_SCHEME_LOOP;
    size_t nc = s->face_offsets[s->face_count];
    out->face_count = loop ? 4 * s->face_count : nc;
    out->face_offsets = large_malloc((out->face_count + 1) * sizeof *out->face_offsets);
    out->face_indices = large_malloc((4 * out->face_count + 1) * sizeof *out->face_indices);
    if (!out->face_offsets || !out->face_indices || 4 * out->face_count > UINT32_MAX)
        return ctx_fail(l->p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu child faces",
                        out->face_count);
    size_t k = 0, f_out = 0;
    out->face_offsets[0] = 0;
    for (size_t i = 0; i < s->face_count; i++) {
        size_t pf = l->star.block_face[i];
        uint32_t b = pm->face_offsets[pf], e = pm->face_offsets[pf + 1];
        if (loop) {
            uint32_t v[3], ep[3];
            for (uint32_t j = 0; j < 3; j++) {
                v[j] = l->star.ids[pm->face_indices[b + j]];
                ep[j] = l->edge_id[l->topo.corner_edge[b + j]];
            }
            uint32_t tris[4][3] = {{v[0], ep[0], ep[2]}, {v[1], ep[1], ep[0]},
                                   {v[2], ep[2], ep[1]}, {ep[0], ep[1], ep[2]}};
            for (int q = 0; q < 4; q++) {
                memcpy(out->face_indices + k, tris[q], sizeof tris[q]);
                k += 3;
                out->face_offsets[++f_out] = (uint32_t)k;
            }
            continue;
        }
        uint32_t fp = (uint32_t)(l->nv + s->face_begin + i);
        for (uint32_t c = b; c < e; c++) {
            uint32_t pc = c == b ? e - 1 : c - 1;
            uint32_t q[4] = {l->star.ids[pm->face_indices[c]], l->edge_id[l->topo.corner_edge[c]],
                             fp, l->edge_id[l->topo.corner_edge[pc]]};
            memcpy(out->face_indices + k, q, sizeof q);
            k += 4;
            out->face_offsets[++f_out] = (uint32_t)k;
        }
    }
    return LIMN_OK;
}

/* The new level: the old segments (taken from in), the face points'
   (Catmull-Clark: nv + the face blocks, split), the edge points' (one per old
   segment), the children. */
static limn_status hand_over(level *l, mpi_rmesh *out)
{
    mpi_part *p = l->p;
    size_t S = (size_t)l->in->segments, R = (size_t)p->size;
    int cc = l->scheme == LIMN_SCHEME_CATMARK;
    memset(out, 0, sizeof *out);
    out->owns_faces = 1;
    out->segments = 2 * (int)S + cc;
    out->seg = calloc((size_t)out->segments, sizeof *out->seg);
    mpi_rseg *fp = out->seg ? &out->seg[S] : NULL;
    if (fp && cc)
        fp->dist = large_malloc((R + 1) * sizeof *fp->dist);
    size_t *fd = large_malloc((R + 1) * sizeof *fd);
    limn_status st = out->seg && fd && (!cc || fp->dist) ? child_faces(l, out)
                                                        : ctx_fail(p->ctx, LIMN_ERR_MEMORY,
                                                                   "out of memory");
    st = mpi_agree(p, st);
    if (!st) {
        mpi_blocks_dist(p, out->face_count, fd);
        out->face_begin = fd[p->rank];
        out->face_total = fd[p->size];
    }
    if (!st && cc) {
        mpi_blocks_dist(p, l->in->face_count, fp->dist);
        for (size_t r = 0; r <= R; r++)
            fp->dist[r] += l->nv;
        fp->start = l->nv;
        fp->end = l->nv + l->nf;
    }
    free(fd);
    if (st) {
        mpi_rmesh_free(out);
        return st;
    }
    memcpy(out->seg, l->in->seg, S * sizeof *out->seg);
    memset(l->in->seg, 0, S * sizeof *l->in->seg);
    memcpy(out->seg + S + (size_t)cc, l->edge_seg, S * sizeof *out->seg);
    memset(l->edge_seg, 0, S * sizeof *l->edge_seg);
    out->vertex_total = l->new_total;
    out->n_owned = l->n_new;
    out->pos = l->new_xyz;
    l->new_xyz = NULL;
    return LIMN_OK;
}

/* Notes an array of n entries of a level of total vertices. */
static void note(mpi_refine_stats *stats, size_t n, size_t total)
{
    if (n > stats->largest_vertex_array)
        stats->largest_vertex_array = n;
    double share = total ? (double)n / (double)total : 0.0;
    if (share > stats->share)
        stats->share = share;
}

static void level_free(level *l)
{
    mpi_star_free(&l->star);
    if (l->have_plan)
        refine_plan_free(&l->plan);
    if (l->have_topo)
        topology_free(&l->topo);
    free(l->edge_id);
    for (int s = 0; l->edge_seg && s < l->in->segments; s++)
        mpi_rseg_free(&l->edge_seg[s]);
    free(l->edge_seg);
    free(l->next_id);
    free(l->new_xyz);
}

limn_status mpi_refine_level(mpi_part *p, mpi_rmesh *mesh, limn_scheme scheme,
                             double alpha, mpi_rmesh *out, mpi_refine_stats *stats)
{
    level l = {.p = p, .in = mesh, .scheme = scheme};
    l.nv = mesh->vertex_total;
    l.nf = mesh->face_total;
    double t0 = MPI_Wtime();
    limn_status st = mpi_star_build(p, mesh, &l.star);
    if (!st) {
        st = refine_plan_build(p->ctx, l.star.mesh, scheme, alpha, 1, &l.plan);
        l.have_plan = !st;
    }
    if (!st) {
        st = topology_build(p->ctx, l.star.mesh, &l.topo);
        l.have_topo = !st;
        if (!st)
            st = topology_corner_edges(p->ctx, &l.topo);
    }
    double t1 = MPI_Wtime();
    stats->seconds_plan += t1 - t0;
    if (!st)
        st = refine_plan_apply(p->ctx, &l.plan, 0, 3, l.star.mesh->positions,
                               l.plan.meshes[1]->positions);
    stats->seconds_apply += MPI_Wtime() - t1;
    st = mpi_agree(p, st);
    if (!st)
        st = number_edges(&l);
    if (!st)
        st = mpi_agree(p, gather_points(&l, stats));
    if (!st)
        st = fetch_edges(&l);
    if (!st) {
        note(stats, l.star.largest_vertex_array, l.nv);
        note(stats, l.plan.meshes[1]->vertex_count, l.new_total);
        note(stats, l.n_new, l.new_total);
    }
    if (l.have_plan) {
        refine_plan_free(&l.plan); /* the kept points are copied out */
        l.have_plan = 0;
    }
    if (!st)
        st = hand_over(&l, out);
    level_free(&l);
    return st;
}

limn_status mpi_refine_limit(mpi_part *p, mpi_rmesh *m, limn_scheme scheme, double alpha,
                             mpi_refine_stats *stats)
{
    mpi_star s;
    limn_status st = mpi_star_build(p, m, &s);
    size_t nb = m->n_owned, n = st ? 0 : s.mesh->vertex_count;
    double *lim = NULL, *block = large_malloc((nb ? 3 * nb : 1) * sizeof *block);
    if (!st && (!block || !(lim = large_malloc((n ? 3 * n : 1) * sizeof *lim))))
        st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu limit positions", n);
    if (!st)
        st = limn_limit_positions(p->ctx, s.mesh, scheme, alpha, lim);
    for (size_t i = 0; !st && i < nb; i++) {
        size_t v = mpi_star_local(&s, (uint32_t)mpi_rmesh_id(m, p->rank, i));
        memcpy(block + 3 * i, lim + 3 * v, 3 * sizeof *block);
    }
    if (!st)
        note(stats, s.largest_vertex_array, m->vertex_total);
    free(lim);
    mpi_star_free(&s);
    st = mpi_agree(p, st);
    if (st) {
        free(block);
        return st;
    }
    free(m->pos);
    m->pos = block;
    return LIMN_OK;
}
