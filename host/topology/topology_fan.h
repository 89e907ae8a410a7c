/* SPDX-License-Identifier: MIT */
/*
 * One vertex's fan from its ring: its edges as it sees them and the walk
 * that tells whether its corners make one fan (topology_rings.c, where the
 * topology orders each fan; topology_census.c counts them without building
 * the topology, and mpi/mpi_mesh_census.c for a distributed mesh, with the
 * same edges and walk).
 */
#ifndef LIMN_TOPOLOGY_FAN_H
#define LIMN_TOPOLOGY_FAN_H

#include <stdint.h>

/* One edge {v, w} as v sees it. */
typedef struct ring_edge {
    uint32_t w, total, forward; /* uses; forward: the corner going v -> w, or UINT32_MAX */
    uint8_t flags;              /* EDGE_* (topology.h); the walk does not read them */
} ring_edge;

/* v's edges from its 2n ring keys, sorted (corner i's next vertex as
   next << 32 | i << 1, its previous as prev << 32 | i << 1 | 1): one per
   neighbour w, increasing, with its uses, forward corner and flags (one use:
   boundary; more than two: non-manifold; two in the same direction:
   non-manifold and inconsistent); fwd and back get each corner's forward and
   backward edge in e. Returns the edge count (v's valence). */
uint32_t topology_ring_edges(const uint64_t *keys, uint32_t n, ring_edge *e, uint32_t *fwd,
                             uint32_t *back);

/* Whether v's n corners make one fan: walked backwards across edges from a
   corner whose forward edge has one use (so an open fan is covered whole),
   from each corner across its backward edge to that edge's forward corner
   while the edge has two uses. fwd, back: each corner's forward and
   backward edge in e. order (NULL: the answer only) gets ids[i] of each
   corner i in walk order, when n > 1. */
int topology_fan_walk(const ring_edge *e, const uint32_t *fwd, const uint32_t *back, uint32_t n,
                      const uint32_t *ids, uint32_t *order);

#endif
