/* SPDX-License-Identifier: MIT */
/*
 * The face operator cut at creases (features.h: feature_cut_creases): faces
 * f and j of a ring keep their weight only if they meet around a shared
 * vertex without crossing an edge whose two faces' normals differ by more
 * than the crease angle. So no product averages across a crease, while a
 * crease that ends inside the mesh stays open around its end (docs/series.md
 * "The crease pass").
 */
#include "series/features.h"

#include "base/context.h"
#include "base/sorted_search.h"
#include "base/vec3.h"

#include <stdlib.h>
#include <string.h>

/* The corners of face f before and after vertex v (f has v). */
static void beside(const feature_mesh *fm, uint32_t f, uint32_t v, uint32_t *prev,
                   uint32_t *next)
{
    uint32_t b = fm->offsets[f], e = fm->offsets[f + 1];
    for (uint32_t k = b; k < e; k++)
        if (fm->indices[k] == v) {
            *prev = fm->indices[k > b ? k - 1 : e - 1];
            *next = fm->indices[k + 1 < e ? k + 1 : b];
            return;
        }
    *prev = *next = v;
}

static uint32_t find_root(uint32_t *parent, uint32_t a)
{
    while (parent[a] != a)
        a = parent[a] = parent[parent[a]];
    return a;
}

/* An edge (v, u) of one face of v's fan: the fan position of the face. */
typedef struct fan_edge {
    uint32_t u, at;
} fan_edge;

static int by_vertex(const void *a, const void *b)
{
    const fan_edge *x = a, *y = b;
    return x->u != y->u ? (x->u < y->u ? -1 : 1) : (x->at < y->at ? -1 : x->at > y->at);
}

/* Component labels of the faces around v (label[i] for fm->vf[begin + i]):
   faces across an edge (v, u) joined when their normals n differ by at most
   the crease angle (cosine at least cos_limit). */
static void fan_labels(const feature_mesh *fm, uint32_t v, const double *n, double cos_limit,
                       fan_edge *edges, uint32_t *label)
{
    uint32_t b = fm->vf_offsets[v], m = fm->vf_offsets[v + 1] - b;
    for (uint32_t i = 0; i < m; i++) {
        label[i] = i;
        uint32_t prev, next;
        beside(fm, fm->vf[b + i], v, &prev, &next);
        edges[2 * i] = (fan_edge){prev, i};
        edges[2 * i + 1] = (fan_edge){next, i};
    }
    qsort(edges, 2 * (size_t)m, sizeof *edges, by_vertex);
    for (uint32_t i = 1; i < 2 * m; i++) {
        if (edges[i].u != edges[i - 1].u || edges[i].u == v)
            continue;
        uint32_t a = edges[i - 1].at, c = edges[i].at;
        if (vec3_dot(n + 3 * (size_t)fm->vf[b + a], n + 3 * (size_t)fm->vf[b + c]) < cos_limit)
            continue;
        uint32_t ra = find_root(label, a), rc = find_root(label, c);
        label[ra > rc ? ra : rc] = ra < rc ? ra : rc;
    }
    for (uint32_t i = 0; i < m; i++)
        label[i] = find_root(label, i);
}

/* The position of column j in row i of W (columns increasing; j present). */
static uint32_t column_at(const stencil_csr *w, size_t i, uint32_t j)
{
    uint32_t b = w->row_offsets[i];
    return b + (uint32_t)sorted_last_at_most_u32(w->columns + b, w->row_offsets[i + 1] - b, j);
}

/* Marks, in the row of the face at fan position at of v, the faces of v's
   fan in its component. */
static void mark_row(feature_mesh *fm, uint32_t v, uint32_t at, const uint32_t *label)
{
    uint32_t b = fm->vf_offsets[v], m = fm->vf_offsets[v + 1] - b, f = fm->vf[b + at];
    for (uint32_t i = 0; i < m; i++)
        if (label[i] == label[at])
            fm->keep[column_at(&fm->ring, f, fm->vf[b + i])] = 1;
}

limn_status feature_cut_creases(limn_context *ctx, feature_mesh *fm, const double *n,
                                double cos_limit)
{
    size_t nonzeros = fm->ring.row_offsets[fm->ring.rows], largest = 1;
    for (size_t v = 0; v < fm->vertices; v++)
        if (fm->vf_offsets[v + 1] - fm->vf_offsets[v] > largest)
            largest = fm->vf_offsets[v + 1] - fm->vf_offsets[v];
    if (!fm->keep)
        fm->keep = malloc(nonzeros ? nonzeros : 1);
    fan_edge *edges = malloc(2 * largest * sizeof *edges);
    uint32_t *label = malloc(largest * sizeof *label);
    limn_status st = LIMN_OK;
    if (!fm->keep || !edges || !label)
        st = ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for the creases of %zu faces",
                      fm->faces);
    if (!st) {
        memset(fm->keep, 0, nonzeros);
        for (size_t v = 0; v < fm->vertices; v++) {
            if (fm->vf_offsets[v + 1] == fm->vf_offsets[v])
                continue;
            fan_labels(fm, (uint32_t)v, n, cos_limit, edges, label);
            for (uint32_t at = 0; at < fm->vf_offsets[v + 1] - fm->vf_offsets[v]; at++)
                mark_row(fm, (uint32_t)v, at, label);
        }
    }
    free(edges);
    free(label);
    return st;
}
