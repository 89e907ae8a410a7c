/* SPDX-License-Identifier: MIT */
/*
 * The slice reader (host/mesh/io/mesh_slice*.c, issue 14 item 1) against the
 * whole-file reader: for P in {1, 2, 3, 5, 7} the parts are read in turn in
 * this process (phase 1 for every part, the counts prefix-summed, phase 2)
 * and their concatenation must be limn_mesh_read's positions, face offsets
 * and indices bit for bit, with contiguous blocks and the file's totals.
 * Files: every shared mesh as it is and written by limn as binary PLY (LE,
 * BE, float32 with `uchar int` lists), ASCII PLY, OBJ and OFF; a mixed
 * polygon mesh (variable face lists); hand-made files for when ../shared is
 * absent (negative OBJ indices, forward references, comments, CRLF, a byte
 * order mark, no final newline, extra vertex properties and elements, the
 * face element first, short index types, an empty face block, more parts
 * than vertices). The split input round trip, and bad files: each gives an
 * error naming the file and the element on every part that meets it.
 */
#include "shell.h"
#include "support.h"
#include "mesh/io/mesh_slice.h"
#include "mesh/mesh.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

static char dir[64];
static const unsigned part_counts[] = {1, 2, 3, 5, 7};
#define MAX_PARTS 7

/* All parts of path read in turn; the first failure's status and message. */
static limn_status read_parts(limn_context *ctx, const char *path, unsigned parts,
                              mesh_slice *s)
{
    mesh_slice_counts c[MAX_PARTS], before, total;
    memset(&total, 0, sizeof total);
    memset(s, 0, parts * sizeof *s);
    for (unsigned p = 0; p < parts; p++) {
        limn_status st = mesh_slice_count(ctx, path, LIMN_FORMAT_AUTO, p, parts, &c[p]);
        if (st)
            return st;
        mesh_slice_counts_add(&total, &c[p]);
    }
    memset(&before, 0, sizeof before);
    for (unsigned p = 0; p < parts; p++) {
        limn_status st = mesh_slice_read(ctx, path, LIMN_FORMAT_AUTO, p, parts, &before, &total, &s[p]);
        if (st)
            return st;
        mesh_slice_counts_add(&before, &c[p]);
    }
    return LIMN_OK;
}

static void free_parts(mesh_slice *s, unsigned parts)
{
    for (unsigned p = 0; p < parts; p++)
        mesh_slice_free(&s[p]);
}

/* The parts' concatenation is m (bit for bit), in contiguous blocks. */
static void assert_concat(const char *what, const limn_mesh *m, const mesh_slice *s,
                          unsigned parts)
{
    size_t v = 0, f = 0;
    for (unsigned p = 0; p < parts; p++) {
        const mesh_slice *q = &s[p];
        if (q->vertex_total != m->vertex_count || q->face_total != m->face_count ||
            q->vertex_begin != v || q->face_begin != f ||
            v + q->vertex_count > m->vertex_count || f + q->face_count > m->face_count)
            fail_msg("%s, part %u of %u: vertices [%zu, +%zu) of %zu, faces [%zu, +%zu) of %zu; "
                     "expected to start at %zu and %zu of %zu and %zu", what, p, parts,
                     q->vertex_begin, q->vertex_count, q->vertex_total, q->face_begin,
                     q->face_count, q->face_total, v, f, m->vertex_count, m->face_count);
        if (q->vertex_count &&
            memcmp(q->positions, m->positions + 3 * v, q->vertex_count * 24) != 0)
            fail_msg("%s, part %u of %u: positions differ", what, p, parts);
        const uint32_t *off = m->face_offsets + f;
        assert_int_equal(q->face_offsets[0], 0);
        for (size_t k = 0; k < q->face_count; k++)
            if (q->face_offsets[k + 1] != off[k + 1] - off[0])
                fail_msg("%s, part %u of %u: face %zu's offset differs", what, p, parts, f + k);
        size_t n = q->face_offsets[q->face_count];
        if (n && memcmp(q->face_indices, m->face_indices + off[0], n * 4) != 0)
            fail_msg("%s, part %u of %u: face indices differ", what, p, parts);
        v += q->vertex_count;
        f += q->face_count;
    }
    if (v != m->vertex_count || f != m->face_count)
        fail_msg("%s, %u parts: %zu vertices and %zu faces in all, the file has %zu and %zu",
                 what, parts, v, f, m->vertex_count, m->face_count);
}

