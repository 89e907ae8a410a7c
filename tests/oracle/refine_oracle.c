/* SPDX-License-Identifier: MIT */
/* Test-only brute-force uniform Loop / Catmull-Clark refinement; see refine_oracle.h. */
#include "refine_oracle.h"
#include "oracle_fail.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* One level of a mesh. Corner (= half-edge) h of face f is fidx[foff[f] + j]; the
   half-edge h goes from corner j to corner j+1 of its face. */
typedef struct {
    int nv;
    double *pos; /* 3*nv */
    int nf;
    int *fsize;  /* nf */
    int *fidx;   /* nidx */
    long nidx;
} ro_mesh;

static void ro_mesh_free(ro_mesh *m) {
    free(m->pos);
    free(m->fsize);
    free(m->fidx);
    memset(m, 0, sizeof *m);
}

/* Edge table of one level. */
typedef struct {
    int ne;
    int *v0, *v1;   /* endpoints, in the direction of half-edge h0 */
    long *h0, *h1;  /* the half-edges; h1 = -1 on a boundary edge */
    int *hedge;     /* nidx: edge of each half-edge */
    int *hface;     /* nidx: face of each half-edge */
    long *foff;     /* nf + 1 */
} ro_edges;

static void ro_edges_free(ro_edges *e) {
    free(e->v0);
    free(e->v1);
    free(e->h0);
    free(e->h1);
    free(e->hedge);
    free(e->hface);
    free(e->foff);
    memset(e, 0, sizeof *e);
}

static long ro_next(const ro_edges *e, long h) {
    int f = e->hface[h];
    return h + 1 == e->foff[f + 1] ? e->foff[f] : h + 1;
}

static long ro_prev(const ro_edges *e, long h) {
    int f = e->hface[h];
    return h == e->foff[f] ? e->foff[f + 1] - 1 : h - 1;
}

/* Builds the edge table in O(nidx): half-edges bucketed by their lower vertex,
   matched by a linear scan inside the (valence-sized) bucket. */
