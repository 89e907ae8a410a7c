/* SPDX-License-Identifier: MIT */
/*
 * Issue 16 items 2-3: limn denoise --preserve-features against bilateral
 * normal filtering (Zheng et al. 2011), Taubin lambda|mu, limn denoise's
 * default (the SURE polynomial) and its paper form (m = 2, K = 3), in one
 * run on CAD-like meshes with sharp edges (fandisk, a bevelled cube, a puck
 * with chamfered caps) and on smooth organic ones.
 *
 *   feature_bench [--meshes DIR] [--device SPEC] [--out DIR] [--sigma S]... [--draw N]
 *                 [--outer K] [--normal T] [--vertex V] [--sigma-r R] [--tangential U]
 *                 [--write DIR]
 *
 * Seeded Gaussian noise of S x the mean edge length on every coordinate
 * (default S = 0.3; repeat --sigma for more; --draw N > 0 other seeds, 0 the
 * draws docs/series.md's tables were measured on). Metrics against the clean mesh
 * vertex by vertex: mean distance / bbox diagonal, mean face-normal angle,
 * volume change against the noisy input, seconds of the filter. BNF runs
 * twice: with Zheng's parameters (20 normal iterations, sigma_r = 0.35, 10
 * vertex iterations) and with the best of a small grid (sigma_r in {0.2,
 * 0.25, 0.35, 0.5} x outer rounds in {1, 3}: tuned on each mesh's normal
 * error, so as favourable to BNF as we could make it). --write puts the
 * clean, noisy and filtered meshes in DIR for pictures (docs/series.md).
 */
#include "bilateral_normal.h"
#include "cad_shapes.h"
#include "limn.h"
#include "noise.h"

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
    fprintf(stderr, "feature_bench: %s: %s\n", what, ctx ? limn_context_message(ctx) : "");
    exit(1);
}

typedef struct bench {
    limn_context *ctx;
    FILE *csv;
    const char *write_dir;
    limn_feature_options fo;
    const char *name;
    double sigma;
    const limn_mesh *clean, *noisy;
    double diag;
} bench;

static double bbox_diag(const limn_mesh *m)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    const double *p = limn_mesh_positions(m);
    for (size_t i = 0; i < limn_mesh_vertex_count(m); i++)
        for (int k = 0; k < 3; k++)
            lo[k] = fmin(lo[k], p[3 * i + k]), hi[k] = fmax(hi[k], p[3 * i + k]);
    return sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                (hi[2] - lo[2]) * (hi[2] - lo[2]));
}

/* The row of one result: printed, in the CSV, optionally written. */
static double report(bench *b, const char *method, const char *tag, const limn_mesh *out,
                     double seconds)
{
    limn_mesh_comparison c = {.size = sizeof c};
    limn_mesh_measures a = {.size = sizeof a}, m = {.size = sizeof m};
    if (limn_mesh_compare(b->ctx, b->clean, out, &c) || limn_mesh_measure(b->ctx, b->noisy, &a) ||
        limn_mesh_measure(b->ctx, out, &m))
        die(b->ctx, "measuring");
    double dv = a.closed ? (m.volume - a.volume) / a.volume : NAN;
    printf("| %-22s | %4.2f | %-34s | %9.3e | %6.2f | %+8.3f%% | %7.3f |\n", b->name, b->sigma,
           method, c.mean_distance / b->diag, c.mean_normal_angle, 100 * dv, seconds);
    /* RFC 4180: the method names hold commas ("BNF tuned (outer 3, sigma_r 0.35)") */
    fprintf(b->csv, "\"%s\",%.2f,\"%s\",%.6e,%.4f,%.6e,%.6f\n", b->name, b->sigma, method,
            c.mean_distance / b->diag, c.mean_normal_angle, dv, seconds);
    if (b->write_dir && tag) {
        char path[4096];
        snprintf(path, sizeof path, "%s/%.*s_%s.ply", b->write_dir,
                 (int)(strchr(b->name, '.') ? strchr(b->name, '.') - b->name : 64), b->name, tag);
        if (limn_mesh_write(b->ctx, out, path, LIMN_FORMAT_PLY))
            die(b->ctx, path);
    }
    return c.mean_normal_angle;
}

static limn_mesh *copy_noisy(bench *b)
{
    limn_mesh *m = NULL;
    if (limn_mesh_copy(b->ctx, b->noisy, &m))
        die(b->ctx, "copy");
    return m;
}

static void run_bnf(bench *b, const bnf_params *p, const char *method, const char *tag)
{
    limn_mesh *m = copy_noisy(b);
    double t0 = now();
    bnf_denoise(m, limn_mesh_positions_mutable(m), p);
    report(b, method, tag, m, now() - t0);
    limn_mesh_destroy(m);
}

