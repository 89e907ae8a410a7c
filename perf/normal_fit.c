/* SPDX-License-Identifier: MIT */
/*
 * The normal-error oracle (normal_fit.h). Each face's Newell normal (as
 * measure_face_normal computes it for limn_mesh_compare) is
 * N = sum_k p_k x p_k+1, so moving its corner k by e changes N by
 * e x (p_k+1 - p_k-1); the angle t = atan2(|u x m|, u . m) (u = N / |N|, m
 * the clean unit normal) has gradient -(m - (u . m) u) / (|N| sin t) in N.
 * The variables are the coefficients scaled so that a unit step moves the
 * vertices by one mean edge length (root mean square), which keeps BFGS's
 * first steps sensible whatever the columns' norms.
 */
#include "normal_fit.h"
#include "topology/measure.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_COLS 64
#define ITERATIONS 400

typedef struct problem {
    const uint32_t *off, *idx;
    size_t faces, n3;
    const double *y, *c, *m; /* m: the clean unit normals, 3 a face (0: skipped) */
    double scale[MAX_COLS];  /* d_i = scale_i * e_i */
    int cols;
    double *p, *gp;
} problem;

/* The mean angle (radians) at scaled coefficients e; its gradient in g. */
static double value(problem *pr, const double *e, double *g)
{
    size_t n3 = pr->n3;
    memcpy(pr->p, pr->y, n3 * sizeof *pr->p);
    for (int i = 0; i < pr->cols; i++) {
        double d = pr->scale[i] * e[i];
        const double *ci = pr->c + (size_t)i * n3;
        for (size_t k = 0; k < n3; k++)
            pr->p[k] += d * ci[k];
    }
    memset(pr->gp, 0, n3 * sizeof *pr->gp);
    double sum = 0.0;
    size_t counted = 0;
    for (size_t f = 0; f < pr->faces; f++) {
        const double *m = pr->m + 3 * f;
        double nv[3];
        measure_face_normal(pr->p, pr->off, pr->idx, f, nv);
        double l = sqrt(nv[0] * nv[0] + nv[1] * nv[1] + nv[2] * nv[2]);
        if (l == 0.0 || (m[0] == 0.0 && m[1] == 0.0 && m[2] == 0.0))
            continue;
        double u[3] = {nv[0] / l, nv[1] / l, nv[2] / l};
        double dot = u[0] * m[0] + u[1] * m[1] + u[2] * m[2];
        double t[3] = {m[0] - dot * u[0], m[1] - dot * u[1], m[2] - dot * u[2]};
        double s = sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
        sum += atan2(s, dot);
        counted++;
        if (s == 0.0)
            continue;
        double G[3] = {-t[0] / (l * s), -t[1] / (l * s), -t[2] / (l * s)};
        uint32_t b = pr->off[f], end = pr->off[f + 1];
        for (uint32_t k = b; k < end; k++) {
            const double *nx = pr->p + 3 * (size_t)pr->idx[k + 1 < end ? k + 1 : b];
            const double *pv = pr->p + 3 * (size_t)pr->idx[k > b ? k - 1 : end - 1];
            double w[3] = {nx[0] - pv[0], nx[1] - pv[1], nx[2] - pv[2]};
            double *gv = pr->gp + 3 * (size_t)pr->idx[k];
            gv[0] += w[1] * G[2] - w[2] * G[1];
            gv[1] += w[2] * G[0] - w[0] * G[2];
            gv[2] += w[0] * G[1] - w[1] * G[0];
        }
    }
    double inv = counted ? 1.0 / (double)counted : 0.0;
    for (int i = 0; g && i < pr->cols; i++) {
        const double *ci = pr->c + (size_t)i * n3;
        double s = 0.0;
        for (size_t k = 0; k < n3; k++)
            s += pr->gp[k] * ci[k];
        g[i] = s * inv * pr->scale[i];
    }
    return sum * inv;
}

static double dotn(const double *a, const double *b, int n)
{
    double s = 0.0;
    for (int i = 0; i < n; i++)
        s += a[i] * b[i];
    return s;
}

