/* SPDX-License-Identifier: MIT */
/*
 * corner_edge on request: the edge leaving each corner is the inverse of
 * edge_corners, which only refinement reads (child faces name their parent's
 * edges). The build leaves it out: its stores land all over the corner
 * array, and interpolation, info and the series never read it.
 */
#include "base/context.h"
#include "base/large_alloc.h"
#include "base/parallel.h"
#include "topology/topology.h"

#include <stdlib.h>

static int invert_range(void *arg, size_t begin, size_t end)
{
    topology *t = arg;
    for (size_t e = begin; e < end; e++)
        for (uint32_t j = t->edge_corner_offsets[e]; j < t->edge_corner_offsets[e + 1]; j++)
            t->corner_edge[t->edge_corners[j]] = (uint32_t)e;
    return 0;
}

limn_status topology_corner_edges(limn_context *ctx, topology *t)
{
    if (t->corner_edge)
        return LIMN_OK;
    size_t nc = t->corner_count;
    t->corner_edge = large_malloc((nc ? nc : 1) * sizeof *t->corner_edge);
    if (!t->corner_edge)
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for the edges of %zu corners", nc);
    /* every corner is in exactly one edge's list: each range writes its own
       edges' corners, whatever the thread count */
    parallel_run(t->edge_count, parallel_threads(ctx, (uint64_t)nc * 12), invert_range, t);
    if (t->lent) /* the mesh's own keeps it (topology_free puts that one back) */
        t->lent->corner_edge = t->corner_edge;
    return LIMN_OK;
}
