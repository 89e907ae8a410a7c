/* SPDX-License-Identifier: MIT */
/* limn_subdivide: refine the control mesh into the surface (the limit
   positions of --limit on the device). */
#include "base/abi.h"
#include "mesh/check.h"
#include "base/context.h"
#include "device/device.h"
#include "mesh/mesh.h"
#include "solve/operator.h"
#include "refine/refine.h"
#include "base/clock.h"
#include "device/choice/choice.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

void limn_subdivide_options_default(limn_subdivide_options *o)
{
    abi_default(&abi_subdivide_options, o);
}

static size_t physical_memory(void)
{
    long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGE_SIZE);
    return pages > 0 && size > 0 ? (size_t)pages * (size_t)size : (size_t)8 << 30;
}

static limn_status check_budget(limn_context *ctx, const limn_mesh *mesh, limn_scheme scheme,
                                const limn_subdivide_options *o, size_t *vertices, size_t *faces,
                                size_t *peak_bytes)
{
    size_t v, f, idx, peak;
    refine_estimate(mesh, scheme, o->levels, o->limit, &v, &f, &idx, &peak);
    *vertices = v;
    *faces = f;
    *peak_bytes = peak;
    size_t budget = o->max_memory ? o->max_memory : physical_memory() / 4 * 3;
    if (peak > budget)
        return ctx_fail(ctx, LIMN_ERR_MEMORY,
                         "refining %zu vertices to level %d makes %zu vertices and %zu faces and "
                         "needs about %.2f GiB, over the limit of %.2f GiB: lower --levels or "
                         "raise --max-memory; nothing was written",
                         mesh->vertex_count, o->levels, v, f, (double)peak / (1 << 30),
                         (double)budget / (1 << 30));
    return LIMN_OK;
}

/* The options both entry points share: scheme, levels (<= LIMN_MAX_SUBDIVIDE_LEVELS), alpha. */
static limn_status check_options(limn_context *ctx, const char *fn,
                                 const limn_subdivide_options *o)
{
    limn_status st = check_scheme(ctx, fn, o->scheme);
    if (!st)
        st = check_count(ctx, fn, "levels", o->levels, 0, LIMN_MAX_SUBDIVIDE_LEVELS,
                         "LIMN_MAX_SUBDIVIDE_LEVELS");
    if (!st && !(o->alpha >= 0.0 && o->alpha <= 1.0))
        st = ctx_fail(ctx, LIMN_ERR_ARGUMENT, "%s: alpha is %g; it must lie in [0, 1]", fn,
                       o->alpha);
    return st;
}

limn_status limn_subdivide_estimate(limn_context *ctx, const limn_mesh *mesh,
                                    const limn_subdivide_options *options, size_t *vertices,
                                    size_t *faces, size_t *peak_bytes)
{
    if (!ctx)
        return LIMN_ERR_ARGUMENT;
    ctx_clear(ctx);
    if (!mesh || !options || !vertices || !faces || !peak_bytes)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "limn_subdivide_estimate: %s is NULL",
                         !mesh ? "mesh" : !options ? "options" : !vertices ? "vertices"
                                        : !faces ? "faces" : "peak_bytes");
    limn_subdivide_options sized;
    limn_subdivide_options_default(&sized);
    limn_status st = abi_options_in(ctx, "limn_subdivide_estimate", "options",
                                    &abi_subdivide_options, options, &sized);
    if (st)
        return st;
    options = &sized;
    st = check_options(ctx, "limn_subdivide_estimate", options);
    if (st)
        return st;
    limn_scheme scheme;
    st = operator_resolve_scheme(ctx, mesh, options->scheme, &scheme);
    if (st)
        return st;
    return check_budget(ctx, mesh, scheme, options, vertices, faces, peak_bytes);
}

/* limn_subdivide on options and report of this library's layout, both never NULL. */
static limn_status subdivide_sized(limn_context *ctx, const limn_mesh *mesh,
                                   const limn_subdivide_options *options, limn_mesh **surface,
                                   limn_subdivide_report *report)
{
    limn_status begun = abi_begin(ctx, "limn_subdivide", "surface", surface);
    if (begun)
        return begun;
    *surface = NULL;
    const limn_subdivide_options *o = options; /* never NULL: abi_enter's copy */
    limn_status st = check_mesh_magnitude(ctx, "limn_subdivide", NULL, mesh);
    if (!st)
        st = check_options(ctx, "limn_subdivide", o);
    if (st)
        return st;
    limn_subdivide_report *r = report; /* never NULL either */
    memset(r, 0, sizeof *r);
    r->input_vertices = mesh->vertex_count;
    r->input_faces = mesh->face_count;
    r->levels = o->levels;
    r->limit = o->limit;
    limn_scheme scheme;
    st = operator_resolve_scheme(ctx, mesh, o->scheme, &scheme);
    if (st)
        return st;
    r->scheme = scheme;
    r->alpha = scheme == LIMN_SCHEME_CATMARK ? o->alpha : 0.0;
    size_t est_v, est_f;
    st = check_budget(ctx, mesh, scheme, o, &est_v, &est_f, &r->estimated_bytes);
    if (st)
        return st;
    struct device *dev;
    st = device_get(ctx, &dev);
    if (st)
        return st;
    snprintf(r->device, sizeof r->device, "%s", dev->name);

    double t0 = clock_seconds();
    limn_mesh *out = NULL;
    double seconds_apply;
    st = refine_surface(ctx, mesh, scheme, r->alpha, o->levels, &out, &r->stencil_nonzeros,
                        &seconds_apply);
    if (st)
        return st;
    double t2 = clock_seconds();
    /* the rows are used as they are made: their time is the apply, the
       rest (topologies, faces) the plan */
    r->seconds_apply = seconds_apply;
    r->seconds_plan = t2 - t0 - seconds_apply;
    if (!st && o->limit) {
        double *lim = malloc((out->vertex_count ? out->vertex_count : 1) * 3 * sizeof *lim);
        if (!lim)
            st = ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for limit positions");
        /* alpha acts on the first step only: past level 0 the limit is standard */
        if (!st)
            st = operator_limit_positions(ctx, out, scheme, o->levels == 0 ? r->alpha : 0.0, lim);
        if (!st)
            memcpy(out->positions, lim, out->vertex_count * 3 * sizeof *lim);
        free(lim);
        r->seconds_limit = clock_seconds() - t2;
    }
    if (!st && mesh->colors && !out->colors)
        ctx_warn(ctx, "the input's vertex colours were dropped: limn_subdivide does not carry "
                       "colours to the refined surface (%zu vertices), which has none",
                  out->vertex_count);
    if (!st) {
        r->vertices = out->vertex_count;
        r->faces = out->face_count;
        *surface = out;
    } else {
        limn_mesh_destroy(out);
    }
    return st;
}

limn_status limn_subdivide(limn_context *ctx, const limn_mesh *mesh,
                           const limn_subdivide_options *options, limn_mesh **surface,
                           limn_subdivide_report *report)
{
    abi_call c;
    limn_status st = abi_enter(&c, ctx, "limn_subdivide", &abi_subdivide_options, options,
                               &abi_subdivide_report, report, surface);
    return st ? st : abi_leave(&c, subdivide_sized(ctx, mesh, c.options, surface, c.report));
}
