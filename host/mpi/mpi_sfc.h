/* SPDX-License-Identifier: MIT */
/*
 * Space-filling-curve vertex partition (issue 14): the default partition of
 * the distributed pipeline, PT-Scotch (mpi_dgraph.h) the alternative.
 *
 * Every vertex gets the 3-D Hilbert key of its position (21 bits an axis in
 * the bounding cube of the whole mesh, 63 bits), ties broken by its global
 * id; the vertices are cut along that order into parts of exactly
 * n * (q + 1) / parts - n * q / parts vertices. Cut q is the vertex of
 * rank n (q + 1) / parts in that order: an Allreduce of a histogram of the
 * keys' top 16 bits names its bucket and its rank there; the vertices of
 * the buckets holding a cut are sorted on each rank, and the rest of the
 * 95-bit (key, id) value is found digit by digit (10 digits of 7 or 8 bits),
 * one Allreduce of (parts - 1) x 255 counts a digit, each count a binary
 * search in a sorted bucket: O(n / P) work per rank (no sort of the block),
 * no edge exchange, no rank holding more than its block. The
 * parts depend on the positions, the ids and the part count only: not on
 * how the vertices are split into blocks, nor on the faces.
 */
#ifndef LIMN_MPI_SFC_H
#define LIMN_MPI_SFC_H

#include "mpi/mpi_part.h"

#include <stddef.h>
#include <stdint.h>

typedef struct mpi_sfc_stats {
    size_t part_max, part_min; /* vertices of the largest and smallest part */
    double imbalance;          /* part_max / (vertices / parts): 1 is perfect */
    double seconds;            /* wall time of the call, the slowest rank's */
} mpi_sfc_stats;

/* The Hilbert key of a point with integer coordinates below 2^21 (each
   axis), 63 bits; consecutive keys are neighbouring cells. */
uint64_t mpi_sfc_hilbert(uint32_t x, uint32_t y, uint32_t z);

/* mpi_sfc_hilbert's keys by a state machine over the 21 levels, top first:
   each level's 3 input bits and the state (the axis exchanges and
   inversions Skilling's loop has made below that level, and the parity of
   the Gray code above it) give the key's 3 bits and the next state, one
   table lookup for two levels (pair, below) in place of the loop's dozens
   of operations. The
   partition's keys; tests/test_mpi_sfc.c checks them against
   mpi_sfc_hilbert. next[state * 8 + (x << 2 | y << 1 | z)] = next state
   << 3 | the key's 3 bits (states of unused codes stay 0). */
#define MPI_SFC_STATES 432 /* (27 axis codes, 6 of them permutations) x 8 inversions x 2 */
/* The states reachable from the top level's, numbered densely, and two
   levels a lookup: pair[dense * 64 + (level bits << 3 | next level's bits)]
   = dense next state << 6 | the key's 6 bits (the same keys, half the
   dependent lookups; 96 states x 64 x 2 bytes stay in L1). */
#define MPI_SFC_REACHABLE 96
typedef struct mpi_sfc_table {
    uint16_t next[MPI_SFC_STATES * 8];
    uint16_t dense[MPI_SFC_STATES];
    uint16_t pair[MPI_SFC_REACHABLE * 64];
} mpi_sfc_table;
void mpi_sfc_table_init(mpi_sfc_table *t);
uint64_t mpi_sfc_hilbert_table(const mpi_sfc_table *t, uint32_t x, uint32_t y, uint32_t z);
/* Four keys at once (cell[3 j ..] = x, y, z of key j): the same keys, the four
   lookup chains overlapped. */
void mpi_sfc_hilbert_table4(const mpi_sfc_table *t, const uint32_t cell[12], uint64_t key[4]);

/*
 * Collective over p->comm. vtxdist[size + 1] as mpi_dgraph_partition's;
 * positions: 3 doubles per vertex of this rank's block (non-finite ones are
 * put at the cube's lowest corner); parts >= 1. *part_of (malloc'd, at
 * least one entry, caller frees) gets the part of each block vertex, in
 * [0, parts); stats (may be NULL) the global figures. On failure every
 * rank gets the same status and message and *part_of is NULL.
 */
limn_status mpi_sfc_partition(mpi_part *p, const size_t *vtxdist, const double *positions,
                              int parts, uint32_t **part_of, mpi_sfc_stats *stats);

#endif
