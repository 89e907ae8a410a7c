/* SPDX-License-Identifier: MIT */
/*
 * limn_mpi_mesh_denoise_features: limn_denoise_features on a distributed
 * mesh, no rank holding the whole mesh (mpi_features.h for the patch). Each
 * rank runs the single process's rounds (features.h: feature_passes) on its
 * patch, the ghosts refreshed between the steps (feature_sync); sigma_s is
 * the single process's sum carried from rank to rank in face order, and
 * keep_volume scales as limn_mpi_mesh_denoise does (mpi_mesh_keep_volume),
 * so the result is the single process's bits.
 */
#include "mpi/mpi_features.h"
#include "base/large_alloc.h"

#include "base/context.h"
#include "mesh/mesh.h"
#include "series/features.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The tag of the running spacing sum passed from rank to rank. */
enum { SPACING_TAG = 7161 };

typedef struct features_mpi {
    mpi_part *p;
    const limn_mpi_mesh *mesh;
    mpi_feature_patch fp;
    feature_mesh fm;
    feature_run run;
    double *n;
} features_mpi;

/* One ghost refresh (faces: normals, else positions), timed and counted. */
static limn_status refresh(features_mpi *f, limn_status st, int faces, double *v)
{
    double t0 = MPI_Wtime();
    st = mpi_agree(f->p, st);
    if (!st)
        st = faces ? mpi_feature_sync_faces(f->p, f->mesh, &f->fp, v)
                   : mpi_feature_sync_vertices(f->p, f->mesh, &f->fp, v);
    f->p->stats.exchanges++;
    f->p->stats.seconds_halo += MPI_Wtime() - t0;
    return st;
}

static limn_status sync_normals(void *user, limn_status st, double *n)
{
    return refresh(user, st, 1, n);
}

static limn_status sync_positions(void *user, limn_status st, double *x)
{
    return refresh(user, st, 0, x);
}

/* The block rows' noise histogram summed over the ranks (integer counts:
   the single process's in any order). */
static limn_status sync_counts(void *user, limn_status st, uint64_t *bins, size_t n)
{
    features_mpi *f = user;
    st = mpi_agree(f->p, st);
    if (!st)
        MPI_Allreduce(MPI_IN_PLACE, bins, (int)n, MPI_UINT64_T, MPI_SUM, f->p->comm);
    return st;
}

/* feature_mean_spacing of the whole mesh: the block rows' distances added
   to the previous rank's running sum (the single process's order). */
static double chained_spacing(features_mpi *f)
{
    mpi_part *p = f->p;
    double sum = 0.0;
    size_t count = 0, begin = f->fp.face_base;
    if (p->rank > 0)
        MPI_Recv(&sum, 1, MPI_DOUBLE, p->rank - 1, SPACING_TAG, p->comm, MPI_STATUS_IGNORE);
    sum = feature_spacing_add(&f->fm, begin, begin + f->mesh->slice.face_count, sum, &count);
    if (p->rank + 1 < p->size)
        MPI_Send(&sum, 1, MPI_DOUBLE, p->rank + 1, SPACING_TAG, p->comm);
    MPI_Bcast(&sum, 1, MPI_DOUBLE, p->size - 1, p->comm);
    uint64_t mine = count, all = 0;
    MPI_Allreduce(&mine, &all, 1, MPI_UINT64_T, MPI_SUM, p->comm);
    return all ? sum / (double)all : 0.0;
}

/* series_check_finite over the block vertices: the lowest failing vertex
   of the whole mesh named on every rank. */
static limn_status check_finite(features_mpi *f)
{
    const double *x = f->fp.mesh->positions + 3 * f->fp.vertex_base;
    uint64_t bad = UINT64_MAX, lowest = UINT64_MAX;
    for (size_t i = 0; i < 3 * f->mesh->slice.vertex_count && bad == UINT64_MAX; i++)
        if (!isfinite(x[i]))
            bad = f->mesh->vertex_dist[f->p->rank] + i / 3;
    MPI_Allreduce(&bad, &lowest, 1, MPI_UINT64_T, MPI_MIN, f->p->comm);
    if (lowest == UINT64_MAX)
        return LIMN_OK;
    return ctx_fail(f->p->ctx, LIMN_ERR_NO_CONVERGENCE,
                    "feature denoising produced a non-finite coordinate at vertex %llu; nothing "
                    "was written (use fewer steps or terms)",
                    (unsigned long long)lowest);
}

/* The patch, its face operator and the device, agreed. */
static limn_status features_open(features_mpi *f, limn_series_report *r)
{
    mpi_part *p = f->p;
    double t0 = MPI_Wtime();
    limn_status st = mpi_feature_patch_build(p, f->mesh, &f->fp);
    if (st)
        return st;
    st = feature_mesh_build(p->ctx, f->fp.mesh, &f->fm);
    if (!st)
        st = feature_run_open(p->ctx, &f->fm, &f->run);
    size_t nf = f->fp.mesh->face_count;
    if (!st && !(f->n = large_malloc(3 * (nf ? nf : 1) * sizeof *f->n)))
        st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu faces", nf);
    st = mpi_agree(p, st);
    r->seconds_stencil = MPI_Wtime() - t0;
    p->stats.seconds_distribute = r->seconds_stencil;
    if (st)
        return st;
    p->stats.owned = f->mesh->slice.vertex_count;
    p->stats.ghosts = f->fp.vertex_ghosts;
    const stencil_csr *w = &f->fm.ring;
    uint64_t mine = w->row_offsets[f->fp.face_base + f->mesh->slice.face_count] -
                    w->row_offsets[f->fp.face_base],
             all = 0;
    MPI_Allreduce(&mine, &all, 1, MPI_UINT64_T, MPI_SUM, p->comm);
    r->stencil_nonzeros = (size_t)all;
    snprintf(r->device, sizeof r->device, "%s", f->run.dev->name);
    snprintf(p->stats.device, sizeof p->stats.device, "%s", f->run.dev->name);
    return LIMN_OK;
}

