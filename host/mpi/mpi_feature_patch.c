/* SPDX-License-Identifier: MIT */
/*
 * A rank's patch for the feature-preserving denoiser (mpi_features.h).
 * Three exchanges build it: every block face goes to the block owner of
 * each of its corners (so an owner knows every face around its vertices);
 * every rank asks those owners for the faces around the corners of its
 * block faces and around its block vertices; the patch vertices' positions
 * come from their block owners. Face records are words: id, size, corners.
 */
#include "mpi/mpi_features.h"
#include "base/large_alloc.h"

#include "base/context.h"
#include "mesh/mesh.h"
#include "mpi/mpi_local.h"

#include <stdlib.h>
#include <string.h>

typedef struct patch_face {
    uint32_t id, size;
    const uint32_t *corners;
} patch_face;

static int face_cmp(const void *a, const void *b)
{
    uint32_t x = ((const patch_face *)a)->id, y = ((const patch_face *)b)->id;
    return (x > y) - (x < y);
}

/* The rank whose block of dist (size + 1 entries) holds id. */
static int owner_of(const mpi_part *p, const size_t *dist, size_t id)
{
    int lo = 0, hi = p->size - 1;
    while (lo < hi) {
        int mid = (lo + hi + 1) / 2;
        if (dist[mid] <= id)
            lo = mid;
        else
            hi = mid - 1;
    }
    return lo;
}

