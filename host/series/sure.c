/* SPDX-License-Identifier: MIT */
/*
 * The SURE-fitted polynomial filter (sure.h). For y = x + noise of deviation
 * sigma on every coordinate and a linear filter F, Stein's lemma gives
 * E|F y - x|^2 = |F y - y|^2 + 2 sigma^2 tr(F) - 3 n sigma^2 (the trace per
 * coordinate, three coordinates). With F = E + sum_i d_i B^i, B = E - A, that
 * is a quadratic in d: |sum_i d_i r_i|^2 + 6 sigma^2 sum_i d_i tr(B^i) + const,
 * r_i = B^i y. Its minimiser is the best polynomial of degree N in A for this
 * mesh, found without the clean mesh: the vectors r_i cost the N products the
 * filter needs anyway, the result is their combination. p(1) = 1 (d_0 = 1), so
 * a translation moves the result by the same translation. The minimiser is
 * taken under the constraint that the gain p on B's spectrum (eigenvalue mu
 * of B, Gershgorin's interval) stays in [0, 1]: no band amplified, none turned
 * over. Unconstrained, the 12 free coefficients fit the risk estimate's noise
 * with gains far outside [0, 1] where A has little energy (-2e5 at the top of
 * bunny's interval); the constraint removes that freedom at no cost in bias.
 * The default fits twice (sure_split): the vectors' parts along the vertex
 * normals of A^k y (one coordinate a vertex: the trace term once) and across
 * them (two: twice), each with its own noise estimate: a scanner's noise
 * lies along the normals, and one polynomial in A also moves vertices along
 * the surface where a scan's sampling is irregular.
 */
#include "series/sure.h"

#include "base/context.h"
#include "mesh/mesh.h"
#include "topology/measure.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { SURE_GRID = 64 }; /* points where the gain is kept in [0, 1] */

/* The symbol of B on the regular lattice at frequency (u, w): Loop's
   triangular lattice (valence 6) or Catmull-Clark's quad lattice (valence 4),
   up to the scale sure_traces fits. */
static double lattice_symbol(limn_scheme scheme, double u, double w)
{
    if (scheme == LIMN_SCHEME_LOOP)
        return 1.0 - (cos(u) + cos(w) + cos(u + w)) / 3.0;
    return 1.0 - (2.0 + cos(u)) * (2.0 + cos(w)) / 9.0;
}

double sure_row_diagonal(const stencil_csr *a, size_t v)
{
    double diag = 1.0;
    for (uint32_t j = a->row_offsets[v]; j < a->row_offsets[v + 1]; j++)
        if (a->columns[j] == v)
            diag -= a->weights[j];
    return diag;
}

void sure_traces(const stencil_csr *a, limn_scheme scheme, int degree, double *t)
{
    double tr1 = 0.0;
    for (size_t v = 0; v < a->rows; v++)
        tr1 += sure_row_diagonal(a, v);
    sure_traces_from(tr1, a->rows, scheme, degree, t);
}

void sure_traces_from(double tr1, size_t n, limn_scheme scheme, int degree, double *t)
{
    enum { GRID = 64 }; /* exact for trigonometric polynomials of degree < 64 */
    for (int i = 0; i < degree; i++)
        t[i] = 0.0;
    const double h = 2.0 * 3.14159265358979323846 / GRID;
    for (int p = 0; p < GRID; p++)
        for (int q = 0; q < GRID; q++) {
            double s = lattice_symbol(scheme, (p + 0.5) * h, (q + 0.5) * h), pw = 1.0;
            for (int i = 0; i < degree; i++)
                t[i] += (pw *= s) / (GRID * GRID);
        }
    double scale = t[0] > 0.0 ? tr1 / (double)n / t[0] : 0.0, sc = 1.0;
    for (int i = 0; i < degree; i++)
        t[i] *= (double)n * (sc *= scale);
}

double sure_dot_from(double s, const double *x, const double *y, size_t n)
{
    for (size_t i = 0; i < n; i++)
        s += x[i] * y[i];
    return s;
}

/* The inner product: sum's (a global one) or this process's. */
static double dot_of(const sure_sum *sum, const double *x, const double *y, size_t n)
{
    return sum ? sum->dot(sum->user, x, y, n) : sure_dot_from(0.0, x, y, n);
}

/* st agreed by every process (sum's), or this process's own. */
static limn_status agree_of(const sure_sum *sum, limn_status st)
{
    return sum ? sum->agree(sum->user, st) : st;
}