/* path read whole and in 1, 2, 3, 5 and 7 parts: the same mesh. */
static void check_file(const char *path)
{
    limn_context *ctx = limn_context_create();
    limn_mesh *m = NULL;
    if (limn_mesh_read(ctx, path, LIMN_FORMAT_AUTO, &m) != LIMN_OK)
        fail_msg("%s: %s", path, limn_context_message(ctx));
    for (size_t i = 0; i < sizeof part_counts / sizeof *part_counts; i++) {
        mesh_slice s[MAX_PARTS];
        limn_status st = read_parts(ctx, path, part_counts[i], s);
        if (st)
            fail_msg("%s in %u parts: %s", path, part_counts[i], limn_context_message(ctx));
        assert_concat(path, m, s, part_counts[i]);
        free_parts(s, part_counts[i]);
    }
    limn_mesh_destroy(m);
    limn_context_destroy(ctx);
}

/* path in every part count fails, each time with a message holding each of
   the words (NULL-terminated). */
static void check_fails(const char *path, ...)
{
    limn_context *ctx = limn_context_create();
    for (size_t i = 0; i < sizeof part_counts / sizeof *part_counts; i++) {
        mesh_slice s[MAX_PARTS];
        limn_status st = read_parts(ctx, path, part_counts[i], s);
        free_parts(s, part_counts[i]);
        if (st == LIMN_OK)
            fail_msg("%s in %u parts: read, but it should fail", path, part_counts[i]);
        const char *msg = limn_context_message(ctx);
        va_list ap;
        va_start(ap, path);
        for (const char *w = path; w; w = va_arg(ap, const char *))
            if (!strstr(msg, w))
                fail_msg("%s in %u parts: the message '%s' lacks '%s'", path, part_counts[i],
                         msg, w);
        va_end(ap);
    }
    limn_context_destroy(ctx);
}

/* ----------------------------------------------------- written formats */

/* m written in every format the slice reader takes, each file checked. */
static void check_written(const limn_mesh *m)
{
    static const struct { limn_format format; const char *name; int single; } out[] = {
        {LIMN_FORMAT_PLY, "w_le.ply", 0},       {LIMN_FORMAT_PLY_BINARY_BE, "w_be.ply", 0},
        {LIMN_FORMAT_PLY, "w_f32.ply", 1},      {LIMN_FORMAT_PLY_ASCII, "w_ascii.ply", 0},
        {LIMN_FORMAT_OBJ, "w.obj", 0},          {LIMN_FORMAT_OFF, "w.off", 0},
    };
    limn_context *ctx = limn_context_create();
    for (size_t i = 0; i < sizeof out / sizeof *out; i++) {
        limn_write_options o;
        limn_write_options_default(&o);
        o.precision = out[i].single ? LIMN_OUTPUT_FLOAT : LIMN_OUTPUT_DOUBLE;
        const char *path = test_join(dir, out[i].name);
        if (limn_mesh_write_with(ctx, m, path, out[i].format, &o, NULL) != LIMN_OK)
            fail_msg("%s: %s", path, limn_context_message(ctx));
        check_file(path);
    }
    limn_context_destroy(ctx);
}

static void shared_meshes(void **state)
{
    (void)state;
    static const char *const subs[] = {"small", "medium", "large", "opensubdiv"};
    size_t seen = 0;
    for (size_t s = 0; s < sizeof subs / sizeof *subs; s++) {
        const char *names[256];
        size_t n = test_list_meshes(subs[s], names, 256);
        for (size_t i = 0; i < n; i++) {
            const char *path = test_shared_path(names[i]);
            limn_context *ctx = limn_context_create();
            limn_mesh *m = NULL;
            if (limn_mesh_read(ctx, path, LIMN_FORMAT_AUTO, &m) != LIMN_OK) {
                limn_context_destroy(ctx);
                continue;
            }
            if (strstr(names[i], "tristrips"))
                check_fails(path, "triangle strips", NULL);
            else
                check_file(path);
            check_written(m);
            seen++;
            limn_mesh_destroy(m);
            limn_context_destroy(ctx);
        }
    }
    if (!seen)
        print_message("no shared meshes (LIMN_SHARED_MESHES): generated and hand-made files "
                      "only\n");
    else
        print_message("%zu shared meshes, each as it is and in 6 written forms\n", seen);
}

