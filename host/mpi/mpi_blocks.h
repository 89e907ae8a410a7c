/* SPDX-License-Identifier: MIT */
/*
 * Records of vertices (or faces) spread over the ranks in blocks: rank r
 * holds items [dist[r], dist[r+1]) of a global numbering (dist has size + 1
 * entries, dist[0] = 0). Used where no rank may hold the whole mesh: a rank
 * asks the owners of the blocks for the records of the ids it needs, or
 * stores records into their blocks. Collective over p->comm; every rank gets
 * the same status (agreed before any exchange), with the message of the
 * lowest failing rank.
 */
#ifndef LIMN_MPI_BLOCKS_H
#define LIMN_MPI_BLOCKS_H

#include "mpi/mpi_part.h"

#include <stddef.h>
#include <stdint.h>

/* The rank whose block holds id (dist sorted, id < dist[size]). */
int mpi_blocks_owner(const size_t *dist, int size, size_t id);

/* out[i] = the width-byte record of ids[i] (global, < dist[size]), read from
   its owner's `block` (this rank's records, dist[rank+1] - dist[rank] of
   them). Ids may repeat and come in any order. */
limn_status mpi_blocks_fetch(mpi_part *p, const size_t *dist, const void *block, size_t width,
                             size_t n, const uint32_t *ids, void *out);

/* The inverse: record values[i] of ids[i] written into its owner's `block`.
   Every id of a block is given by exactly one rank (the caller's contract:
   a partition of the ids); the others' entries are left as they are. */
limn_status mpi_blocks_store(mpi_part *p, const size_t *dist, size_t n, const uint32_t *ids,
                             const void *values, size_t width, void *block);

/* dist from each rank's count (an Allgather): dist[0] = 0, dist[r+1] =
   dist[r] + count of rank r. dist: size + 1 entries, the caller's. */
void mpi_blocks_dist(mpi_part *p, size_t count, size_t *dist);

#endif
