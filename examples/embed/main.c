/* SPDX-License-Identifier: MIT */
/*
 * Embedding limn: the application's own arrays in, results into its own
 * buffers, no files. It makes a bumpy torus (quads), computes the control
 * mesh P whose Catmull-Clark limit surface passes through every vertex,
 * checks that (the limit positions of P reproduce the torus), and smooths
 * the torus with the series (limn_smooth).
 *
 * Build against an installed limn: CMakeLists.txt (find_package) or Makefile
 * (pkg-config). Exit status 0 when the check passes.
 */
#include <limn.h>

#include <math.h>
#include <stdint.h>
#include <stdio.h>

enum { RING = 32, TUBE = 12, NV = RING * TUBE, NF = RING * TUBE };

/* The application's mesh: NV vertices (3 doubles each), NF quads. */
static double torus_pos[3 * NV];
static uint32_t torus_offsets[NF + 1], torus_indices[4 * NF];

static void make_torus(void)
{
    const double pi = 3.14159265358979323846;
    for (int i = 0; i < RING; i++)
        for (int j = 0; j < TUBE; j++) {
            double u = 2 * pi * i / RING, v = 2 * pi * j / TUBE;
            double r = 0.3 + 0.05 * sin(5 * u) * cos(3 * v);
            double *p = torus_pos + 3 * (i * TUBE + j);
            p[0] = (1 + r * cos(v)) * cos(u);
            p[1] = (1 + r * cos(v)) * sin(u);
            p[2] = r * sin(v);
            int f = i * TUBE + j, i1 = (i + 1) % RING, j1 = (j + 1) % TUBE;
            torus_offsets[f] = (uint32_t)(4 * f);
            torus_indices[4 * f] = (uint32_t)(i * TUBE + j);
            torus_indices[4 * f + 1] = (uint32_t)(i1 * TUBE + j);
            torus_indices[4 * f + 2] = (uint32_t)(i1 * TUBE + j1);
            torus_indices[4 * f + 3] = (uint32_t)(i * TUBE + j1);
        }
    torus_offsets[NF] = 4 * NF;
}

static int failed(limn_context *ctx, const char *what, limn_status st)
{
    fprintf(stderr, "embed: %s failed: %s: %s\n", what, limn_status_name(st),
            limn_context_message(ctx));
    return 1;
}

int main(void)
{
    /* the application's result buffers */
    static double control[3 * NV], limit[3 * NV], smoothed[3 * NV];
    make_torus();

    limn_context *ctx = limn_context_create();
    if (!ctx)
        return 1;
    limn_mesh *torus = NULL, *p = NULL, *smooth = NULL;
    int rc = 1;
    limn_status st = limn_mesh_create(ctx, NV, torus_pos, NF, torus_offsets, torus_indices,
                                      &torus); /* copies the arrays: ours stay ours */
    if (st) {
        rc = failed(ctx, "limn_mesh_create", st);
        goto done;
    }

    limn_interpolate_options opt;
    limn_interpolate_options_default(&opt);
    opt.tolerance = 1e-8;
    limn_report report = {.size = sizeof report};
    if ((st = limn_interpolate(ctx, torus, &opt, &p, &report)) ||
        (st = limn_mesh_copy_positions(ctx, p, control, NV))) {
        rc = failed(ctx, "interpolation", st);
        goto done;
    }

    /* the check: A P = M, A the limit operator of the scheme that ran */
    if ((st = limn_limit_positions(ctx, p, report.scheme, report.alpha, limit))) {
        rc = failed(ctx, "limn_limit_positions", st);
        goto done;
    }
    double max_err = 0.0, moved = 0.0;
    for (int i = 0; i < NV; i++) {
        double dx = limit[3 * i] - torus_pos[3 * i], dy = limit[3 * i + 1] - torus_pos[3 * i + 1],
               dz = limit[3 * i + 2] - torus_pos[3 * i + 2];
        max_err = fmax(max_err, sqrt(dx * dx + dy * dy + dz * dz) / report.bbox_diagonal);
    }

    /* one series operation: the partial sum of the first 3 bands */
    if ((st = limn_smooth(ctx, torus, NULL, 3, &smooth, NULL)) ||
        (st = limn_mesh_copy_positions(ctx, smooth, smoothed, NV))) {
        rc = failed(ctx, "limn_smooth", st);
        goto done;
    }
    for (int i = 0; i < 3 * NV; i++)
        moved = fmax(moved, fabs(smoothed[i] - torus_pos[i]));

    int threads;
    const char *source;
    limn_context_threads(ctx, &threads, &source);
    printf("device: %s\n", limn_context_device_name(ctx));
    printf("threads: %d (%s)\n", threads, source);
    printf("interpolate: %d vertices, %s, %d iterations, reported max error %.3g\n", NV,
           limn_scheme_name(report.scheme), report.iterations, report.max_rel_error);
    printf("limit of P against M: max relative error %.3g (tolerance %.3g)\n", max_err,
           opt.tolerance);
    printf("smooth (3 terms): largest coordinate change %.3g\n", moved);
    int ok = max_err <= opt.tolerance && moved > 0.0;
    printf("check: %s\n", ok ? "OK" : "FAILED");
    rc = ok ? 0 : 1;
done:
    limn_mesh_destroy(smooth);
    limn_mesh_destroy(p);
    limn_mesh_destroy(torus);
    limn_context_destroy(ctx);
    return rc;
}
