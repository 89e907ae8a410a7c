/* SPDX-License-Identifier: MIT */
#include "support.h"

#include <dirent.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <cmocka.h>

const char *test_shared_meshes(void)
{
    static char dir[4096];
    const char *env = getenv("LIMN_SHARED_MESHES");
    if (env && *env)
        snprintf(dir, sizeof dir, "%s", env);
    else
        snprintf(dir, sizeof dir, "%s/../shared/meshes", LIMN_SOURCE_DIR);
    struct stat st;
    return stat(dir, &st) == 0 && S_ISDIR(st.st_mode) ? dir : NULL;
}

const char *test_shared_path(const char *rel)
{
    static char path[4][4096];
    static int slot;
    const char *dir = test_shared_meshes();
    slot = (slot + 1) % 4;
    snprintf(path[slot], sizeof path[slot], "%s/%s", dir ? dir : ".", rel);
    return path[slot];
}

static int cmp_str(const void *a, const void *b)
{
    return strcmp(*(const char *const *)a, *(const char *const *)b);
}

size_t test_list_meshes(const char *sub, const char **names, size_t max)
{
    static char storage[256][128];
    static size_t used;
    const char *dir = test_shared_meshes();
    if (!dir)
        return 0;
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, sub);
    DIR *d = opendir(path);
    if (!d)
        return 0;
    size_t n = 0;
    struct dirent *e;
    while ((e = readdir(d)) && n < max && used < 256) {
        const char *dot = strrchr(e->d_name, '.');
        if (!dot || (strcmp(dot, ".obj") && strcmp(dot, ".ply") && strcmp(dot, ".off")))
            continue;
        snprintf(storage[used], sizeof storage[used], "%s/%s", sub, e->d_name);
        names[n++] = storage[used++];
    }
    closedir(d);
    qsort(names, n, sizeof *names, cmp_str);
    return n;
}

static limn_mesh *make(limn_context *ctx, size_t nv, const double *pos, size_t nf,
                       const uint32_t *off, const uint32_t *idx)
{
    limn_mesh *m = NULL;
    if (limn_mesh_create(ctx, nv, pos, nf, off, idx, &m) != LIMN_OK) {
        fprintf(stderr, "test mesh: %s\n", limn_context_message(ctx));
        return NULL;
    }
    return m;
}

limn_mesh *test_mesh_grid(limn_context *ctx, int nx, int ny, int triangulate)
{
    size_t nv = (size_t)(nx + 1) * (ny + 1), nq = (size_t)nx * ny;
    size_t nf = triangulate ? 2 * nq : nq;
    double *pos = malloc(nv * 3 * sizeof *pos);
    uint32_t *off = malloc((nf + 1) * sizeof *off), *idx = malloc(nf * 4 * sizeof *idx);
    for (int j = 0; j <= ny; j++)
        for (int i = 0; i <= nx; i++) {
            double *p = pos + 3 * ((size_t)j * (nx + 1) + i);
            p[0] = i;
            p[1] = j;
            p[2] = 0.1 * sin(0.7 * i) * cos(0.5 * j);
        }
    size_t f = 0, k = 0;
    off[0] = 0;
    for (int j = 0; j < ny; j++)
        for (int i = 0; i < nx; i++) {
            uint32_t a = (uint32_t)(j * (nx + 1) + i), b = a + 1, c = b + (uint32_t)(nx + 1),
                     d = a + (uint32_t)(nx + 1);
            if (triangulate) {
                idx[k++] = a, idx[k++] = b, idx[k++] = c, off[++f] = (uint32_t)k;
                idx[k++] = a, idx[k++] = c, idx[k++] = d, off[++f] = (uint32_t)k;
            } else {
                idx[k++] = a, idx[k++] = b, idx[k++] = c, idx[k++] = d, off[++f] = (uint32_t)k;
            }
        }
    limn_mesh *m = make(ctx, nv, pos, nf, off, idx);
    free(pos);
    free(off);
    free(idx);
    return m;
}

limn_mesh *test_mesh_cube(limn_context *ctx)
{
    static const double pos[] = {-1, -1, -1, 1, -1, -1, 1, 1, -1, -1, 1, -1,
                                 -1, -1, 1,  1, -1, 1,  1, 1, 1,  -1, 1, 1};
    static const uint32_t idx[] = {0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4,
                                   1, 2, 6, 5, 2, 3, 7, 6, 3, 0, 4, 7};
    static const uint32_t off[] = {0, 4, 8, 12, 16, 20, 24};
    return make(ctx, 8, pos, 6, off, idx);
}

