/* SPDX-License-Identifier: MIT */
/*
 * Times the solve loop's kernels alone, on the operator limn interpolate
 * builds (same reordering, same prefetch choice), repeated on resident
 * buffers; one JSON line per kernel with the best and median seconds per step,
 * the bytes one step must move and GB/s from them (perf/run_suite.py --focus
 * sets them against STREAM triad):
 *   double paper:     r = m - A p, p_next = p + r, norms of r (interp_step);
 *   double chebyshev: r = m - A p, x_next = p + c1 (p - x_prev) + c2 r
 *                     (cheb_step, the default method's step);
 *   float paper, float chebyshev: the same on the correction system of the
 *                     mixed solve (step_f: float weights, float4 vectors,
 *                     norms in double).
 *   step_bench MESH loop|catmark [repeats, default 20]
 * Device: LIMN_DEVICE as for limn; threads: POCL_MAX_PTHREAD_COUNT.
 *
 * Bytes: the compulsory traffic of one step. The CSR table (4-byte column +
 * 8-byte weight, or 4 + 4 in float, a nonzero; a 4-byte row offset a row)
 * and each vector stream read or written once: 32 bytes a row in double, 16
 * in float; three streams for paper (m, p, p_next), four for chebyshev (x_prev
 * is read, then overwritten by x_next). The gather of p is not counted again:
 * in a local vertex order it hits the cache lines the p stream brings
 * (counting it would add 32 or 16 bytes a row and flatter the rate).
 * Write-allocate traffic is not counted, as in STREAM.
 */
#include "bench_operator.h"
#include "device/device.h"
#include "limn.h"
#include "mesh/mesh.h"
#include "solve/operator.h"
#include "base/clock.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static void report(const char *precision, const char *method, const struct device *dev,
                   size_t n, size_t nnz, double *times, int repeats, double bytes)
{
    qsort(times, repeats, sizeof *times, cmp_double);
    printf("{\"impl\": \"limn_step\", \"precision\": \"%s\", \"method\": \"%s\", "
           "\"device\": \"%s\", \"vertices\": %zu, \"nonzeros\": %zu, \"repeats\": %d, "
           "\"seconds_best\": %.6f, \"seconds_median\": %.6f, \"bytes\": %.0f, "
           "\"gb_per_s\": %.3f}\n",
           precision, method, dev->name, n, nnz, repeats, times[0], times[repeats / 2], bytes,
           bytes / times[0] / 1e9);
}

/* c1, c2 of the timed Chebyshev steps: a stable two-term recurrence on a
   spectrum in (0, 1] (the values do not matter to the time, only that they
   stay finite). */
#define BENCH_C1 0.3
#define BENCH_C2 1.0

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: step_bench MESH loop|catmark [repeats]\n");
        return 2;
    }
    int repeats = argc > 3 ? atoi(argv[3]) : 20;
    if (repeats < 1)
        repeats = 1;
    limn_context *ctx;
    limn_mesh *mesh;
    stencil_operator op;
    if (bench_operator("step_bench", argv[1], argv[2], &ctx, &mesh, &op))
        return 1;
    size_t n = op.vertex_count, nnz = op.host.row_offsets[n];
    struct device *dev = op.dev;
    double *buf = malloc(4 * n * sizeof *buf), *times = malloc(repeats * sizeof *times);
    float *fbuf = malloc(4 * n * sizeof *fbuf);
    operator_pack(&op, mesh->positions, buf);
    for (size_t i = 0; i < 4 * n; i++)
        fbuf[i] = (float)buf[i];
    /* double: m = M, p = M; float: b = M rounded, d = b */
    device_buffer *m = NULL, *p[2] = {NULL, NULL}, *b = NULL, *d[2] = {NULL, NULL};
    limn_status st = device_csr_add_float(dev, &op.device);
    if (!st)
        st = dev->ops->buffer_create(dev, 4 * n * sizeof(double), buf, &m);
    if (!st)
        st = dev->ops->buffer_create(dev, 4 * n * sizeof(float), fbuf, &b);
    for (int i = 0; i < 2 && !st; i++) {
        st = dev->ops->buffer_create(dev, 4 * n * sizeof(double), buf, &p[i]);
        if (!st)
            st = dev->ops->buffer_create(dev, 4 * n * sizeof(float), fbuf, &d[i]);
    }
    const char *names[4][2] = {
        {"double", "paper"}, {"double", "chebyshev"}, {"float", "paper"}, {"float", "chebyshev"}};
    double rows_bytes[4] = {4 + 3 * 32, 4 + 4 * 32, 4 + 3 * 16, 4 + 4 * 16};
    for (int kind = 0; kind < 4 && !st; kind++) {
        device_norms nr;
        /* two untimed steps: first touch and kernel compilation */
        for (int k = 0; k < repeats + 2 && !st; k++) {
            int c = k & 1; /* x_k in [c], x_{k-1} in and x_{k+1} out in [1 - c] */
            double t = clock_seconds();
            if (kind == 0)
                st = dev->ops->stationary->interp_step(dev, &op.device, m, p[c], p[1 - c], 1.0, &nr);
            else if (kind == 1)
                st = dev->ops->stationary->cheb_step(dev, &op.device, m, p[c], p[1 - c], BENCH_C1, BENCH_C2,
                                         &nr);
            else if (kind == 2)
                st = dev->ops->mixed->step_f(dev, &op.device, b, d[c], d[c], d[1 - c], 0.0f, 1.0f, &nr);
            else
                st = dev->ops->mixed->step_f(dev, &op.device, b, d[c], d[1 - c], d[1 - c],
                                      (float)BENCH_C1, (float)BENCH_C2, &nr);
            if (k >= 2)
                times[k - 2] = clock_seconds() - t;
        }
        double per_nnz = kind < 2 ? 12.0 : 8.0;
        if (!st)
            report(names[kind][0], names[kind][1], dev, n, nnz, times, repeats,
                   per_nnz * (double)nnz + rows_bytes[kind] * (double)n);
    }
    if (st) {
        fprintf(stderr, "step_bench: %s\n", limn_context_message(ctx));
        return 1;
    }
    device_buffer *all[] = {m, p[0], p[1], b, d[0], d[1]};
    for (int i = 0; i < 6; i++)
        dev->ops->buffer_release(dev, all[i]);
    operator_free(&op);
    limn_mesh_destroy(mesh);
    free(buf);
    free(fbuf);
    free(times);
    limn_context_destroy(ctx);
    return 0;
}