/* The smallest over i of |x_i|^2 / (dims tr B^{2(i+1)}) (x_i = x + i*len),
   its square root; 0 when no trace is positive (sure_sigma's rule for a
   part of dims coordinates a vertex). */
static double part_sigma(const double *x, size_t len, int degree, const double *t, double dims,
                         const sure_sum *sum)
{
    double s2 = INFINITY;
    for (int i = 0; i < degree; i++) {
        const double *xi = x + (size_t)i * len;
        if (t[2 * i + 1] > 0.0)
            s2 = fmin(s2, dot_of(sum, xi, xi, len) / (dims * t[2 * i + 1]));
    }
    return isinf(s2) ? 0.0 : sqrt(s2);
}

double sure_sigma(const double *r, size_t n3, int degree, const double *t, const sure_sum *sum)
{
    return part_sigma(r, n3, degree, t, 3.0, sum);
}

/* Modified Gram-Schmidt, twice, of the columns r_i into q (q == r: in
   place): u (degree^2, upper triangular) with r = q u; keep[i] = 0 where r_i
   lies (to 1e-10 of its length) in the span of the earlier ones. */
static void orthogonalise(const double *r, size_t n3, int degree, const sure_sum *sum, double *q,
                          double *u, int *keep)
{
    memset(u, 0, (size_t)degree * degree * sizeof *u);
    for (int i = 0; i < degree; i++) {
        double *qi = q + (size_t)i * n3;
        if (q != r)
            memcpy(qi, r + (size_t)i * n3, n3 * sizeof *qi);
        double len = sqrt(dot_of(sum, qi, qi, n3));
        for (int pass = 0; pass < 2; pass++)
            for (int j = 0; j < i; j++) {
                if (!keep[j])
                    continue;
                double *qj = q + (size_t)j * n3, c = dot_of(sum, qj, qi, n3);
                u[j * degree + i] += c;
                for (size_t k = 0; k < n3; k++)
                    qi[k] -= c * qj[k];
            }
        double rest = sqrt(dot_of(sum, qi, qi, n3));
        keep[i] = rest > 1e-10 * len && rest > 0.0;
        u[i * degree + i] = keep[i] ? rest : 1.0;
        for (size_t k = 0; keep[i] && k < n3; k++)
            qi[k] /= rest;
    }
}

/* w = U^{-T} rhs on the kept columns (forward substitution). */
static void solve_transposed(const double *u, const int *keep, int degree, const double *rhs,
                             double *w)
{
    for (int i = 0; i < degree; i++) {
        double s = keep[i] ? rhs[i] : 0.0;
        for (int j = 0; j < i && keep[i]; j++)
            s -= keep[j] ? u[j * degree + i] * w[j] : 0.0;
        w[i] = keep[i] ? s / u[i * degree + i] : 0.0;
    }
}

/* d = U^{-1} z on the kept columns (back substitution), 0 elsewhere. */
static void solve_upper(const double *u, const int *keep, int degree, const double *z, double *d)
{
    for (int i = degree - 1; i >= 0; i--) {
        double s = z[i];
        for (int j = i + 1; j < degree && keep[i]; j++)
            s -= keep[j] ? u[i * degree + j] * d[j] : 0.0;
        d[i] = keep[i] ? s / u[i * degree + i] : 0.0;
    }
}

/* The gain's rows on the grid: g(mu_k) = 1 + sum_i d_i mu_k^{i+1} = 1 + h_k . z
   for z = U d, so h_k = v_k U^{-1} (v_k the powers of mu_k), normalised: h[k]
   unit rows, len[k] their lengths. Chebyshev points on (0, mu_max]. */
static void gain_rows(const double *u, const int *keep, int degree, double mu_max, double *h,
                      double *len)
{
    for (int k = 0; k < SURE_GRID; k++) {
        double mu = 0.5 * mu_max * (1.0 - cos(3.14159265358979323846 * (k + 1) / SURE_GRID));
        double *hk = h + (size_t)k * degree, pw = 1.0, l2 = 0.0;
        for (int j = 0; j < degree; j++) {
            double s = (pw *= mu);
            for (int i = 0; i < j && keep[j]; i++)
                s -= keep[i] ? hk[i] * u[i * degree + j] : 0.0;
            hk[j] = keep[j] ? s / u[j * degree + j] : 0.0;
            l2 += hk[j] * hk[j];
        }
        len[k] = sqrt(l2);
        for (int j = 0; j < degree && len[k] > 0.0; j++)
            hk[j] /= len[k];
    }
}

