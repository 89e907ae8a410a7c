/* SPDX-License-Identifier: MIT */
/*
 * Writes limn's limit operator A of a mesh, M, the vertex rules and the row
 * scales D (A = D S on the smooth block) as one raw little-endian file for the
 * SciPy anchor (perf/scipy_anchor.py):
 *   uint64 n, uint64 nnz, uint32 row_offsets[n+1], uint32 columns[nnz],
 *   double weights[nnz], double M[3n], uint8 rule[n] (0 isolated, 1 smooth,
 *   2 crease, 3 pinned), double scale[n]
 *   export_operator MESH loop|catmark OUT.bin [alpha] [rcm]
 * rcm: rows and columns (and M, rule, scale) in limn's reverse Cuthill-McKee
 * order, as a solve renumbers a mesh whose rows hop (README "Locality").
 */
#include "limn.h"
#include "mesh/mesh.h"
#include "scheme/scheme.h"
#include "stencil/stencil.h"
#include "stencil/reorder.h"
#include "topology/topology.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int main(int argc, char **argv)
{
    if (argc < 4) {
        fprintf(stderr, "usage: export_operator MESH loop|catmark OUT.bin [alpha] [rcm]\n");
        return 2;
    }
    limn_context *ctx = limn_context_create();
    limn_mesh *m = NULL;
    limn_scheme scheme = strcmp(argv[2], "loop") == 0 ? LIMN_SCHEME_LOOP : LIMN_SCHEME_CATMARK;
    double alpha = argc > 4 ? atof(argv[4]) : 0.0;
    topology t;
    stencil_csr a;
    if (limn_mesh_read(ctx, argv[1], LIMN_FORMAT_AUTO, &m) || topology_build(ctx, m, &t) ||
        stencil_limit_build(ctx, &t, scheme, alpha, &a)) {
        fprintf(stderr, "%s\n", limn_context_message(ctx));
        return 1;
    }
    uint32_t *order = NULL, *rank = NULL;
    if (argc > 5 && strcmp(argv[5], "rcm") == 0) {
        stencil_csr permuted;
        if (reorder_rcm(ctx, &t, &order, &rank) ||
            stencil_permute(ctx, &a, order, rank, &permuted)) {
            fprintf(stderr, "%s\n", limn_context_message(ctx));
            return 1;
        }
        stencil_free(&a);
        a = permuted;
    }
    FILE *f = fopen(argv[3], "wb");
    if (!f)
        return 1;
    uint64_t n = a.rows, nnz = a.row_offsets[a.rows];
    double *scale = malloc(n * sizeof *scale), *pos = malloc(3 * n * sizeof *pos);
    uint8_t *rule = malloc(n);
    for (uint32_t k = 0; k < n; k++) {
        uint32_t v = order ? order[k] : k; /* row k is input vertex v */
        scale[k] = scheme_limit_row_scale(&t, scheme, v);
        rule[k] = (uint8_t)t.vertex_rule[v];
        memcpy(pos + 3 * k, m->positions + 3 * v, 3 * sizeof *pos);
    }
    int ok = fwrite(&n, 8, 1, f) == 1 && fwrite(&nnz, 8, 1, f) == 1 &&
             fwrite(a.row_offsets, 4, n + 1, f) == n + 1 && fwrite(a.columns, 4, nnz, f) == nnz &&
             fwrite(a.weights, 8, nnz, f) == nnz && fwrite(pos, 8, 3 * n, f) == 3 * n &&
             fwrite(rule, 1, n, f) == n && fwrite(scale, 8, n, f) == n;
    if (fclose(f) != 0 || !ok)
        return 1;
    free(scale);
    free(pos);
    free(rule);
    free(order);
    free(rank);
    stencil_free(&a);
    topology_free(&t);
    limn_mesh_destroy(m);
    limn_context_destroy(ctx);
    return 0;
}
