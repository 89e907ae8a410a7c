/* SPDX-License-Identifier: MIT */
/*
 * One rank's share of a distributed limit operator (README "MPI").
 *
 * The root builds the global operator exactly as the single process does
 * (operator_build_ex, RCM included), partitions the input vertices with METIS
 * and sends each rank the rows of its owned vertices, entries in the global
 * row's order with columns renamed to local numbers. Each row is then summed
 * in the same order as in the single process, so a stencil product gives the
 * same bits on any number of ranks.
 *
 * Local numbering: owned rows, then ghosts. Owned rows are ordered in four
 * classes, each in the global (solve) order:
 *   [0, send_begin)            no ghost column, not needed by another rank
 *   [send_begin, n_interior)   no ghost column, needed by another rank
 *   [n_interior, send_end)     ghost columns, needed by another rank
 *   [send_end, n_owned)        ghost columns, not needed
 * so rows free of ghosts come first (computed while the halo is in flight)
 * and the values other ranks need are one contiguous device range. Ghosts
 * are sorted by owner, then by the owner's local number: what a neighbour
 * sends arrives as one contiguous block.
 */
#ifndef LIMN_MPI_PART_H
#define LIMN_MPI_PART_H

#include "limn_mpi.h"

#include "base/abi.h"
#include "device/device.h"
#include "solve/operator.h"
#include "solve/solve.h"
#include "stencil/stencil.h"

#include <mpi.h>

typedef struct mpi_halo {
    int n_recv, n_send;
    int *recv_rank, *send_rank;
    size_t *recv_off, *recv_cnt;  /* ghost index of each neighbour's block */
    size_t *send_off, *send_cnt;  /* into send_idx */
    uint32_t *send_idx;           /* owned row - send_begin, per neighbour */
    double *stage4;               /* rows [send_begin, send_end), 4 doubles */
    double *send3, *recv3;        /* 3 doubles per value on the wire */
    double *ghost4;               /* ghost rows, 4 doubles */
    MPI_Request *req;             /* n_recv receives, then n_send sends */
} mpi_halo;

typedef struct mpi_part {
    limn_context *ctx;
    MPI_Comm comm;                /* a duplicate of the caller's */
    int rank, size, root;
    int local_size;               /* ranks on this node */
    int partition;                /* limn_mpi_partition of a distributed mesh: SFC or SCOTCH */
    /* the global problem (same on every rank) */
    limn_scheme scheme;
    double alpha, diag;
    size_t n_global, faces_global, nnz_global, edge_cut;
    int reordered;
    /* this rank's rows */
    size_t n_owned, n_ghost, n_interior, send_begin, send_end;
    size_t n_split;               /* interior rows rounded down to whole chunks */
    uint32_t *owned_ids, *ghost_ids; /* input vertex of each local row / ghost */
    uint8_t *owned_rule, *ghost_rule; /* vertex_rule of each row / ghost (CG tiers) */
    double *owned_scale;          /* scheme_limit_row_scale of each owned row (CG) */
    stencil_csr host;             /* owned rows, local columns */
    struct device *dev;
    device_csr all;               /* the owned rows on the device */
    mpi_halo halo;
    limn_mpi_stats stats;
    int echo;                     /* the last failure was another rank's */
    /* root only */
    stencil_operator global;         /* host table and topology, no device copy */
    int has_global;
    size_t *root_off;             /* rank r owns root_ids[root_off[r] .. root_off[r+1]) */
    uint32_t *root_ids;           /* in each rank's local order */
    uint32_t *part_of;            /* rank of each input vertex */
    double *root_buf;             /* 3 doubles per vertex, for scatter and gather */
} mpi_part;

/* --------------------------------------------------------------- mpi_common.c */

/* Duplicates comm, records rank and size, checks the root; every rank gets
   the same status (a bad root is refused everywhere). */
limn_status mpi_part_begin(limn_context *ctx, MPI_Comm comm, const limn_mpi_options *mpi,
                           mpi_part *p);
void mpi_part_end(mpi_part *p);
/* The owned rows' tables (p->all on the device, then p->host) released once
   the last product is done, before the results move (per-rank peak); the
   rest of p stays. mpi_part_end after it is fine. */
