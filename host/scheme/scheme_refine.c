/* SPDX-License-Identifier: MIT */
/* Refinement masks of Catmull-Clark (with alpha) and Loop. */
#include "scheme/scheme_refine.h"

#include <math.h>

double scheme_loop_cos_term(uint32_t n)
{
    /* the formula's values below (printed with %a from it; test_masks checks
       them against it): a row of a mesh's stencils costs a cos call less,
       about a quarter of the Loop stencil build */
    static const double table[] = {
        0, /* n = 0: not a valence */
        0x1.4p-1,              0x1p-3,                0x1.0000000000001p-2,
        0x1.8p-2,              0x1.cf1bbcdcbfa54p-2,  0x1p-1,
        0x1.0fce838a2fb74p-1,  0x1.1a827999fcef3p-1,  0x1.220dbe8b3d40ep-1,
        0x1.278dde6e5fd2ap-1,  0x1.2bae321d93c2ep-1,  0x1.2ed9eba16132bp-1,
        0x1.31569f801d03ap-1,  0x1.3352f2a72d71cp-1,  0x1.34ef0ebbfdfe5p-1,
        0x1.3641af3cca352p-1,
    };
    if (n > 0 && n < sizeof table / sizeof table[0])
        return table[n];
    return scheme_loop_cos_term_formula(n);
}

double scheme_loop_cos_term_formula(uint32_t n)
{
    const double pi = 3.14159265358979323846;
    return 0.375 + 0.25 * cos(2.0 * pi / (double)n);
}

double scheme_loop_refine_beta(uint32_t n)
{
    double c = scheme_loop_cos_term(n);
    return (0.625 - c * c) / (double)n;
}

size_t scheme_refine_vertex_bound(const topology *t, limn_scheme scheme, uint32_t v)
{
    /* exact for a smooth vertex (Loop: v and its n neighbours; Catmull-Clark
       adds every vertex of its faces); a sharp one writes at most 3 */
    size_t bound = 1 + (t->vertex_edge_offsets[v + 1] - t->vertex_edge_offsets[v]);
    if (scheme != LIMN_SCHEME_LOOP) {
        uint32_t b = t->vertex_corner_offsets[v], e = t->vertex_corner_offsets[v + 1];
        if (t->triangles == t->face_count || t->quads == t->face_count)
            bound += (size_t)(e - b) * (t->quads == t->face_count ? 4 : 3);
        else
            for (uint32_t i = b; i < e; i++)
                bound += topology_face_size(t, t->corner_face[t->vertex_corners[i]]);
    }
    return bound < 3 ? 3 : bound;
}

size_t scheme_refine_edge_bound(const topology *t, limn_scheme scheme, uint32_t e)
{
    if (scheme == LIMN_SCHEME_LOOP)
        return 4; /* the ends and the two opposite vertices; a sharp edge 2 */
    size_t bound = 2;
    for (uint32_t j = t->edge_corner_offsets[e]; j < t->edge_corner_offsets[e + 1]; j++)
        bound += topology_face_size(t, t->corner_face[t->edge_corners[j]]);
    return bound;
}

size_t scheme_refine_face_mask(const topology *t, uint32_t f, uint32_t *cols, double *w)
{
    uint32_t b = t->face_offsets[f], d = t->face_offsets[f + 1] - b;
    for (uint32_t k = 0; k < d; k++) {
        cols[k] = t->face_indices[b + k];
        w[k] = 1.0 / (double)d;
    }
    return d;
}

