/* SPDX-License-Identifier: MIT */
/*
 * The binary PLY fast path (host/mesh/io/mesh_ply_fast.c, issue 13.1)
 * against the general reader, forced by the test-only LIMN_TEST_PLY_GENERAL=1:
 * every shared mesh PLY and generated files of the layouts scanners write
 * (little and big endian, float and double, every count type, triangles,
 * quads and mixed polygons, extra vertex and face properties, other
 * elements) give the same status, message, warnings and mesh bit for bit,
 * also when truncated or corrupt, under a memory limit and for 1 to 7
 * threads. The fast path must actually run: it reports progress once an
 * element where the general reader reports it every buffer.
 */
#ifndef _POSIX_C_SOURCE
#define _POSIX_C_SOURCE 200809L /* setenv */
#endif
#include "shell.h"
#include "support.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

static char dir[64];

enum { BAD_NONE, BAD_INDEX, BAD_NEGATIVE, BAD_COUNT2, BAD_COUNT_HUGE, BAD_NAN, BAD_INF,
       BAD_TRAILING, BAD_COUNT };

/* What a generated file holds. */
typedef struct spec {
    int big, dbl;              /* big endian; double coordinates */
    const char *count_type, *index_type;
    int shape;                 /* 0 triangles, 1 quads, 2 mixed polygons */
    int normals, colours, confidence, face_extra, other;
    int n;                     /* grid of n x n vertices */
    int bad;                   /* BAD_* */
} spec;

typedef struct bytes {
    unsigned char *p;
    size_t len, cap;
} bytes;

static void put(bytes *b, const void *v, size_t n)
{
    if (b->len + n > b->cap) {
        b->cap = (b->len + n) * 2;
        b->p = realloc(b->p, b->cap);
        assert_non_null(b->p);
    }
    memcpy(b->p + b->len, v, n);
    b->len += n;
}

static void put_text(bytes *b, const char *s) { put(b, s, strlen(s)); }

/* An n-byte value in the file's byte order. */
static void put_u(bytes *b, uint64_t v, int n, int big)
{
    unsigned char c[8];
    for (int i = 0; i < n; i++)
        c[big ? n - 1 - i : i] = (unsigned char)(v >> (8 * i));
    put(b, c, (size_t)n);
}

static int type_bytes(const char *t)
{
    return strstr(t, "char") || strstr(t, "8") ? 1 : strstr(t, "short") || strstr(t, "16") ? 2 : 4;
}

static void put_coord(bytes *b, const spec *s, double x)
{
    uint64_t u;
    if (s->dbl) {
        memcpy(&u, &x, 8);
        put_u(b, u, 8, s->big);
    } else {
        float f = (float)x;
        uint32_t w;
        memcpy(&w, &f, 4);
        put_u(b, w, 4, s->big);
    }
}

static void put_header(bytes *b, const spec *s, int nv, int nf)
{
    char line[256];
    const char *ct = s->dbl ? "double" : "float";
    snprintf(line, sizeof line, "ply\nformat binary_%s_endian 1.0\ncomment test\n"
             "element vertex %d\n", s->big ? "big" : "little", nv);
    put_text(b, line);
    if (s->confidence)
        put_text(b, "property float confidence\n");
    snprintf(line, sizeof line, "property %s x\nproperty %s y\nproperty %s z\n", ct, ct, ct);
    put_text(b, line);
    if (s->normals)
        put_text(b, "property float nx\nproperty float ny\nproperty float nz\n");
    if (s->colours)
        put_text(b, "property uchar red\nproperty uchar green\nproperty uchar blue\n");
    if (s->other)
        put_text(b, "element material 3\nproperty uchar id\nproperty double shine\n");
    snprintf(line, sizeof line, "element face %d\n%sproperty list %s %s vertex_indices\n%s"
             "end_header\n", nf, s->face_extra ? "property uchar flags\n" : "", s->count_type,
             s->index_type, s->face_extra ? "property float quality\n" : "");
    put_text(b, line);
}