void mpi_part_drop_rows(mpi_part *p);
/* p's owned and ghost arrays (ids, rules, scales) and its host row table
   for no owned rows, ng ghosts and nnz entries (none of length 0); 1 when
   all are there (mpi_part_end frees them either way). */
int mpi_part_rows_alloc(mpi_part *p, size_t no, size_t ng, size_t nnz);
/* The owned and ghost arrays alone (the local rows take their table from the
   sub-mesh's operator); 1 when all are there. */
int mpi_part_ids_alloc(mpi_part *p, size_t no, size_t ng);

/*
 * Agreement before a collective phase: every rank passes its own status;
 * all get the status and message of the lowest-numbered rank that failed
 * (a failure that only echoes another rank's, p->echo, gives way to the
 * real one). One Allreduce when all is well.
 */
limn_status mpi_agree(mpi_part *p, limn_status st);
/* mpi_agree over any communicator (rank and size in it; echo: this rank's
   failure only repeats another rank's). */
limn_status mpi_agree_comm(limn_context *ctx, MPI_Comm comm, int rank, int size, int echo,
                           limn_status st);

/* Local norms -> global ones (max exact, sums in double-double so that the
   result does not depend on how MPI associates them), together with a
   failure flag: returns LIMN_ERR_DEVICE with p->echo set when another rank
   failed and this one did not. */
limn_status mpi_reduce_norms(mpi_part *p, limn_status local, const device_norms *in,
                             device_norms *out);
/* A sum over ranks in double-double (the same on every rank). */
double mpi_sum(mpi_part *p, double x);

/* Root's 3 doubles per input vertex -> each rank's owned rows (4 doubles a
   row, w = 0), and back (gather: out on root only). */
limn_status mpi_scatter_rows(mpi_part *p, const double *xyz_root, double *rows4);
limn_status mpi_gather_rows(mpi_part *p, const double *rows4, double *xyz_root);

/* Sets the device slot (local rank) and, unless the user set it, PoCL's
   thread count to the cores this rank may use; then opens the device. */
limn_status mpi_open_device(mpi_part *p);

/* ------------------------------------------------------------ mpi_partition.c */

/* Root: part_of[v] for every input vertex, METIS k-way on the vertex graph
   of the faces (isolated vertices and components included), and the edge
   cut. One rank, or fewer vertices than ranks, needs no METIS. */
limn_status mpi_partition(limn_context *ctx, const limn_mesh *mesh, int parts,
                          uint32_t *part_of, size_t *edge_cut);
/* The edge cut of a given partition (part_of[v] < parts, checked), as
   mpi_partition counts it. */
limn_status mpi_edge_cut(limn_context *ctx, const limn_mesh *mesh, int parts,
                         const uint32_t *part_of, size_t *edge_cut);

/* ----------------------------------------------------------- mpi_distribute.c */

/*
 * Collective: root (mesh != NULL there) builds the global operator (reorder:
 * as limn_interpolate's option), partitions, and sends each rank its rows
 * and halo plan; every rank opens its device and uploads its rows.
 */
limn_status mpi_distribute(mpi_part *p, const limn_mesh *mesh, limn_scheme scheme, double alpha,
                           int reorder);
/* The same with the root's partition given (part_of: a rank per input
   vertex, on the root; NULL: METIS as mpi_distribute). */
limn_status mpi_distribute_part(mpi_part *p, const limn_mesh *mesh, limn_scheme scheme,
                                double alpha, int reorder, const uint32_t *part_of);
/* Every rank: device views of its rows (p->host), halo buffers, statistics
   (mpi_halo.c; used by mpi_distribute and mpi_local_build). */
limn_status mpi_open_rows(mpi_part *p);

/* ----------------------------------------------------------------- mpi_halo.c */

/* Work on a row range of the local table (one device op). */
typedef limn_status (*mpi_rows_fn)(void *user, const device_csr *rows, device_norms *norms);

/*
 * One overlapped product with `table` (p->all, or a table of the same rows):
 * posts the exchange of x's ghost values, runs fn on the rows [0, n_split)
 * (free of ghosts), waits, writes the ghosts into x, runs fn on the rest;
 * *norms gets the local norms of both. With a failure already (prior,
 * or on the way) the device is left alone but every MPI call is still made,
 * so the other ranks never wait in vain; returns the first failure.
 */
limn_status mpi_overlapped(mpi_part *p, const device_csr *table, device_buffer *x,
                           mpi_rows_fn fn, void *user, limn_status prior, device_norms *norms);
