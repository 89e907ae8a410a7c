/* SPDX-License-Identifier: MIT */
/* Building the limit operator of a mesh on the context's device. */
#include "base/abi.h"
#include "solve/operator.h"
#include "mesh/check.h"
#include "base/context.h"
#include "mesh/mesh.h"
#include "stencil/reorder.h"
#include "base/clock.h"
#include "base/parallel.h"
#include "device/choice/choice.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

const char *limn_scheme_name(limn_scheme s)
{
    switch (s) {
    case LIMN_SCHEME_LOOP: return "loop";
    case LIMN_SCHEME_CATMARK: return "catmark";
    case LIMN_SCHEME_AUTO: return "auto";
    }
    return "unknown";
}

limn_status operator_resolve_scheme(limn_context *ctx, const limn_mesh *mesh, limn_scheme want,
                                    limn_scheme *out)
{
    /* a backstop: the public entry points name themselves in this check first */
    limn_status st = check_scheme(ctx, "operator", want);
    if (st)
        return st;
    size_t first_other = SIZE_MAX;
    for (size_t f = 0; f < mesh->face_count && first_other == SIZE_MAX; f++)
        if (mesh->face_offsets[f + 1] - mesh->face_offsets[f] != 3)
            first_other = f;
    if (want == LIMN_SCHEME_AUTO)
        want = first_other == SIZE_MAX && mesh->face_count > 0 ? LIMN_SCHEME_LOOP
                                                                : LIMN_SCHEME_CATMARK;
    if (want == LIMN_SCHEME_LOOP && first_other != SIZE_MAX)
        return ctx_fail(ctx, LIMN_ERR_TOPOLOGY,
                         "face %zu has %u vertices but Loop subdivision needs triangles only: "
                         "use --scheme catmark (or auto), or triangulate the mesh",
                         first_other,
                         mesh->face_offsets[first_other + 1] - mesh->face_offsets[first_other]);
    *out = want;
    return LIMN_OK;
}

limn_status operator_build(limn_context *ctx, const limn_mesh *mesh, limn_scheme scheme,
                           double alpha, stencil_operator *op)
{
    return operator_build_ex(ctx, mesh, scheme, alpha, 0, op);
}

typedef struct pack_job {
    const stencil_operator *op;
    const double *xyz;
    double *rows4;
} pack_job;

static int pack_range(void *arg, size_t begin, size_t end)
{
    const pack_job *j = arg;
    const uint32_t *order = j->op->order;
    for (size_t k = begin; k < end; k++) {
        const double *src = j->xyz + 3 * (size_t)(order ? order[k] : k);
        double *dst = j->rows4 + 4 * k;
        dst[0] = src[0];
        dst[1] = src[1];
        dst[2] = src[2];
        dst[3] = 0.0;
    }
    return 0;
}

void operator_pack(const stencil_operator *op, const double *xyz, double *rows4)
{
    /* over the host threads: rows4 is usually fresh memory, whose first
       touches are most of the cost */
    pack_job j = {op, xyz, rows4};
    parallel_run(op->vertex_count, parallel_threads(op->dev->ctx, (uint64_t)op->vertex_count * 56),
                 pack_range, &j);
}

void operator_unpack(const stencil_operator *op, const double *rows4, double *xyz)
{
    for (size_t k = 0; k < op->vertex_count; k++)
        memcpy(xyz + 3 * (size_t)(op->order ? op->order[k] : k), rows4 + 4 * k,
               3 * sizeof(double));
}