static void put_vertices(bytes *b, const spec *s, int nv)
{
    for (int v = 0; v < nv; v++) {
        double xyz[3] = {0.1 * (v % s->n) + 1e-7 * v, 0.37 * (v / s->n), sin(0.01 * v)};
        if (s->bad == BAD_NAN && v == nv / 2)
            xyz[1] = NAN;
        if (s->bad == BAD_INF && v == nv - 1)
            xyz[2] = -INFINITY;
        if (s->confidence)
            put_u(b, 0x3f800000u, 4, s->big);
        for (int c = 0; c < 3; c++)
            put_coord(b, s, xyz[c]);
        for (int c = 0; s->normals && c < 3; c++)
            put_u(b, 0x3f000000u + (uint32_t)c, 4, s->big);
        for (int c = 0; s->colours && c < 3; c++)
            put_u(b, (uint64_t)(v * 7 + c) & 0xff, 1, 0);
    }
    for (int m = 0; s->other && m < 3; m++) {
        put_u(b, (uint64_t)m, 1, 0);
        put_u(b, 0x3ff0000000000000ull, 8, s->big);
    }
}

/* Corners of face f of cell c (one per cell; mixed: a quad, a triangle or a
   pentagon); returns how many. */
static int corners(const spec *s, int c, uint32_t *v)
{
    int n = s->n, i = c % (n - 1), j = c / (n - 1);
    uint32_t a = (uint32_t)(j * n + i);
    uint32_t q[5] = {a, a + 1, a + 1 + (uint32_t)n, a + (uint32_t)n, a + 2};
    int k = s->shape == 0 ? 3 : s->shape == 1 || i >= n - 2 ? 4 : 3 + c % 3;
    memcpy(v, q, sizeof q);
    return k;
}

static void put_faces(bytes *b, const spec *s, int nf, int nv)
{
    int cs = type_bytes(s->count_type), is = type_bytes(s->index_type);
    for (int f = 0; f < nf; f++) {
        uint32_t v[5];
        int k = corners(s, f, v);
        if (s->bad == BAD_INDEX && f == nf / 3)
            v[1] = (uint32_t)nv;
        if (s->bad == BAD_NEGATIVE && f == nf - 1)
            v[0] = UINT32_MAX;
        if (s->bad == BAD_COUNT2 && f == nf / 2)
            k = 2;
        if (s->face_extra)
            put_u(b, (uint64_t)f & 0xff, 1, 0);
        put_u(b, s->bad == BAD_COUNT_HUGE && f == nf - 1 ? 120 : (uint64_t)k, cs, s->big);
        for (int c = 0; c < k; c++)
            put_u(b, v[c], is, s->big);
        if (s->face_extra)
            put_u(b, 0x40000000u, 4, s->big);
    }
    if (s->bad == BAD_TRAILING)
        put_text(b, "tail");
}

/* Writes the file of s; *header gets where the data starts. */
static const char *generate(const spec *s, size_t *header, size_t *len)
{
    bytes b = {0};
    int nv = s->n * s->n, nf = (s->n - 1) * (s->n - 1);
    put_header(&b, s, nv, nf);
    *header = b.len;
    put_vertices(&b, s, nv);
    put_faces(&b, s, nf, nv);
    *len = b.len;
    const char *path = test_write_bytes(test_join(dir, "gen.ply"), b.p, b.len);
    free(b.p);
    return path;
}

/* What one read gave. */
typedef struct outcome {
    limn_status st;
    char msg[2048], warn[4096];
    limn_mesh *m;
    int progress; /* calls of the progress callback */
} outcome;

static void count_progress(void *user, const char *stage, double fraction)
{
    (void)stage;
    (void)fraction;
    (*(int *)user)++;
}

static char last_message[2048]; /* of the last both_ways */

