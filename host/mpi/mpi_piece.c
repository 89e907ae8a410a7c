/* SPDX-License-Identifier: MIT */
/*
 * Each rank's piece of a result, for output one file per rank: its owned
 * vertices, then the other vertices of the faces incident to them, and those
 * faces (a face on a partition boundary is in the piece of every rank owning
 * one of its vertices). Built on the root from the gathered result and sent.
 */
#include "mpi/mpi_part.h"
#include "base/large_alloc.h"

#include "base/context.h"
#include "mesh/mesh.h"

#include <limits.h>
#include <stdlib.h>
#include <string.h>

enum { TAG_PIECE = 7301, TAG_PIECE_IDS, TAG_PIECE_POS, TAG_PIECE_OFF, TAG_PIECE_IDX };
enum { P_STATUS, P_VERTICES, P_OWNED, P_FACES, P_INDICES, P_WIDTH };

typedef struct piece {
    uint64_t h[P_WIDTH];
    uint32_t *ids, *off, *idx;
    double *pos;
} piece;

static void piece_free(piece *pc)
{
    free(pc->ids);
    free(pc->off);
    free(pc->idx);
    free(pc->pos);
    memset(pc, 0, sizeof *pc);
}

static int cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return x < y ? -1 : x > y;
}

/* Faces of each rank's piece, in input order (CSR over ranks). */
static limn_status face_lists(mpi_part *p, const limn_mesh *mesh, size_t **off_out,
                              uint32_t **faces_out)
{
    size_t R = (size_t)p->size, total = 0;
    size_t *off = calloc(R + 1, sizeof *off);
    if (!off)
        return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for the pieces");
    for (int pass = 0; pass < 2; pass++) {
        uint32_t *faces = NULL;
        size_t *fill = NULL;
        if (pass == 1) {
            for (size_t r = 0; r < R; r++)
                off[r + 1] += off[r];
            total = off[R];
            faces = large_malloc((total ? total : 1) * sizeof *faces);
            fill = large_malloc(R * sizeof *fill);
            if (!faces || !fill) {
                free(faces);
                free(fill);
                free(off);
                return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for the pieces");
            }
            memcpy(fill, off, R * sizeof *fill);
        }
        for (size_t f = 0; f < mesh->face_count; f++) {
            uint32_t b = mesh->face_offsets[f], e = mesh->face_offsets[f + 1];
            for (uint32_t c = b; c < e; c++) {
                uint32_t q = p->part_of[mesh->face_indices[c]], seen = 0;
                for (uint32_t c2 = b; c2 < c && !seen; c2++)
                    seen = p->part_of[mesh->face_indices[c2]] == q;
                if (seen)
                    continue;
                if (pass == 0)
                    off[q + 1]++;
                else
                    faces[fill[q]++] = (uint32_t)f;
            }
        }
        if (pass == 1) {
            free(fill);
            *faces_out = faces;
        }
    }
    *off_out = off;
    return LIMN_OK;
}

/* Rank r's piece; loc: scratch, one entry per input vertex. */
static limn_status build_piece(mpi_part *p, const limn_mesh *mesh, const double *xyz,
                               const size_t *face_off, const uint32_t *faces, int r,
                               uint32_t *loc, piece *pc)
{
    memset(pc, 0, sizeof *pc);
    size_t no = p->root_off[r + 1] - p->root_off[r], nf = face_off[r + 1] - face_off[r];
    size_t corners = 0;
    for (size_t k = face_off[r]; k < face_off[r + 1]; k++)
        corners += mesh->face_offsets[faces[k] + 1] - mesh->face_offsets[faces[k]];
    pc->ids = large_malloc((no + corners + 1) * sizeof *pc->ids);
    pc->off = large_malloc((nf + 1) * sizeof *pc->off);
    pc->idx = large_malloc((corners + 1) * sizeof *pc->idx);
    if (!pc->ids || !pc->off || !pc->idx)
        return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for the piece of rank %d", r);
    memcpy(pc->ids, p->root_ids + p->root_off[r], no * sizeof *pc->ids);
    qsort(pc->ids, no, sizeof *pc->ids, cmp_u32);
    for (size_t i = 0; i < no; i++)
        loc[pc->ids[i]] = (uint32_t)i;
    /* the other vertices of the faces: unique, in input order */
    size_t nv = no;
    for (size_t k = face_off[r]; k < face_off[r + 1]; k++)
        for (uint32_t c = mesh->face_offsets[faces[k]]; c < mesh->face_offsets[faces[k] + 1];
             c++) {
            uint32_t v = mesh->face_indices[c];
            if (p->part_of[v] != (uint32_t)r && loc[v] != UINT32_MAX - 1) {
                loc[v] = UINT32_MAX - 1; /* seen (marks are cleared after each rank) */
                pc->ids[nv++] = v;
            }
        }
    qsort(pc->ids + no, nv - no, sizeof *pc->ids, cmp_u32);
    for (size_t i = no; i < nv; i++)
        loc[pc->ids[i]] = (uint32_t)i;
    pc->pos = large_malloc((nv ? 3 * nv : 1) * sizeof *pc->pos);
    if (!pc->pos)
        return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for the piece of rank %d", r);
    for (size_t i = 0; i < nv; i++)
        memcpy(pc->pos + 3 * i, xyz + 3 * (size_t)pc->ids[i], 3 * sizeof(double));
    size_t k2 = 0;
    pc->off[0] = 0;
    for (size_t k = 0; k < nf; k++) {
        uint32_t f = faces[face_off[r] + k];
        for (uint32_t c = mesh->face_offsets[f]; c < mesh->face_offsets[f + 1]; c++)
            pc->idx[k2++] = loc[mesh->face_indices[c]];
        pc->off[k + 1] = (uint32_t)k2;
    }
    /* clear this rank's marks for the next rank */
    for (size_t i = 0; i < nv; i++)
        loc[pc->ids[i]] = UINT32_MAX;
    pc->h[P_VERTICES] = nv;
    pc->h[P_OWNED] = no;
    pc->h[P_FACES] = nf;
    pc->h[P_INDICES] = k2;
    if (3 * nv > INT_MAX || k2 > INT_MAX)
        return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "the piece of rank %d is too large for MPI", r);
    return LIMN_OK;
}