/* s[P] minimising |E_P s - e| for the columns in P (count of them, each
   rows long, at e + col*rows), by modified Gram-Schmidt twice; q: count *
   rows scratch, u: count^2. */
static void passive_least_squares(const double *e, int rows, const int *set, int count,
                                  double *q, double *u, double *s)
{
    for (int i = 0; i < count; i++) {
        double *qi = q + (size_t)i * rows;
        memcpy(qi, e + (size_t)set[i] * rows, (size_t)rows * sizeof *qi);
        for (int j = 0; j < count; j++)
            u[j * count + i] = 0.0;
        for (int pass = 0; pass < 2; pass++)
            for (int j = 0; j < i; j++) {
                double c = sure_dot_from(0.0, q + (size_t)j * rows, qi, (size_t)rows);
                u[j * count + i] += c;
                for (int k = 0; k < rows; k++)
                    qi[k] -= c * q[(size_t)j * rows + k];
            }
        double l = sqrt(sure_dot_from(0.0, qi, qi, (size_t)rows));
        u[i * count + i] = l > 0.0 ? l : 1.0;
        for (int k = 0; k < rows && l > 0.0; k++)
            qi[k] /= l;
    }
    for (int i = count - 1; i >= 0; i--) { /* target (0, ..., 0, 1) */
        double v = q[(size_t)i * rows + rows - 1];
        for (int j = i + 1; j < count; j++)
            v -= u[i * count + j] * s[j];
        s[i] = v / u[i * count + i];
    }
}

/* Lawson & Hanson's NNLS (1974, ch. 23) for min |E x - e|, x >= 0, E: rows x
   cols, column-major, e = (0, ..., 0, 1); work: 2 cols + rows^2 + rows * cols
   doubles, set: 2 cols ints. */
static void nnls(const double *e, int rows, int cols, double *x, double *work, int *set)
{
    double *w = work, *sp = w + cols, *u = sp + cols, *q = u + (size_t)rows * rows;
    int *passive = set, *in = set + cols, count = 0;
    memset(x, 0, (size_t)cols * sizeof *x);
    memset(in, 0, (size_t)cols * sizeof *in);
    for (int outer = 0; outer < 3 * cols; outer++) {
        int best = -1;
        for (int j = 0; j < cols; j++) { /* the gradient E^T (e - E x) */
            const double *ej = e + (size_t)j * rows;
            w[j] = ej[rows - 1];
            for (int i = 0; i < count; i++)
                w[j] -= sure_dot_from(0.0, ej, e + (size_t)passive[i] * rows, (size_t)rows) * x[passive[i]];
            if (!in[j] && w[j] > 1e-12 && (best < 0 || w[j] > w[best]))
                best = j;
        }
        if (best < 0 || count == rows)
            return;
        passive[count++] = best, in[best] = 1;
        for (int inner = 0; inner < 3 * cols; inner++) {
            passive_least_squares(e, rows, passive, count, q, u, sp);
            double alpha = 1.0;
            for (int i = 0; i < count; i++)
                if (sp[i] <= 0.0)
                    alpha = fmin(alpha, x[passive[i]] / (x[passive[i]] - sp[i]));
            for (int i = 0; i < count; i++)
                x[passive[i]] += alpha * (sp[i] - x[passive[i]]);
            if (alpha >= 1.0)
                break;
            for (int i = 0; i < count; i++)
                if (x[passive[i]] <= 1e-15) {
                    x[passive[i]] = 0.0, in[passive[i]] = 0;
                    passive[i--] = passive[--count];
                }
        }
    }
}

/* z nearest c with the gain in [0, 1] on the grid, a least-distance problem:
   x = z - c minimises |x| with G x >= f (G x >= f: -h . x >= h . c and
   h . x >= -1/len - h . c), solved through NNLS on E = [G^T; f^T] (Lawson &
   Hanson, ch. 23: x = -r/r_last, r = E u - e), f scaled to 1 and back. */
