/* SPDX-License-Identifier: MIT */
/* The previous (sequential) topology_build, the oracle of test_topology. */
#ifndef LIMN_TOPOLOGY_PREVIOUS_H
#define LIMN_TOPOLOGY_PREVIOUS_H

#include "topology/topology.h"

limn_status topology_previous_build(limn_context *ctx, const limn_mesh *mesh, topology *out);
void topology_previous_free(topology *topo);

#endif