/* BFGS with a backtracking (Armijo) line search from e, in place. */
static double bfgs(problem *pr, double *e)
{
    int n = pr->cols;
    double H[MAX_COLS * MAX_COLS], g[MAX_COLS], gn[MAX_COLS], dir[MAX_COLS], en[MAX_COLS];
    double s[MAX_COLS], yv[MAX_COLS], Hy[MAX_COLS];
    for (int i = 0; i < n * n; i++)
        H[i] = i % (n + 1) == 0;
    double f = value(pr, e, g);
    for (int it = 0, quiet = 0; it < ITERATIONS && quiet < 5; it++) {
        for (int i = 0; i < n; i++)
            dir[i] = -dotn(H + i * n, g, n);
        double slope = dotn(g, dir, n);
        if (slope >= 0.0) { /* not a descent direction: start again from steepest descent */
            for (int i = 0; i < n * n; i++)
                H[i] = i % (n + 1) == 0;
            for (int i = 0; i < n; i++)
                dir[i] = -g[i];
            slope = -dotn(g, g, n);
        }
        if (slope == 0.0)
            break;
        double a = 1.0, fn = f;
        for (; a > 1e-14; a *= 0.5) {
            for (int i = 0; i < n; i++)
                en[i] = e[i] + a * dir[i];
            fn = value(pr, en, gn);
            if (fn <= f + 1e-4 * a * slope)
                break;
        }
        if (a <= 1e-14)
            break;
        for (int i = 0; i < n; i++)
            s[i] = en[i] - e[i], yv[i] = gn[i] - g[i];
        double sy = dotn(s, yv, n);
        if (sy > 1e-300) {
            /* H <- (I - r s y') H (I - r y s') + r s s', r = 1 / (s' y) */
            double r = 1.0 / sy;
            for (int i = 0; i < n; i++)
                Hy[i] = dotn(H + i * n, yv, n);
            double yHy = dotn(yv, Hy, n);
            for (int i = 0; i < n; i++)
                for (int j = 0; j < n; j++)
                    H[i * n + j] += -r * (s[i] * Hy[j] + Hy[i] * s[j]) +
                                    (r * r * yHy + r) * s[i] * s[j];
        }
        quiet = f - fn < 1e-12 * fabs(f) ? quiet + 1 : 0;
        memcpy(e, en, (size_t)n * sizeof *e);
        memcpy(g, gn, (size_t)n * sizeof *g);
        f = fn;
    }
    return f;
}

double normal_fit(const limn_mesh *clean, const double *y, const double *c, size_t n3, int cols,
                  const double *starts, int nstarts, int restarts, double *d)
{
    size_t faces = limn_mesh_face_count(clean), n = n3 / 3;
    problem pr = {limn_mesh_face_offsets(clean), limn_mesh_face_indices(clean), faces, n3, y, c,
                  NULL, {0}, cols, malloc(n3 * sizeof(double)), malloc(n3 * sizeof(double))};
    double *m = malloc(3 * (faces ? faces : 1) * sizeof *m);
    if (!pr.p || !pr.gp || !m || cols > MAX_COLS) {
        fprintf(stderr, "normal_fit: out of memory or too many columns\n");
        exit(1);
    }
    const double *x = limn_mesh_positions(clean);
    double edges = 0.0;
    size_t count = 0;
    for (size_t f = 0; f < faces; f++) {
        measure_face_normal(x, pr.off, pr.idx, f, m + 3 * f);
        double l = sqrt(m[3 * f] * m[3 * f] + m[3 * f + 1] * m[3 * f + 1] +
                        m[3 * f + 2] * m[3 * f + 2]);
        for (int k = 0; k < 3; k++)
            m[3 * f + k] = l > 0.0 ? m[3 * f + k] / l : 0.0;
        for (uint32_t k = pr.off[f]; k < pr.off[f + 1]; k++) {
            const double *a = x + 3 * (size_t)pr.idx[k];
            const double *b = x + 3 * (size_t)pr.idx[k + 1 < pr.off[f + 1] ? k + 1 : pr.off[f]];
            edges += sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                          (a[2] - b[2]) * (a[2] - b[2]));
            count++;
        }
    }
    pr.m = m;
    double edge = count ? edges / (double)count : 1.0;
    for (int i = 0; i < cols; i++) {
        double s = 0.0;
        for (size_t k = 0; k < n3; k++)
            s += c[(size_t)i * n3 + k] * c[(size_t)i * n3 + k];
        pr.scale[i] = s > 0.0 ? edge * sqrt((double)n / s) : 0.0;
    }
    double best = INFINITY, e[MAX_COLS];
    uint64_t seed = 0x9e3779b97f4a7c15u;
    for (int k = 0; k < nstarts + restarts; k++) {
        for (int i = 0; i < cols; i++) {
            if (k < nstarts) {
                e[i] = pr.scale[i] > 0.0 ? starts[(size_t)k * cols + i] / pr.scale[i] : 0.0;
                continue;
            }
            /* a restart: the best so far moved by a uniform step of up to 1 in each
               scaled coefficient (one mean edge of movement each) */
            seed = seed * 6364136223846793005u + 1442695040888963407u;
            double u = (double)(seed >> 11) * 0x1.0p-53;
            e[i] = (pr.scale[i] > 0.0 ? d[i] / pr.scale[i] : 0.0) + (2.0 * u - 1.0);
        }
        double v = bfgs(&pr, e);
        if (v < best) {
            best = v;
            for (int i = 0; i < cols; i++)
                d[i] = pr.scale[i] * e[i];
        }
    }
    free(pr.p), free(pr.gp), free(m);
    return best * (180.0 / 3.14159265358979323846);
}
