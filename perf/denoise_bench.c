/* SPDX-License-Identifier: MIT */
/*
 * Issue 4's figures: limn denoise (seed 000 eq. 8) against Taubin lambda|mu
 * smoothing, and the series morph against the linear blend.
 *
 *   denoise_bench [--meshes DIR] [--device SPEC] [--out DIR] [--m M] [--steps K]
 *
 * Denoising: on three shared meshes, seeded Gaussian noise of sigma = 0.2 and
 * 0.5 x the mean edge length on every coordinate; then
 *   - limn denoise, m = 2, K = 4 (the paper's range): (m + 1) K = 12 stencil
 *     products; and m = 1, K = 6: also 12 (--m/--steps replace the first);
 *   - Taubin (lambda = 0.5, mu = -0.53, uniform Laplacian, MeshLab's default
 *     weights) with 6 lambda|mu pairs = 12 Laplacian applications: the same
 *     budget of operator applications (each is one sparse product of about
 *     the same size as A's);
 *   - Taubin with 10 pairs (MeshLab's default step count) for reference.
 * Metrics against the clean mesh, vertex by vertex (same topology): mean
 * distance / bbox diagonal, mean face-normal angle in degrees, volume change
 * relative to the noisy input, seconds: setup (limn: topology + CSR table +
 * upload; Taubin: the adjacency lists) and filter (limn: on the device, after
 * a warm-up run so that the OpenCL program is built; Taubin: a plain
 * single-threaded C loop).
 *
 * Morph: a mesh and its projection onto the sphere about its centroid (radius
 * = mean distance), seed 000 Fig. 5; 30 frames each way: series (m = 2,
 * p = 0.8) and linear; volume, area and flipped faces per frame.
 *
 * Prints tables and writes out/denoise_bench.csv and out/morph_volume.csv.
 */
#include "limn.h"
#include "noise.h"
#include "taubin.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void die(limn_context *ctx, const char *what)
{
    fprintf(stderr, "denoise_bench: %s: %s\n", what, ctx ? limn_context_message(ctx) : "");
    exit(1);
}

/* outdir/name opened for writing with its CSV header line, or the bench dies. */
static FILE *open_csv(const char *outdir, const char *name, const char *header)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", outdir, name);
    FILE *csv = fopen(path, "w");
    if (!csv)
        die(NULL, path);
    fputs(header, csv);
    return csv;
}

/* ------------------------------------------------------------- tables */

typedef struct row {
    const char *mesh, *method;
    double sigma, distance, normal, volume_change, setup, seconds;
    int applications;
} row;

static row measure_row(limn_context *ctx, const char *mesh, const char *method, double sigma,
                       const limn_mesh *clean, const limn_mesh *noisy, const limn_mesh *out,
                       double setup, double seconds, int applications)
{
    limn_mesh_comparison c = {.size = sizeof c};
    limn_mesh_measures a = {.size = sizeof a}, b = {.size = sizeof b};
    if (limn_mesh_compare(ctx, clean, out, &c) || limn_mesh_measure(ctx, noisy, &a) ||
        limn_mesh_measure(ctx, out, &b))
        die(ctx, "measuring");
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    const double *p = limn_mesh_positions(clean);
    for (size_t i = 0; i < limn_mesh_vertex_count(clean); i++)
        for (int k = 0; k < 3; k++)
            lo[k] = fmin(lo[k], p[3 * i + k]), hi[k] = fmax(hi[k], p[3 * i + k]);
    double diag = sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                       (hi[2] - lo[2]) * (hi[2] - lo[2]));
    row r = {mesh, method, sigma, c.mean_distance / diag, c.mean_normal_angle,
             a.closed ? (b.volume - a.volume) / a.volume : NAN, setup, seconds, applications};
    return r;
}

static void print_row(const row *r, FILE *csv)
{
    printf("| %-17s | %4.1f | %-21s | %3d | %9.3e | %6.2f | %+8.3f%% | %6.4f | %6.4f |\n",
           r->mesh, r->sigma, r->method, r->applications, r->distance, r->normal,
           100.0 * r->volume_change, r->setup, r->seconds);
    fprintf(csv, "%s,%.2f,%s,%d,%.6e,%.4f,%.6e,%.6f,%.6f\n", r->mesh, r->sigma, r->method,
            r->applications, r->distance, r->normal, r->volume_change, r->setup, r->seconds);
}

/* --------------------------------------------------------------- morph */

typedef struct morph_log {
    int frames;
    double volume[64], area[64];
    size_t flipped[64];
} morph_log;