static void send_piece(mpi_part *p, int r, piece *pc, limn_status st)
{
    pc->h[P_STATUS] = (uint64_t)st;
    MPI_Send(pc->h, P_WIDTH, MPI_UINT64_T, r, TAG_PIECE, p->comm);
    if (st)
        return;
    MPI_Send(pc->ids, (int)pc->h[P_VERTICES], MPI_UINT32_T, r, TAG_PIECE_IDS, p->comm);
    MPI_Send(pc->pos, (int)(3 * pc->h[P_VERTICES]), MPI_DOUBLE, r, TAG_PIECE_POS, p->comm);
    MPI_Send(pc->off, (int)(pc->h[P_FACES] + 1), MPI_UINT32_T, r, TAG_PIECE_OFF, p->comm);
    MPI_Send(pc->idx, (int)pc->h[P_INDICES], MPI_UINT32_T, r, TAG_PIECE_IDX, p->comm);
}

static limn_status recv_piece(mpi_part *p, piece *pc)
{
    memset(pc, 0, sizeof *pc);
    MPI_Recv(pc->h, P_WIDTH, MPI_UINT64_T, p->root, TAG_PIECE, p->comm, MPI_STATUS_IGNORE);
    if (pc->h[P_STATUS]) {
        p->echo = 1;
        return ctx_fail(p->ctx, (limn_status)pc->h[P_STATUS], "the root failed");
    }
    size_t nv = pc->h[P_VERTICES], nf = pc->h[P_FACES], ni = pc->h[P_INDICES];
    pc->ids = large_malloc((nv ? nv : 1) * sizeof *pc->ids);
    pc->pos = large_malloc((nv ? 3 * nv : 1) * sizeof *pc->pos);
    pc->off = large_malloc((nf + 1) * sizeof *pc->off);
    pc->idx = large_malloc((ni ? ni : 1) * sizeof *pc->idx);
    int ok = pc->ids && pc->pos && pc->off && pc->idx;
    void *dst[] = {pc->ids, pc->pos, pc->off, pc->idx};
    int tags[] = {TAG_PIECE_IDS, TAG_PIECE_POS, TAG_PIECE_OFF, TAG_PIECE_IDX};
    for (int k = 0; k < 4; k++) {
        MPI_Status status;
        int bytes = 0;
        MPI_Probe(p->root, tags[k], p->comm, &status);
        MPI_Get_count(&status, MPI_BYTE, &bytes);
        /* without memory the message is still taken, so the root's send completes */
        void *scratch = ok ? NULL : large_malloc(bytes > 0 ? (size_t)bytes : 1);
        MPI_Recv(ok ? dst[k] : scratch, bytes, MPI_BYTE, p->root, tags[k], p->comm,
                 MPI_STATUS_IGNORE);
        free(scratch);
    }
    return ok ? LIMN_OK : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for this rank's piece");
}

/* The piece as the caller's result. */
static limn_status adopt(mpi_part *p, piece *pc, limn_mpi_result *result)
{
    if (!result)
        return LIMN_OK;
    limn_status st = limn_mesh_create(p->ctx, pc->h[P_VERTICES], pc->pos, pc->h[P_FACES],
                                      pc->off, pc->idx, &result->piece);
    if (st)
        return st;
    result->piece_owned = pc->h[P_OWNED];
    result->piece_vertices = pc->ids;
    pc->ids = NULL;
    return LIMN_OK;
}

limn_status mpi_pieces(mpi_part *p, const limn_mesh *mesh_root, const double *xyz_root,
                       limn_mpi_result *result)
{
    piece mine;
    memset(&mine, 0, sizeof mine);
    limn_status st = LIMN_OK;
    if (p->rank == p->root) {
        size_t *face_off = NULL;
        uint32_t *faces = NULL;
        uint32_t *loc = large_malloc((p->n_global ? p->n_global : 1) * sizeof *loc);
        st = loc ? face_lists(p, mesh_root, &face_off, &faces)
                 : ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for the pieces");
        for (size_t v = 0; loc && v < p->n_global; v++)
            loc[v] = UINT32_MAX;
        for (int r = 0; r < p->size; r++) {
            piece pc;
            memset(&pc, 0, sizeof pc);
            limn_status built =
                st ? st : build_piece(p, mesh_root, xyz_root, face_off, faces, r, loc, &pc);
            st = st ? st : built;
            if (r == p->root) {
                mine = pc;
                continue;
            }
            send_piece(p, r, &pc, built);
            piece_free(&pc);
        }
        free(face_off);
        free(faces);
        free(loc);
    } else {
        st = recv_piece(p, &mine);
    }
    if (!st)
        st = adopt(p, &mine, result);
    piece_free(&mine);
    return mpi_agree(p, st);
}
