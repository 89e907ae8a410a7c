/* SPDX-License-Identifier: MIT */
/*
 * limn_mpi_mesh_subdivide: limn_subdivide with no rank holding the whole
 * mesh. Every level is one mpi_refine_level (each rank refines its star and
 * keeps its own points, numbered as the single process numbers them), the
 * limit (--limit) a last product on the finest level's stars; the surface
 * is a distributed mesh, written in parallel by limn_mpi_mesh_write. Every
 * point is computed from the same parents with the same weights in the
 * same order as one process computes it, so the file is its bytes.
 */
#include "mpi/mpi_refine.h"

#include "base/context.h"
#include "mpi/mpi_mesh.h"
#include "refine/refine.h"
#include "device/device.h"
#include "device/choice/choice.h"
#include "mesh/check.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static limn_status check_options(limn_context *ctx, const limn_subdivide_options *o,
                                 limn_mpi_mesh **surface)
{
    const char *fn = "limn_mpi_mesh_subdivide";
    if (!surface)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "%s: surface is NULL", fn);
    limn_status st = check_scheme(ctx, fn, o->scheme);
    if (!st)
        st = check_count(ctx, fn, "levels", o->levels, 0, LIMN_MAX_SUBDIVIDE_LEVELS,
                         "LIMN_MAX_SUBDIVIDE_LEVELS");
    if (!st && !(o->alpha >= 0.0 && o->alpha <= 1.0))
        st = ctx_fail(ctx, LIMN_ERR_ARGUMENT, "%s: alpha is %g; it must lie in [0, 1]", fn,
                      o->alpha);
    return st;
}

/* The share of the single process's estimate one of P ranks holds:
   test_mpi_refine bounds each rank's per-vertex arrays by 1/P + 0.15 of a
   level's vertices; measured peaks (docs/mpi.md, "Refinement over ranks"):
   0.61x of one process at 2 ranks, 0.34x at 4. */
static double rank_share(int ranks)
{
    double s = 1.0 / ranks + 0.2; /* 0.05 of margin */
    return s < 1.0 ? s : 1.0;
}

limn_status mpi_refine_budget(mpi_part *p, const limn_mpi_mesh *mesh, limn_scheme scheme,
                              int levels, int limit, size_t max_memory, size_t *estimate)
{
    mpi_mesh_counts k = mesh->counts;
    limn_status st = mesh->has_counts ? LIMN_OK : mpi_mesh_census(p, mesh, &k);
    if (st)
        return st;
    unsigned long long corners = mesh->slice.face_offsets[mesh->slice.face_count], c = 0;
    MPI_Allreduce(&corners, &c, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, p->comm);
    double v = (double)mesh->vertex_dist[p->size], f = (double)mesh->face_dist[p->size];
    double e = ((double)c + (double)k.boundary_edges) / 2.0;
    size_t nv, nf, ni, whole;
    refine_estimate_counts(v, f, (double)c, e, scheme, levels, limit, &nv, &nf, &ni, &whole);
    size_t runtime = whole < REFINE_RUNTIME_BYTES ? whole : REFINE_RUNTIME_BYTES;
    size_t est = (size_t)((double)(whole - runtime) * rank_share(p->size)) + runtime;
    size_t on_node = p->local_size > 0 ? (size_t)p->local_size : 1;
    size_t budget = max_memory ? max_memory : context_max_memory(NULL) / on_node;
    *estimate = est;
    if (est > budget)
        st = ctx_fail(p->ctx, LIMN_ERR_MEMORY,
                      "refining %zu vertices to level %d on %d ranks makes %zu vertices and %zu "
                      "faces and needs about %.2f GiB a rank, over the limit of %.2f GiB a "
                      "rank: lower --levels, use more ranks or raise --max-memory; nothing was "
                      "written",
                      mesh->vertex_dist[p->size], levels, p->size, nv, nf,
                      (double)est / (1 << 30), (double)budget / (1 << 30));
    return mpi_agree(p, st);
}