static void project_gain(const double *h, const double *len, int degree, const double *c,
                         double *z, double *work)
{
    int rows = degree + 1, cols = 2 * SURE_GRID, set[4 * SURE_GRID];
    double *e = work, *u = e + (size_t)rows * cols, *rest = u + cols, scale = 0.0;
    memcpy(z, c, (size_t)degree * sizeof *z);
    for (int k = 0; k < cols; k++) {
        const double *hk = h + (size_t)(k / 2) * degree;
        double sign = k % 2 ? 1.0 : -1.0, hc = sure_dot_from(0.0, hk, c, (size_t)degree);
        double f = len[k / 2] > 0.0 ? (k % 2 ? -1.0 / len[k / 2] - hc : hc) : -1.0;
        for (int j = 0; j < degree; j++)
            e[(size_t)k * rows + j] = sign * hk[j];
        e[(size_t)k * rows + degree] = f;
        scale = fmax(scale, fabs(f));
    }
    for (int k = 0; k < cols && scale > 0.0; k++)
        e[(size_t)k * rows + degree] /= scale;
    nnls(e, rows, cols, u, rest, set);
    double r[LIMN_MAX_SURE_PRODUCTS + 1];
    for (int i = 0; i < rows; i++) {
        r[i] = -(i == degree);
        for (int k = 0; k < cols; k++)
            r[i] += e[(size_t)k * rows + i] * u[k];
    }
    for (int j = 0; j < degree && r[degree] != 0.0; j++)
        z[j] = c[j] - scale * r[j] / r[degree];
}

/* The fit in the orthonormal basis: z = U^{-T} rhs minimises |z - c|^2;
   with mu_max > 0 projected onto the gains in [0, 1]; d = U^{-1} z. */
static void fit(const double *u, const int *keep, int degree, const double *rhs, double mu_max,
                double *work, double *d)
{
    double *c = work, *z = c + degree, *h = z + degree, *len = h + (size_t)SURE_GRID * degree;
    double *scratch = len + SURE_GRID;
    solve_transposed(u, keep, degree, rhs, c);
    memcpy(z, c, (size_t)degree * sizeof *z);
    if (mu_max > 0.0) {
        gain_rows(u, keep, degree, mu_max, h, len);
        project_gain(h, len, degree, c, z, scratch);
    }
    solve_upper(u, keep, degree, z, d);
}

/* The least squares with the columns orthogonalised into q (q == r: in
   place); w (may be NULL) gets U d, 0 where a column was dropped, so that
   sum_i d_i r_i = sum_j w_j q_j. */
static limn_status least_squares_into(limn_context *ctx, const double *r, double *q, size_t n3,
                                      int degree, const double *rhs, const sure_sum *sum,
                                      double mu_max, double *d, double *w)
{
    size_t rows = (size_t)degree + 1, cols = 2 * SURE_GRID;
    size_t nwork = 2 * (size_t)degree + (size_t)SURE_GRID * (degree + 1) + rows * cols + cols +
                   2 * cols + rows * rows + rows * cols;
    double *u = malloc(((size_t)degree * degree + nwork) * sizeof *u);
    int *keep = calloc((size_t)degree, sizeof *keep);
    limn_status st = u && keep ? LIMN_OK
                               : ctx_fail(ctx, LIMN_ERR_MEMORY,
                                          "out of memory for a fit of degree %d", degree);
    if ((st = agree_of(sum, st))) {
        free(u), free(keep);
        return st;
    }
    orthogonalise(r, n3, degree, sum, q, u, keep);
    fit(u, keep, degree, rhs, mu_max, u + (size_t)degree * degree, d);
    for (int j = 0; w && j < degree; j++) {
        double x = 0.0;
        for (int i = j; i < degree && keep[j]; i++)
            x += u[j * degree + i] * d[i];
        w[j] = x;
    }
    free(u), free(keep);
    return LIMN_OK;
}

limn_status sure_least_squares(limn_context *ctx, const double *r, size_t n3, int degree,
                               const double *rhs, const sure_sum *sum, double mu_max, double *d)
{
    double *q = malloc((size_t)degree * (n3 ? n3 : 1) * sizeof *q); /* n3 = 0: an empty rank */
    limn_status st = q ? LIMN_OK
                       : ctx_fail(ctx, LIMN_ERR_MEMORY,
                                  "out of memory for %d vectors of %zu doubles", degree, n3);
    if ((st = agree_of(sum, st))) {
        free(q);
        return st;
    }
    st = least_squares_into(ctx, r, q, n3, degree, rhs, sum, mu_max, d, NULL);
    free(q);
    return st;
}

