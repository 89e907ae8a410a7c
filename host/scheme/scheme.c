/* SPDX-License-Identifier: MIT */
/* Limit masks of Loop and general Catmull-Clark (DESIGN.md §1). */
#include "scheme/scheme.h"
#include "scheme/scheme_refine.h"

double scheme_loop_limit_beta(uint32_t n)
{
    double c = scheme_loop_cos_term(n);
    return 3.0 / (11.0 - 8.0 * (0.375 + c * c));
}

size_t scheme_limit_mask_bound(const topology *t, limn_scheme scheme, uint32_t v)
{
    /* exactly what scheme_limit_mask writes for a smooth vertex: v, its n
       neighbours and, for Catmull-Clark, the d - 3 other vertices of each
       face; a sharp vertex writes at most 3. A tight bound keeps the stencil
       build's scratch (and its first-touch page faults) small. */
    size_t bound = 1 + (t->vertex_edge_offsets[v + 1] - t->vertex_edge_offsets[v]);
    if (scheme != LIMN_SCHEME_LOOP && t->triangles != t->face_count) {
        uint32_t b = t->vertex_corner_offsets[v], e = t->vertex_corner_offsets[v + 1];
        if (t->quads == t->face_count)
            bound += e - b;
        else
            for (uint32_t i = b; i < e; i++)
                bound += topology_face_size(t, t->corner_face[t->vertex_corners[i]]) - 3;
    }
    return bound < 3 ? 3 : bound;
}

static size_t loop_smooth(const topology *t, uint32_t v, uint32_t *cols, double *w)
{
    uint32_t eb = t->vertex_edge_offsets[v], n = t->vertex_edge_offsets[v + 1] - eb;
    double beta = scheme_loop_limit_beta(n);
    size_t k = 0;
    cols[k] = v;
    w[k++] = beta;
    for (uint32_t i = 0; i < n; i++) {
        cols[k] = topology_edge_other(t, t->vertex_edges[eb + i], v);
        w[k++] = (1.0 - beta) / (double)n;
    }
    return k;
}

/*
 * General Catmull-Clark limit with alpha (seed 000 App. A, corrected):
 * V = (a V + sum_j b_j E_j + sum c_k F_k) / (n (n + 5)),
 * a = n(n-1) + n alpha + sum_faces 4/d, b_j = 2 - alpha + 4/d over the (two)
 * faces of edge j, c = 4/d for the face vertices not adjacent to V.
 */
static size_t catmark_smooth(const topology *t, double alpha, uint32_t v, uint32_t *cols,
                             double *w)
{
    uint32_t eb = t->vertex_edge_offsets[v], n = t->vertex_edge_offsets[v + 1] - eb;
    double nn = (double)n, denom = nn * (nn + 5.0);
    double a = nn * (nn - 1.0) + nn * alpha;
    size_t k = 1;
    for (uint32_t i = 0; i < n; i++) {
        uint32_t e = t->vertex_edges[eb + i];
        double b = 2.0 - alpha;
        for (uint32_t j = t->edge_corner_offsets[e]; j < t->edge_corner_offsets[e + 1]; j++)
            b += 4.0 / (double)topology_face_size(t, t->corner_face[t->edge_corners[j]]);
        cols[k] = topology_edge_other(t, e, v);
        w[k++] = b / denom;
    }
    for (uint32_t i = t->vertex_corner_offsets[v]; i < t->vertex_corner_offsets[v + 1]; i++) {
        uint32_t c = t->vertex_corners[i];
        uint32_t f = t->corner_face[c], d = topology_face_size(t, f);
        double cw = 4.0 / (double)d;
        a += cw;
        /* the d - 3 vertices of the face that are not v or its two neighbours */
        uint32_t x = topology_corner_next(t, topology_corner_next(t, c));
        for (uint32_t m = 0; m + 3 < d; m++) {
            cols[k] = t->face_indices[x];
            w[k++] = cw / denom;
            x = topology_corner_next(t, x);
        }
    }
    cols[0] = v;
    w[0] = a / denom;
    return k;
}

size_t scheme_limit_mask(const topology *t, limn_scheme scheme, double alpha, uint32_t v,
                         uint32_t *cols, double *w)
{
    size_t sharp = scheme_sharp_vertex_mask(t, v, 4.0 / 6.0, 1.0 / 6.0, cols, w);
    if (sharp)
        return sharp;
    if (scheme == LIMN_SCHEME_LOOP)
        return loop_smooth(t, v, cols, w);
    return catmark_smooth(t, alpha, v, cols, w);
}

double scheme_limit_row_scale(const topology *t, limn_scheme scheme, uint32_t v)
{
    switch ((vertex_rule)t->vertex_rule[v]) {
    case RULE_ISOLATED:
    case RULE_CORNER:
        return 1.0;
    case RULE_CREASE:
        return 1.0 / 6.0;
    case RULE_SMOOTH:
        break;
    }
    uint32_t n = t->vertex_edge_offsets[v + 1] - t->vertex_edge_offsets[v];
    if (scheme == LIMN_SCHEME_LOOP)
        return (1.0 - scheme_loop_limit_beta(n)) / (double)n;
    return 1.0 / ((double)n * ((double)n + 5.0));
}