limn_status operator_build_ex(limn_context *ctx, const limn_mesh *mesh, limn_scheme scheme,
                              double alpha, int flags, stencil_operator *op)
{
    memset(op, 0, sizeof *op);
    limn_status st = operator_resolve_scheme(ctx, mesh, scheme, &op->scheme);
    if (st)
        return st;
    op->alpha = op->scheme == LIMN_SCHEME_CATMARK ? alpha : 0.0;
    op->vertex_count = mesh->vertex_count;
    double lo[3], hi[3];
    op->bbox_diagonal = mesh_bbox_diagonal(mesh, lo, hi);

    double t0 = clock_seconds();
    st = topology_take(ctx, mesh, &op->topo);
    if (st)
        return st;
    double t1 = clock_seconds();
    op->seconds_topology = t1 - t0;
    st = stencil_limit_build(ctx, &op->topo, op->scheme, op->alpha, &op->host);
    double t2 = clock_seconds();
    op->seconds_stencil = t2 - t1;
    /* Renumber only when rows hop around memory: a mean jump of the first
       column above 256 rows (8 KiB of vertex records) per row. Refined meshes
       and most scans stream already (README "Locality"). */
    if (!st && (flags & OPERATOR_REORDER) && stencil_mean_row_jump(&op->host) > 256.0) {
        stencil_csr permuted;
        st = reorder_rcm(ctx, &op->topo, &op->order, &op->rank);
        if (!st)
            st = stencil_permute(ctx, &op->host, op->order, op->rank, &permuted);
        if (!st) {
            stencil_free(&op->host);
            op->host = permuted;
        }
        op->seconds_reorder = clock_seconds() - t2;
    }
    /* the rest of the run reads only the row rules and the statistics */
    if (!st)
        topology_slim(&op->topo);
    if (!st && !(flags & OPERATOR_HOST_ONLY))
        st = device_get(ctx, &op->dev);
    if (!st && !(flags & OPERATOR_HOST_ONLY))
        st = device_csr_share(op->dev, &op->host, &op->device); /* op->host outlives it */
    if (st)
        operator_free(op);
    return st;
}

void operator_free(stencil_operator *op)
{
    if (op->dev)
        device_csr_release(op->dev, &op->device);
    stencil_free(&op->host);
    topology_free(&op->topo);
    free(op->order);
    free(op->rank);
    memset(op, 0, sizeof *op);
}

limn_status limn_limit_positions(limn_context *ctx, const limn_mesh *mesh, limn_scheme scheme,
                                 double alpha, double *out)
{
    limn_status begun = abi_begin(ctx, "limn_limit_positions", "out", out);
    if (begun)
        return begun;
    limn_status st = check_mesh_magnitude(ctx, "limn_limit_positions", NULL, mesh);
    if (!st)
        st = check_scheme(ctx, "limn_limit_positions", scheme);
    if (st)
        return st;
    if (!(alpha >= 0.0 && alpha <= 1.0))
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                         "limn_limit_positions: alpha is %g; it must lie in [0, 1]", alpha);
    return operator_limit_positions(ctx, mesh, scheme, alpha, out);
}

limn_status operator_limit_positions(limn_context *ctx, const limn_mesh *mesh, limn_scheme scheme,
                                     double alpha, double *out)
{
    stencil_operator op;
    limn_status st = operator_build(ctx, mesh, scheme, alpha, &op);
    if (st)
        return st;
    size_t n = mesh->vertex_count;
    double *buf = calloc(n ? 4 * n : 4, sizeof *buf);
    device_buffer *x = NULL, *y = NULL;
    if (!buf)
        st = ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for %zu vertices", n);
    for (size_t i = 0; !st && i < n; i++)
        memcpy(buf + 4 * i, mesh->positions + 3 * i, 3 * sizeof(double));
    if (!st)
        st = op.dev->ops->buffer_create(op.dev, 4 * n * sizeof(double), buf, &x);
    if (!st)
        st = op.dev->ops->buffer_create(op.dev, 4 * n * sizeof(double), NULL, &y);
    if (!st)
        st = op.dev->ops->spmv(op.dev, &op.device, x, y);
    if (!st)
        st = op.dev->ops->buffer_read(op.dev, y, 4 * n * sizeof(double), buf);
    for (size_t i = 0; !st && i < n; i++)
        memcpy(out + 3 * i, buf + 4 * i, 3 * sizeof(double));
    if (x)
        op.dev->ops->buffer_release(op.dev, x);
    if (y)
        op.dev->ops->buffer_release(op.dev, y);
    free(buf);
    operator_free(&op);
    return st;
}