/* Triangles, quads, pentagons and a hexagon: variable face lists. */
static limn_mesh *mixed_mesh(limn_context *ctx)
{
    enum { NX = 9, NY = 7 };
    double pos[3 * (NX + 1) * (NY + 1)];
    uint32_t off[NX * NY * 2 + 1], idx[NX * NY * 8];
    size_t nf = 0, ni = 0;
    for (int y = 0; y <= NY; y++)
        for (int x = 0; x <= NX; x++) {
            double *p = pos + 3 * (y * (NX + 1) + x);
            p[0] = x + 0.1 * y;
            p[1] = y * 1.25;
            p[2] = 0.03 * x * y;
        }
    off[0] = 0;
    for (int y = 0; y < NY; y++)
        for (int x = 0; x < NX; x++) {
            uint32_t a = (uint32_t)(y * (NX + 1) + x), b = a + 1, c = b + NX + 1, d = a + NX + 1;
            if ((x + y) % 3 == 0) { /* two triangles */
                uint32_t t[6] = {a, b, c, a, c, d};
                memcpy(idx + ni, t, sizeof t);
                ni += 6;
                off[++nf] = (uint32_t)ni - 3;
                off[++nf] = (uint32_t)ni;
            } else {
                uint32_t q[4] = {a, b, c, d};
                memcpy(idx + ni, q, sizeof q);
                ni += 4;
                off[++nf] = (uint32_t)ni;
            }
        }
    limn_mesh *m = NULL;
    assert_int_equal(limn_mesh_create(ctx, (NX + 1) * (NY + 1), pos, nf, off, idx, &m),
                     LIMN_OK);
    return m;
}

static void generated(void **state)
{
    (void)state;
    limn_context *ctx = limn_context_create();
    limn_mesh *meshes[] = {mixed_mesh(ctx), test_mesh_cube(ctx), test_mesh_pyramid(ctx),
                           test_mesh_fan(ctx, 5, 1), test_mesh_grid(ctx, 13, 11, 1)};
    for (size_t i = 0; i < sizeof meshes / sizeof *meshes; i++) {
        check_written(meshes[i]);
        limn_mesh_destroy(meshes[i]);
    }
    limn_context_destroy(ctx);
}

/* ---------------------------------------------------------- hand-made files */

static const char *text_file(const char *name, const char *text)
{
    return test_write_bytes(test_join(dir, name), text, strlen(text));
}

static void hand_text(void **state)
{
    (void)state;
    /* negative and forward references, texture/normal forms, comments, records
       limn skips, an unknown record, a line without a final newline */
    check_file(text_file("a.obj", "# hand-made\nv 0 0 0\nv 1 0 0\nvt 0 0\nv 1 1 0\n"
                                  "f 1/1 2/1 -1/1\nf 4 -2 -3\nv 0 1 0\n\n  v 0.5 0.5 1e-3 1\n"
                                  "o x\nf -5//1 -4//1 -3//1 -2//1\nusemtl q\nfoo bar\n"
                                  "f 5 4 3\nv 2 2 2\nf -1 1 2"));
    /* CRLF, tabs, a byte order mark */
    check_file(text_file("crlf.obj", "\xEF\xBB\xBFv 0 0 0\r\nv 1 0 0\r\n\tv 0 1 0\r\n"
                                     "v 1 1 1\r\nf 1 2 3\r\nf 2 4 3\r\n"));
    /* vertices only: an empty face block */
    check_file(text_file("nofaces.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n"));
    /* OFF: counts on the header line, comments, blank lines, colours, CRLF */
    check_file(text_file("a.off", "OFF 5 3 0\n# c\n0 0 0\n1 0 0 # x\n\n1 1 0\n0 1 0\n"
                                  "0.5 0.5 1\n3 0 1 4\n4 0 1 2 3\n3 2 3 4\n"));
    check_file(text_file("c.off", "COFF\r\n4 2 0\r\n0 0 0 255 0 0 255\r\n1 0 0 0 255 0 255\r\n"
                                  "1 1 0 0 0 255 255\r\n0 1 0 9 9 9 255\r\n3 0 1 2\r\n"
                                  "3 0 2 3\r\n"));
    check_file(text_file("nofaces.off", "OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n"));
    /* ASCII PLY: extra properties, the face element first, colours */
    check_file(text_file("a.ply", "ply\nformat ascii 1.0\ncomment x\nelement face 2\n"
                                  "property uchar flags\nproperty list uchar int vertex_indices\n"
                                  "element vertex 4\nproperty float x\nproperty float y\n"
                                  "property float z\nproperty uchar red\nproperty uchar green\n"
                                  "property uchar blue\nproperty float confidence\nend_header\n"
                                  "7 3 0 1 2\n7 4 0 2 3 1\n0 0 0 1 2 3 0.5\n1 0 0 1 2 3 0.5\n"
                                  "1 1 0 1 2 3 0.5\n0 1 0 1 2 3 0.5\n"));
}