static int ro_build_edges(const ro_mesh *m, ro_edges *e, char *err, size_t errlen) {
    memset(e, 0, sizeof *e);
    long nidx = m->nidx;
    int nv = m->nv;
    e->foff = malloc(sizeof(long) * ((size_t)m->nf + 1));
    e->hface = malloc(sizeof(int) * (size_t)(nidx > 0 ? nidx : 1));
    e->hedge = malloc(sizeof(int) * (size_t)(nidx > 0 ? nidx : 1));
    long *cnt = calloc((size_t)nv + 1, sizeof(long));
    long *bucket = malloc(sizeof(long) * (size_t)(nidx > 0 ? nidx : 1));
    /* at most nidx edges */
    e->v0 = malloc(sizeof(int) * (size_t)(nidx > 0 ? nidx : 1));
    e->v1 = malloc(sizeof(int) * (size_t)(nidx > 0 ? nidx : 1));
    e->h0 = malloc(sizeof(long) * (size_t)(nidx > 0 ? nidx : 1));
    e->h1 = malloc(sizeof(long) * (size_t)(nidx > 0 ? nidx : 1));
    int rc = 0;
    if (!e->foff || !e->hface || !e->hedge || !cnt || !bucket || !e->v0 || !e->v1 || !e->h0 ||
        !e->h1) {
        rc = oracle_fail(err, errlen, "refine_oracle: out of memory");
        goto out;
    }
    e->foff[0] = 0;
    for (int f = 0; f < m->nf; ++f) {
        e->foff[f + 1] = e->foff[f] + m->fsize[f];
        for (long h = e->foff[f]; h < e->foff[f + 1]; ++h) e->hface[h] = f;
    }
    for (long h = 0; h < nidx; ++h) {
        int a = m->fidx[h], b = m->fidx[ro_next(e, h)];
        cnt[(a < b ? a : b) + 1]++;
    }
    for (int v = 0; v < nv; ++v) cnt[v + 1] += cnt[v];
    {
        long *fill = malloc(sizeof(long) * ((size_t)nv + 1));
        if (!fill) {
            rc = oracle_fail(err, errlen, "refine_oracle: out of memory");
            goto out;
        }
        memcpy(fill, cnt, sizeof(long) * ((size_t)nv + 1));
        for (long h = 0; h < nidx; ++h) {
            int a = m->fidx[h], b = m->fidx[ro_next(e, h)];
            bucket[fill[a < b ? a : b]++] = h;
        }
        free(fill);
    }
    int ne = 0;
    for (int v = 0; v < nv; ++v) {
        int first = ne;
        for (long k = cnt[v]; k < cnt[v + 1]; ++k) {
            long h = bucket[k];
            int a = m->fidx[h], b = m->fidx[ro_next(e, h)];
            int hi = a < b ? b : a;
            int found = -1;
            for (int x = first; x < ne; ++x)
                if ((e->v0[x] == hi || e->v1[x] == hi)) {
                    found = x;
                    break;
                }
            if (found < 0) {
                e->v0[ne] = a;
                e->v1[ne] = b;
                e->h0[ne] = h;
                e->h1[ne] = -1;
                e->hedge[h] = ne;
                ++ne;
            } else {
                if (e->h1[found] >= 0) {
                    rc = oracle_fail(err, errlen,
                                 "refine_oracle: non-manifold edge (%d,%d): more than two faces",
                                 a, b);
                    goto out;
                }
                if (e->v0[found] == a) {
                    rc = oracle_fail(err, errlen,
                                 "refine_oracle: inconsistent orientation at edge (%d,%d) "
                                 "(faces %d and %d)",
                                 a, b, e->hface[e->h0[found]], e->hface[h]);
                    goto out;
                }
                e->h1[found] = h;
                e->hedge[h] = found;
            }
        }
    }
    e->ne = ne;
out:
    free(cnt);
    free(bucket);
    if (rc) ro_edges_free(e);
    return rc;
}

/* Union-find over corners, for the one-fan-per-vertex check. */
static long uf_find(long *p, long x) {
    while (p[x] != x) {
        p[x] = p[p[x]];
        x = p[x];
    }
    return x;
}

static int ro_check_fans(const ro_mesh *m, const ro_edges *e, char *err, size_t errlen) {
    long *par = malloc(sizeof(long) * (size_t)(m->nidx > 0 ? m->nidx : 1));
    long *root = malloc(sizeof(long) * (size_t)(m->nv > 0 ? m->nv : 1));
    if (!par || !root) {
        free(par);
        free(root);
        return oracle_fail(err, errlen, "refine_oracle: out of memory");
    }
    for (long h = 0; h < m->nidx; ++h) par[h] = h;
    for (int x = 0; x < e->ne; ++x) {
        if (e->h1[x] < 0) continue;
        /* h0: a->b in face A (corners h0 at a, next(h0) at b);
           h1: b->a in face B (corners h1 at b, next(h1) at a). */
        long h0 = e->h0[x], h1 = e->h1[x];
        long ra = uf_find(par, h0), rb = uf_find(par, ro_next(e, h1));
        if (ra != rb) par[ra] = rb;
        ra = uf_find(par, ro_next(e, h0));
        rb = uf_find(par, h1);
        if (ra != rb) par[ra] = rb;
    }
    for (int v = 0; v < m->nv; ++v) root[v] = -1;
    int rc = 0;
    for (long h = 0; h < m->nidx && !rc; ++h) {
        int v = m->fidx[h];
        long r = uf_find(par, h);
        if (root[v] < 0)
            root[v] = r;
        else if (root[v] != r)
            rc = oracle_fail(err, errlen,
                         "refine_oracle: non-manifold vertex %d (its faces form more than one "
                         "fan)",
                         v);
    }
    free(par);
    free(root);
    return rc;
}

