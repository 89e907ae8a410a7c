/* SPDX-License-Identifier: MIT */
/*
 * How far a pure-float iteration gets: the seeds' iteration run entirely in
 * float (P and M as float4, float weights: the float path's own kernel with
 * b = M), its true residual max |M - A P| measured in double after every
 * step. Prints one JSON line: the best relative error reached in `steps`
 * steps, the step that reached it, and the first steps at which 1e-6 and 1e-8
 * held (-1: never). This is the measurement behind README "Precision": why
 * limn's float path refines in double rather than iterating P in float.
 *   float_floor MESH loop|catmark [steps, default 300]
 */
#include "bench_operator.h"
#include "device/device.h"
#include "limn.h"
#include "mesh/mesh.h"
#include "solve/operator.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: float_floor MESH loop|catmark [steps]\n");
        return 2;
    }
    int steps = argc > 3 ? atoi(argv[3]) : 300;
    limn_context *ctx;
    limn_mesh *mesh;
    stencil_operator op;
    if (bench_operator("float_floor", argv[1], argv[2], &ctx, &mesh, &op))
        return 1;
    size_t n = op.vertex_count;
    struct device *dev = op.dev;
    double *m4 = malloc(4 * n * sizeof *m4), *zero = calloc(4 * n, sizeof *zero);
    float *f4 = malloc(4 * n * sizeof *f4);
    operator_pack(&op, mesh->positions, m4);
    for (size_t i = 0; i < 4 * n; i++)
        f4[i] = (float)m4[i];
    device_buffer *m = NULL, *p = NULL, *r = NULL, *b = NULL, *d[2] = {NULL, NULL};
    limn_status st = device_csr_add_float(dev, &op.device);
    if (!st)
        st = dev->ops->buffer_create(dev, 4 * n * sizeof(double), m4, &m);
    if (!st)
        st = dev->ops->buffer_create(dev, 4 * n * sizeof(double), NULL, &p);
    if (!st)
        st = dev->ops->buffer_create(dev, 4 * n * sizeof(float), NULL, &r);
    if (!st)
        st = dev->ops->buffer_create(dev, 4 * n * sizeof(float), f4, &b);
    for (int i = 0; i < 2 && !st; i++)
        st = dev->ops->buffer_create(dev, 4 * n * sizeof(float), f4, &d[i]);
    double best = 1e300, diag = op.bbox_diagonal;
    int best_step = -1, at6 = -1, at8 = -1;
    for (int k = 0; k < steps && !st; k++) {
        device_norms nf, nd;
        st = dev->ops->mixed->step_f(dev, &op.device, b, d[k & 1], d[k & 1], d[1 - (k & 1)], 0.0f, 1.0f,
                              &nf);
        /* P = the float iterate, widened exactly; its residual in double */
        if (!st)
            st = dev->ops->buffer_write(dev, p, 4 * n * sizeof(double), zero);
        if (!st)
            st = dev->ops->mixed->add_f(dev, n, p, d[1 - (k & 1)]);
        if (!st)
            st = dev->ops->mixed->residual_f(dev, &op.device, m, p, r, &nd);
        double rel = nd.max / diag;
        if (rel < best) {
            best = rel;
            best_step = k + 1;
        }
        if (at6 < 0 && rel <= 1e-6)
            at6 = k + 1;
        if (at8 < 0 && rel <= 1e-8)
            at8 = k + 1;
    }
    if (st) {
        fprintf(stderr, "float_floor: %s\n", limn_context_message(ctx));
        return 1;
    }
    printf("{\"mesh\": \"%s\", \"scheme\": \"%s\", \"vertices\": %zu, \"steps\": %d, "
           "\"best_rel_error\": %.3e, \"best_step\": %d, \"first_step_1e-6\": %d, "
           "\"first_step_1e-8\": %d}\n",
           argv[1], argv[2], n, steps, best, best_step, at6, at8);
    device_buffer *all[] = {m, p, r, b, d[0], d[1]};
    for (int i = 0; i < 6; i++)
        dev->ops->buffer_release(dev, all[i]);
    operator_free(&op);
    limn_mesh_destroy(mesh);
    free(m4);
    free(zero);
    free(f4);
    limn_context_destroy(ctx);
    return 0;
}
