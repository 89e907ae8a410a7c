/* SPDX-License-Identifier: MIT */
/* Cores inside a CPU binding, counted with hwloc (cores.h). */
#include "base/cores.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>

unsigned cores_count(hwloc_topology_t topo, hwloc_const_cpuset_t set)
{
    /* cores, not PUs: the kernels are memory bound (DESIGN.md §6), and SMT
       siblings share one core's load/store bandwidth */
    hwloc_obj_type_t type =
        hwloc_get_type_depth(topo, HWLOC_OBJ_CORE) >= 0 ? HWLOC_OBJ_CORE : HWLOC_OBJ_PU;
    unsigned n = 0;
    for (hwloc_obj_t obj = NULL; (obj = hwloc_get_next_obj_by_type(topo, type, obj));)
        n += hwloc_bitmap_intersects(obj->cpuset, set) ? 1u : 0u;
    return n;
}

unsigned cores_in_binding(char *why, size_t why_size)
{
    hwloc_topology_t topo;
    if (hwloc_topology_init(&topo) != 0) {
        snprintf(why, why_size, "hwloc_topology_init failed");
        return 0;
    }
#if HWLOC_API_VERSION >= 0x00020100
    /* hwloc's opencl plugin would query the OpenCL platforms itself, before
       the environment is set: keep it out */
    hwloc_topology_set_components(topo, HWLOC_TOPOLOGY_COMPONENTS_FLAG_BLACKLIST, "opencl");
#endif
    hwloc_topology_set_io_types_filter(topo, HWLOC_TYPE_FILTER_KEEP_NONE);
    hwloc_topology_set_cache_types_filter(topo, HWLOC_TYPE_FILTER_KEEP_NONE);
    hwloc_topology_set_icache_types_filter(topo, HWLOC_TYPE_FILTER_KEEP_NONE);
    unsigned n = 0;
    hwloc_cpuset_t set = NULL;
    if (hwloc_topology_load(topo) != 0) {
        snprintf(why, why_size, "hwloc_topology_load: %s", strerror(errno));
    } else if (!(set = hwloc_bitmap_alloc())) {
        snprintf(why, why_size, "out of memory");
    } else if (hwloc_get_cpubind(topo, set, HWLOC_CPUBIND_PROCESS) != 0) {
        snprintf(why, why_size, "hwloc_get_cpubind: %s", strerror(errno));
    } else if ((n = cores_count(topo, set)) == 0) {
        snprintf(why, why_size, "the CPU binding holds no core that hwloc knows");
    }
    hwloc_bitmap_free(set);
    hwloc_topology_destroy(topo);
    return n;
}