limn_mesh *test_mesh_pyramid(limn_context *ctx)
{
    static const double pos[] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0, 0, 0, 1.5};
    static const uint32_t idx[] = {0, 3, 2, 1, 0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4};
    static const uint32_t off[] = {0, 4, 7, 10, 13, 16};
    return make(ctx, 5, pos, 5, off, idx);
}

limn_mesh *test_mesh_icosahedron(limn_context *ctx)
{
    const double t = (1.0 + sqrt(5.0)) / 2.0;
    const double pos[] = {-1, t, 0, 1, t, 0, -1, -t, 0, 1, -t, 0, 0, -1, t, 0, 1, t,
                          0, -1, -t, 0, 1, -t, t, 0, -1, t, 0, 1, -t, 0, -1, -t, 0, 1};
    static const uint32_t idx[] = {0, 11, 5,  0, 5,  1, 0, 1, 7, 0, 7,  10, 0, 10, 11,
                                   1, 5,  9,  5, 11, 4, 11, 10, 2, 10, 7, 6, 7, 1, 8,
                                   3, 9,  4,  3, 4,  2, 3, 2, 6, 3, 6,  8,  3, 8,  9,
                                   4, 9,  5,  2, 4,  11, 6, 2, 10, 8, 6, 7, 9, 8, 1};
    uint32_t off[21];
    for (int i = 0; i <= 20; i++)
        off[i] = (uint32_t)(3 * i);
    return make(ctx, 12, pos, 20, off, idx);
}

void test_perturb(limn_mesh *mesh, double amp, unsigned seed)
{
    double *p = limn_mesh_positions_mutable(mesh);
    unsigned long long s = seed * 6364136223846793005ULL + 1442695040888963407ULL;
    for (size_t i = 0; i < 3 * limn_mesh_vertex_count(mesh); i++) {
        s = s * 6364136223846793005ULL + 1442695040888963407ULL;
        double u = (double)(s >> 11) / 9007199254740992.0;
        p[i] += amp * (2.0 * u - 1.0);
    }
}

void test_oracle_faces(const limn_mesh *mesh, int **sizes, int **indices)
{
    size_t nf = limn_mesh_face_count(mesh);
    const uint32_t *off = limn_mesh_face_offsets(mesh), *idx = limn_mesh_face_indices(mesh);
    *sizes = malloc((nf ? nf : 1) * sizeof **sizes);
    *indices = malloc((off[nf] ? off[nf] : 1) * sizeof **indices);
    for (size_t f = 0; f < nf; f++)
        (*sizes)[f] = (int)(off[f + 1] - off[f]);
    for (size_t i = 0; i < off[nf]; i++)
        (*indices)[i] = (int)idx[i];
}

int test_all_triangles(const limn_mesh *mesh)
{
    const uint32_t *off = limn_mesh_face_offsets(mesh);
    for (size_t f = 0; f < limn_mesh_face_count(mesh); f++)
        if (off[f + 1] - off[f] != 3)
            return 0;
    return limn_mesh_face_count(mesh) > 0;
}

void test_dense_product(const double *a, size_t n, const double *x, size_t stride, double *y)
{
    for (size_t i = 0; i < n; i++)
        for (size_t c = 0; c < 3; c++) {
            double acc = 0.0;
            for (size_t j = 0; j < n; j++)
                acc += a[i * n + j] * x[stride * j + c];
            y[stride * i + c] = acc;
        }
}

double test_bbox_diagonal(const limn_mesh *mesh)
{
    const double *p = limn_mesh_positions(mesh);
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t i = 0; i < limn_mesh_vertex_count(mesh); i++)
        for (int c = 0; c < 3; c++) {
            lo[c] = fmin(lo[c], p[3 * i + c]);
            hi[c] = fmax(hi[c], p[3 * i + c]);
        }
    return sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                (hi[2] - lo[2]) * (hi[2] - lo[2]));
}

int test_write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "wb");
    if (!f)
        return -1;
    size_t n = strlen(text);
    int ok = fwrite(text, 1, n, f) == n;
    return (fclose(f) == 0 && ok) ? 0 : -1;
}

int test_file_exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

