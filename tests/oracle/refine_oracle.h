/* SPDX-License-Identifier: MIT */
/* Test-only brute-force uniform subdivision (plain C, no OpenSubdiv, independent
 * of limn's code). Manifold meshes with boundaries only.
 *
 * Catmull-Clark (scheme 1), any polygons (>= 3 sides):
 *   face point      centroid of the face
 *   edge point      interior (a + b + f1 + f2)/4, boundary (a + b)/2
 *   vertex point    interior, n incident edges Ej (their other vertices) and
 *                   n incident face points fj:
 *                     V' = (n-2)/n V + 1/n^2 sum_j(alpha V + (1-alpha) Ej)
 *                          + 1/n^2 sum_j fj
 *                   with alpha = alpha_first at the first level only, 0 after;
 *                   boundary (V_prev + 6 V + V_next)/8;
 *                   corner (boundary vertex with one incident face): V' = V.
 * Loop (scheme 0), triangles only:
 *   edge point      interior 3/8 (a + b) + 1/8 (c + d), boundary (a + b)/2
 *   vertex point    interior (1 - n beta) V + beta sum(neighbours),
 *                   beta = (5/8 - (3/8 + cos(2 pi/n)/4)^2)/n;
 *                   boundary (1,6,1)/8; corner (one incident face) stays put.
 *   alpha_first is ignored.
 * Vertices referenced by no face are copied unchanged.
 *
 * Numbering of level k: [0, V) vertex points (vertex i is the child of vertex
 * i of level k-1), then for Catmull-Clark [V, V+F) face points in face order,
 * then edge points; for Loop [V, V+E) edge points. Child faces are listed
 * parent by parent: CC face f of size d gives quads (v_j, e_j, f, e_{j-1}),
 * j = 0..d-1, e_j the edge from corner j to j+1; Loop triangle (a,b,c), edges
 * e0=ab, e1=bc, e2=ca, gives (a,e0,e2), (e0,b,e1), (e2,e1,c), (e1,e2,e0).
 *
 * Refuses (non-zero return, message in err): non-manifold edges (> 2 faces),
 * inconsistent orientation, vertices whose faces form more than one fan
 * (bow-ties), faces repeating a vertex, faces with < 3 vertices, non-triangles
 * for Loop, out-of-range indices.
 *
 * Output arrays are malloc'ed; the caller frees them with free(). Cost is
 * O(size) per level (edges found by bucketing half-edges by lower vertex).
 */
#ifndef LIMN_TEST_REFINE_ORACLE_H
#define LIMN_TEST_REFINE_ORACLE_H

#include <stddef.h>

int refine_oracle(int scheme /*0 Loop, 1 CC*/, double alpha_first, int levels, int nverts,
                  const double *pos, int nfaces, const int *face_sizes, const int *face_indices,
                  int *out_nverts, double **out_pos, int *out_nfaces, int **out_face_sizes,
                  int **out_face_indices, char *err, size_t errlen);

#endif