double sure_spectrum_bound(const stencil_csr *a)
{
    double top = 0.0;
    for (size_t v = 0; v < a->rows; v++) {
        double row = 0.0, diag = 1.0;
        for (uint32_t j = a->row_offsets[v]; j < a->row_offsets[v + 1]; j++) {
            if (a->columns[j] == v)
                diag -= a->weights[j];
            else
                row += fabs(a->weights[j]);
        }
        top = fmax(top, fabs(diag) + row);
    }
    return top;
}

limn_status sure_coefficients(limn_context *ctx, const double *r, size_t n3, int degree,
                              double sigma, const double *t, const sure_sum *sum, double mu_max,
                              double *d)
{
    double rhs[LIMN_MAX_SURE_PRODUCTS];
    for (int i = 0; i < degree; i++)
        rhs[i] = -3.0 * sigma * sigma * t[i];
    return sure_least_squares(ctx, r, n3, degree, rhs, sum, mu_max, d);
}

limn_status sure_fit(limn_context *ctx, const double *r, size_t n3, int degree, const double *t,
                     const sure_sum *sum, double mu_max, double *sigma, double *d)
{
    *sigma = sure_sigma(r, n3, degree, t, sum);
    return sure_coefficients(ctx, r, n3, degree, *sigma, t, sum, mu_max, d);
}

void sure_combine(const double *y, const double *r, size_t n3, int degree, const double *d,
                  double *out)
{
    for (size_t k = 0; k < n3; k++) {
        double v = y[k];
        for (int i = 0; i < degree; i++)
            v += d[i] * r[(size_t)i * n3 + k];
        out[k] = v;
    }
}

void sure_frame_positions(const double *y, const double *r, size_t n3, int degree, double *out)
{
    int k = degree < SURE_FRAME_POWER ? degree : SURE_FRAME_POWER;
    double c[SURE_FRAME_POWER], binom = 1.0;
    for (int i = 0; i < k; i++) { /* (E - B)^k: (-1)^j C(k, j) B^j, r_i = B^{i+1} y */
        binom = binom * (k - i) / (i + 1);
        c[i] = i % 2 ? binom : -binom;
    }
    sure_combine(y, r, n3, k, c, out);
}

void sure_vertex_normals(const limn_mesh *mesh, const double *x, double *nrm)
{
    memset(nrm, 0, 3 * mesh->vertex_count * sizeof *nrm);
    for (size_t f = 0; f < mesh->face_count; f++) {
        double n[3];
        measure_face_normal(x, mesh->face_offsets, mesh->face_indices, f, n);
        for (uint32_t c = mesh->face_offsets[f]; c < mesh->face_offsets[f + 1]; c++) {
            double *v = nrm + 3 * (size_t)mesh->face_indices[c];
            v[0] += n[0], v[1] += n[1], v[2] += n[2];
        }
    }
    for (size_t v = 0; v < mesh->vertex_count; v++) {
        double *n = nrm + 3 * v, len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        for (int a = 0; a < 3; a++)
            n[a] = len > 0.0 ? n[a] / len : 0.0;
    }
}

/* The normal part of r's vertex v (3 doubles at r + 3v) along n (3 doubles). */
static double along(const double *r, const double *n)
{
    return r[0] * n[0] + r[1] * n[1] + r[2] * n[2];
}