static size_t catmark_vertex(const topology *t, double alpha, uint32_t v, uint32_t *cols, double *w)
{
    uint32_t eb = t->vertex_edge_offsets[v], n = t->vertex_edge_offsets[v + 1] - eb;
    double nn = (double)n, inv2 = 1.0 / (nn * nn);
    size_t k = 1;
    double self = (nn - 2.0) / nn + nn * alpha * inv2;
    for (uint32_t i = 0; i < n; i++) {
        cols[k] = topology_edge_other(t, t->vertex_edges[eb + i], v);
        w[k++] = (1.0 - alpha) * inv2;
    }
    for (uint32_t i = t->vertex_corner_offsets[v]; i < t->vertex_corner_offsets[v + 1]; i++) {
        uint32_t f = t->corner_face[t->vertex_corners[i]];
        uint32_t fb = t->face_offsets[f], d = t->face_offsets[f + 1] - fb;
        for (uint32_t j = 0; j < d; j++) {
            cols[k] = t->face_indices[fb + j];
            w[k++] = inv2 / (double)d;
        }
    }
    cols[0] = v;
    w[0] = self;
    return k;
}

static size_t loop_vertex(const topology *t, uint32_t v, uint32_t *cols, double *w)
{
    uint32_t eb = t->vertex_edge_offsets[v], n = t->vertex_edge_offsets[v + 1] - eb;
    double beta = scheme_loop_refine_beta(n);
    cols[0] = v;
    w[0] = 1.0 - (double)n * beta;
    for (uint32_t i = 0; i < n; i++) {
        cols[1 + i] = topology_edge_other(t, t->vertex_edges[eb + i], v);
        w[1 + i] = beta;
    }
    return 1 + n;
}

size_t scheme_sharp_vertex_mask(const topology *t, uint32_t v, double centre, double side,
                                uint32_t *cols, double *w)
{
    switch ((vertex_rule)t->vertex_rule[v]) {
    case RULE_ISOLATED:
    case RULE_CORNER:
        cols[0] = v;
        w[0] = 1.0;
        return 1;
    case RULE_CREASE:
        cols[0] = v;
        w[0] = centre;
        cols[1] = t->crease_neighbors[2 * v];
        w[1] = side;
        cols[2] = t->crease_neighbors[2 * v + 1];
        w[2] = side;
        return 3;
    case RULE_SMOOTH:
        break;
    }
    return 0;
}

size_t scheme_refine_vertex_mask(const topology *t, limn_scheme scheme, double alpha, uint32_t v,
                                 uint32_t *cols, double *w)
{
    size_t sharp = scheme_sharp_vertex_mask(t, v, 0.75, 0.125, cols, w);
    if (sharp)
        return sharp;
    return scheme == LIMN_SCHEME_LOOP ? loop_vertex(t, v, cols, w)
                                      : catmark_vertex(t, alpha, v, cols, w);
}

size_t scheme_refine_edge_mask(const topology *t, limn_scheme scheme, uint32_t e, uint32_t *cols,
                               double *w)
{
    uint32_t a = t->edge_vertices[2 * e], b = t->edge_vertices[2 * e + 1];
    cols[0] = a;
    cols[1] = b;
    if (t->edge_flags[e] & (EDGE_BOUNDARY | EDGE_NONMANIFOLD)) {
        w[0] = w[1] = 0.5;
        return 2;
    }
    uint32_t c0 = t->edge_corners[t->edge_corner_offsets[e]];
    uint32_t c1 = t->edge_corners[t->edge_corner_offsets[e] + 1];
    if (scheme == LIMN_SCHEME_LOOP) {
        /* the vertex of each triangle opposite the edge */
        w[0] = w[1] = 0.375;
        cols[2] = t->face_indices[topology_corner_prev(t, c0)];
        cols[3] = t->face_indices[topology_corner_prev(t, c1)];
        w[2] = w[3] = 0.125;
        return 4;
    }
    w[0] = w[1] = 0.25;
    size_t k = 2;
    uint32_t corners[2] = {c0, c1};
    for (int s = 0; s < 2; s++) {
        uint32_t f = t->corner_face[corners[s]];
        uint32_t fb = t->face_offsets[f], d = t->face_offsets[f + 1] - fb;
        for (uint32_t j = 0; j < d; j++) {
            cols[k] = t->face_indices[fb + j];
            w[k++] = 0.25 / (double)d;
        }
    }
    return k;
}