/* BNF at the grid point with the lowest normal error (not printed). */
static bnf_params tune_bnf(bench *b)
{
    static const double srs[] = {0.2, 0.25, 0.35, 0.5};
    static const int outers[] = {1, 3};
    bnf_params best = {1, 20, 10, 0.35, 0};
    double best_err = INFINITY;
    for (size_t i = 0; i < 4; i++)
        for (size_t k = 0; k < 2; k++) {
            bnf_params p = {outers[k], 20, 10, srs[i], 0};
            limn_mesh *m = copy_noisy(b);
            bnf_denoise(m, limn_mesh_positions_mutable(m), &p);
            limn_mesh_comparison c = {.size = sizeof c};
            if (limn_mesh_compare(b->ctx, b->clean, m, &c))
                die(b->ctx, "compare");
            if (c.mean_normal_angle < best_err)
                best_err = c.mean_normal_angle, best = p;
            limn_mesh_destroy(m);
        }
    return best;
}

static void run_limn(bench *b)
{
    limn_mesh *m = NULL;
    limn_series_report r = {.size = sizeof r};
    double t0 = now();
    /* limn denoise's default: the SURE polynomial, 12 products, a closed mesh's volume kept */
    limn_mesh_measures a = {.size = sizeof a};
    if (limn_mesh_measure(b->ctx, b->noisy, &a))
        die(b->ctx, "measure");
    if (limn_denoise_sure(b->ctx, b->noisy, NULL, 12, a.closed, &m, NULL, &r))
        die(b->ctx, "denoise");
    report(b, "limn denoise (default: SURE, 12)", "default", m, now() - t0);
    limn_mesh_destroy(m);
    t0 = now();
    if (limn_denoise(b->ctx, b->noisy, NULL, 2, 3, 0, &m, &r))
        die(b->ctx, "denoise --m 2 --steps 3");
    report(b, "limn denoise --m 2 --steps 3", NULL, m, now() - t0);
    limn_mesh_destroy(m);
    t0 = now();
    if (limn_denoise_features(b->ctx, b->noisy, &b->fo, &m, &r))
        die(b->ctx, "denoise --preserve-features");
    char method[64];
    snprintf(method, sizeof method, "limn --preserve-features (%lld W)", r.products);
    report(b, method, "features", m, now() - t0);
    limn_mesh_destroy(m);
}

static void run_mesh(bench *b, const limn_mesh *clean, const char *name, double sigma,
                     uint64_t seed)
{
    limn_mesh *noisy = NULL;
    if (limn_mesh_copy(b->ctx, clean, &noisy))
        die(b->ctx, "copy");
    test_gaussian_noise(noisy, sigma * test_mean_edge(clean), seed);
    b->name = name;
    b->sigma = sigma;
    b->clean = clean;
    b->noisy = noisy;
    b->diag = bbox_diag(clean);
    report(b, "noisy input", "noisy", noisy, 0);
    if (b->write_dir) { /* the reference too, for other tools' metrics */
        char path[4096];
        snprintf(path, sizeof path, "%s/%.*s_clean.ply", b->write_dir,
                 (int)(strchr(name, '.') ? strchr(name, '.') - name : 64), name);
        if (limn_mesh_write(b->ctx, clean, path, LIMN_FORMAT_PLY))
            die(b->ctx, path);
    }
    run_limn(b);
    limn_mesh *m = copy_noisy(b);
    double t0 = now();
    taubin_denoise(m, limn_mesh_positions_mutable(m), 5, 0.5, -0.53);
    report(b, "Taubin 0.5|-0.53, 5 pairs", "taubin", m, now() - t0);
    limn_mesh_destroy(m);
    bnf_params zheng = {1, 20, 10, 0.35, 0};
    run_bnf(b, &zheng, "BNF Zheng (20, 0.35, 10)", "bnf");
    bnf_params best = tune_bnf(b);
    char method[64];
    snprintf(method, sizeof method, "BNF tuned (outer %d, sigma_r %.2f)", best.outer,
             best.sigma_r);
    run_bnf(b, &best, method, "bnf_tuned");
    limn_mesh_destroy(noisy);
}