limn_status sure_split(limn_context *ctx, const double *y, double *r, size_t n3, int degree,
                       const double *t, const sure_sum *sum, double mu_max, const double *nrm,
                       double sigma[2], double *out)
{
    size_t n = n3 / 3;
    double rhs[LIMN_MAX_SURE_PRODUCTS], d[LIMN_MAX_SURE_PRODUCTS], w[LIMN_MAX_SURE_PRODUCTS];
    /* calloc: GCC cannot tell every entry is written; a block this size is fresh, cleared
       by the kernel anyway */
    double *s = calloc((size_t)degree * (n ? n : 1), sizeof *s);
    limn_status st = s ? LIMN_OK
                       : ctx_fail(ctx, LIMN_ERR_MEMORY,
                                  "out of memory for %d vectors of %zu vertices", degree, n);
    if ((st = agree_of(sum, st))) {
        free(s);
        return st;
    }
    for (int i = 0; i < degree; i++)
        for (size_t v = 0; v < n; v++)
            s[(size_t)i * n + v] = along(r + (size_t)i * n3 + 3 * v, nrm + 3 * v);
    /* the normal parts: one coordinate a vertex, SURE's trace term once */
    sigma[0] = part_sigma(s, n, degree, t, 1.0, sum);
    for (int i = 0; i < degree; i++)
        rhs[i] = -sigma[0] * sigma[0] * t[i];
    /* in place: s becomes the orthonormal q, its combination by w = U d */
    st = least_squares_into(ctx, s, s, n, degree, rhs, sum, mu_max, d, w);
    for (size_t v = 0; !st && v < n; v++) {
        double a = 0.0;
        for (int i = 0; i < degree; i++)
            a += w[i] * s[(size_t)i * n + v];
        for (int c = 0; c < 3; c++)
            out[3 * v + c] = y[3 * v + c] + a * nrm[3 * v + c];
    }
    free(s);
    if (st)
        return st;
    /* the tangential parts, in place of r: two coordinates a vertex */
    for (int i = 0; i < degree; i++)
        for (size_t v = 0; v < n; v++) {
            double *x = r + (size_t)i * n3 + 3 * v, a = along(x, nrm + 3 * v);
            for (int c = 0; c < 3; c++)
                x[c] -= a * nrm[3 * v + c];
        }
    sigma[1] = part_sigma(r, n3, degree, t, 2.0, sum);
    for (int i = 0; i < degree; i++)
        rhs[i] = -2.0 * sigma[1] * sigma[1] * t[i];
    st = least_squares_into(ctx, r, r, n3, degree, rhs, sum, mu_max, d, w);
    for (size_t k = 0; !st && k < n3; k++) {
        double a = 0.0;
        for (int i = 0; i < degree; i++)
            a += w[i] * r[(size_t)i * n3 + k];
        out[k] += a;
    }
    return st;
}

limn_status sure_filter(limn_context *ctx, const limn_mesh *mesh, double *r, int degree,
                        const double *t, double mu_max, double *sigma, double *out)
{
    size_t n3 = 3 * mesh->vertex_count;
    double *nrm = malloc((n3 ? n3 : 1) * sizeof *nrm), split_sigma[2];
    *sigma = sure_sigma(r, n3, degree, t, NULL);
    if (!nrm)
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for %zu normals",
                        mesh->vertex_count);
    sure_frame_positions(mesh->positions, r, n3, degree, out);
    sure_vertex_normals(mesh, out, nrm);
    limn_status st = sure_split(ctx, mesh->positions, r, n3, degree, t, NULL, mu_max, nrm,
                                split_sigma, out);
    free(nrm);
    return st;
}

/* r + i*3n = B^{i+1} y, i < degree, on the host (degree products). */
static limn_status sure_vectors(series_run *s, const limn_mesh *mesh, int degree, double *r,
                                long long *products)
{
    limn_status st = series_upload(s, s->buf[0], mesh->positions);
    device_buffer *cur = s->buf[0];
    for (int i = 0; !st && i < degree; i++) {
        device_buffer *next = cur == s->buf[1] ? s->buf[2] : s->buf[1];
        device_norms nr;
        st = s->dev->ops->series->series_step(s->dev, &s->op.device, cur, next, NULL, s->buf[3],
                                              SERIES_STORE_NEXT, SERIES_ACC_NONE, &nr);
        ++*products;
        if (!st)
            st = series_download(s, next, r + (size_t)i * 3 * s->n);
        cur = next;
    }
    return st;
}

limn_status sure_denoise_run(limn_context *ctx, series_run *s, const limn_mesh *mesh,
                             int degree, limn_mesh **out, double *sigma, long long *products)
{
    size_t n3 = 3 * s->n;
    double *r = malloc((size_t)degree * n3 * sizeof *r);
    double *t = malloc((size_t)degree * 2 * sizeof *t);
    if (!r || !t) {
        free(r), free(t);
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for %d vectors of %zu vertices",
                        degree, s->n);
    }
    limn_status st = sure_vectors(s, mesh, degree, r, products);
    double sg = 0.0;
    limn_mesh *m = NULL;
    if (!st) {
        sure_traces(&s->op.host, s->op.scheme, 2 * degree, t);
        st = limn_mesh_copy(ctx, mesh, &m);
    }
    if (!st)
        st = sure_filter(ctx, mesh, r, degree, t, sure_spectrum_bound(&s->op.host), &sg,
                         m->positions);
    if (!st)
        st = series_check_finite(ctx, m->positions, s->n, "denoising");
    if (sigma)
        *sigma = sg;
    free(r), free(t);
    return mesh_hand_over(st, m, out);
}
