/* SPDX-License-Identifier: MIT */
/*
 * Distributed vertex partition (issue 14, piece 2): PT-Scotch on the mesh's
 * edge graph with no rank holding the whole graph (internal to limn_mpi).
 *
 * The vertices are in blocks: rank r holds [vtxdist[r], vtxdist[r+1]). The
 * faces are anywhere (each face on exactly one rank, in any distribution).
 * Each face edge goes, in both directions, to the ranks owning its ends;
 * each rank builds its block's symmetric adjacency, sorted, without repeats
 * or self loops, so the graph, and hence the partition, is the same
 * whatever the face distribution; PT-Scotch (SCOTCH_dgraphPart, fixed seed,
 * a fixed strategy) splits it. Isolated vertices and several components are
 * vertices without edges and a disconnected graph. One part, no more
 * vertices than parts, or no edges at all need no Scotch (mpi_partition.c's
 * rules: everything in part 0 | vertex v in part v | contiguous blocks).
 */
#ifndef LIMN_MPI_DGRAPH_H
#define LIMN_MPI_DGRAPH_H

#include "limn.h"

#include <mpi.h>
#include <stddef.h>
#include <stdint.h>

/* Global figures of a partition (the same on every rank). */
typedef struct mpi_dgraph_stats {
    size_t vertices;        /* vtxdist[size] */
    size_t edges;           /* undirected edges of the graph */
    size_t edge_cut;        /* edges whose ends are in different parts */
    size_t part_max;        /* vertices of the largest part */
    size_t part_min;        /* vertices of the smallest part */
    double imbalance;       /* part_max / (vertices / parts): 1 is perfect */
    double seconds;         /* wall time of the call, the slowest rank's */
    double seconds_graph;   /* of which the edge exchange and the adjacency */
} mpi_dgraph_stats;

/* PT-Scotch's strategy flags (SCOTCH_STRATQUALITY, SCOTCH_STRATDEFAULT,
   SCOTCH_STRATSPEED); mpi_dgraph_partition takes QUALITY. */
typedef enum mpi_dgraph_strategy {
    MPI_DGRAPH_QUALITY,
    MPI_DGRAPH_DEFAULT,
    MPI_DGRAPH_SPEED
} mpi_dgraph_strategy;

/*
 * Collective over comm. vtxdist[size+1] (the same on every rank, from 0,
 * non-decreasing); this rank's face_count faces in CSR form, face_offsets
 * from 0, face_indices GLOBAL vertex ids (< vtxdist[size]); parts >= 1.
 * On success *part_of (malloc'd, the caller frees it; vtxdist[rank+1] -
 * vtxdist[rank] entries, at least one allocated) holds the part of each
 * vertex of this rank's block, in [0, parts); stats (may be NULL) the global
 * figures. The same input and rank count give the same parts. On failure
 * every rank returns the same status and message (the lowest failing
 * rank's) and *part_of is NULL.
 */
limn_status mpi_dgraph_partition(limn_context *ctx, MPI_Comm comm, const size_t *vtxdist,
                                 size_t face_count, const uint32_t *face_offsets,
                                 const uint32_t *face_indices, int parts, uint32_t **part_of,
                                 mpi_dgraph_stats *stats);
/* The same with another strategy (perf/partition_compare). */
limn_status mpi_dgraph_partition_with(limn_context *ctx, MPI_Comm comm, const size_t *vtxdist,
                                      size_t face_count, const uint32_t *face_offsets,
                                      const uint32_t *face_indices, int parts,
                                      mpi_dgraph_strategy strategy, uint32_t **part_of,
                                      mpi_dgraph_stats *stats);

#endif