static void read_way(const char *path, int general, size_t max_memory, int threads, outcome *o)
{
    assert_int_equal(setenv("LIMN_TEST_PLY_GENERAL", general ? "1" : "0", 1), 0);
    limn_context *ctx = limn_context_create();
    assert_non_null(ctx);
    if (max_memory)
        limn_context_set_max_memory(ctx, max_memory);
    if (threads)
        assert_int_equal(limn_context_set_threads(ctx, threads), LIMN_OK);
    o->progress = 0;
    limn_context_set_progress(ctx, count_progress, &o->progress);
    o->m = NULL;
    o->st = limn_mesh_read(ctx, path, LIMN_FORMAT_AUTO, &o->m);
    const char *w = limn_context_warnings(ctx);
    snprintf(o->msg, sizeof o->msg, "%s", limn_context_message(ctx));
    snprintf(o->warn, sizeof o->warn, "%s", w ? w : "");
    limn_context_destroy(ctx);
    unsetenv("LIMN_TEST_PLY_GENERAL");
}

/* Reads path with the fast path allowed and with the general reader only:
   the same status, message, warnings and mesh. Returns the fast read's
   progress calls, and the general one's in *general_progress. */
static int both_ways(const char *path, size_t max_memory, int threads, limn_status *st,
                     int *general_progress)
{
    static outcome a, b;
    read_way(path, 0, max_memory, threads, &a);
    read_way(path, 1, max_memory, threads, &b);
    if (a.st != b.st || strcmp(a.msg, b.msg) != 0 || strcmp(a.warn, b.warn) != 0)
        fail_msg("%s: fast path %s '%s' [%s]; general reader %s '%s' [%s]", path,
                 limn_status_name(a.st), a.msg, a.warn, limn_status_name(b.st), b.msg, b.warn);
    snprintf(last_message, sizeof last_message, "%s", a.msg);
    if (a.m)
        test_assert_same_mesh(a.m, b.m);
    limn_mesh_destroy(a.m);
    limn_mesh_destroy(b.m);
    if (st)
        *st = a.st;
    if (general_progress)
        *general_progress = b.progress;
    return a.progress;
}

static void shared_meshes(void **state)
{
    (void)state;
    static const char *const subs[] = {"small", "medium", "large"};
    size_t seen = 0;
    for (size_t s = 0; s < 3; s++) {
        const char *names[256];
        size_t n = test_list_meshes(subs[s], names, 256);
        for (size_t i = 0; i < n; i++) {
            size_t len = strlen(names[i]);
            if (len < 4 || strcmp(names[i] + len - 4, ".ply") != 0)
                continue;
            limn_status st;
            both_ways(test_shared_path(names[i]), 0, 0, &st, NULL);
            assert_int_equal(st, LIMN_OK);
            seen++;
        }
    }
    if (!seen)
        print_message("no shared PLY meshes (LIMN_SHARED_MESHES): generated files only\n");
}

static const char *const count_types[] = {"uchar", "ushort", "uint", "int", "char", "uint8"};
static const char *const index_types[] = {"int", "uint", "ushort", "int32", "uint32"};

/* Layout number i of the generated ones (every field cycles). */
static spec layout(int i)
{
    spec s = {i & 1, i >> 1 & 1, count_types[i % 6], index_types[i % 5], i % 3, i % 4 == 1,
              i % 5 == 2, i % 7 == 3, i % 3 == 1, i % 4 == 3, 12, BAD_NONE};
    return s;
}

static void layouts(void **state)
{
    (void)state;
    for (int i = 0; i < 60; i++) {
        spec s = layout(i);
        size_t header, len;
        limn_status st;
        both_ways(generate(&s, &header, &len), 0, 0, &st, NULL);
        if (st != LIMN_OK)
            fail_msg("layout %d does not read: %s", i, last_message);
    }
}