int test_dir_entries(const char *dir)
{
    DIR *d = opendir(dir);
    int n = 0;
    for (struct dirent *e; d && (e = readdir(d));)
        n += strcmp(e->d_name, ".") && strcmp(e->d_name, "..");
    if (d)
        closedir(d);
    return n;
}

limn_mesh *test_mesh_fan(limn_context *ctx, int n, int triangles)
{
    /* centre 0, inner ring 1..n, outer ring n+1..2n (quads only) */
    size_t nv = triangles ? (size_t)n + 1 : 2 * (size_t)n + 1;
    double *pos = malloc(nv * 3 * sizeof *pos);
    uint32_t *off = malloc(((size_t)n + 1) * sizeof *off), *idx = malloc((size_t)n * 4 * sizeof *idx);
    const double pi = 3.14159265358979323846;
    pos[0] = 0, pos[1] = 0, pos[2] = 0.3;
    for (int k = 0; k < n; k++) {
        double a = 2 * pi * k / n, b = a + pi / n;
        double *p = pos + 3 * (1 + k);
        p[0] = cos(a), p[1] = sin(a), p[2] = 0.1 * (k % 2);
        if (!triangles) {
            double *q = pos + 3 * (1 + n + k);
            q[0] = 1.6 * cos(b), q[1] = 1.6 * sin(b), q[2] = -0.1;
        }
    }
    size_t k = 0;
    off[0] = 0;
    for (int f = 0; f < n; f++) {
        uint32_t v = 1 + (uint32_t)f, w = 1 + (uint32_t)((f + 1) % n);
        idx[k++] = 0, idx[k++] = v;
        if (!triangles)
            idx[k++] = 1 + (uint32_t)n + (uint32_t)f;
        idx[k++] = w;
        off[f + 1] = (uint32_t)k;
    }
    limn_mesh *m = make(ctx, nv, pos, (size_t)n, off, idx);
    free(pos);
    free(off);
    free(idx);
    return m;
}

/* Same vertices (bit for bit), faces and colours. */
void test_assert_same_mesh(const limn_mesh *a, const limn_mesh *b)
{
    size_t nv = limn_mesh_vertex_count(a), nf = limn_mesh_face_count(a);
    assert_int_equal(nv, limn_mesh_vertex_count(b));
    assert_int_equal(nf, limn_mesh_face_count(b));
    assert_memory_equal(limn_mesh_positions(a), limn_mesh_positions(b), nv * 3 * sizeof(double));
    assert_memory_equal(limn_mesh_face_offsets(a), limn_mesh_face_offsets(b),
                        (nf + 1) * sizeof(uint32_t));
    assert_memory_equal(limn_mesh_face_indices(a), limn_mesh_face_indices(b),
                        limn_mesh_index_count(a) * sizeof(uint32_t));
    assert_int_equal(limn_mesh_colors(a) != NULL, limn_mesh_colors(b) != NULL);
    if (limn_mesh_colors(a))
        assert_memory_equal(limn_mesh_colors(a), limn_mesh_colors(b), nv * 3);
}

limn_mesh *test_mesh_shuffle(limn_context *ctx, limn_mesh *a, unsigned seed)
{
    size_t n = limn_mesh_vertex_count(a), nf = limn_mesh_face_count(a);
    const uint32_t *off = limn_mesh_face_offsets(a), *idx = limn_mesh_face_indices(a);
    uint32_t *perm = malloc(n * sizeof *perm), *idx2 = malloc(off[nf] * sizeof *idx2);
    double *pos = malloc(3 * n * sizeof *pos);
    for (size_t i = 0; i < n; i++)
        perm[i] = (uint32_t)i;
    unsigned long long s = seed;
    for (size_t i = n - 1; i > 0; i--) {
        s = s * 6364136223846793005ULL + 1442695040888963407ULL;
        size_t j = (size_t)((s >> 33) % (i + 1));
        uint32_t t = perm[i];
        perm[i] = perm[j];
        perm[j] = t;
    }
    for (size_t i = 0; i < n; i++)
        memcpy(pos + 3 * perm[i], limn_mesh_positions(a) + 3 * i, 3 * sizeof *pos);
    for (size_t k = 0; k < off[nf]; k++)
        idx2[k] = perm[idx[k]];
    limn_mesh *m = NULL;
    limn_mesh_create(ctx, n, pos, nf, off, idx2, &m);
    free(perm);
    free(idx2);
    free(pos);
    limn_mesh_destroy(a);
    return m;
}