static limn_status log_frame(void *user, const limn_morph_frame *f)
{
    morph_log *l = user;
    l->volume[f->index] = f->volume;
    l->area[f->index] = f->area;
    l->flipped[f->index] = f->flipped_faces;
    l->frames = f->index + 1;
    return LIMN_OK;
}

static limn_mesh *spherized(limn_context *ctx, const limn_mesh *m)
{
    limn_mesh *s = NULL;
    limn_mesh_measures me = {.size = sizeof me};
    if (limn_mesh_copy(ctx, m, &s) || limn_mesh_measure(ctx, m, &me))
        die(ctx, "sphere");
    test_spherize(s, me.centroid);
    return s;
}

int main(int argc, char **argv)
{
    const char *meshes = getenv("LIMN_SHARED_MESHES") ? getenv("LIMN_SHARED_MESHES")
                                                       : "../shared/meshes";
    const char *device = "opencl", *outdir = "out", *write_noisy = NULL;
    int ms[2] = {2, 1}, ks[2] = {4, 6};
    int m = 2, steps = 4;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--meshes") == 0 && i + 1 < argc)
            meshes = argv[++i];
        else if (strcmp(argv[i], "--device") == 0 && i + 1 < argc)
            device = argv[++i];
        else if (strcmp(argv[i], "--out") == 0 && i + 1 < argc)
            outdir = argv[++i];
        else if (strcmp(argv[i], "--m") == 0 && i + 1 < argc)
            m = atoi(argv[++i]);
        else if (strcmp(argv[i], "--steps") == 0 && i + 1 < argc)
            steps = atoi(argv[++i]);
        else if (strcmp(argv[i], "--write-noisy") == 0 && i + 1 < argc)
            write_noisy = argv[++i]; /* writes DIR/<mesh>_sigma<s>.ply for figures */
        else {
            fprintf(stderr,
                    "usage: denoise_bench [--meshes DIR] [--device SPEC] [--out DIR] [--m M] "
                    "[--steps K] [--write-noisy DIR]\n");
            return 2;
        }
    }
    mkdir(outdir, 0777);
    limn_context *ctx = limn_context_create();
    if (limn_context_set_device(ctx, device))
        die(ctx, "device");
    char path[4096];
    FILE *csv = open_csv(outdir, "denoise_bench.csv",
                         "mesh,sigma_edges,method,applications,mean_rel_distance,"
                         "mean_normal_deg,volume_change,setup_seconds,filter_seconds\n");
    ms[0] = m;
    ks[0] = steps;
    static const char *files[] = {"medium/bunny_closed.off", "medium/horse.ply",
                                  "medium/bob_quad.obj"};
    static const double sigmas[] = {0.2, 0.5};
    int pairs = (m + 1) * steps / 2;
    printf("Denoising: limn denoise m=%d K=%d and m=1 K=6 vs Taubin lambda=0.5 mu=-0.53 (uniform "
           "Laplacian), %d pairs = %d applications (the same budget) and 10 pairs\n\n",
           m, steps, pairs, 2 * pairs);
    printf("| %-17s | %4s | %-21s | %3s | %9s | %6s | %9s | %6s | %6s |\n", "mesh", "sigma",
           "method", "ops", "mean dist", "normal", "volume", "setup", "filter");
    printf("|-------------------|------|-----------------------|-----|-----------|--------|"
           "-----------|--------|--------|\n");
    {
        /* warm-up: open the device and build the OpenCL program once */
        limn_mesh *w = NULL;
        snprintf(path, sizeof path, "%s/small/spot_control_mesh.obj", meshes);
        limn_mesh *cube = NULL;
        if (limn_mesh_read(ctx, path, LIMN_FORMAT_AUTO, &cube) ||
            limn_denoise(ctx, cube, NULL, 1, 1, 0, &w, NULL))
            die(ctx, "warm-up");
        limn_mesh_destroy(w);
        limn_mesh_destroy(cube);
    }
    for (size_t fi = 0; fi < sizeof files / sizeof *files; fi++) {
        snprintf(path, sizeof path, "%s/%s", meshes, files[fi]);
        limn_mesh *clean = NULL;
        if (limn_mesh_read(ctx, path, LIMN_FORMAT_AUTO, &clean))
            die(ctx, path);
        const char *name = strrchr(files[fi], '/') + 1;
        double ta = now();
        adjacency adj = build_adjacency(clean);
        double adj_seconds = now() - ta;
        double edge = test_mean_edge(clean);
        for (size_t si = 0; si < 2; si++) {
            limn_mesh *noisy = NULL, *out = NULL;
            if (limn_mesh_copy(ctx, clean, &noisy))
                die(ctx, "copy");
            test_gaussian_noise(noisy, sigmas[si] * edge, 1000 + 17 * fi + si);
            if (write_noisy) {
                char np[4096];
                snprintf(np, sizeof np, "%s/%.*s_sigma%.1f.ply", write_noisy,
                         (int)(strrchr(name, '.') - name), name, sigmas[si]);
                if (limn_mesh_write(ctx, noisy, np, LIMN_FORMAT_PLY))
                    die(ctx, np);
            }
            row r = measure_row(ctx, name, "noisy input", sigmas[si], clean, noisy, noisy, 0, 0,
                                0);
            print_row(&r, csv);
            for (int v = 0; v < 2; v++) {
                limn_series_report rep = {.size = sizeof rep};
                double t0 = now();
                if (limn_denoise(ctx, noisy, NULL, ms[v], ks[v], 0, &out, &rep))
                    die(ctx, "denoise");
                double t = now() - t0;
                char method[64];
                snprintf(method, sizeof method, "limn denoise m=%d K=%d", ms[v], ks[v]);
                r = measure_row(ctx, name, method, sigmas[si], clean, noisy, out,
                                t - rep.seconds_compute, rep.seconds_compute, (int)rep.products);
                print_row(&r, csv);
                limn_mesh_destroy(out);
            }
            int counts[2] = {pairs, 10};
            for (int k = 0; k < 2; k++) {
                if (limn_mesh_copy(ctx, noisy, &out))
                    die(ctx, "copy");
                double t0 = now();
                taubin_steps(&adj, limn_mesh_positions_mutable(out), 2 * counts[k], 0.5, -0.53);
                double t = now() - t0;
                char method[64];
                snprintf(method, sizeof method, "Taubin %d pairs", counts[k]);
                r = measure_row(ctx, name, method, sigmas[si], clean, noisy, out, adj_seconds, t,
                                2 * counts[k]);
                print_row(&r, csv);
                limn_mesh_destroy(out);
            }
            limn_mesh_destroy(noisy);
        }
        adjacency_free(&adj);
        limn_mesh_destroy(clean);
    }
    fclose(csv);
    printf("\n(setup and filter in seconds; limn on '%s', Taubin in plain C on 1 thread)\n\n",
           limn_context_device_name(ctx));

    /* morph: bunny to its sphere */
    snprintf(path, sizeof path, "%s/medium/bunny_closed.off", meshes);
    limn_mesh *bunny = NULL;
    if (limn_mesh_read(ctx, path, LIMN_FORMAT_AUTO, &bunny))
        die(ctx, path);
    limn_mesh *sphere = spherized(ctx, bunny);
    morph_log series = {0}, linear = {0};
    limn_morph_options o;
    limn_morph_options_default(&o);
    o.frames = 30;
    o.m = 2;
    o.p = 0.8;
    if (limn_morph(ctx, bunny, sphere, &o, log_frame, &series, NULL))
        die(ctx, "morph");
    o.linear = 1;
    if (limn_morph(ctx, bunny, sphere, &o, log_frame, &linear, NULL))
        die(ctx, "linear morph");
    FILE *mc = open_csv(outdir, "morph_volume.csv",
                        "frame,series_volume,series_area,series_flipped,linear_volume,"
                        "linear_area,linear_flipped\n");
    printf("Morph bunny_closed -> its sphere (30 frames): series eq. 9 (m=2, p=0.8) vs linear\n\n");
    printf("| frame | series volume | series area | flips | linear volume | linear area | flips |\n");
    printf("|------:|--------------:|------------:|------:|--------------:|------------:|------:|\n");
    for (int k = 0; k < 30; k++) {
        fprintf(mc, "%d,%.9g,%.9g,%zu,%.9g,%.9g,%zu\n", k, series.volume[k], series.area[k],
                series.flipped[k], linear.volume[k], linear.area[k], linear.flipped[k]);
        if (k % 3 == 0 || k == 29)
            printf("| %5d | %13.6g | %11.6g | %5zu | %13.6g | %11.6g | %5zu |\n", k,
                   series.volume[k], series.area[k], series.flipped[k], linear.volume[k],
                   linear.area[k], linear.flipped[k]);
    }
    fclose(mc);
    printf("\nCSV: %s/denoise_bench.csv, %s/morph_volume.csv\n", outdir, outdir);
    limn_mesh_destroy(bunny);
    limn_mesh_destroy(sphere);
    limn_context_destroy(ctx);
    return 0;
}