/* The same on a float vector (4 floats a row, 3 sent a vertex): the
   corrections of the float path (solve_mixed.c). */
limn_status mpi_overlapped_f(mpi_part *p, const device_csr *table, device_buffer *x_f,
                             mpi_rows_fn fn, void *user, limn_status prior, device_norms *norms);
/* Where a vector of another row layout (the Gauss-Seidel tables, mpi_sgs.c)
   keeps what the halo moves: the send slots of p->halo read rows begin +
   idx[k] of x (staged in stage, 4 doubles a row of [begin, end)), and the
   ghosts land at rows ghost_at .. ghost_at + n_ghost - 1. */
typedef struct mpi_send_view {
    size_t begin, end;
    const uint32_t *idx;
    size_t ghost_at;
    double *stage;
} mpi_send_view;
limn_status mpi_exchange_view(mpi_part *p, const mpi_send_view *v, device_buffer *x,
                              limn_status prior);
/* Just the exchange (x's ghosts made current). */
limn_status mpi_exchange(mpi_part *p, device_buffer *x, limn_status prior);
void mpi_halo_free(mpi_halo *h);

/* ------------------------------------------------------------ mpi_interpolate.c */

/* limn_interpolate_mpi's solve on a part already built (mpi_local_build),
   every rank with its rows: m4 the owned rows' positions (4 doubles a row),
   p4 (owned + ghost rows, 4 doubles) gets the control points of the owned
   rows. Options as limn_interpolate's (checked; the root needs no mesh). */
limn_status mpi_interpolate_part(mpi_part *p, const limn_interpolate_options *o,
                                 const double *m4, double *p4, limn_report *r);

/* ------------------------------------------------------------------- mpi_cg.c */

/* Solver tier of a vertex rule (solve_cg.c's): 0 pinned, 1 crease, 2 smooth. */
int mpi_tier_of(uint8_t rule);

/* ------------------------------------------------------- mpi_sgs_colour.c */

/* Collective, agreed: sgs_colour_rows's colouring (greedy in input order
   within each tier) of the rows of a distributed mesh (p from
   mpi_local_build, p->host alive), computed rank by rank: colour (owned
   then ghost rows, p->n_owned + p->n_ghost) and each tier's count. */
limn_status mpi_sgs_colour_local(mpi_part *p, uint32_t *colour, size_t colours[3]);

/* One tier's block on a rank: every owned row (rows of other tiers empty,
   columns local, ghosts included), b4 (owned rows), x4 (owned and ghost
   rows: the start, and the answer), dinv (one per owned row). */
typedef struct mpi_block {
    stencil_csr s;
    double *b4, *x4, *dinv;
} mpi_block;

/* Solves tier t's block (tier: of every local row; share: its rows' part
   of the mesh, for the product count); collective. */
typedef limn_status (*mpi_block_fn)(mpi_part *p, void *user, const mpi_block *bl,
                                    const int8_t *tier, int t, double tol_abs, int max_iter,
                                    double share, solve_stats *stats);

/* solve_tiers over the ranks: pinned rows P = M, then the crease and the
   smooth block, each by solve_block. LIMN_ERR_TOPOLOGY (no message) on
   every rank when A is not block triangular by vertex rule. */
limn_status mpi_solve_tiers(mpi_part *p, const double *m4, double tol_abs, int max_iter,
                            double *p4, mpi_block_fn solve_block, void *user, solve_stats *stats);

/*
 * The tiered, D-preconditioned CG of solve_cg.c over the ranks: m4 and p4
 * hold this rank's owned rows (4 doubles a row); p4 receives P. Dot products
 * are reduced in double-double. LIMN_ERR_TOPOLOGY (no message) on every
 * rank when A is not block triangular by vertex rule.
 */
limn_status mpi_solve_cg(mpi_part *p, const double *m4, double tol_abs, int max_iter, double *p4,
                         solve_stats *stats);

/* ----------------------------------------------------------- mpi_interpolate.c */

/* The option checks of an interpolation over the ranks (after st, this
   rank's own checks so far), agreed, and the method (auto = chebyshev)
   with its reason in r. */
limn_status mpi_interpolate_method(mpi_part *p, const limn_interpolate_options *o,
                                   limn_status st, limn_method *method, limn_report *r);

