/* SPDX-License-Identifier: MIT */
/*
 * Local rows (issue 14 item 3, docs/mpi.md "Local rows"): every rank builds
 * its share of the distributed operator from distributed input, no rank
 * holding the whole mesh. Internal to the MPI layer.
 *
 * The input is a vertex block per rank and any contiguous range of faces per
 * rank, with a partition of the vertices (part = owning rank). Each rank
 * learns the parts of the vertices its faces use from their block owners,
 * sends every face to each distinct part among its vertices, receives its
 * owned vertices from the block owners, and so holds every face incident to
 * an owned vertex. It builds the sub-mesh of those faces (vertices in
 * increasing global index, faces in increasing global face index), repairs
 * it as limn_mesh_repair repairs the whole mesh (every decision about a face
 * depends only on faces sharing its vertices: all here), builds its operator
 * without reordering and keeps the owned vertices' rows: the single
 * process's rows bit for bit, entries in the same order (tests/
 * test_local_rows.c; a row RCM renumbers keeps its entries' order). Classes, ghost order and halo are mpi_part.h's,
 * with ghost rules and the owners' local numbers exchanged between ranks;
 * tests/test_mpi_local.c checks the whole mpi_part against mpi_distribute's.
 */
#ifndef LIMN_MPI_LOCAL_H
#define LIMN_MPI_LOCAL_H

#include "mpi/mpi_part.h"

/* What one rank held (per-rank memory, checked by test_mpi_local). */
typedef struct mpi_local_stats {
    size_t sub_vertices, sub_faces; /* this rank's sub-mesh: owned vertices and their ring */
    size_t faces_received;          /* input faces incident to an owned vertex */
    size_t largest_vertex_array;    /* entries of the largest per-vertex array this
                                       build allocated itself (sub-mesh, owned, ghost,
                                       request and answer lists); test_mpi_local
                                       checks it stays below vertex_total on 2+ ranks */
    size_t bytes_held_at_operator;  /* bytes of the build's own arrays alive while the
                                       sub-mesh's operator is built (its peak): sub-mesh
                                       ids, parts, positions and owned list only, the
                                       received face records, the referenced lists and
                                       the sub-mesh's CSR freed by then (test_mpi_local) */
    double seconds;                 /* the whole build, this rank (wall clock) */
} mpi_local_stats;

/* This rank's sub-mesh and its operator, as mpi_local.c leaves them. */
typedef struct local_sub {
    size_t n;               /* sub-mesh vertices */
    uint32_t *ids;          /* global id of each, increasing */
    uint32_t *part;         /* owning rank of each */
    size_t n_owned;
    uint32_t *owned;        /* sub-mesh index of each owned vertex, increasing */
    uint64_t *near;         /* a bit per sub-mesh vertex: owned, on a face with a vertex
                               of another part (mpi_local_counts; the rows that may
                               have ghost columns) */
    stencil_operator op;    /* the sub-mesh's operator (host only, input order) */
    mpi_local_stats *stats;
} local_sub;

/* A rank's repaired sub-mesh before its operator (mpi_local_mesh_build):
   what limn_mpi_mesh_repair keeps for the command after it, as the single
   process's repair keeps the topology for the operator (mpi_mesh.h). */
typedef struct mpi_local_mesh {
    local_sub s;           /* ids, part, owned (its operator still empty) */
    limn_mesh *mesh;       /* the sub-mesh: faces by increasing global id */
    double *pos;           /* 3 per sub-mesh vertex */
    uint64_t *face_ids;    /* global id of each sub-mesh face, when asked; else NULL */
} mpi_local_mesh;

/* Collective: the first half of mpi_local_build (arguments as there): the
   partition's sub-mesh of this rank into *lm, with the faces' global ids
   when face_ids. On failure *lm is empty. */
limn_status mpi_local_mesh_build(mpi_part *p, const size_t *vtxdist, const double *positions,
                                 const uint32_t *part_of, size_t face_begin, size_t face_count,
                                 const uint32_t *face_offsets, const uint32_t *face_indices,
                                 const limn_repair_options *repair, int face_ids,
                                 mpi_local_mesh *lm, mpi_local_stats *stats);

/* Collective: the second half, from *lm (emptied whatever the status):
   the operator, p filled and the device opened, as mpi_local_build. */
limn_status mpi_local_build_on(mpi_part *p, const size_t *vtxdist, const double *positions,
                               mpi_local_mesh *lm, limn_scheme scheme, double alpha,
                               double **owned_rows4, mpi_local_stats *stats);

void mpi_local_mesh_free(mpi_local_mesh *lm);

/* ---------------------------------------------------- mpi_local_faces.c */