/* A binary PLY built byte by byte: big endian, an element before the
   vertices, a short count and index type, scalars around the list, extra
   vertex properties. */
static void put(unsigned char **o, uint64_t v, unsigned n, int big)
{
    for (unsigned i = 0; i < n; i++)
        (*o)[i] = (unsigned char)(v >> 8 * (big ? n - 1 - i : i));
    *o += n;
}

static const char *binary_file(const char *name, int big, int faces, const int *counts,
                               uint32_t bad_index)
{
    unsigned char buf[8192], *o = buf;
    o += sprintf((char *)o,
                 "ply\nformat binary_%s_endian 1.0\nelement camera 2\nproperty short a\n"
                 "element vertex 6\nproperty uchar tag\nproperty float x\nproperty double y\n"
                 "property short z\nproperty float quality\nelement face %d\nproperty ushort f0\n"
                 "property list ushort short vertex_indices\nproperty uchar f1\nend_header\n",
                 big ? "big" : "little", faces);
    put(&o, 1, 2, big);
    put(&o, 2, 2, big);
    for (int v = 0; v < 6; v++) {
        float x = (float)v * 0.3f, q = 1.0f;
        double y = v * 1.7 - 0.1;
        uint32_t u;
        uint64_t w;
        memcpy(&u, &x, 4);
        memcpy(&w, &y, 8);
        put(&o, (uint64_t)v, 1, big);
        put(&o, u, 4, big);
        put(&o, w, 8, big);
        put(&o, (uint64_t)(v * 3), 2, big);
        memcpy(&u, &q, 4);
        put(&o, u, 4, big);
    }
    for (int f = 0; f < faces; f++) {
        put(&o, 9, 2, big);
        put(&o, (uint64_t)counts[f], 2, big);
        for (int k = 0; k < counts[f]; k++)
            put(&o, f == faces - 1 && k == 1 && bad_index ? bad_index
                                                          : (uint64_t)((f + k) % 6), 2, big);
        put(&o, 5, 1, big);
    }
    return test_write_bytes(test_join(dir, name), buf, (size_t)(o - buf));
}

static void hand_binary(void **state)
{
    (void)state;
    static const int fixed[] = {3, 3, 3, 3, 3}, mixed[] = {3, 4, 5, 3, 6};
    for (int big = 0; big < 2; big++) {
        check_file(binary_file("fixed.ply", big, 5, fixed, 0));
        check_file(binary_file("mixed.ply", big, 5, mixed, 0));
        check_file(binary_file("noface.ply", big, 0, fixed, 0));
        check_fails(binary_file("bad.ply", big, 5, mixed, 6), "bad.ply", "byte", "face 4",
                    "references vertex 6", NULL);
        check_fails(binary_file("badfixed.ply", big, 5, fixed, 9), "badfixed.ply", "face 4",
                    "references vertex 9", NULL);
    }
}

/* ------------------------------------------------------------ bad files */

static void truncate_file(const char *path, size_t drop)
{
    size_t n;
    char *b = test_slurp(path, &n);
    assert_non_null(b);
    test_write_bytes(path, b, n - drop);
    free(b);
}