static int ro_check_input(int scheme, const ro_mesh *m, char *err, size_t errlen) {
    long k = 0;
    for (int f = 0; f < m->nf; ++f) {
        int d = m->fsize[f];
        if (d < 3) return oracle_fail(err, errlen, "refine_oracle: face %d has %d vertices", f, d);
        if (scheme == 0 && d != 3)
            return oracle_fail(err, errlen, "refine_oracle: Loop needs triangles; face %d has %d", f,
                           d);
        for (int j = 0; j < d; ++j) {
            int v = m->fidx[k + j];
            if (v < 0 || v >= m->nv)
                return oracle_fail(err, errlen, "refine_oracle: face %d: vertex %d out of range", f,
                               v);
            for (int i = 0; i < j; ++i)
                if (m->fidx[k + i] == v)
                    return oracle_fail(err, errlen, "refine_oracle: face %d repeats vertex %d", f,
                                   v);
        }
        k += d;
    }
    return 0;
}

static void axpy3(double *y, double a, const double *x) {
    y[0] += a * x[0];
    y[1] += a * x[1];
    y[2] += a * x[2];
}

/* One refinement step in -> out. */
static int ro_step(int scheme, double alpha, const ro_mesh *in, int check_fans, ro_mesh *out,
                   char *err, size_t errlen) {
    memset(out, 0, sizeof *out);
    ro_edges E;
    if (ro_build_edges(in, &E, err, errlen)) return 1;
    if (check_fans && ro_check_fans(in, &E, err, errlen)) {
        ro_edges_free(&E);
        return 1;
    }
    const int nv = in->nv, nf = in->nf, ne = E.ne;
    const double *P = in->pos;
    long nvo = (long)nv + ne + (scheme == 1 ? nf : 0);
    long nfo = scheme == 1 ? in->nidx : 4L * nf;
    long nidxo = (scheme == 1 ? 4L : 3L) * nfo;
    if (nvo > INT_MAX || nfo > INT_MAX) {
        ro_edges_free(&E);
        return oracle_fail(err, errlen, "refine_oracle: mesh too large for int indices");
    }
    out->nv = (int)nvo;
    out->nf = (int)nfo;
    out->nidx = nidxo;
    out->pos = calloc((size_t)nvo * 3, sizeof(double));
    out->fsize = malloc(sizeof(int) * (size_t)(nfo > 0 ? nfo : 1));
    out->fidx = malloc(sizeof(int) * (size_t)(nidxo > 0 ? nidxo : 1));
    /* per-vertex accumulators */
    int *vf = calloc((size_t)nv + 1, sizeof(int));     /* incident faces */
    int *ve = calloc((size_t)nv + 1, sizeof(int));     /* incident edges */
    int *vb = calloc((size_t)nv + 1, sizeof(int));     /* incident boundary edges */
    double *esum = calloc((size_t)nv * 3 + 3, sizeof(double));
    double *bsum = calloc((size_t)nv * 3 + 3, sizeof(double));
    double *fsum = calloc((size_t)nv * 3 + 3, sizeof(double));
    int rc = 0;
    if (!out->pos || !out->fsize || !out->fidx || !vf || !ve || !vb || !esum || !bsum || !fsum) {
        rc = oracle_fail(err, errlen, "refine_oracle: out of memory");
        goto done;
    }

    double *fp = scheme == 1 ? out->pos + 3L * nv : NULL;                 /* face points */
    double *ep = out->pos + 3L * nv + (scheme == 1 ? 3L * nf : 0);       /* edge points */
    int fbase = nv, ebase = nv + (scheme == 1 ? nf : 0);

    /* face points (CC) */
    if (scheme == 1) {
        for (int f = 0; f < nf; ++f) {
            double *c = fp + 3L * f;
            int d = in->fsize[f];
            for (long h = E.foff[f]; h < E.foff[f + 1]; ++h) axpy3(c, 1.0 / d, P + 3L * in->fidx[h]);
        }
    }
    /* edge points and per-vertex edge sums */
    for (int x = 0; x < ne; ++x) {
        int a = E.v0[x], b = E.v1[x];
        double *q = ep + 3L * x;
        ve[a]++;
        ve[b]++;
        axpy3(esum + 3L * a, 1.0, P + 3L * b);
        axpy3(esum + 3L * b, 1.0, P + 3L * a);
        if (E.h1[x] < 0) {
            vb[a]++;
            vb[b]++;
            axpy3(bsum + 3L * a, 1.0, P + 3L * b);
            axpy3(bsum + 3L * b, 1.0, P + 3L * a);
            axpy3(q, 0.5, P + 3L * a);
            axpy3(q, 0.5, P + 3L * b);
        } else if (scheme == 1) {
            axpy3(q, 0.25, P + 3L * a);
            axpy3(q, 0.25, P + 3L * b);
            axpy3(q, 0.25, fp + 3L * E.hface[E.h0[x]]);
            axpy3(q, 0.25, fp + 3L * E.hface[E.h1[x]]);
        } else {
            int c = in->fidx[ro_prev(&E, E.h0[x])]; /* triangle: prev corner = opposite */
            int d = in->fidx[ro_prev(&E, E.h1[x])];
            axpy3(q, 0.375, P + 3L * a);
            axpy3(q, 0.375, P + 3L * b);
            axpy3(q, 0.125, P + 3L * c);
            axpy3(q, 0.125, P + 3L * d);
        }
    }
    /* per-vertex face counts and face-point sums */
    for (long h = 0; h < in->nidx; ++h) {
        int v = in->fidx[h];
        vf[v]++;
        if (scheme == 1) axpy3(fsum + 3L * v, 1.0, fp + 3L * E.hface[h]);
    }
    /* vertex points */
    for (int v = 0; v < nv && !rc; ++v) {
        const double *V = P + 3L * v;
        double *q = out->pos + 3L * v;
        if (vf[v] == 0) { /* unreferenced */
            memcpy(q, V, 3 * sizeof(double));
        } else if (vb[v] == 0) { /* interior */
            int n = ve[v];
            if (n != vf[v]) {
                rc = oracle_fail(err, errlen, "refine_oracle: interior vertex %d: %d edges, %d faces",
                             v, n, vf[v]);
                break;
            }
            if (scheme == 1) {
                double n2 = (double)n * n;
                axpy3(q, (n - 2.0) / n + alpha / n, V);
                axpy3(q, (1.0 - alpha) / n2, esum + 3L * v);
                axpy3(q, 1.0 / n2, fsum + 3L * v);
            } else {
                double t = 0.375 + 0.25 * cos(2.0 * M_PI / n);
                double beta = (0.625 - t * t) / n;
                axpy3(q, 1.0 - n * beta, V);
                axpy3(q, beta, esum + 3L * v);
            }
        } else if (vb[v] == 2) {
            if (vf[v] == 1) {
                memcpy(q, V, 3 * sizeof(double));
            } else {
                axpy3(q, 0.75, V);
                axpy3(q, 0.125, bsum + 3L * v);
            }
        } else {
            rc = oracle_fail(err, errlen, "refine_oracle: non-manifold vertex %d (%d boundary edges)",
                         v, vb[v]);
        }
    }
    if (rc) goto done;

    /* topology */
    if (scheme == 1) {
        long k = 0;
        for (int f = 0; f < nf; ++f) {
            for (long h = E.foff[f]; h < E.foff[f + 1]; ++h) {
                out->fsize[h] = 4;
                out->fidx[k++] = in->fidx[h];
                out->fidx[k++] = ebase + E.hedge[h];
                out->fidx[k++] = fbase + f;
                out->fidx[k++] = ebase + E.hedge[ro_prev(&E, h)];
            }
        }
    } else {
        long k = 0;
        for (int f = 0; f < nf; ++f) {
            long h = E.foff[f];
            int a = in->fidx[h], b = in->fidx[h + 1], c = in->fidx[h + 2];
            int e0 = ebase + E.hedge[h], e1 = ebase + E.hedge[h + 1], e2 = ebase + E.hedge[h + 2];
            int tri[4][3] = {{a, e0, e2}, {e0, b, e1}, {e2, e1, c}, {e1, e2, e0}};
            for (int t = 0; t < 4; ++t) {
                out->fsize[4L * f + t] = 3;
                for (int j = 0; j < 3; ++j) out->fidx[k++] = tri[t][j];
            }
        }
    }
done:
    free(vf);
    free(ve);
    free(vb);
    free(esum);
    free(bsum);
    free(fsum);
    ro_edges_free(&E);
    if (rc) ro_mesh_free(out);
    return rc;
}