/* The solve on p's rows after the checks: m4 the owned rows of M (4 doubles
   a row, w = 0), p4 (owned and ghost rows) gets P's owned rows; *method may
   change (cg falls back to the seeds' iteration where it cannot run); r gets
   the iteration's figures. Collective; agreed. */
limn_status mpi_interpolate_rows(mpi_part *p, const limn_interpolate_options *o,
                                 limn_method *method, const double *m4, double *p4,
                                 limn_report *r);

/* ------------------------------------------------------------------ mpi_sgs.c */

/*
 * The tiered, SGS-preconditioned CG of solve_sgs.c over the ranks, on the
 * root's colouring (broadcast); m4, p4 as mpi_solve_cg. LIMN_ERR_TOPOLOGY
 * (no message) on every rank when A is not block triangular or a block does
 * not suit the sweeps.
 */
limn_status mpi_solve_sgs(mpi_part *p, const double *m4, double tol_abs, int max_iter,
                          double *p4, solve_stats *stats);

/* ---------------------------------------------------------------- mpi_piece.c */

/* Collective, after a result is gathered on root (xyz_root: 3 per input
   vertex): each rank gets its piece in result (may be NULL: dropped). */
limn_status mpi_pieces(mpi_part *p, const limn_mesh *mesh_root, const double *xyz_root,
                       limn_mpi_result *result);

/* The size fields of limn_mpi.h's structs (abi.h). */
extern const abi_layout abi_mpi_options, abi_mpi_stats, abi_mpi_result;

/*
 * The size checks of a limn_*_mpi call, agreed over comm (one Allreduce on
 * it) so that a rank refusing its structs does not leave the others waiting:
 * every rank returns a refusal, the refusing ranks with their own message.
 * Also reads mpi (may be NULL) into *mpi_sized and checks result (may be
 * NULL) into *result_sized.
 */
limn_status mpi_abi_begin(limn_context *ctx, MPI_Comm comm, const char *fn, limn_status st,
                          const limn_mpi_options *mpi, limn_mpi_options *mpi_sized,
                          const limn_mpi_result *result, limn_mpi_result *result_sized);

/* Copies the library-side result into the caller's, within its size; a
   piece the caller's struct cannot hold is freed. */
void mpi_abi_end(limn_mpi_result *result, limn_mpi_result *result_sized);

/* The distributed operator's part of a report r of either kind (limn_report,
   limn_series_report: the same field names) from the distributed part p. */
#define MPI_REPORT_OPERATOR(r, p)                                                                  \
    do {                                                                                           \
        (r)->vertices = (p)->n_global;                                                             \
        (r)->faces = (p)->faces_global;                                                            \
        (r)->scheme = (p)->scheme;                                                                 \
        (r)->alpha = (p)->alpha;                                                                   \
        (r)->bbox_diagonal = (p)->diag;                                                            \
        (r)->stencil_nonzeros = (p)->nnz_global;                                                   \
        snprintf((r)->device, sizeof (r)->device, "%s", (p)->stats.device);                        \
        if ((p)->has_global) { /* the root's build times (no reordering: 0) */                     \
            (r)->seconds_topology = (p)->global.seconds_topology;                                  \
            (r)->seconds_stencil = (p)->global.seconds_stencil + (p)->global.seconds_reorder;      \
        }                                                                                          \
    } while (0)

/* abi_call (base/abi.h) with the MPI structs, for the limn_*_mpi entries:
   c.mpi and c.result are what the *_mpi_sized function takes. */
typedef struct mpi_call {
    abi_call abi;
    limn_mpi_result *caller_result;
    const limn_mpi_options *mpi; /* &mo or NULL, &res or NULL */
    limn_mpi_result *result;
    limn_mpi_options mo;
    limn_mpi_result res;
} mpi_call;

/* abi_enter, then mpi_abi_begin (agreed over comm even after a refusal). */
limn_status mpi_enter(mpi_call *c, limn_context *ctx, MPI_Comm comm, const char *fn,
                      const abi_layout *options_layout, const void *options,
                      const abi_layout *report_layout, void *report, const limn_mpi_options *mpi,
                      limn_mpi_result *result, limn_mesh **out);
/* After an entered call: the report and result copied out; returns st. */
limn_status mpi_leave(mpi_call *c, limn_status st);

#endif
