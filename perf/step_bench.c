/*
 * Times the solve loop's kernels alone, on the operator limn interpolate
 * builds (same reordering), repeated on resident buffers:
 *   double: the fused step r = m - A p, p_next = p + r, norms of r;
 *   float:  the float step of the mixed solve, s = b - A_f d, d_next = d + s,
 *           norms of s in double (float weights, float4 vectors).
 * Prints one JSON line per precision with the best and median seconds per
 * step and the bytes one step must move, and GB/s from them
 * (perf/run_suite.py --focus sets them against STREAM triad).
 *   step_bench MESH loop|catmark [repeats, default 20]
 * Device: LIMN_DEVICE as for limn; threads: POCL_MAX_PTHREAD_COUNT.
 *
 * Bytes: the compulsory traffic of one step. The CSR table (4-byte column +
 * 8-byte weight, or 4 + 4 in float, a nonzero; a 4-byte row offset a row),
 * and three vector streams read or written once (m, p, p_next: 32 bytes a
 * row each; b, d, d_next: 16). The gather of p is not counted again: in a
 * local vertex order it hits the cache lines the p stream brings (counting
 * it would add 32 or 16 bytes a row and flatter the rate). Write-allocate
 * traffic is not counted, as in STREAM.
 */
#include "device.h"
#include "limn.h"
#include "mesh.h"
#include "operator.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static void report(const char *precision, const struct limn_device *dev, size_t n, size_t nnz,
                   double *times, int repeats, double bytes)
{
    qsort(times, repeats, sizeof *times, cmp_double);
    printf("{\"impl\": \"limn_step\", \"precision\": \"%s\", \"device\": \"%s\", "
           "\"vertices\": %zu, \"nonzeros\": %zu, \"repeats\": %d, \"seconds_best\": %.6f, "
           "\"seconds_median\": %.6f, \"bytes\": %.0f, \"gb_per_s\": %.3f}\n",
           precision, dev->name, n, nnz, repeats, times[0], times[repeats / 2], bytes,
           bytes / times[0] / 1e9);
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: step_bench MESH loop|catmark [repeats]\n");
        return 2;
    }
    int repeats = argc > 3 ? atoi(argv[3]) : 20;
    if (repeats < 1)
        repeats = 1;
    limn_scheme scheme = strcmp(argv[2], "loop") == 0 ? LIMN_SCHEME_LOOP : LIMN_SCHEME_CATMARK;
    limn_context *ctx = limn_context_create();
    limn_mesh *mesh = NULL;
    limn_operator op;
    if (limn_mesh_read(ctx, argv[1], LIMN_FORMAT_AUTO, &mesh) ||
        operator_build_ex(ctx, mesh, scheme, 0.0, OPERATOR_REORDER, &op)) {
        fprintf(stderr, "step_bench: %s\n", limn_context_message(ctx));
        return 1;
    }
    size_t n = op.vertex_count, nnz = op.host.row_offsets[n];
    struct limn_device *dev = op.dev;
    double *buf = malloc(4 * n * sizeof *buf), *times = malloc(repeats * sizeof *times);
    operator_pack(&op, mesh->positions, buf);
    device_buffer *m = NULL, *p[2] = {NULL, NULL};
    limn_status st = dev->ops->buffer_create(dev, 4 * n * sizeof(double), buf, &m);
    for (int i = 0; i < 2 && !st; i++)
        st = dev->ops->buffer_create(dev, 4 * n * sizeof(double), buf, &p[i]);
    device_norms nr;
    /* two untimed steps: first touch of p_next and kernel compilation */
    for (int k = 0; k < repeats + 2 && !st; k++) {
        double t = limn_seconds();
        st = dev->ops->interp_step(dev, &op.device, m, p[k & 1], p[1 - (k & 1)], 1.0, &nr);
        if (k >= 2)
            times[k - 2] = limn_seconds() - t;
    }
    if (!st)
        report("double", dev, n, nnz, times, repeats, 12.0 * (double)nnz + 100.0 * (double)n);

    /* float: b = M rounded, d = b, as the mixed solve's first float step */
    float *fbuf = malloc(4 * n * sizeof *fbuf);
    for (size_t i = 0; i < 4 * n; i++)
        fbuf[i] = (float)buf[i];
    device_buffer *b = NULL, *d[2] = {NULL, NULL};
    if (!st)
        st = device_csr_add_float(dev, &op.device);
    if (!st)
        st = dev->ops->buffer_create(dev, 4 * n * sizeof(float), fbuf, &b);
    for (int i = 0; i < 2 && !st; i++)
        st = dev->ops->buffer_create(dev, 4 * n * sizeof(float), fbuf, &d[i]);
    for (int k = 0; k < repeats + 2 && !st; k++) {
        double t = limn_seconds();
        st = dev->ops->interp_step_f(dev, &op.device, b, d[k & 1], d[1 - (k & 1)], 1.0f, &nr);
        if (k >= 2)
            times[k - 2] = limn_seconds() - t;
    }
    if (!st)
        report("float", dev, n, nnz, times, repeats, 8.0 * (double)nnz + 52.0 * (double)n);
    if (st) {
        fprintf(stderr, "step_bench: %s\n", limn_context_message(ctx));
        return 1;
    }
    dev->ops->buffer_release(dev, b);
    dev->ops->buffer_release(dev, d[0]);
    dev->ops->buffer_release(dev, d[1]);
    free(fbuf);
    dev->ops->buffer_release(dev, m);
    dev->ops->buffer_release(dev, p[0]);
    dev->ops->buffer_release(dev, p[1]);
    operator_free(&op);
    limn_mesh_destroy(mesh);
    free(buf);
    free(times);
    limn_context_destroy(ctx);
    return 0;
}