/* The levels and the limit from mesh; *out the finest, in even blocks. */
static limn_status refine_levels(mpi_part *p, const limn_mpi_mesh *mesh,
                                 const limn_subdivide_options *o, limn_subdivide_report *r,
                                 limn_mpi_mesh **out, mpi_refine_stats *stats)
{
    mpi_refine_stats rs = {0};
    mpi_rmesh cur, next;
    limn_status st = mpi_rmesh_of(p, mesh, &cur);
    for (int k = 0; !st && k < o->levels; k++) {
        st = mpi_refine_level(p, &cur, r->scheme, k == 0 ? r->alpha : 0.0, &next, &rs);
        mpi_rmesh_free(&cur);
        if (!st)
            cur = next;
        ctx_progress(p->ctx, "refine", (double)(k + 1) / (double)o->levels);
    }
    double t0 = MPI_Wtime();
    /* alpha acts on the first step only: past level 0 the limit is standard */
    if (!st && o->limit)
        st = mpi_refine_limit(p, &cur, r->scheme, o->levels == 0 ? r->alpha : 0.0, &rs);
    r->seconds_limit = o->limit ? MPI_Wtime() - t0 : 0.0;
    rs.owned = cur.n_owned;
    if (!st)
        st = mpi_rmesh_to_mesh(p, &cur, out);
    mpi_rmesh_free(&cur);
    r->seconds_plan = rs.seconds_plan;
    r->seconds_apply = rs.seconds_apply;
    unsigned long long nnz = rs.stencil_nonzeros, all = 0;
    MPI_Allreduce(&nnz, &all, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, p->comm);
    r->stencil_nonzeros = (size_t)all;
    if (stats)
        *stats = rs;
    return st;
}

/* limn_mpi_mesh_subdivide on structs of this library's layout. */
static limn_status subdivide_sized(limn_context *ctx, const limn_mpi_mesh *mesh,
                                   const limn_subdivide_options *o, limn_mpi_mesh **surface,
                                   limn_subdivide_report *r, const limn_mpi_options *mpi,
                                   limn_mpi_result *result, mpi_refine_stats *stats)
{
    memset(r, 0, sizeof *r);
    mpi_part p;
    limn_status st = mpi_mesh_part(ctx, mesh, mpi, &p);
    if (p.comm == MPI_COMM_NULL)
        return st;
    mpi_mesh_drop_sub(mesh); /* no rows from the repair's sub-mesh here */
    if (!st)
        st = check_options(ctx, o, surface);
    struct device *dev = NULL;
    if (!st)
        st = device_get(ctx, &dev);
    st = mpi_agree(&p, st);
    if (!st)
        st = mpi_mesh_check(&p, "limn_mpi_mesh_subdivide", mesh);
    limn_scheme scheme = LIMN_SCHEME_AUTO;
    if (!st)
        st = mpi_mesh_scheme(&p, mesh, o->scheme, &scheme);
    if (!st)
        st = mpi_refine_budget(&p, mesh, scheme, o->levels, o->limit, o->max_memory,
                               &r->estimated_bytes);
    r->input_vertices = mesh->vertex_dist[p.size];
    r->input_faces = mesh->face_dist[p.size];
    r->levels = o->levels;
    r->limit = o->limit;
    r->scheme = scheme;
    r->alpha = scheme == LIMN_SCHEME_CATMARK ? o->alpha : 0.0;
    if (dev)
        snprintf(r->device, sizeof r->device, "%s", dev->name);
    limn_mpi_mesh *out = NULL;
    mpi_refine_stats rs = {0};
    double t0 = MPI_Wtime();
    if (!st)
        st = refine_levels(&p, mesh, o, r, &out, &rs);
    if (!st) {
        r->vertices = out->vertex_dist[p.size];
        r->faces = out->face_dist[p.size];
        *surface = out;
    }
    if (stats)
        *stats = rs;
    if (result) {
        result->stats.owned = rs.owned;
        result->stats.seconds_solve = MPI_Wtime() - t0;
        if (dev)
            snprintf(result->stats.device, sizeof result->stats.device, "%s", dev->name);
    }
    mpi_part_end(&p);
    return st;
}

limn_status mpi_mesh_subdivide(limn_context *ctx, const limn_mpi_mesh *mesh,
                               const limn_subdivide_options *options, limn_mpi_mesh **surface,
                               limn_subdivide_report *report, const limn_mpi_options *mpi,
                               limn_mpi_result *result, mpi_refine_stats *stats)
{
    if (!mesh)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "limn_mpi_mesh_subdivide: the mesh is NULL");
    mpi_call c;
    limn_status st = mpi_enter(&c, ctx, mesh->comm, "limn_mpi_mesh_subdivide",
                               &abi_subdivide_options, options, &abi_subdivide_report, report,
                               mpi, result, NULL);
    return st ? st
              : mpi_leave(&c, subdivide_sized(ctx, mesh, c.abi.options, surface, c.abi.report,
                                              c.mpi, c.result, stats));
}

limn_status limn_mpi_mesh_subdivide(limn_context *ctx, const limn_mpi_mesh *mesh,
                                    const limn_subdivide_options *options,
                                    limn_mpi_mesh **surface, limn_subdivide_report *report,
                                    const limn_mpi_options *mpi, limn_mpi_result *result)
{
    return mpi_mesh_subdivide(ctx, mesh, options, surface, report, mpi, result, NULL);
}
