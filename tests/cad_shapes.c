/* SPDX-License-Identifier: MIT */
/* The shapes of cad_shapes.h: lattice points of the cube's surface, each
   moved along its ray from the origin to where the ray leaves the shape (the
   shapes are convex and hold the origin, so that point is unique). */
#include "cad_shapes.h"

#include <math.h>
#include <stdlib.h>

/* The distance along the unit direction d to the shape's surface. */
static double ray_exit(cad_shape shape, const double d[3])
{
    double t = INFINITY;
    if (shape == CAD_PART) {
        double r = sqrt(d[0] * d[0] + d[1] * d[1]), z = fabs(d[2]);
        if (r > 0)
            t = fmin(t, 1.0 / r);
        if (z > 0)
            t = fmin(t, 0.6 / z);
        /* the chamfer r + z <= 1.45 (a 45 degree cut of the cap's rim) */
        return fmin(t, 1.45 / (r + z));
    }
    for (int a = 0; a < 3; a++)
        if (d[a] != 0)
            t = fmin(t, 1.0 / fabs(d[a]));
    if (shape == CAD_BEVELLED_CUBE)
        for (int a = 0; a < 3; a++) {
            double s = fabs(d[a]) + fabs(d[(a + 1) % 3]);
            if (s > 0)
                t = fmin(t, 1.7 / s);
        }
    return t;
}

/* The lattice point (i, j, k) of 0..n as a vertex id, made on first use. */
static uint32_t lattice_vertex(int *ids, double *pos, uint32_t *count, cad_shape shape, int n,
                               int i, int j, int k)
{
    int *id = ids + ((size_t)i * (n + 1) + j) * (n + 1) + k;
    if (*id >= 0)
        return (uint32_t)*id;
    double d[3] = {2.0 * i / n - 1.0, 2.0 * j / n - 1.0, 2.0 * k / n - 1.0};
    double l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (int c = 0; c < 3; c++)
        d[c] /= l;
    double t = ray_exit(shape, d);
    for (int c = 0; c < 3; c++)
        pos[3 * *count + c] = t * d[c];
    *id = (int)*count;
    return (*count)++;
}

/* The four corners of cell (u, v) of cube face (axis, side), counter-clockwise
   seen from outside. */
static void cell_corners(int n, int axis, int side, int u, int v, int ijk[4][3])
{
    static const int du[4] = {0, 1, 1, 0}, dv[4] = {0, 0, 1, 1};
    int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    for (int c = 0; c < 4; c++) {
        int q = side ? c : 3 - c; /* the far side runs the other way round */
        ijk[c][axis] = side ? n : 0;
        ijk[c][a1] = u + du[q];
        ijk[c][a2] = v + dv[q];
    }
}

limn_mesh *cad_shape_mesh(limn_context *ctx, cad_shape shape, int n, int triangles)
{
    size_t cells = 6 * (size_t)n * n, per = triangles ? 3 : 4, faces = triangles ? 2 * cells : cells;
    int *ids = malloc((size_t)(n + 1) * (n + 1) * (n + 1) * sizeof *ids);
    double *pos = malloc(3 * (6 * (size_t)(n + 1) * (n + 1)) * sizeof *pos);
    uint32_t *off = malloc((faces + 1) * sizeof *off), *idx = malloc(faces * per * sizeof *idx);
    limn_mesh *m = NULL;
    if (ids && pos && off && idx) {
        for (size_t i = 0; i < (size_t)(n + 1) * (n + 1) * (n + 1); i++)
            ids[i] = -1;
        uint32_t count = 0;
        size_t f = 0, w = 0;
        off[0] = 0;
        for (int axis = 0; axis < 3; axis++)
            for (int side = 0; side < 2; side++)
                for (int u = 0; u < n; u++)
                    for (int v = 0; v < n; v++) {
                        int ijk[4][3];
                        uint32_t q[4];
                        cell_corners(n, axis, side, u, v, ijk);
                        for (int c = 0; c < 4; c++)
                            q[c] = lattice_vertex(ids, pos, &count, shape, n, ijk[c][0],
                                                  ijk[c][1], ijk[c][2]);
                        /* alternate the diagonals so that no direction is favoured */
                        int s = triangles && (u + v) % 2;
                        static const int split[2][6] = {{0, 1, 2, 0, 2, 3}, {0, 1, 3, 1, 2, 3}};
                        if (triangles)
                            for (int t = 0; t < 2; t++) {
                                for (int c = 0; c < 3; c++)
                                    idx[w++] = q[split[s][3 * t + c]];
                                off[++f] = (uint32_t)w;
                            }
                        else {
                            for (int c = 0; c < 4; c++)
                                idx[w++] = q[c];
                            off[++f] = (uint32_t)w;
                        }
                    }
        limn_mesh_create(ctx, count, pos, faces, off, idx, &m);
    }
    free(ids);
    free(pos);
    free(off);
    free(idx);
    return m;
}
