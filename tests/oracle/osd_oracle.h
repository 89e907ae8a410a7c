/* SPDX-License-Identifier: MIT */
/* Test-only oracle: OpenSubdiv 3.5 (Far, double precision) limit positions and
 * uniform refinement, behind a plain C interface.
 *
 * Independent of limn's code. Link with osd_oracle.cpp, -losdCPU -lstdc++.
 *
 * Common conventions:
 *   scheme      0 = Loop, 1 = Catmull-Clark (OSD Catmark, triangles subdivided the
 *               Catmark way, i.e. plain Catmull-Clark for every polygon).
 *   pos         3*nverts doubles (x,y,z per vertex).
 *   faces       face_sizes[nfaces] and the concatenated 0-based face_indices.
 *   boundary    Sdc VTX_BOUNDARY_EDGE_AND_CORNER, no creases, no holes, no
 *               semi-sharp anything; face-varying data is not used.
 *   return      0 on success; non-zero with a NUL-terminated message in err
 *               (err may be NULL, errlen may be 0).
 * OSD's own errors and warnings are captured (never printed) while a call runs;
 * the functions are not thread-safe (OSD's error callback is global).
 */
#ifndef LIMN_TEST_OSD_ORACLE_H
#define LIMN_TEST_OSD_ORACLE_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Limit position of every base vertex i, written to limit_out[3*i..3*i+2].
 * Route: one uniform refinement level, then PrimvarRefinerReal<double>::Limit on
 * level 1, read back through the level-0 vertex -> child-vertex map.
 * What OSD does with unusual input (all passed through unchanged):
 *   - vertex referenced by no face: tagged non-manifold, infinitely sharp; its
 *     limit is its own position;
 *   - non-manifold edges (> 2 faces, or 2 faces of opposite orientation, or a
 *     degenerate edge of a face repeating a vertex) are infinitely sharp;
 *   - non-manifold vertices are pinned (limit = own position), except a vertex
 *     on exactly two non-manifold edges, no boundary edge and more faces than
 *     edges (an interior "fin" line), which follows the crease (1,4,1)/6 along
 *     those two edges.
 * Loop with a non-triangle face fails (OSD refuses it). */
int osd_oracle_limit(int scheme, int nverts, const double *pos, int nfaces,
                     const int *face_sizes, const int *face_indices,
                     double *limit_out, char *err, size_t errlen);

/* Uniform refinement to `levels` (>= 0; 0 returns a copy of the input).
 * Outputs the finest level only: *out_nverts vertices in *out_pos (3 per
 * vertex), *out_nfaces faces as *out_face_sizes / *out_face_indices. All arrays
 * are malloc'ed; the caller frees them with free(). On failure nothing is
 * allocated and the outputs are set to 0/NULL.
 * Numbering: vertex i of every level is the child of vertex i of the previous
 * level (OSD's default order: vertex-vertices first); this is checked at every
 * level and reported as an error if OSD ever numbers differently. */
int osd_oracle_refine(int scheme, int nverts, const double *pos, int nfaces,
                      const int *face_sizes, const int *face_indices, int levels,
                      int *out_nverts, double **out_pos, int *out_nfaces,
                      int **out_face_sizes, int **out_face_indices,
                      char *err, size_t errlen);

/* Diagnostic: OSD's classification of the base-level vertices of a mesh
 * (without refining). Each output array may be NULL; else it has nverts
 * entries, set to 0/1. Used to document how OSD treats non-manifold input. */
int osd_oracle_classify(int scheme, int nverts, int nfaces,
                        const int *face_sizes, const int *face_indices,
                        int *is_boundary, int *is_nonmanifold, int *is_corner,
                        char *err, size_t errlen);

/* Errors and warnings OSD reported during the last call (possibly ""). */
const char *osd_oracle_last_messages(void);

#ifdef __cplusplus
}
#endif

#endif
