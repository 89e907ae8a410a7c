/* SPDX-License-Identifier: MIT */
/* Self-check of the test oracles (plain C, no test framework):
 *   1. brute-force refinement (refine_oracle) vs OpenSubdiv refinement (osd_oracle)
 *      at levels 1..3: same counts, vertex i of level k-1 at index i, same point
 *      sets, same faces;
 *   2. brute force at up to 10 levels: base vertex i vs OSD's limit position
 *      (geometric convergence, error per level printed);
 *   3. closed-form limit masks: regular Catmull-Clark (16,4,1)/36, Loop valence-6
 *      1/2 + 1/2 mean, boundary (1,4,1)/6, corners fixed, the general
 *      Catmull-Clark mask with alpha (DESIGN.md section 1) and Loop's beta_n;
 *   4. what OSD does with unreferenced vertices and non-manifold input, and that
 *      the brute force refuses non-manifold input.
 * Usage: oracle_selfcheck [MESH_DIR]   (default /work/shared/meshes/opensubdiv,
 *        or $LIMN_OSD_MESH_DIR). Exit status 0 iff every check passed.
 * Build (from the repository root; ~10 s run, ~1 GB peak memory):
 *   g++ -O2 -std=c++14 -Wall -Wextra -c tests/oracle/osd_oracle.cpp -o osd_oracle.o
 *   gcc -std=c11 -O2 -Wall -Wextra -Wpedantic tests/oracle/obj_mini.c \
 *       tests/oracle/refine_oracle.c tests/oracle/oracle_selfcheck.c osd_oracle.o \
 *       -losdCPU -lstdc++ -lm -o oracle_selfcheck
 */
#include "obj_mini.h"
#include "osd_oracle.h"
#include "refine_oracle.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

static int g_fail = 0;
static int g_checks = 0;

#define CHECK(cond, ...)                                       \
    do {                                                       \
        ++g_checks;                                            \
        if (!(cond)) {                                         \
            ++g_fail;                                          \
            printf("FAIL %s:%d: ", __FILE__, __LINE__);        \
            printf(__VA_ARGS__);                               \
            printf("\n");                                      \
        }                                                      \
    } while (0)

/* ------------------------------------------------------------ small utils -- */
typedef struct {
    const char *name;
    int scheme; /* 0 Loop, 1 CC */
    int nverts;
    double *pos;
    int nfaces;
    int *fs;
    int *fi;
} mesh;

static void mesh_free(mesh *m) {
    free(m->pos);
    free(m->fs);
    free(m->fi);
    memset(m, 0, sizeof *m);
}

/* A hand-built mesh: named, its scheme and nverts positions allocated, no faces yet. */
static void mesh_start(mesh *m, const char *name, int scheme, int nverts) {
    memset(m, 0, sizeof *m);
    m->name = name;
    m->scheme = scheme;
    m->nverts = nverts;
    m->pos = malloc(sizeof(double) * 3 * (size_t)nverts);
}

static unsigned long g_rng = 12345;
static double urand(void) { /* [0,1) */
    g_rng = g_rng * 6364136223846793005UL + 1442695040888963407UL;
    return (double)((g_rng >> 11) & ((1UL << 53) - 1)) / 9007199254740992.0;
}