static int parse(int argc, char **argv, const char **meshes, const char **device,
                 const char **outdir, const char **write_dir, double *sigmas, int *ns,
                 unsigned long *draw, limn_feature_options *fo)
{
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!v)
            return 2;
        i++;
        if (!strcmp(a, "--meshes"))
            *meshes = v;
        else if (!strcmp(a, "--device"))
            *device = v;
        else if (!strcmp(a, "--out"))
            *outdir = v;
        else if (!strcmp(a, "--write"))
            *write_dir = v;
        else if (!strcmp(a, "--sigma") && *ns < 8)
            sigmas[(*ns)++] = atof(v);
        else if (!strcmp(a, "--draw"))
            *draw = strtoul(v, NULL, 10);
        else if (!strcmp(a, "--outer"))
            fo->outer_steps = atoi(v);
        else if (!strcmp(a, "--normal"))
            fo->normal_steps = atoi(v);
        else if (!strcmp(a, "--vertex"))
            fo->vertex_steps = atoi(v);
        else if (!strcmp(a, "--sigma-r"))
            fo->sigma_r = atof(v);
        else if (!strcmp(a, "--keep-volume"))
            fo->keep_volume = atoi(v);
        else if (!strcmp(a, "--tangential"))
            fo->tangential = atof(v);
        else
            return 2;
    }
    return 0;
}

int main(int argc, char **argv)
{
    const char *meshes = "../shared/meshes", *device = "opencl", *outdir = "out", *wd = NULL;
    double sigmas[8];
    int ns = 0;
    unsigned long draw = 0; /* 0: the draws the docs' tables were measured on */
    bench b = {0};
    limn_feature_options_default(&b.fo);
    if (parse(argc, argv, &meshes, &device, &outdir, &wd, sigmas, &ns, &draw, &b.fo)) {
        fprintf(stderr, "usage: feature_bench [--meshes DIR] [--device SPEC] [--out DIR] "
                        "[--sigma S]... [--draw N] [--outer K] [--normal T] [--vertex V] "
                        "[--sigma-r R] [--tangential U] [--write DIR]\n");
        return 2;
    }
    if (!ns)
        sigmas[ns++] = 0.3;
    b.write_dir = wd;
    mkdir(outdir, 0777);
    b.ctx = limn_context_create();
    if (limn_context_set_device(b.ctx, device))
        die(b.ctx, "device");
    char path[4096];
    snprintf(path, sizeof path, "%s/feature_bench.csv", outdir);
    b.csv = fopen(path, "w");
    if (!b.csv)
        die(NULL, path);
    fputs("mesh,sigma_edges,method,mean_rel_distance,mean_normal_deg,volume_change,seconds\n",
          b.csv);
    printf("feature options: outer %d, normal %d, vertex %d, sigma_r %.3g, tangential %.3g\n\n",
           b.fo.outer_steps, b.fo.normal_steps, b.fo.vertex_steps, b.fo.sigma_r, b.fo.tangential);
    printf("| %-22s | %4s | %-34s | %9s | %6s | %9s | %7s |\n", "mesh", "sig", "method",
           "mean dist", "normal", "volume", "seconds");
    printf("|---|---:|---|---:|---:|---:|---:|\n");
    limn_mesh *cad[3] = {NULL, NULL, NULL};
    const char *cad_names[3] = {"fandisk_quads.off", "bevelled_cube.tri", "part.tri"};
    snprintf(path, sizeof path, "%s/small/fandisk_quads.off", meshes);
    if (limn_mesh_read(b.ctx, path, LIMN_FORMAT_AUTO, &cad[0]))
        die(b.ctx, path);
    cad[1] = cad_shape_mesh(b.ctx, CAD_BEVELLED_CUBE, 24, 1);
    cad[2] = cad_shape_mesh(b.ctx, CAD_PART, 24, 1);
    static const char *organic[] = {"medium/bunny_closed.off", "small/spot_quadrangulated.obj"};
    for (int s = 0; s < ns; s++) {
        for (int k = 0; k < 3; k++)
            run_mesh(&b, cad[k], cad_names[k], sigmas[s], 1600 + 7 * k + s + 1000 * draw);
        for (int k = 0; k < 2; k++) {
            limn_mesh *m = NULL;
            snprintf(path, sizeof path, "%s/%s", meshes, organic[k]);
            if (limn_mesh_read(b.ctx, path, LIMN_FORMAT_AUTO, &m))
                die(b.ctx, path);
            run_mesh(&b, m, strchr(organic[k], '/') + 1, sigmas[s],
                     1700 + 7 * k + s + 1000 * draw);
            limn_mesh_destroy(m);
        }
    }
    for (int k = 0; k < 3; k++)
        limn_mesh_destroy(cad[k]);
    fclose(b.csv);
    printf("\n(limn on '%s'; BNF and Taubin plain C on 1 thread)\nCSV: %s/feature_bench.csv\n",
           limn_context_device_name(b.ctx), outdir);
    limn_context_destroy(b.ctx);
    return 0;
}