/* Corrupt data and truncated files: the general reader's refusals, both ways. */
static void corrupt(void **state)
{
    (void)state;
    for (int i = 0; i < 6; i++)
        for (int bad = BAD_NONE; bad < BAD_COUNT; bad++) {
            spec s = layout(i * 7);
            s.bad = bad;
            size_t header, len;
            limn_status st;
            const char *path = generate(&s, &header, &len);
            both_ways(path, 0, 0, &st, NULL);
            assert_true(bad == BAD_NONE || bad == BAD_TRAILING ? st == LIMN_OK : st != LIMN_OK);
            if (bad != BAD_NONE)
                continue;
            size_t n;
            char *all = test_slurp(path, &n);
            assert_non_null(all);
            size_t cuts[] = {header, header + 1, header + (len - header) / 3,
                             header + (len - header) / 2, len - 5, len - 1};
            for (size_t c = 0; c < sizeof cuts / sizeof *cuts; c++) {
                both_ways(test_write_bytes(path, all, cuts[c]), 0, 0, &st, NULL);
                assert_int_not_equal(st, LIMN_OK);
            }
            free(all);
        }
}

/* Vertices only (no face element), with another element after them. */
static void no_faces(void **state)
{
    (void)state;
    static const char head[] = "ply\nformat binary_little_endian 1.0\nelement vertex 2\n"
                               "property float x\nproperty float y\nproperty float z\n"
                               "element flag 1\nproperty uchar f\nend_header\n";
    unsigned char file[sizeof head - 1 + 25] = {0};
    memcpy(file, head, sizeof head - 1);
    file[sizeof head - 1 + 3] = 0x3f; /* x of the first vertex: 0.5 */
    limn_status st;
    for (size_t cut = sizeof file; cut >= sizeof file - 1; cut--) {
        both_ways(test_write_bytes(test_join(dir, "nofaces.ply"), file, cut), 0, 0, &st, NULL);
        assert_int_equal(st, cut == sizeof file ? LIMN_OK : LIMN_ERR_FORMAT);
    }
}

/* Under a memory limit the fast path gives way and the general reader's
   message stands. */
static void memory_limit(void **state)
{
    (void)state;
    spec s = layout(5);
    s.n = 80;
    size_t header, len;
    const char *path = generate(&s, &header, &len);
    int refused = 0, read = 0;
    for (size_t limit = 66000; limit < 700000; limit += 7919) {
        limn_status st;
        both_ways(path, limit, 0, &st, NULL);
        refused += st == LIMN_ERR_MEMORY;
        read += st == LIMN_OK;
    }
    assert_true(refused > 0 && read > 0);
}

/* A file large enough for several ranges: the same mesh for 1 to 7 threads,
   and the fast path did read it (progress once an element, not every
   buffer). */
static void threads_and_engaged(void **state)
{
    (void)state;
    spec s = {0, 1, "uchar", "int", 2, 1, 1, 0, 1, 0, 700, BAD_NONE};
    size_t header, len;
    const char *path = generate(&s, &header, &len);
    static const int threads[] = {1, 2, 4, 7};
    for (size_t i = 0; i < sizeof threads / sizeof *threads; i++) {
        limn_status st;
        int general = 0, fast = both_ways(path, 0, threads[i], &st, &general);
        assert_int_equal(st, LIMN_OK);
        if (fast > 3 || general <= 20)
            fail_msg("progress calls: fast path %d, general reader %d", fast, general);
    }
}

static int setup(void **state)
{
    (void)state;
    return test_make_dir(dir, sizeof dir, "ply_fast");
}

static int teardown(void **state)
{
    (void)state;
    return test_remove_dir(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(shared_meshes),
        cmocka_unit_test(layouts),
        cmocka_unit_test(corrupt),
        cmocka_unit_test(no_faces),
        cmocka_unit_test(memory_limit),
        cmocka_unit_test(threads_and_engaged),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