/* A face record as mpi_local_send_faces sends it: the face's global id (2
   words, low first), its corner count d, d global vertex ids, d parts. */
static inline size_t mpi_face_record_words(uint32_t d) { return 3 + 2 * (size_t)d; }

/* Collective: every face of this rank's range (face_count faces from global
   face face_begin; CSR from 0, global vertex ids) to each distinct part
   among its vertices other than this rank (part_of: this rank's block's;
   the others' from their block owners), checked first with global names:
   every part a rank, every face 3 or more vertices below vtxdist[size] and,
   with repair's repeated_vertices off, none twice in a face. *corner_part
   (caller frees): the part of each corner of the range; *mine (caller
   frees): a bit per face of the range, set for those with this rank among
   their corners' parts, the range's faces this rank keeps, read where they
   are. *recv (caller frees):
   the records this rank gets from the others, each sender's in its face
   order, senders in rank order; *nrecv their words, *nlow those from lower
   ranks. Every rank gets the same status. */
limn_status mpi_local_send_faces(mpi_part *p, local_sub *s, const size_t *vtxdist,
                                 const uint32_t *part_of, size_t face_begin, size_t face_count,
                                 const uint32_t *face_offsets, const uint32_t *face_indices,
                                 const limn_repair_options *repair, uint32_t **corner_part,
                                 uint64_t **mine, uint32_t **recv, size_t *nrecv, size_t *nlow);

/* Collective (mpi_local_census.c): limn_mpi_mesh_repair's census and
   duplicate search read from the sub-meshes (lm->face_ids needed), in
   place of their exchanges: every face at an owned vertex is in its
   sub-mesh, so a vertex's ring, an edge's faces and every copy of a face
   are whole on each rank holding one of their vertices; each is counted on
   the rank owning its lowest vertex. *k summed over the ranks; r gets
   duplicate_faces, first_duplicate_face (SIZE_MAX when none) and _of. The
   sub-mesh keeps the topology built here for its operator. */
struct mpi_mesh_counts;
limn_status mpi_local_census(mpi_part *p, mpi_local_mesh *lm, struct mpi_mesh_counts *k,
                             limn_repair_report *r);

/*
 * Collective over p->comm (p from mpi_part_begin). vtxdist[size + 1]: rank r
 * holds input vertices [vtxdist[r], vtxdist[r + 1]); positions (3 per
 * vertex) and part_of (owning rank of each) are this rank's block. This
 * rank's faces: face_count faces from global face face_begin (CSR from 0,
 * global vertex ids). repair: as limn_mesh_repair's options (NULL: the
 * defaults). Fills *p as mpi_distribute does (same owned-row classes, ghost
 * order and halo; p->has_global stays 0) and opens the device with the rows;
 * every rank gets the same status and message. owned_rows4 (may be NULL)
 * gets the input positions of the owned rows, 4 doubles a row (w = 0), in
 * local order (caller frees): the right-hand side of a solve. stats may be
 * NULL.
 */
limn_status mpi_local_build(mpi_part *p, const size_t *vtxdist, const double *positions,
                            const uint32_t *part_of, size_t face_begin, size_t face_count,
                            const uint32_t *face_offsets, const uint32_t *face_indices,
                            limn_scheme scheme, double alpha, const limn_repair_options *repair,
                            double **owned_rows4, mpi_local_stats *stats);

/* ------------------------------------------------------- mpi_local_comm.c */

/* Collective: rank r gets cnt[r] elements of elem bytes from this rank's
   send (grouped by destination, in rank order); *recv (allocated, caller
   frees) gets every rank's elements in rank order, rcnt[r] of them (rcnt:
   size ints, filled). *total: the elements received. Every rank gets the
   same status. */
limn_status mpi_local_alltoallv(mpi_part *p, const void *send, const int *cnt, size_t elem,
                                void **recv, int *rcnt, size_t *total);

/* Collective: mpi_local_alltoallv with the elements packed by the caller
   once the counts are exchanged: pack(user, to) writes the cnt[r] elements
   for rank r at to[r], which for this rank's own share is their place in
   *recv (no send buffer for them, no copy by the MPI library: at 2 ranks
   most of a rank's faces are its own), for the others a send buffer. */
limn_status mpi_local_alltoallv_packed(mpi_part *p, const int *cnt, size_t elem,
                                       void (*pack)(void *user, char *const *to), void *user,
                                       void **recv, int *rcnt, size_t *total);

/* Collective: for n increasing global ids, the block owners' values (elem
   bytes each, from `mine`, this rank's block of vtxdist) into out. Each
   block owner answers in the order asked, so answers land in id order,
   straight into out; the ids in this rank's own block are answered here,
   outside the exchange. */