static double clock_s(void) {
    struct timespec ts;
    timespec_get(&ts, TIME_UTC);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static double dist3(const double *a, const double *b) {
    double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
    return sqrt(dx * dx + dy * dy + dz * dz);
}

static double bbox_diag(const mesh *m) {
    double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
    for (int i = 0; i < m->nverts; ++i)
        for (int c = 0; c < 3; ++c) {
            if (m->pos[3 * i + c] < lo[c]) lo[c] = m->pos[3 * i + c];
            if (m->pos[3 * i + c] > hi[c]) hi[c] = m->pos[3 * i + c];
        }
    return dist3(lo, hi);
}

static long nidx_of(int nf, const int *fs) {
    long n = 0;
    for (int f = 0; f < nf; ++f) n += fs[f];
    return n;
}

static int load_obj(const char *dir, const char *file, int scheme, mesh *m) {
    char path[1024], err[512];
    obj_mini_mesh om;
    snprintf(path, sizeof path, "%s/%s", dir, file);
    if (obj_mini_read(path, &om, err, sizeof err)) {
        printf("FAIL cannot read %s: %s\n", path, err);
        ++g_fail;
        return 1;
    }
    m->name = file;
    m->scheme = scheme;
    m->nverts = om.nverts;
    m->pos = om.pos;
    m->nfaces = om.nfaces;
    m->fs = om.face_sizes;
    m->fi = om.face_indices;
    return 0;
}

/* (nx+1) x (ny+1) vertex grid; quads (CC) or triangles (Loop) with alternating
   diagonals (interior valences 4 and 8); optionally closed into a torus. */
static void make_grid(mesh *m, const char *name, int scheme, int nx, int ny, int torus,
                      int alternate, double jitter) {
    int vx = torus ? nx : nx + 1, vy = torus ? ny : ny + 1;
    m->name = name;
    m->scheme = scheme;
    m->nverts = vx * vy;
    m->pos = malloc(sizeof(double) * 3 * (size_t)m->nverts);
    for (int i = 0; i < vx; ++i)
        for (int j = 0; j < vy; ++j) {
            double *p = m->pos + 3 * (i * vy + j);
            if (torus) {
                double u = 2 * M_PI * i / nx, v = 2 * M_PI * j / ny, R = 3, r = 1;
                p[0] = (R + r * cos(v)) * cos(u);
                p[1] = (R + r * cos(v)) * sin(u);
                p[2] = r * sin(v);
            } else {
                p[0] = i;
                p[1] = j;
                p[2] = 0.3 * sin(1.3 * i) * cos(0.7 * j);
            }
            for (int c = 0; c < 3; ++c) p[c] += jitter * (2 * urand() - 1);
        }
    int per = scheme == 1 ? 1 : 2, d = scheme == 1 ? 4 : 3;
    m->nfaces = nx * ny * per;
    m->fs = malloc(sizeof(int) * (size_t)m->nfaces);
    m->fi = malloc(sizeof(int) * (size_t)m->nfaces * (size_t)d);
    int k = 0, f = 0;
    for (int i = 0; i < nx; ++i)
        for (int j = 0; j < ny; ++j) {
            int a = i * vy + j, b = ((i + 1) % vx) * vy + j, c = ((i + 1) % vx) * vy + (j + 1) % vy,
                e = i * vy + (j + 1) % vy;
            if (scheme == 1) {
                m->fs[f++] = 4;
                m->fi[k++] = a, m->fi[k++] = b, m->fi[k++] = c, m->fi[k++] = e;
            } else if (!alternate || (i + j) % 2 == 0) {
                m->fs[f++] = 3, m->fs[f++] = 3;
                m->fi[k++] = a, m->fi[k++] = b, m->fi[k++] = c;
                m->fi[k++] = a, m->fi[k++] = c, m->fi[k++] = e;
            } else {
                m->fs[f++] = 3, m->fs[f++] = 3;
                m->fi[k++] = a, m->fi[k++] = b, m->fi[k++] = e;
                m->fi[k++] = b, m->fi[k++] = c, m->fi[k++] = e;
            }
        }
}

/* Topological facts per vertex: face count, distinct edge neighbours, boundary
   neighbours (an edge is boundary when used by one face). O(V * F), small meshes. */
typedef struct {
    int nfaces, nnb, nbnd;
    int nb[64];
    int bnd[64];
} vinfo;

static void vertex_info(const mesh *m, int v, vinfo *vi) {
    memset(vi, 0, sizeof *vi);
    int cnt[64] = {0};
    long k = 0;
    for (int f = 0; f < m->nfaces; ++f) {
        int d = m->fs[f];
        for (int j = 0; j < d; ++j)
            if (m->fi[k + j] == v) {
                vi->nfaces++;
                int u[2] = {m->fi[k + (j + 1) % d], m->fi[k + (j + d - 1) % d]};
                for (int t = 0; t < 2; ++t) {
                    int q = 0;
                    while (q < vi->nnb && vi->nb[q] != u[t]) ++q;
                    if (q == vi->nnb && q < 64) vi->nb[vi->nnb++] = u[t];
                    if (q < 64) cnt[q]++;
                }
            }
        k += d;
    }
    for (int q = 0; q < vi->nnb; ++q)
        if (cnt[q] == 1) vi->bnd[vi->nbnd++] = vi->nb[q];
}

/* ------------------------------------------------ closed-form limit masks -- */
/* General Catmull-Clark limit mask with alpha (DESIGN.md section 1), interior
   vertex v: (a V + sum b_j E_j + sum c_k F_k) / (n (n+5)). */
static void cc_general_limit(const mesh *m, int v, double alpha, double out[3]) {
    vinfo vi;
    vertex_info(m, v, &vi);
    int n = vi.nnb;
    double a = n * (n - 1.0) + n * alpha;
    double acc[3] = {0, 0, 0};
    for (int q = 0; q < n; ++q)
        for (int c = 0; c < 3; ++c) acc[c] += (2.0 - alpha) * m->pos[3 * vi.nb[q] + c];
    long k = 0;
    for (int f = 0; f < m->nfaces; ++f) {
        int d = m->fs[f];
        for (int j = 0; j < d; ++j)
            if (m->fi[k + j] == v) {
                a += 4.0 / d;
                /* the two edge neighbours in this face get 4/d (their share of
                   b_ij = 2 - alpha + 4/d_ij + 4/d_ji), the other vertices of the
                   face get c = 4/d */
                for (int t = 0; t < d; ++t) {
                    int u = m->fi[k + t];
                    if (u == v) continue;
                    for (int c = 0; c < 3; ++c) acc[c] += 4.0 / d * m->pos[3 * u + c];
                }
            }
        k += d;
    }
    for (int c = 0; c < 3; ++c) out[c] = (a * m->pos[3 * v + c] + acc[c]) / (n * (n + 5.0));
}

/* Loop interior limit (DESIGN.md): beta_n V + (1 - beta_n) mean(neighbours). */
static void loop_interior_limit(const mesh *m, int v, double out[3]) {
    vinfo vi;
    vertex_info(m, v, &vi);
    int n = vi.nnb;
    double s = 3.0 / 8.0 + cos(2 * M_PI / n) / 4.0;
    double beta = 3.0 / (11.0 - 8.0 * (3.0 / 8.0 + s * s));
    for (int c = 0; c < 3; ++c) {
        double mean = 0;
        for (int q = 0; q < n; ++q) mean += m->pos[3 * vi.nb[q] + c];
        out[c] = beta * m->pos[3 * v + c] + (1 - beta) * mean / n;
    }
}

/* Limit of any vertex of a manifold mesh by the closed forms (alpha used for
   Catmull-Clark interior vertices). Returns the kind: 'i' interior, 'b' boundary,
   'c' corner, 'u' unreferenced. */
static char closed_form_limit(const mesh *m, int v, double alpha, double out[3]) {
    vinfo vi;
    vertex_info(m, v, &vi);
    const double *V = m->pos + 3 * v;
    if (vi.nfaces == 0) {
        memcpy(out, V, 3 * sizeof(double));
        return 'u';
    }
    if (vi.nbnd == 2) {
        if (vi.nfaces == 1) {
            memcpy(out, V, 3 * sizeof(double));
            return 'c';
        }
        for (int c = 0; c < 3; ++c)
            out[c] = (m->pos[3 * vi.bnd[0] + c] + 4 * V[c] + m->pos[3 * vi.bnd[1] + c]) / 6.0;
        return 'b';
    }
    if (m->scheme == 1)
        cc_general_limit(m, v, alpha, out);
    else
        loop_interior_limit(m, v, out);
    return 'i';
}

/* ------------------------------------------- 1. refinement vs OpenSubdiv -- */
typedef struct {
    int *v;
    int n;
} face_key;

static int cmp_faces(const void *a, const void *b) {
    const face_key *x = a, *y = b;
    if (x->n != y->n) return x->n - y->n;
    for (int i = 0; i < x->n; ++i)
        if (x->v[i] != y->v[i]) return x->v[i] < y->v[i] ? -1 : 1;
    return 0;
}

/* canonical faces: rotate so the smallest index is first (orientation kept) */
static face_key *canon_faces(int nf, const int *fs, const int *fi, const int *map, int **store) {
    long nidx = nidx_of(nf, fs);
    face_key *keys = malloc(sizeof(face_key) * (size_t)nf);
    int *buf = malloc(sizeof(int) * (size_t)nidx);
    long k = 0;
    for (int f = 0; f < nf; ++f) {
        int d = fs[f], lo = 0;
        for (int j = 1; j < d; ++j)
            if ((map ? map[fi[k + j]] : fi[k + j]) < (map ? map[fi[k + lo]] : fi[k + lo])) lo = j;
        for (int j = 0; j < d; ++j) {
            int x = fi[k + (lo + j) % d];
            buf[k + j] = map ? map[x] : x;
        }
        keys[f].v = buf + k;
        keys[f].n = d;
        k += d;
    }
    qsort(keys, (size_t)nf, sizeof(face_key), cmp_faces);
    *store = buf;
    return keys;
}

static void check_refinement(const mesh *m, int maxlevel) {
    char err[2048];
    double diag = bbox_diag(m), tol = 1e-12 * (diag > 1 ? diag : 1);
    for (int L = 1; L <= maxlevel; ++L) {
        int nv1, nf1, *fs1, *fi1, nv2, nf2, *fs2, *fi2;
        double *p1, *p2;
        if (osd_oracle_refine(m->scheme, m->nverts, m->pos, m->nfaces, m->fs, m->fi, L, &nv1, &p1,
                              &nf1, &fs1, &fi1, err, sizeof err)) {
            CHECK(0, "%s: osd_oracle_refine L%d: %s", m->name, L, err);
            return;
        }
        if (refine_oracle(m->scheme, 0.0, L, m->nverts, m->pos, m->nfaces, m->fs, m->fi, &nv2, &p2,
                          &nf2, &fs2, &fi2, err, sizeof err)) {
            CHECK(0, "%s: refine_oracle L%d: %s", m->name, L, err);
            free(p1), free(fs1), free(fi1);
            return;
        }
        CHECK(nv1 == nv2 && nf1 == nf2, "%s L%d: counts OSD %d/%d brute %d/%d", m->name, L, nv1,
              nf1, nv2, nf2);
        double dmax_idx = 0, dmax_set = 0;
        int bad_match = 0, faces_equal = 0;
        if (nv1 == nv2 && nf1 == nf2) {
            /* base vertex i is vertex i of every level in both */
            for (int i = 0; i < m->nverts; ++i) {
                double d = dist3(p1 + 3 * i, p2 + 3 * i);
                if (d > dmax_idx) dmax_idx = d;
            }
            /* point sets: nearest OSD point of every brute-force point, bijective */
            int *map = malloc(sizeof(int) * (size_t)nv2);
            char *used = calloc((size_t)nv1, 1);
            for (int i = 0; i < nv2; ++i) {
                int best = -1;
                double bd = 1e300;
                for (int j = 0; j < nv1; ++j) {
                    double d = dist3(p2 + 3 * i, p1 + 3 * j);
                    if (d < bd) bd = d, best = j;
                }
                map[i] = best;
                if (bd > dmax_set) dmax_set = bd;
                if (used[best]) bad_match++;
                used[best] = 1;
            }
            /* faces, through the point map, rotation-canonical, as sorted sets */
            int *b1, *b2;
            face_key *k1 = canon_faces(nf1, fs1, fi1, NULL, &b1);
            face_key *k2 = canon_faces(nf2, fs2, fi2, map, &b2);
            faces_equal = 1;
            for (int f = 0; f < nf1 && faces_equal; ++f)
                if (cmp_faces(k1 + f, k2 + f)) faces_equal = 0;
            free(k1), free(k2), free(b1), free(b2), free(map), free(used);
        }
        printf("  %-22s %-4s L%d: %6d verts %6d faces  |base vertices diff| %.1e  "
               "|point-set diff| %.1e  faces %s\n",
               m->name, m->scheme ? "CC" : "Loop", L, nv1, nf1, dmax_idx, dmax_set,
               faces_equal ? "same" : "DIFFER");
        CHECK(dmax_idx <= tol, "%s L%d: base vertices differ by %.3g", m->name, L, dmax_idx);
        CHECK(dmax_set <= tol && bad_match == 0, "%s L%d: point sets differ (%.3g, %d collisions)",
              m->name, L, dmax_set, bad_match);
        CHECK(faces_equal, "%s L%d: face sets differ", m->name, L);
        free(p1), free(fs1), free(fi1), free(p2), free(fs2), free(fi2);
    }
}

/* ------------------------------------------------ 2. convergence to limit -- */
/* Max over base vertices of |brute force level L vertex i - reference limit i|,
   for L = 1..levels while the finest mesh stays below max_faces (8M).
   Passes when at least 8 levels ran, the per-level ratio of the last two levels
   is <= 0.4 (geometric convergence; or the error is at rounding level), and the
   final error is below 1e-4 of the mesh size. */
static void convergence(const mesh *m, double alpha, const double *ref, const char *label) {
    const int levels = 10;
    const long max_faces = 8000000;
    char err[2048];
    double prev = 0, e = 0, ratio = 0;
    int last = 0;
    /* faces after one level: one quad per corner (CC), four per triangle (Loop) */
    long nfL = m->scheme == 1 ? nidx_of(m->nfaces, m->fs) : 4L * m->nfaces;
    printf("  %-22s %-4s %s\n", m->name, m->scheme ? "CC" : "Loop", label);
    for (int L = 1; L <= levels; ++L) {
        if (L > 1) nfL *= 4;
        if (nfL > max_faces) break;
        int nv, nfo, *fs, *fi;
        double *p;
        double t0 = clock_s();
        if (refine_oracle(m->scheme, alpha, L, m->nverts, m->pos, m->nfaces, m->fs, m->fi, &nv, &p,
                          &nfo, &fs, &fi, err, sizeof err)) {
            CHECK(0, "%s: refine_oracle L%d: %s", m->name, L, err);
            break;
        }
        double t1 = clock_s();
        e = 0;
        for (int i = 0; i < m->nverts; ++i) {
            double d = dist3(p + 3 * i, ref + 3 * i);
            if (d > e) e = d;
        }
        printf("    L%-2d max error %.3e", L, e);
        ratio = prev > 0 ? e / prev : 0;
        if (L > 1 && prev > 0 && e > 0) printf("  ratio %.3f", ratio);
        printf("  (%d faces, %.2f s)\n", nfo, t1 - t0);
        prev = e;
        last = L;
        free(p), free(fs), free(fi);
    }
    double scale = 1 + bbox_diag(m);
    CHECK(last >= 8 && e < 1e-4 * scale && (ratio <= 0.4 || e < 1e-14 * scale),
          "%s %s: error %.3g at level %d, last ratio %.3f", m->name, label, e, last, ratio);
}

/* ------------------------------------------------------------- sections -- */
/* The OSD limit of m, or NULL after a failed check when OSD refuses the mesh. */
static double *osd_limit_checked(const mesh *m) {
    char err[2048];
    double *lim = malloc(sizeof(double) * 3 * (size_t)m->nverts);
    if (osd_oracle_limit(m->scheme, m->nverts, m->pos, m->nfaces, m->fs, m->fi, lim, err,
                         sizeof err)) {
        CHECK(0, "%s: osd_oracle_limit: %s", m->name, err);
        free(lim);
        return NULL;
    }
    return lim;
}

static void check_closed_forms_vs_osd(const mesh *m) {
    double *lim = osd_limit_checked(m);
    if (!lim) return;
    double emax[4] = {0, 0, 0, 0};
    int cnt[4] = {0, 0, 0, 0};
    const char *kinds = "ibcu";
    for (int v = 0; v < m->nverts; ++v) {
        double cf[3];
        char kind = closed_form_limit(m, v, 0.0, cf);
        int ki = (int)(strchr(kinds, kind) - kinds);
        double d = dist3(cf, lim + 3 * v);
        if (d > emax[ki]) emax[ki] = d;
        cnt[ki]++;
    }
    printf("  %-22s %-4s OSD limit vs closed form: interior %d (%.1e) boundary %d (%.1e) "
           "corner %d (%.1e) unreferenced %d (%.1e)\n",
           m->name, m->scheme ? "CC" : "Loop", cnt[0], emax[0], cnt[1], emax[1], cnt[2], emax[2],
           cnt[3], emax[3]);
    for (int k = 0; k < 4; ++k)
        CHECK(emax[k] <= 1e-14 * (1 + bbox_diag(m)), "%s: OSD vs closed form (%c) %.3g", m->name,
              kinds[k], emax[k]);
    free(lim);
}

/* Regular closed forms named in the brief, computed independently of the general
   formula: CC interior (16 V + 4 sum E + sum D)/36, Loop valence 6 V/2 + mean/2. */

/* One grid of section 3 with its OSD limit; returns 0 when OSD refused (err printed),
   so the caller's error stays at 1e300 and fails its check. */
static int grid_with_osd_limit(mesh *t, const char *name, int scheme, int nx, int ny, int torus,
                               int alternate, double jitter, double **lim) {
    char err[2048];
    make_grid(t, name, scheme, nx, ny, torus, alternate, jitter);
    *lim = malloc(sizeof(double) * 3 * (size_t)t->nverts);
    if (!osd_oracle_limit(scheme, t->nverts, t->pos, t->nfaces, t->fs, t->fi, *lim, err,
                          sizeof err))
        return 1;
    printf("  %s\n", err);
    return 0;
}

/* CC regular interior (16,4,1)/36 on the 8x6 torus: max error against lim. */
static double cc_regular_error(const mesh *t, const double *lim) {
    double e = 0;
    int vy = 6;
    for (int i = 0; i < 8; ++i)
        for (int j = 0; j < 6; ++j) {
            int v = i * vy + j;
#define ID(a, b) ((((a) + 8) % 8) * vy + (((b) + 6) % 6))
            int E[4] = {ID(i + 1, j), ID(i - 1, j), ID(i, j + 1), ID(i, j - 1)};
            int D[4] = {ID(i + 1, j + 1), ID(i - 1, j + 1), ID(i + 1, j - 1), ID(i - 1, j - 1)};
#undef ID
            for (int c = 0; c < 3; ++c) {
                double x = 16 * t->pos[3 * v + c];
                for (int q = 0; q < 4; ++q) x += 4 * t->pos[3 * E[q] + c] + t->pos[3 * D[q] + c];
                double d = fabs(x / 36 - lim[3 * v + c]);
                if (d > e) e = d;
            }
        }
    return e;
}

/* Loop valence 6: V/2 + mean/2 on the all-valence-6 torus: max error against lim. */
static double loop_regular_error(const mesh *t, const double *lim) {
    double e = 0;
    for (int v = 0; v < t->nverts; ++v) {
        vinfo vi;
        vertex_info(t, v, &vi);
        CHECK(vi.nnb == 6, "loop torus valence %d", vi.nnb);
        for (int c = 0; c < 3; ++c) {
            double mean = 0;
            for (int q = 0; q < vi.nnb; ++q) mean += t->pos[3 * vi.nb[q] + c] / vi.nnb;
            double d = fabs(0.5 * t->pos[3 * v + c] + 0.5 * mean - lim[3 * v + c]);
            if (d > e) e = d;
        }
    }
    return e;
}

static void check_regular_masks(void) {
    static const struct {
        const char *grid, *scheme_name, *form, *label;
        int scheme;
        double (*error)(const mesh *, const double *);
    } regular[] = {
        {"cc_torus_8x6", "CC", "CC regular interior (16,4,1)/36",
         "brute force vs (16,4,1)/36 (== OSD)", 1, cc_regular_error},
        {"loop_torus_8x6", "Loop", "Loop valence 6: V/2 + mean/2",
         "brute force vs V/2 + mean/2 (== OSD)", 0, loop_regular_error},
    };
    printf("\n== 3. Regular closed forms\n");
    mesh t;
    double *lim;
    for (size_t k = 0; k < sizeof regular / sizeof regular[0]; ++k) {
        double e = 1e300;
        if (grid_with_osd_limit(&t, regular[k].grid, regular[k].scheme, 8, 6, 1, 0, 0.15, &lim))
            e = regular[k].error(&t, lim);
        printf("  %s vs OSD limit, 48 vertices: %.1e\n", regular[k].form, e);
        CHECK(e < 1e-14, "%s regular mask vs OSD %.3g", regular[k].scheme_name, e);
        convergence(&t, 0.0, lim, regular[k].label);
        free(lim);
        mesh_free(&t);
    }

    /* boundary (1,4,1)/6 and corners on open grids, both schemes */
    for (int s = 0; s <= 1; ++s) {
        double eb1 = 1e300, ec = 1e300;
        int nb = 0, nc = 0;
        if (grid_with_osd_limit(&t, s ? "cc_open_grid_5x4" : "loop_open_grid_5x4", s, 5, 4, 0, 1,
                                0.1, &lim)) {
            eb1 = ec = 0;
            for (int v = 0; v < t.nverts; ++v) {
                vinfo vi;
                vertex_info(&t, v, &vi);
                if (vi.nbnd != 2) continue;
                for (int c = 0; c < 3; ++c) {
                    double x = vi.nfaces == 1
                                   ? t.pos[3 * v + c]
                                   : (t.pos[3 * vi.bnd[0] + c] + 4 * t.pos[3 * v + c] +
                                      t.pos[3 * vi.bnd[1] + c]) / 6;
                    double d = fabs(x - lim[3 * v + c]);
                    if (vi.nfaces == 1) {
                        if (d > ec) ec = d;
                    } else if (d > eb1)
                        eb1 = d;
                }
                if (vi.nfaces == 1)
                    nc++;
                else
                    nb++;
            }
        }
        printf("  %s boundary (1,4,1)/6 vs OSD: %d vertices %.1e; corners fixed: %d vertices "
               "%.1e\n",
               s ? "CC  " : "Loop", nb, eb1, nc, ec);
        CHECK(eb1 < 1e-14 && ec == 0 && nb > 0 && nc > 0, "boundary/corner masks %.3g %.3g", eb1,
              ec);
        free(lim);
        mesh_free(&t);
    }
}

/* General CC mask with alpha vs brute force with the alpha first step. */
static void check_alpha(const mesh *m, double alpha) {
    double *ref = malloc(sizeof(double) * 3 * (size_t)m->nverts);
    for (int v = 0; v < m->nverts; ++v) closed_form_limit(m, v, alpha, ref + 3 * v);
    char label[128];
    snprintf(label, sizeof label, "alpha %.2f: brute force (alpha first step) vs closed form",
             alpha);
    convergence(m, alpha, ref, label);
    free(ref);
}

/* ------------------------------------------------------ 4. non-manifold -- */
static int is_pinned(const double *lim, const double *pos, int v) {
    return dist3(lim + 3 * v, pos + 3 * v) == 0.0;
}

static int is_crease(const double *lim, const double *pos, int v, int a, int b) {
    double x[3];
    for (int c = 0; c < 3; ++c) x[c] = (pos[3 * a + c] + 4 * pos[3 * v + c] + pos[3 * b + c]) / 6;
    return dist3(x, lim + 3 * v) < 1e-14;
}

static int brute_refuses(const mesh *m, char *err, size_t errlen) {
    int nv, nf, *fs, *fi;
    double *p;
    int rc = refine_oracle(m->scheme, 0.0, 1, m->nverts, m->pos, m->nfaces, m->fs, m->fi, &nv, &p,
                           &nf, &fs, &fi, err, errlen);
    if (!rc) free(p), free(fs), free(fi);
    return rc;
}

static void nonmanifold_case(mesh *m, const int *pinned, int npinned, int (*creases)[3],
                             int ncreases, int expect_refusal) {
    char err[2048];
    double *lim = osd_limit_checked(m);
    if (!lim) return;
    int *nm = malloc(sizeof(int) * (size_t)m->nverts);
    osd_oracle_classify(m->scheme, m->nverts, m->nfaces, m->fs, m->fi, NULL, nm, NULL, err,
                        sizeof err);
    int nnm = 0, npin = 0;
    for (int v = 0; v < m->nverts; ++v) {
        nnm += nm[v];
        npin += is_pinned(lim, m->pos, v);
    }
    int ok = 1;
    for (int k = 0; k < npinned; ++k) ok &= is_pinned(lim, m->pos, pinned[k]);
    for (int k = 0; k < ncreases; ++k)
        ok &= is_crease(lim, m->pos, creases[k][0], creases[k][1], creases[k][2]);
    char berr[512];
    int refused = brute_refuses(m, berr, sizeof berr);
    printf("  %-44s %-4s OSD non-manifold vertices %2d, pinned %2d: %s; brute force %s\n", m->name,
           m->scheme ? "CC" : "Loop", nnm, npin, ok ? "as documented" : "NOT as documented",
           refused ? berr : "accepts");
    CHECK(ok, "%s: OSD behaviour changed", m->name);
    CHECK(refused == expect_refusal, "%s: brute force %s", m->name,
          refused ? "refused" : "accepted");
    free(nm);
    free(lim);
}

static void triangulate(const mesh *q, mesh *t, const char *name) {
    t->name = name;
    t->scheme = 0;
    t->nverts = q->nverts;
    t->pos = malloc(sizeof(double) * 3 * (size_t)q->nverts);
    memcpy(t->pos, q->pos, sizeof(double) * 3 * (size_t)q->nverts);
    t->nfaces = 2 * q->nfaces;
    t->fs = malloc(sizeof(int) * (size_t)t->nfaces);
    t->fi = malloc(sizeof(int) * 3 * (size_t)t->nfaces);
    for (int f = 0; f < q->nfaces; ++f) {
        const int *a = q->fi + 4 * f;
        int tri[6] = {a[0], a[1], a[2], a[0], a[2], a[3]};
        t->fs[2 * f] = t->fs[2 * f + 1] = 3;
        memcpy(t->fi + 6 * f, tri, sizeof tri);
    }
}

static void check_nonmanifold(const char *dir) {
    char err[2048];
    printf("\n== 4. Unusual input: what OSD does (limit positions), brute-force refusal\n");
    /* unreferenced vertices: OSD keeps them (limit and refinement) */
    {
        double P[18] = {0, 0, 0, 1, 0, 0, 1, 1, 0.2, 0, 1, 0, 5, 6, 7, 8, 9, 10};
        int fs[1] = {4}, fi[4] = {0, 1, 2, 3}, fs3[1] = {3}, fi3[3] = {0, 1, 2};
        for (int s = 0; s <= 1; ++s) {
            double lim[18];
            int rc = osd_oracle_limit(s, 6, P, 1, s ? fs : fs3, s ? fi : fi3, lim, err, sizeof err);
            int nv, nf, *a, *b;
            double *p = NULL;
            int rc2 = osd_oracle_refine(s, 6, P, 1, s ? fs : fs3, s ? fi : fi3, 3, &nv, &p, &nf, &a,
                                        &b, err, sizeof err);
            /* unreferenced: 4 and 5 (and 3 for the triangle) */
            int ok = !rc && !rc2 && is_pinned(lim, P, 4) && is_pinned(lim, P, 5) &&
                     is_pinned(p, P, 4) && is_pinned(p, P, 5);
            if (ok && s == 0) ok = is_pinned(lim, P, 3) && is_pinned(p, P, 3);
            printf("  unreferenced vertices (%s): OSD limit and 3-level refinement keep them: %s\n",
                   s ? "CC" : "Loop", ok ? "yes" : "NO");
            CHECK(ok, "unreferenced vertices not kept by OSD (%s)", s ? "CC" : "Loop");
            int nv2, nf2, *a2, *b2;
            double *p2;
            int rc3 = refine_oracle(s, 0.0, 3, 6, P, 1, s ? fs : fs3, s ? fi : fi3, &nv2, &p2, &nf2,
                                    &a2, &b2, err, sizeof err);
            CHECK(!rc3 && nv2 == nv && is_pinned(p2, P, 4) && is_pinned(p2, P, 5),
                  "brute force unreferenced vertices");
            if (!rc3) free(p2), free(a2), free(b2);
            if (!rc2) free(p), free(a), free(b);
        }
    }
    /* fin: three quad sheets on the line 0-1-2-3-4 */
    {
        mesh m;
        mesh_start(&m, "fin: 3 sheets on line 0-1-2-3-4", 1, 20);
        double dirs[3][3] = {{0, 1, 0}, {0, 0, 1}, {0, -0.7, -0.7}};
        int nv = 0;
        for (int i = 0; i < 5; ++i, ++nv) {
            m.pos[3 * nv] = i + 0.1 * urand();
            m.pos[3 * nv + 1] = 0.1 * urand();
            m.pos[3 * nv + 2] = 0.1 * urand();
        }
        for (int s = 0; s < 3; ++s)
            for (int i = 0; i < 5; ++i, ++nv)
                for (int c = 0; c < 3; ++c)
                    m.pos[3 * nv + c] = (c == 0 ? i : dirs[s][c]) + 0.1 * urand();
        m.nfaces = 12;
        m.fs = malloc(sizeof(int) * 12);
        m.fi = malloc(sizeof(int) * 48);
        int k = 0;
        for (int s = 0; s < 3; ++s)
            for (int i = 0; i < 4; ++i) {
                int q[4] = {i, i + 1, 5 + 5 * s + i + 1, 5 + 5 * s + i};
                m.fs[4 * s + i] = 4;
                for (int t = 0; t < 4; ++t) m.fi[k++] = s == 1 ? q[t] : q[3 - t];
            }
        int pinned[2] = {0, 4};
        int creases[3][3] = {{1, 0, 2}, {2, 1, 3}, {3, 2, 4}};
        nonmanifold_case(&m, pinned, 2, creases, 3, 1);
        mesh t;
        triangulate(&m, &t, "fin, triangulated");
        nonmanifold_case(&t, pinned, 2, creases, 3, 1);
        mesh_free(&t);
        mesh_free(&m);
    }
    /* bow-tie: two 2x2 quad grids sharing their centre vertex 0 (two cones) */
    {
        mesh m;
        mesh_start(&m, "bow-tie: two cones share apex 0", 1, 17);
        m.nfaces = 8;
        m.fs = malloc(sizeof(int) * 8);
        m.fi = malloc(sizeof(int) * 32);
        int id[2][3][3], n = 1, k = 0, f = 0;
        for (int c = 0; c < 3; ++c) m.pos[c] = 0.1 * urand();
        for (int g = 0; g < 2; ++g)
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j) {
                    if (i == 1 && j == 1) {
                        id[g][i][j] = 0;
                        continue;
                    }
                    id[g][i][j] = n;
                    m.pos[3 * n] = i - 1 + 0.1 * urand();
                    m.pos[3 * n + 1] = j - 1 + 0.1 * urand();
                    m.pos[3 * n + 2] = (g ? -1 : 1) * 0.7 + 0.1 * urand();
                    n++;
                }
        for (int g = 0; g < 2; ++g)
            for (int i = 0; i < 2; ++i)
                for (int j = 0; j < 2; ++j) {
                    int q[4] = {id[g][i][j], id[g][i + 1][j], id[g][i + 1][j + 1], id[g][i][j + 1]};
                    m.fs[f++] = 4;
                    for (int t = 0; t < 4; ++t) m.fi[k++] = q[g ? 3 - t : t];
                }
        int pinned[1] = {0};
        nonmanifold_case(&m, pinned, 1, NULL, 0, 1);
        mesh t;
        triangulate(&m, &t, "bow-tie, triangulated");
        nonmanifold_case(&t, pinned, 1, NULL, 0, 1);
        mesh_free(&t);
        /* two quads sharing only one corner vertex */
        int fs2[2] = {4, 4}, fi2[8] = {0, 1, 2, 3, 0, 5, 6, 7};
        mesh q = m;
        q.name = "bow-tie: two quads share vertex 0 only";
        q.nverts = 8;
        q.nfaces = 2;
        q.fs = fs2;
        q.fi = fi2;
        nonmanifold_case(&q, pinned, 1, NULL, 0, 1);
        mesh_free(&m);
    }
    /* 3x3 quad grid with one face flipped; and with a face repeating a vertex */
    {
        mesh m;
        make_grid(&m, "3x3 grid, centre face flipped", 1, 3, 3, 0, 0, 0.1);
        /* centre face is face 4: (5,9,10,6) with vy = 4 */
        int *c4 = m.fi + 16, tmp;
        tmp = c4[1], c4[1] = c4[3], c4[3] = tmp; /* (5,6,10,9) */
        int pinned[4] = {5, 6, 9, 10};
        nonmanifold_case(&m, pinned, 4, NULL, 0, 1);
        /* OSD makes the inconsistent edges infinitely sharp: edge points at midpoints */
        {
            int nv, nf, *a, *b;
            double *p;
            if (!osd_oracle_refine(1, m.nverts, m.pos, m.nfaces, m.fs, m.fi, 1, &nv, &p, &nf, &a,
                                   &b, err, sizeof err)) {
                int pairs[4][2] = {{5, 6}, {6, 10}, {10, 9}, {9, 5}}, found = 0;
                for (int e = 0; e < 4; ++e) {
                    double mid[3];
                    for (int c = 0; c < 3; ++c)
                        mid[c] = 0.5 * (m.pos[3 * pairs[e][0] + c] + m.pos[3 * pairs[e][1] + c]);
                    for (int i = 0; i < nv; ++i)
                        if (dist3(mid, p + 3 * i) < 1e-14) {
                            found++;
                            break;
                        }
                }
                printf("    inconsistently oriented edges refined to their midpoints (sharp): "
                       "%d of 4\n",
                       found);
                CHECK(found == 4, "flipped-face edges not sharp in OSD");
                free(p), free(a), free(b);
            }
        }
        c4[1] = 9, c4[2] = 10, c4[3] = 10; /* (5,9,10,10): repeats vertex 10, drops 6 */
        m.name = "3x3 grid, face (5,9,10,10) repeats 10";
        int pinned2[1] = {10};
        int creases2[2][3] = {{5, 6, 10}, {6, 5, 10}};
        nonmanifold_case(&m, pinned2, 1, creases2, 2, 1);
        mesh_free(&m);
    }
    /* OpenSubdiv's own non-manifold shapes: OSD must accept them */
    {
        const char *files[3] = {"catmark_nonman_edges.obj", "catmark_nonman_verts.obj",
                                "loop_nonman_edges.obj"};
        for (int k = 0; k < 3; ++k) {
            mesh m;
            if (load_obj(dir, files[k], k == 2 ? 0 : 1, &m)) continue;
            nonmanifold_case(&m, NULL, 0, NULL, 0, 1);
            mesh_free(&m);
        }
    }
}