static void bad_files(void **state)
{
    (void)state;
    check_fails(text_file("big.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 4\n"),
                "big.obj:5:", "references vertex 4", NULL);
    check_fails(text_file("neg.obj", "v 0 0 0\nv 1 0 0\nf -1 -2 -3\nv 0 1 0\n"), "neg.obj:3:",
                "face 0", NULL);
    check_fails(text_file("cont.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 \\\n3\n"),
                "cont.obj:4:", "continuation", NULL);
    check_fails(text_file("novert.obj", "# nothing\n"), "novert.obj", "no vertices", NULL);
    check_fails(text_file("big.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n"),
                "big.off:6:", "face 0", "3 vertices", NULL);
    check_fails(text_file("short.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n1 1 1\n3 0 1 2\n"
                                        "# a comment longer than the face it replaces\n"),
                "short.off", "truncated", NULL);
    check_fails(text_file("nan.off", "OFF\n3 1 0\n0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n"),
                "nan.off:4:", "vertex 1", NULL);
    check_fails(text_file("cr.obj", "v 0 0 0\rv 1 0 0\nv 0 1 0\nf 1 2 3\n"), "cr.obj:1:",
                "carriage return", NULL);
    check_fails(text_file("a.stl", "solid x\nendsolid x\n"), "a.stl", "STL", NULL);
    check_fails(text_file("strips.ply", "ply\nformat binary_little_endian 1.0\n"
                                        "element vertex 0\nproperty float x\nproperty float y\n"
                                        "property float z\nelement tristrips 1\n"
                                        "property list int int vertex_indices\nend_header\n"),
                "strips.ply", NULL);
    /* a variable face block cut short, and a fixed one */
    static const int mixed[] = {3, 4, 5, 3, 6}, fixed[] = {3, 3, 3, 3, 3};
    const char *p = binary_file("cut.ply", 0, 5, mixed, 0);
    truncate_file(p, 3);
    check_fails(p, "cut.ply", NULL);
    p = binary_file("cutfixed.ply", 1, 5, fixed, 0);
    truncate_file(p, 2);
    check_fails(p, "cutfixed.ply", NULL);
    /* a non-finite coordinate */
    limn_context *ctx = limn_context_create();
    limn_mesh *m = test_mesh_cube(ctx);
    const char *q = test_join(dir, "inf.ply");
    assert_int_equal(limn_mesh_write(ctx, m, q, LIMN_FORMAT_PLY), LIMN_OK);
    size_t n;
    char *b = test_slurp(q, &n);
    const char *body = strstr(b, "end_header\n") + 11;
    double inf = 1e308 * 10;
    memcpy(b + (body - b) + 5 * 24 + 8, &inf, 8); /* vertex 5's y (little endian host) */
    test_write_bytes(q, b, n);
    free(b);
    check_fails(q, "inf.ply", "vertex 5", "not finite", NULL);
    limn_mesh_destroy(m);
    limn_context_destroy(ctx);
}

/* --------------------------------------------------------------- memory */

/* Each part holds its share only: under a memory limit (the readers' own
   accounting, limn_context_set_max_memory) of twice the largest part's
   arrays plus the 64 KiB read buffer, the whole-file reader fails and every
   part of 7 is read, in every format. */
static void memory_share(void **state)
{
    (void)state;
    enum { P = 7 };
    static const limn_format formats[] = {LIMN_FORMAT_PLY, LIMN_FORMAT_PLY_ASCII,
                                          LIMN_FORMAT_OBJ, LIMN_FORMAT_OFF};
    static const char *const names[] = {"mem.ply", "mem_ascii.ply", "mem.obj", "mem.off"};
    limn_context *ctx = limn_context_create();
    limn_mesh *m = test_mesh_grid(ctx, 120, 100, 1);
    size_t share = 0;
    for (unsigned p = 0; p < P; p++) {
        mesh_slice s;
        assert_int_equal(mesh_slice_of(ctx, m, p, P, &s), LIMN_OK);
        size_t bytes = s.vertex_count * 24 + (s.face_count + 1) * 4 +
                       s.face_offsets[s.face_count] * 4;
        share = bytes > share ? bytes : share;
        mesh_slice_free(&s);
    }
    size_t limit = 2 * share + 65536 + 4096;
    print_message("%zu vertices, %zu faces: the limit %zu bytes, a part's arrays %zu\n",
                  m->vertex_count, m->face_count, limit, share);
    for (size_t i = 0; i < sizeof formats / sizeof *formats; i++) {
        const char *path = test_join(dir, names[i]);
        assert_int_equal(limn_mesh_write(ctx, m, path, formats[i]), LIMN_OK);
        limn_context *lim = limn_context_create();
        limn_context_set_max_memory(lim, limit);
        limn_mesh *whole = NULL;
        assert_int_equal(limn_mesh_read(lim, path, LIMN_FORMAT_AUTO, &whole), LIMN_ERR_MEMORY);
        mesh_slice s[P];
        if (read_parts(lim, path, P, s) != LIMN_OK)
            fail_msg("%s: %s", path, limn_context_message(lim));
        limn_mesh *back = NULL;
        assert_int_equal(limn_mesh_read(ctx, path, LIMN_FORMAT_AUTO, &back), LIMN_OK);
        assert_concat(path, back, s, P);
        free_parts(s, P);
        limn_mesh_destroy(back);
        /* and a limit below one part's arrays is refused by the parts too */
        limn_context_set_max_memory(lim, 65536 + share / 4);
        assert_int_equal(read_parts(lim, path, P, s), LIMN_ERR_MEMORY);
        free_parts(s, P);
        limn_context_destroy(lim);
    }
    limn_mesh_destroy(m);
    limn_context_destroy(ctx);
}

