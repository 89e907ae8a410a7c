/* SPDX-License-Identifier: MIT */
/*
 * Cores inside this process's CPU binding (hwloc): the count the OpenCL
 * runtime is given (device/threads.h) and the host threads' default
 * (parallel.h), so both sides of a run use the same cores.
 */
#ifndef LIMN_BASE_CORES_H
#define LIMN_BASE_CORES_H

#include <hwloc.h>

/* Cores of topo with at least one PU in set; PUs in set when the topology
   has no core level. 0 for an empty set. */
unsigned cores_count(hwloc_topology_t topo, hwloc_const_cpuset_t set);

/* Cores inside this process's CPU binding; 0 with a reason in why on failure. */
unsigned cores_in_binding(char *why, size_t why_size);

#endif