/* ------------------------------------------------------------------ main -- */
int main(int argc, char **argv) {
    const char *dir = argc > 1 ? argv[1] : getenv("LIMN_OSD_MESH_DIR");
    if (!dir) dir = "/work/shared/meshes/opensubdiv";
    double t_start = clock_s();

    mesh meshes[8];
    int nm = 0;
    struct {
        const char *file;
        int scheme;
    } files[] = {{"catmark_cube.obj", 1},     {"catmark_pyramid.obj", 1},
                 {"catmark_nonquads.obj", 1}, {"loop_cube.obj", 0},
                 {"loop_icosahedron.obj", 0}, {"loop_cube.obj", 1}};
    for (size_t k = 0; k < sizeof files / sizeof files[0]; ++k)
        if (!load_obj(dir, files[k].file, files[k].scheme, &meshes[nm])) ++nm;
    make_grid(&meshes[nm++], "loop_open_grid_4x4", 0, 4, 4, 0, 1, 0.1);
    make_grid(&meshes[nm++], "cc_open_grid_3x4", 1, 3, 4, 0, 0, 0.1);

    printf("== 1. Brute-force refinement vs OpenSubdiv (levels 1..3; OSD's vertex i of level k "
           "is checked to be the child of vertex i of level k-1 at every level)\n");
    for (int k = 0; k < nm; ++k) check_refinement(&meshes[k], 3);

    printf("\n== 2. Brute force (up to 10 levels) vs OSD limit, base vertices\n");
    for (int k = 0; k < nm; ++k) {
        mesh *m = &meshes[k];
        double *lim = osd_limit_checked(m);
        if (!lim) continue;
        convergence(m, 0.0, lim, "vs OSD limit");
        free(lim);
    }

    check_regular_masks();

    printf("\n   General closed forms (DESIGN.md section 1) vs OSD limit (alpha = 0)\n");
    for (int k = 0; k < nm; ++k) check_closed_forms_vs_osd(&meshes[k]);
    printf("\n   General Catmull-Clark mask with alpha vs brute force with alpha at the first "
           "step only\n");
    for (int k = 0; k < nm; ++k)
        if (meshes[k].scheme == 1) check_alpha(&meshes[k], 0.5);
    check_alpha(&meshes[0], 6.0 / 7.0);

    check_nonmanifold(dir);

    for (int k = 0; k < nm; ++k) mesh_free(&meshes[k]);
    printf("\n%d checks, %d failed (%.1f s)\n", g_checks, g_fail, clock_s() - t_start);
    return g_fail ? 1 : 0;
}