int refine_oracle(int scheme, double alpha_first, int levels, int nverts, const double *pos,
                  int nfaces, const int *face_sizes, const int *face_indices, int *out_nverts,
                  double **out_pos, int *out_nfaces, int **out_face_sizes, int **out_face_indices,
                  char *err, size_t errlen) {
    if (out_nverts) *out_nverts = 0;
    if (out_nfaces) *out_nfaces = 0;
    if (out_pos) *out_pos = NULL;
    if (out_face_sizes) *out_face_sizes = NULL;
    if (out_face_indices) *out_face_indices = NULL;
    if (err && errlen) err[0] = '\0';
    if (!out_nverts || !out_pos || !out_nfaces || !out_face_sizes || !out_face_indices)
        return oracle_fail(err, errlen, "refine_oracle: NULL output pointer");
    if (scheme != 0 && scheme != 1)
        return oracle_fail(err, errlen, "refine_oracle: scheme must be 0 (Loop) or 1 (CC)");
    if (levels < 0) return oracle_fail(err, errlen, "refine_oracle: negative levels");
    if (nverts < 0 || nfaces < 0 || (nverts > 0 && !pos) ||
        (nfaces > 0 && (!face_sizes || !face_indices)))
        return oracle_fail(err, errlen, "refine_oracle: bad input arrays");

    ro_mesh cur;
    memset(&cur, 0, sizeof cur);
    cur.nv = nverts;
    cur.nf = nfaces;
    long nidx = 0;
    for (int f = 0; f < nfaces; ++f) nidx += face_sizes[f] > 0 ? face_sizes[f] : 0;
    cur.nidx = nidx;
    cur.pos = malloc(sizeof(double) * 3 * (size_t)(nverts > 0 ? nverts : 1));
    cur.fsize = malloc(sizeof(int) * (size_t)(nfaces > 0 ? nfaces : 1));
    cur.fidx = malloc(sizeof(int) * (size_t)(nidx > 0 ? nidx : 1));
    if (!cur.pos || !cur.fsize || !cur.fidx) {
        ro_mesh_free(&cur);
        return oracle_fail(err, errlen, "refine_oracle: out of memory");
    }
    if (nverts > 0) memcpy(cur.pos, pos, sizeof(double) * 3 * (size_t)nverts);
    if (nfaces > 0) memcpy(cur.fsize, face_sizes, sizeof(int) * (size_t)nfaces);
    if (nidx > 0) memcpy(cur.fidx, face_indices, sizeof(int) * (size_t)nidx);
    if (ro_check_input(scheme, &cur, err, errlen)) {
        ro_mesh_free(&cur);
        return 1;
    }
    for (int l = 0; l < levels; ++l) {
        ro_mesh next;
        double alpha = (scheme == 1 && l == 0) ? alpha_first : 0.0;
        if (ro_step(scheme, alpha, &cur, l == 0, &next, err, errlen)) {
            ro_mesh_free(&cur);
            return 1;
        }
        ro_mesh_free(&cur);
        cur = next;
    }
    *out_nverts = cur.nv;
    *out_pos = cur.pos;
    *out_nfaces = cur.nf;
    *out_face_sizes = cur.fsize;
    *out_face_indices = cur.fidx;
    return 0;
}