/* ----------------------------------------------------------- split input */

static void split_round_trip(void **state)
{
    (void)state;
    limn_context *ctx = limn_context_create();
    limn_mesh *meshes[] = {mixed_mesh(ctx), test_mesh_icosahedron(ctx), test_mesh_pyramid(ctx)};
    char name[4096];
    snprintf(name, sizeof name, "%s", test_join(dir, "split.ply"));
    for (size_t i = 0; i < sizeof meshes / sizeof *meshes; i++)
        for (size_t k = 0; k < sizeof part_counts / sizeof *part_counts; k++) {
            unsigned parts = part_counts[k];
            mesh_slice s[MAX_PARTS];
            char path[4096];
            for (unsigned p = 0; p < MAX_PARTS + 1; p++)
                if (mesh_slice_split_name(name, p, path, sizeof path))
                    unlink(path);
            for (unsigned p = 0; p < parts; p++) {
                assert_int_equal(mesh_slice_of(ctx, meshes[i], p, parts, &s[p]), LIMN_OK);
                assert_int_equal(mesh_slice_write_split(ctx, name, p, parts, &s[p]), LIMN_OK);
                mesh_slice_free(&s[p]);
            }
            for (unsigned p = 0; p < parts; p++)
                if (mesh_slice_read_split(ctx, name, p, parts, &s[p]) != LIMN_OK)
                    fail_msg("part %u of %u: %s", p, parts, limn_context_message(ctx));
            assert_concat("split input", meshes[i], s, parts);
            free_parts(s, parts);
            if (parts < 3)
                continue;
            /* read as fewer parts, a missing part, the parts swapped */
            mesh_slice t;
            assert_int_equal(mesh_slice_read_split(ctx, name, 1, parts - 1, &t), LIMN_ERR_FORMAT);
            assert_non_null(strstr(limn_context_message(ctx), "disagree"));
            char a[4096], b[4096];
            assert_true(mesh_slice_split_name(name, 0, a, sizeof a));
            assert_true(mesh_slice_split_name(name, 1, b, sizeof b));
            assert_int_equal(rename(a, test_join(dir, "swap.ply")), 0);
            assert_int_equal(rename(b, a), 0);
            assert_int_equal(mesh_slice_read_split(ctx, name, 0, parts, &t), LIMN_ERR_FORMAT);
            assert_non_null(strstr(limn_context_message(ctx), "part 1 of"));
            if (mesh_slice_read_split(ctx, name, 1, parts, &t) != LIMN_ERR_IO ||
                !strstr(limn_context_message(ctx), ".r1.ply"))
                fail_msg("a missing part: %s", limn_context_message(ctx));
            assert_null(t.positions);
        }
    for (size_t i = 0; i < sizeof meshes / sizeof *meshes; i++)
        limn_mesh_destroy(meshes[i]);
    /* a plain PLY is not a part */
    mesh_slice t;
    limn_mesh *m = test_mesh_cube(ctx);
    char path[4096];
    assert_true(mesh_slice_split_name(test_join(dir, "plain"), 0, path, sizeof path));
    assert_int_equal(limn_mesh_write(ctx, m, path, LIMN_FORMAT_PLY), LIMN_OK);
    assert_int_equal(mesh_slice_read_split(ctx, test_join(dir, "plain"), 0, 1, &t),
                     LIMN_ERR_FORMAT);
    assert_non_null(strstr(limn_context_message(ctx), "limn-slice"));
    limn_mesh_destroy(m);
    limn_context_destroy(ctx);
}

static int setup(void **state)
{
    (void)state;
    return test_make_dir(dir, sizeof dir, "mesh_slice");
}
static int teardown(void **state)
{
    (void)state;
    return test_remove_dir(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(hand_text),      cmocka_unit_test(hand_binary),
        cmocka_unit_test(bad_files),      cmocka_unit_test(generated),
        cmocka_unit_test(split_round_trip), cmocka_unit_test(memory_share),
        cmocka_unit_test(shared_meshes),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