limn_status mpi_local_fetch(mpi_part *p, struct local_sub *s, const size_t *vtxdist,
                            const uint32_t *ids, size_t n, const void *mine, size_t elem,
                            void *out);

/* Collective: the bounding box diagonal of every rank's block (pos, nb
   vertices here), as mesh_bbox_diagonal gives it for the whole mesh. */
double mpi_local_diagonal(mpi_part *p, const double *pos, size_t nb);

/* Sorts n keys increasing (radix passes; qsort when short or out of memory). */
void mpi_local_sort(uint64_t *a, size_t n);

/* mpi_local_sort's result for keys spread evenly over their high bits (a
   hash's): one counting pass by the top bits, then each bucket (a few keys
   on average) sorted alone, in place of up to four 16-bit radix passes. */
void mpi_local_sort_uniform(uint64_t *a, size_t n);

/* The distinct values of ids[0 .. n) into distinct, increasing (*nd of
   them; room for n), and each element's place in that list into index[i]:
   a bitmap over the ids' range when it is at most 32 n wide (no sort), else
   a radix sort of the packed (id, element) keys. Same output either way. */
limn_status mpi_local_distinct(limn_context *ctx, const uint32_t *ids, size_t n,
                               uint32_t *distinct, size_t *nd, uint32_t *index);

/* The ranks of ids among the distinct ones by a bitmap of [lo, lo + range)
   and the count of set bits below each word, no sort: add every id, then
   finish, then the rank of any added id (its place in the increasing list
   of the distinct ones) in a few instructions. */
typedef struct mpi_id_rank {
    uint32_t lo;
    size_t words;
    uint64_t *bits;
    size_t *below; /* after finish */
} mpi_id_rank;
/* Room for ids lo..hi; 0 when out of memory (nothing to free then). */
int mpi_id_rank_init(mpi_id_rank *r, uint32_t lo, uint32_t hi);
static inline void mpi_id_rank_add(mpi_id_rank *r, uint32_t id)
{
    uint32_t x = id - r->lo;
    r->bits[x >> 6] |= (uint64_t)1 << (x & 63);
}
/* The counts below each word; the number of distinct ids added. */
size_t mpi_id_rank_finish(mpi_id_rank *r);
/* The distinct ids, increasing, into out (room for finish's count). */
void mpi_id_rank_list(const mpi_id_rank *r, uint32_t *out);
/* The set bits of x, branch-free (SWAR): __builtin_popcountll is a call
   into libgcc on a build without -mpopcnt, and this runs once per corner. */
static inline int mpi_ones64(uint64_t x)
{
    x -= (x >> 1) & 0x5555555555555555u;
    x = (x & 0x3333333333333333u) + ((x >> 2) & 0x3333333333333333u);
    x = (x + (x >> 4)) & 0x0f0f0f0f0f0f0f0fu;
    return (int)((x * 0x0101010101010101u) >> 56);
}
/* On a function whose loop calls mpi_id_rank_of once per corner or id: a second
   copy for CPUs with POPCNT, picked at load time (GCC folds mpi_ones64 into
   the instruction there), the SWAR one elsewhere; nothing off x86-64 GCC. */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__)
#define MPI_POPCNT_CLONES __attribute__((target_clones("popcnt", "default")))
#else
#define MPI_POPCNT_CLONES
#endif
static inline uint32_t mpi_id_rank_of(const mpi_id_rank *r, uint32_t id)
{
    uint32_t x = id - r->lo;
    uint64_t w = r->bits[x >> 6] & (((uint64_t)1 << (x & 63)) - 1);
    return (uint32_t)(r->below[x >> 6] + (size_t)mpi_ones64(w));
}
void mpi_id_rank_free(mpi_id_rank *r);

/* Notes a per-vertex array of `entries` in s->stats. */
void mpi_local_note(struct local_sub *s, size_t entries);

/* --------------------------------------------------------- mpi_local_rows.c */


/* Collective: p's owned rows (classes), ghosts (by owner, then the owner's
   local number, their rules from the owners) and halo from s. */
limn_status mpi_local_rows(mpi_part *p, local_sub *s);

/* Collective (mpi_local_comm.c): p->faces_global (each face counted by the
   lowest part among its vertices) and p->edge_cut (distinct edges between
   parts, counted by the lower one) from the repaired sub-mesh m of s, and
   s->near (freed by mpi_local_rows): a row's columns are vertices of its
   vertex's faces (the operator's stencils), so only a near row can have a
   ghost column. */
limn_status mpi_local_counts(mpi_part *p, local_sub *s, const limn_mesh *m);

#endif