/* The first index of ids (n, increasing) not below id. */
static size_t lower_bound(const uint32_t *ids, size_t n, size_t id)
{
    size_t lo = 0, hi = n;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (ids[mid] < id)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

/* The owner of corner k of c, or -1 when an earlier corner has that owner. */
static int new_owner(const mpi_part *p, const limn_mpi_mesh *m, const uint32_t *c, uint32_t k)
{
    int r = owner_of(p, m->vertex_dist, c[k]);
    for (uint32_t j = 0; j < k; j++)
        if (owner_of(p, m->vertex_dist, c[j]) == r)
            return -1;
    return r;
}

/* The block faces' records for the owners of their corners, grouped by
   rank (cnt: words per rank). */
static limn_status pack_block(mpi_part *p, const limn_mpi_mesh *mesh, int *cnt, uint32_t **send)
{
    const mesh_slice *s = &mesh->slice;
    size_t R = (size_t)p->size, *at = calloc(R + 1, sizeof *at);
    *send = NULL;
    if (!at)
        return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory");
    for (int pass = 0; pass < 2; pass++) {
        for (size_t f = 0; f < s->face_count; f++) {
            const uint32_t *c = s->face_indices + s->face_offsets[f];
            uint32_t n = s->face_offsets[f + 1] - s->face_offsets[f];
            for (uint32_t k = 0; k < n; k++) {
                int r = new_owner(p, mesh, c, k);
                if (r >= 0 && pass == 0)
                    at[r + 1] += 2 + (size_t)n;
                if (r < 0 || pass == 0)
                    continue;
                uint32_t *w = *send + at[r];
                w[0] = (uint32_t)(s->face_begin + f);
                w[1] = n;
                memcpy(w + 2, c, n * sizeof *c);
                at[r] += 2 + (size_t)n;
            }
        }
        for (size_t r = 0; pass == 0 && r < R; r++) {
            cnt[r] = (int)at[r + 1];
            at[r + 1] += at[r];
        }
        if (pass == 0 && !(*send = large_malloc((at[R] ? at[R] : 1) * sizeof **send))) {
            size_t words = at[R];
            free(at);
            return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu face words", words);
        }
    }
    free(at);
    return LIMN_OK;
}

/* The records in w (words of them) as faces. */
static limn_status parse_faces(mpi_part *p, const uint32_t *w, size_t words, patch_face **out,
                               size_t *n)
{
    size_t count = 0;
    for (size_t i = 0; i < words; i += 2 + (size_t)w[i + 1])
        count++;
    *n = count;
    *out = large_malloc((count ? count : 1) * sizeof **out);
    if (!*out)
        return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu faces", count);
    size_t k = 0;
    for (size_t i = 0; i < words; i += 2 + (size_t)w[i + 1])
        (*out)[k++] = (patch_face){w[i], w[i + 1], w + i + 2};
    return LIMN_OK;
}

/* What a block owner knows after the first exchange: the faces around its
   vertices (records, as received) and, per block vertex, which of them. */
typedef struct vertex_faces {
    uint32_t *words;
    patch_face *faces;
    size_t n;
    size_t *off, *of; /* CSR over the block vertices: indices into faces */
} vertex_faces;

static void vertex_faces_free(vertex_faces *v)
{
    free(v->words);
    free(v->faces);
    free(v->off);
    free(v->of);
}

static limn_status build_incidence(mpi_part *p, const limn_mpi_mesh *mesh, vertex_faces *v)
{
    size_t vb = mesh->vertex_dist[p->rank], nb = mesh->slice.vertex_count, total = 0;
    v->off = calloc(nb + 1, sizeof *v->off);
    if (!v->off)
        return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu vertices", nb);
    for (int pass = 0; pass < 2; pass++) {
        for (size_t f = 0; f < v->n; f++)
            for (uint32_t k = 0; k < v->faces[f].size; k++) {
                size_t c = v->faces[f].corners[k];
                if (c < vb || c - vb >= nb)
                    continue;
                if (pass == 0)
                    v->off[c - vb + 1]++;
                else
                    v->of[v->off[c - vb]++] = f;
            }
        if (pass == 0) {
            for (size_t i = 0; i < nb; i++)
                v->off[i + 1] += v->off[i];
            total = v->off[nb];
            if (!(v->of = large_malloc((total ? total : 1) * sizeof *v->of)))
                return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu faces", total);
        }
    }
    for (size_t i = nb; i > 0; i--) /* the fill moved each start to the next's */
        v->off[i] = v->off[i - 1];
    v->off[0] = 0;
    return LIMN_OK;
}

/* Collective: every rank's vertex_faces over its block. */
static limn_status gather_around(mpi_part *p, const limn_mpi_mesh *mesh, vertex_faces *v)
{
    memset(v, 0, sizeof *v);
    int *cnt = large_malloc(2 * (size_t)p->size * sizeof *cnt);
    uint32_t *send = NULL;
    size_t words = 0;
    limn_status st = cnt ? pack_block(p, mesh, cnt, &send)
                         : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory");
    st = mpi_agree(p, st);
    if (!st)
        st = mpi_local_alltoallv(p, send, cnt, sizeof *send, (void **)&v->words, cnt + p->size,
                                 &words);
    if (!st)
        st = parse_faces(p, v->words, words, &v->faces, &v->n);
    if (!st)
        st = build_incidence(p, mesh, v);
    free(send);
    free(cnt);
    return mpi_agree(p, st);
}

/* The vertices this rank asks about (increasing): the corners of its block
   faces and its block vertices. */
static limn_status wanted_vertices(mpi_part *p, const limn_mpi_mesh *mesh, uint32_t **ids,
                                   size_t *n)
{
    const mesh_slice *s = &mesh->slice;
    size_t nc = s->face_offsets[s->face_count], total = nc + s->vertex_count;
    uint64_t *keys = large_malloc((total ? total : 1) * sizeof *keys);
    *ids = large_malloc((total ? total : 1) * sizeof **ids);
    if (!keys || !*ids) {
        free(keys);
        return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu vertices", total);
    }
    for (size_t k = 0; k < nc; k++)
        keys[k] = s->face_indices[k];
    for (size_t i = 0; i < s->vertex_count; i++)
        keys[nc + i] = mesh->vertex_dist[p->rank] + i;
    mpi_local_sort(keys, total);
    size_t u = 0;
    for (size_t i = 0; i < total; i++)
        if (u == 0 || keys[i] != (*ids)[u - 1])
            (*ids)[u++] = (uint32_t)keys[i];
    free(keys);
    *n = u;
    return LIMN_OK;
}

/* The records of the faces around the vertices asked (req, rcnt[r] from
   rank r), each face once per asking rank; acnt: words per rank. */
static limn_status answer(mpi_part *p, const limn_mpi_mesh *mesh, const vertex_faces *v,
                          const uint32_t *req, const int *rcnt, int *acnt, uint32_t **ans)
{
    size_t R = (size_t)p->size, vb = mesh->vertex_dist[p->rank], words = 0;
    size_t *stamp = calloc(v->n ? v->n : 1, sizeof *stamp);
    *ans = NULL;
    if (!stamp)
        return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu faces", v->n);
    for (int pass = 0; pass < 2; pass++) {
        size_t at = 0, w = 0;
        for (size_t r = 0; r < R; r++) {
            size_t mark = 2 * r + (size_t)pass + 1, begin = w;
            for (int q = 0; q < rcnt[r]; q++) {
                size_t i = req[at++] - vb;
                for (size_t k = v->off[i]; k < v->off[i + 1]; k++) {
                    const patch_face *f = &v->faces[v->of[k]];
                    if (stamp[v->of[k]] == mark)
                        continue;
                    stamp[v->of[k]] = mark;
                    if (pass == 1) {
                        (*ans)[w] = f->id;
                        (*ans)[w + 1] = f->size;
                        memcpy(*ans + w + 2, f->corners, f->size * sizeof *f->corners);
                    }
                    w += 2 + (size_t)f->size;
                }
            }
            acnt[r] = (int)(w - begin);
        }
        words = w;
        if (pass == 0 && !(*ans = large_malloc((words ? words : 1) * sizeof **ans))) {
            free(stamp);
            return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu words", words);
        }
    }
    free(stamp);
    return LIMN_OK;
}

/* Collective: the faces around the wanted vertices, sorted by id, each
   once (*words: the records they point into, caller frees). */
static limn_status patch_faces(mpi_part *p, const limn_mpi_mesh *mesh, const vertex_faces *v,
                               uint32_t **words, patch_face **faces, size_t *nf)
{
    size_t R = (size_t)p->size, n = 0, asked = 0, got = 0;
    int *cnt = calloc(4 * R, sizeof *cnt);
    uint32_t *ids = NULL, *req = NULL, *ans = NULL;
    *words = NULL;
    limn_status st = cnt ? wanted_vertices(p, mesh, &ids, &n)
                         : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory");
    for (size_t i = 0; !st && i < n; i++)
        cnt[owner_of(p, mesh->vertex_dist, ids[i])]++;
    st = mpi_agree(p, st);
    if (!st)
        st = mpi_local_alltoallv(p, ids, cnt, sizeof *ids, (void **)&req, cnt + R, &asked);
    if (!st)
        st = answer(p, mesh, v, req, cnt + R, cnt + 2 * R, &ans);
    st = mpi_agree(p, st);
    if (!st)
        st = mpi_local_alltoallv(p, ans, cnt + 2 * R, sizeof *ans, (void **)words, cnt + 3 * R,
                                 &got);
    if (!st)
        st = parse_faces(p, *words, got, faces, nf);
    if (!st) {
        qsort(*faces, *nf, sizeof **faces, face_cmp);
        size_t u = 0;
        for (size_t i = 0; i < *nf; i++)
            if (u == 0 || (*faces)[i].id != (*faces)[u - 1].id)
                (*faces)[u++] = (*faces)[i];
        *nf = u;
    }
    free(cnt);
    free(ids);
    free(req);
    free(ans);
    return mpi_agree(p, st);
}

/* The patch vertices (the faces' corners and the block vertices,
   increasing) and the patch mesh in local numbers. */
static limn_status patch_mesh(mpi_part *p, const limn_mpi_mesh *mesh, const patch_face *f,
                              size_t nf, mpi_feature_patch *fp)
{
    size_t nb = mesh->slice.vertex_count, vb = mesh->vertex_dist[p->rank], nc = 0;
    for (size_t i = 0; i < nf; i++)
        nc += f[i].size;
    uint64_t *keys = large_malloc((nc + nb ? nc + nb : 1) * sizeof *keys);
    fp->vertex_ids = large_malloc((nc + nb ? nc + nb : 1) * sizeof *fp->vertex_ids);
    fp->face_ids = large_malloc((nf ? nf : 1) * sizeof *fp->face_ids);
    if (!keys || !fp->vertex_ids || !fp->face_ids) {
        free(keys);
        return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu patch corners", nc);
    }
    size_t k = 0, u = 0;
    for (size_t i = 0; i < nf; i++)
        for (uint32_t c = 0; c < f[i].size; c++)
            keys[k++] = f[i].corners[c];
    for (size_t i = 0; i < nb; i++)
        keys[k++] = vb + i;
    mpi_local_sort(keys, k);
    for (size_t i = 0; i < k; i++)
        if (u == 0 || keys[i] != fp->vertex_ids[u - 1])
            fp->vertex_ids[u++] = (uint32_t)keys[i];
    free(keys);
    limn_status st = mesh_alloc(p->ctx, u, nf, nc, &fp->mesh);
    if (st)
        return st;
    limn_mesh *m = fp->mesh;
    k = 0;
    m->face_offsets[0] = 0;
    for (size_t i = 0; i < nf; i++) {
        fp->face_ids[i] = f[i].id;
        for (uint32_t c = 0; c < f[i].size; c++)
            m->face_indices[k++] = (uint32_t)lower_bound(fp->vertex_ids, u, f[i].corners[c]);
        m->face_offsets[i + 1] = (uint32_t)k;
    }
    fp->vertex_base = lower_bound(fp->vertex_ids, u, vb);
    fp->face_base = lower_bound(fp->face_ids, nf, mesh->slice.face_begin);
    memcpy(m->positions + 3 * fp->vertex_base, mesh->slice.positions, 3 * nb * sizeof(double));
    return LIMN_OK;
}

/* The patch items outside [base, base + own) of ids (n): their ids and
   indices. */
static limn_status ghosts_of(mpi_part *p, const uint32_t *ids, size_t n, size_t base, size_t own,
                             uint32_t **gid, size_t **at, size_t *count)
{
    *count = n - own;
    *gid = large_malloc((*count ? *count : 1) * sizeof **gid);
    *at = large_malloc((*count ? *count : 1) * sizeof **at);
    if (!*gid || !*at)
        return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu ghosts", *count);
    size_t k = 0;
    for (size_t i = 0; i < n; i++)
        if (i < base || i >= base + own) {
            (*gid)[k] = ids[i];
            (*at)[k++] = i;
        }
    return LIMN_OK;
}

static limn_status patch_ghosts(mpi_part *p, const limn_mpi_mesh *mesh, mpi_feature_patch *fp)
{
    limn_status st = ghosts_of(p, fp->vertex_ids, fp->mesh->vertex_count, fp->vertex_base,
                               mesh->slice.vertex_count, &fp->vertex_ghost_ids,
                               &fp->vertex_ghost_at, &fp->vertex_ghosts);
    if (!st)
        st = ghosts_of(p, fp->face_ids, fp->mesh->face_count, fp->face_base,
                       mesh->slice.face_count, &fp->face_ghost_ids, &fp->face_ghost_at,
                       &fp->face_ghosts);
    size_t most = fp->vertex_ghosts > fp->face_ghosts ? fp->vertex_ghosts : fp->face_ghosts;
    if (!st && !(fp->buf = large_malloc(3 * (most ? most : 1) * sizeof *fp->buf)))
        st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu ghosts", most);
    return st;
}

limn_status mpi_feature_patch_build(mpi_part *p, const limn_mpi_mesh *mesh,
                                    mpi_feature_patch *out)
{
    memset(out, 0, sizeof *out);
    vertex_faces v;
    uint32_t *words = NULL;
    patch_face *faces = NULL;
    size_t nf = 0;
    limn_status st = gather_around(p, mesh, &v);
    if (!st)
        st = patch_faces(p, mesh, &v, &words, &faces, &nf);
    vertex_faces_free(&v);
    if (!st)
        st = patch_mesh(p, mesh, faces, nf, out);
    if (!st)
        st = patch_ghosts(p, mesh, out);
    free(words);
    free(faces);
    st = mpi_agree(p, st);
    if (!st)
        st = mpi_feature_sync_vertices(p, mesh, out, out->mesh->positions);
    if (st)
        mpi_feature_patch_free(out);
    return st;
}

void mpi_feature_patch_free(mpi_feature_patch *fp)
{
    limn_mesh_destroy(fp->mesh);
    free(fp->vertex_ids);
    free(fp->face_ids);
    free(fp->vertex_ghost_ids);
    free(fp->face_ghost_ids);
    free(fp->vertex_ghost_at);
    free(fp->face_ghost_at);
    free(fp->buf);
    memset(fp, 0, sizeof *fp);
}

/* The ghosts' values (3 each) from the block owners of dist into v, whose
   block values start at base. */
static limn_status sync(mpi_part *p, const size_t *dist, const uint32_t *ids, const size_t *at,
                        size_t n, double *buf, double *v, size_t base)
{
    local_sub sub;
    memset(&sub, 0, sizeof sub);
    limn_status st = mpi_local_fetch(p, &sub, dist, ids, n, v + 3 * base, 3 * sizeof *v, buf);
    for (size_t i = 0; !st && i < n; i++)
        memcpy(v + 3 * at[i], buf + 3 * i, 3 * sizeof *v);
    return st;
}

limn_status mpi_feature_sync_vertices(mpi_part *p, const limn_mpi_mesh *mesh,
                                      mpi_feature_patch *fp, double *x)
{
    return sync(p, mesh->vertex_dist, fp->vertex_ghost_ids, fp->vertex_ghost_at,
                fp->vertex_ghosts, fp->buf, x, fp->vertex_base);
}

limn_status mpi_feature_sync_faces(mpi_part *p, const limn_mpi_mesh *mesh,
                                   mpi_feature_patch *fp, double *n)
{
    return sync(p, mesh->face_dist, fp->face_ghost_ids, fp->face_ghost_at, fp->face_ghosts,
                fp->buf, n, fp->face_base);
}