static void features_close(features_mpi *f)
{
    free(f->n);
    if (f->run.dev)
        feature_run_close(&f->run);
    feature_mesh_free(&f->fm);
    mpi_feature_patch_free(&f->fp);
}

/* The rounds on the patch, then the block vertices as *out. */
static limn_status features_run(mpi_part *p, const limn_mpi_mesh *mesh,
                                const limn_feature_options *o, limn_mpi_mesh **out,
                                limn_series_report *r)
{
    features_mpi f;
    memset(&f, 0, sizeof f);
    f.p = p;
    f.mesh = mesh;
    limn_status st = features_open(&f, r);
    double *x = f.fp.mesh ? f.fp.mesh->positions : NULL;
    if (!st) {
        feature_faces_update(&f.fm, x);
        f.fm.sigma_s = o->sigma_s > 0.0 ? o->sigma_s : chained_spacing(&f);
        size_t begin = f.fp.face_base;
        feature_sync sync = {sync_normals, sync_positions, sync_counts, begin,
                             begin + mesh->slice.face_count, &f};
        double t1 = MPI_Wtime();
        st = mpi_agree(p, feature_passes(p->ctx, &f.fm, &f.run, o, x, f.n, r, &sync));
        r->seconds_compute = MPI_Wtime() - t1;
        p->stats.seconds_solve = r->seconds_compute;
        p->stats.seconds_compute = r->seconds_compute - p->stats.seconds_halo;
    }
    if (!st)
        st = mpi_agree(p, check_finite(&f));
    size_t nb = mesh->slice.vertex_count;
    double *block = NULL;
    if (!st && !(block = large_malloc(3 * (nb ? nb : 1) * sizeof *block)))
        st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu vertices", nb);
    st = mpi_agree(p, st);
    if (!st) {
        memcpy(block, x + 3 * f.fp.vertex_base, 3 * nb * sizeof *block);
        st = mpi_mesh_control_of(p, mesh, block, out);
    } else {
        free(block);
    }
    if (!st && o->keep_volume)
        st = mpi_agree(p, mpi_mesh_keep_volume(p, mesh, *out));
    features_close(&f);
    return st;
}

/* limn_mpi_mesh_denoise_features on structs of this library's layout. */
static limn_status features_sized(limn_context *ctx, const limn_mpi_mesh *mesh,
                                  const limn_feature_options *o, limn_mpi_mesh **out,
                                  limn_series_report *r, const limn_mpi_options *mpi,
                                  limn_mpi_result *result)
{
    const char *fn = "limn_mpi_mesh_denoise_features";
    mpi_part p;
    memset(r, 0, sizeof *r);
    limn_status st = mpi_mesh_part(ctx, mesh, mpi, &p);
    if (p.comm == MPI_COMM_NULL)
        return st;
    mpi_mesh_drop_sub(mesh); /* no rows from the repair's sub-mesh here */
    if (!st)
        st = feature_check_options(ctx, fn, o);
    if (!st && !out)
        st = ctx_fail(ctx, LIMN_ERR_ARGUMENT, "%s: out is NULL", fn);
    st = mpi_agree(&p, st);
    size_t nv = mesh->vertex_dist[mesh->size], nf = mesh->face_dist[mesh->size];
    if (!st && (nv == 0 || nf == 0))
        st = ctx_fail(ctx, LIMN_ERR_TOPOLOGY, "the mesh has no %s", nv ? "faces" : "vertices");
    if (!st)
        st = mpi_mesh_check(&p, fn, mesh);
    if (!st && o->keep_volume)
        st = mpi_mesh_check_closed(&p, mesh);
    r->vertices = nv;
    r->faces = nf;
    if (!st)
        r->bbox_diagonal = mpi_mesh_bbox_diagonal(&p, mesh);
    if (!st)
        st = features_run(&p, mesh, o, out, r);
    if (st && out) {
        limn_mpi_mesh_destroy(*out);
        *out = NULL;
    }
    if (result)
        result->stats = p.stats;
    mpi_part_end(&p);
    return st;
}

limn_status limn_mpi_mesh_denoise_features(limn_context *ctx, const limn_mpi_mesh *mesh,
                                           const limn_feature_options *options,
                                           limn_mpi_mesh **out, limn_series_report *report,
                                           const limn_mpi_options *mpi, limn_mpi_result *result)
{
    const char *fn = "limn_mpi_mesh_denoise_features";
    if (out)
        *out = NULL;
    if (!mesh)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "%s: the mesh is NULL", fn);
    mpi_call c;
    limn_status st = mpi_enter(&c, ctx, mesh->comm, fn, &abi_feature_options, options,
                               &abi_series_report, report, mpi, result, NULL);
    return st ? st
              : mpi_leave(&c, features_sized(ctx, mesh, c.abi.options, out, c.abi.report, c.mpi,
                                             c.result));
}
