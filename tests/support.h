/* SPDX-License-Identifier: MIT */
/* Shared helpers for limn's tests: mesh locations, generated meshes,
   conversions to the oracles' face arrays. */
#ifndef LIMN_TEST_SUPPORT_H
#define LIMN_TEST_SUPPORT_H

#include "fixture.h"
#include "limn.h"
#include <stddef.h>

/* Directory of the shared real meshes ($LIMN_SHARED_MESHES, else
   ../shared/meshes beside the source tree), or NULL when absent. */
const char *test_shared_meshes(void);
/* Joins the shared directory and a relative path into a static buffer. */
const char *test_shared_path(const char *rel);

/* Lists mesh files (.obj .ply .off) of a shared subdirectory, sorted; returns
   the count (at most max); names are "sub/file" in static storage. */
size_t test_list_meshes(const char *sub, const char **names, size_t max);

/* Generated meshes (deterministic). */
limn_mesh *test_mesh_grid(limn_context *ctx, int nx, int ny, int triangulate);
limn_mesh *test_mesh_cube(limn_context *ctx);
limn_mesh *test_mesh_icosahedron(limn_context *ctx);
limn_mesh *test_mesh_pyramid(limn_context *ctx);
/* n faces around one interior vertex of valence n (triangles or quads). */
limn_mesh *test_mesh_fan(limn_context *ctx, int n, int triangles);
/* a with its vertices renumbered by a fixed pseudo-random permutation (rows
   that hop around memory: RCM runs); frees a. */
limn_mesh *test_mesh_shuffle(limn_context *ctx, limn_mesh *a, unsigned seed);
/* Moves every vertex by a deterministic pseudo-random offset in [-amp, amp]^3. */
void test_perturb(limn_mesh *mesh, double amp, unsigned seed);

/* Face arrays as ints for the oracles; caller frees both. */
void test_oracle_faces(const limn_mesh *mesh, int **sizes, int **indices);
int test_all_triangles(const limn_mesh *mesh);
double test_bbox_diagonal(const limn_mesh *mesh);

/* y = A x for a dense n x n matrix A (row-major) and the first 3 channels of
   points stored stride doubles apart in x and y (3 or 4); y's other channels
   are left as they are. */
void test_dense_product(const double *a, size_t n, const double *x, size_t stride, double *y);

/* Fails the test unless a and b have the same vertices (bit for bit),
   faces and colours. */
void test_assert_same_mesh(const limn_mesh *a, const limn_mesh *b);

/* Writes a file with the given text; returns 0 on success. */
int test_write_text(const char *path, const char *text);
int test_file_exists(const char *path);
/* The entries of directory dir besides . and .. (0 when it cannot be read). */
int test_dir_entries(const char *dir);

#endif
