/* SPDX-License-Identifier: MIT */
/* Mesh file readers and writers: real files, round trips, malformed input,
   atomic writes. Real meshes come from $LIMN_SHARED_MESHES (default
   /work/shared/meshes); tests that need them are skipped when it is absent. */
#ifndef _POSIX_C_SOURCE
#define _POSIX_C_SOURCE 200809L
#endif
#include <dirent.h>
#include <errno.h>
#include <setjmp.h>
#include <signal.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include <cmocka.h>

#include "fixture.h"
#include "limn.h"
#include "shell.h"

static limn_context *ctx;

/* ----------------------------------------------------------------- helpers */

static const char *shared(void)
{
    const char *d = getenv("LIMN_SHARED_MESHES");
    return d && *d ? d : "/work/shared/meshes";
}

static int shared_present(void)
{
    struct stat st;
    return stat(shared(), &st) == 0 && S_ISDIR(st.st_mode);
}

static char *fmt(const char *f, ...)
{
    static char buf[8][4096];
    static int slot;
    char *b = buf[slot++ % 8];
    va_list ap;
    va_start(ap, f);
    vsnprintf(b, sizeof buf[0], f, ap);
    va_end(ap);
    return b;
}

static const char *tmp_path(const char *name) { return fmt("%s/%s", test_dir, name); }

static const char *write_bytes(const char *name, const void *data, size_t n)
{
    return test_write_bytes(tmp_path(name), data, n);
}

static const char *write_text(const char *name, const char *text)
{
    return write_bytes(name, text, strlen(text));
}

static int count_entries(const char *dir)
{
    DIR *d = opendir(dir);
    if (!d)
        return -1;
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d)))
        if (strcmp(e->d_name, ".") && strcmp(e->d_name, ".."))
            n++;
    closedir(d);
    return n;
}

static void remove_tree(const char *dir)
{
    DIR *d = opendir(dir);
    if (!d)
        return;
    struct dirent *e;
    while ((e = readdir(d))) {
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, ".."))
            continue;
        char p[4096];
        snprintf(p, sizeof p, "%s/%s", dir, e->d_name);
        struct stat st;
        if (lstat(p, &st) == 0 && S_ISDIR(st.st_mode)) {
            chmod(p, 0755);
            remove_tree(p);
        } else {
            unlink(p);
        }
    }
    closedir(d);
    rmdir(dir);
}

static int setup(void **state)
{
    (void)state;
    umask(022); /* the modes the writers' files are checked against */
    return test_scratch_make("test_mesh_io", &ctx);
}

static int teardown(void **state)
{
    (void)state;
    limn_context_destroy(ctx);
    remove_tree(test_dir);
    return 0;
}

/* Reads a file that must fail with status and a message containing want. */
static void expect_fail(const char *path, limn_status status, const char *want)
{
    limn_mesh *m = (limn_mesh *)&m;
    limn_status st = limn_mesh_read(ctx, path, LIMN_FORMAT_AUTO, &m);
    const char *msg = limn_context_message(ctx);
    if (st != status || !strstr(msg, want))
        print_error("status %s, message \"%s\"; wanted %s with \"%s\"\n", limn_status_name(st),
                    msg, limn_status_name(status), want);
    assert_int_equal(st, status);
    assert_non_null(strstr(msg, want));
    assert_null(m);
}

static limn_mesh *read_ok(const char *path)
{
    limn_mesh *m = NULL;
    limn_status st = limn_mesh_read(ctx, path, LIMN_FORMAT_AUTO, &m);
    if (st)
        print_error("%s\n", limn_context_message(ctx));
    assert_int_equal(st, LIMN_OK);
    assert_non_null(m);
    return m;
}

/* --------------------------------------------------------------- real files */

static void check_real(const char *rel, size_t nv, size_t nf)
{
    if (!shared_present())
        skip();
    limn_mesh *m = read_ok(fmt("%s/%s", shared(), rel));
    assert_int_equal(limn_mesh_vertex_count(m), nv);
    assert_int_equal(limn_mesh_face_count(m), nf);
    limn_mesh_destroy(m);
}

static void test_real_spot(void **s) { (void)s; check_real("small/spot_control_mesh.obj", 188, 180); }
static void test_real_suzanne(void **s) { (void)s; check_real("small/suzanne.obj", 507, 500); }
static void test_real_knight(void **s) { (void)s; check_real("small/decimated-knight.off", 502, 1000); }
static void test_real_bunny(void **s) { (void)s; check_real("medium/bun_zipper.ply", 35947, 69451); }
static void test_real_igea(void **s) { (void)s; check_real("large/igea.ply", 134345, 268686); }

/* The strips decode to igea.ply's faces (same order, each up to rotation). */
static void test_real_tristrips(void **s)
{
    (void)s;
    if (!shared_present())
        skip();
    limn_mesh *a = read_ok(fmt("%s/large/igea.ply", shared()));
    limn_mesh *b = read_ok(fmt("%s/large/igea_tristrips.ply", shared()));
    assert_int_equal(limn_mesh_vertex_count(b), 134345);
    assert_int_equal(limn_mesh_face_count(b), 268686);
    assert_memory_equal(limn_mesh_positions(a), limn_mesh_positions(b), 134345 * 24);
    const uint32_t *x = limn_mesh_face_indices(a), *y = limn_mesh_face_indices(b);
    for (size_t f = 0; f < 268686; f++, x += 3, y += 3) {
        int r = 0;
        while (r < 3 && !(x[0] == y[r] && x[1] == y[(r + 1) % 3] && x[2] == y[(r + 2) % 3]))
            r++;
        assert_true(r < 3);
    }
    limn_mesh_destroy(a);
    limn_mesh_destroy(b);
}

/* Every file listed in stats.jsonl: vertex, face and face-index counts. */
static void test_real_all_stats(void **s)
{
    (void)s;
    if (!shared_present())
        skip();
    size_t n;
    char *text = test_slurp(fmt("%s/stats.jsonl", shared()), &n);
    if (!text)
        skip();
    int files = 0;
    for (char *line = text; line && *line;) {
        char *next = strchr(line, '\n');
        if (next)
            *next++ = '\0';
        char *file = strstr(line, "\"file\": \""), *v = strstr(line, "\"vertices\": ");
        char *f = strstr(line, "\"faces\": "), *deg = strstr(line, "\"face_degrees\": {");
        assert_non_null(file && v && f && deg);
        file += 9;
        *strchr(file, '"') = '\0';
        size_t nv = strtoul(v + 12, NULL, 10), nf = strtoul(f + 9, NULL, 10), ni = 0;
        for (char *p = deg + 17; *p == '"';) {
            unsigned long d = strtoul(p + 1, &p, 10);
            unsigned long c = strtoul(p + 3, &p, 10);
            ni += d * c;
            p += *p == ',' ? 2 : 0;
        }
        limn_mesh *m = read_ok(fmt("%s/%s", shared(), file));
        if (limn_mesh_vertex_count(m) != nv || limn_mesh_face_count(m) != nf)
            print_error("%s\n", file);
        assert_int_equal(limn_mesh_vertex_count(m), nv);
        assert_int_equal(limn_mesh_face_count(m), nf);
        assert_int_equal(limn_mesh_face_offsets(m)[nf], ni);
        limn_mesh_destroy(m);
        files++;
        line = next;
    }
    assert_true(files >= 40);
    free(text);
}

/* --------------------------------------------------------------- round trip */

static limn_mesh *sample_mesh(size_t extra_gon)
{
    /* two quads, a triangle, a pentagon; vertex 4 is unreferenced */
    double pos[3 * 12] = {
        0.1, 1.0 / 3.0, -2.0 / 7.0,   1e300, -1e-300, 4.9e-324,
        3.141592653589793, -0.0, 2.5, 1, 2, 3,
        123456789.123456789, 1e-17, -7,   0.7, 0.2, 0.9,
        5, 5, 5,   6, 6, 6,   7, 8, 9,
        -1, -2, -3,   0.30000000000000004, 2, 1,   8, 8, 8,
    };
    uint32_t offsets[6] = {0, 4, 8, 11, 16, 16};
    uint32_t indices[16 + 400] = {0, 1, 2, 3,  3, 2, 5, 6,  6, 7, 8,  8, 9, 10, 11, 0};
    size_t nf = 4;
    if (extra_gon) {
        for (size_t i = 0; i < extra_gon; i++)
            indices[16 + i] = (uint32_t)(i % 2 ? 11 - i % 5 : i % 4);
        offsets[5] = (uint32_t)(16 + extra_gon);
        nf = 5;
    }
    limn_mesh *m = NULL;
    assert_int_equal(limn_mesh_create(ctx, 12, pos, nf, offsets, indices, &m), LIMN_OK);
    uint8_t rgb[36];
    for (int i = 0; i < 36; i++)
        rgb[i] = (uint8_t)(i * 7 + 3);
    assert_int_equal(limn_mesh_set_colors(ctx, m, rgb), LIMN_OK);
    return m;
}

static void round_trip(const char *name, limn_format format, int keeps_colors, size_t gon)
{
    limn_mesh *a = sample_mesh(gon), *b = NULL;
    char *dir = strdup(tmp_path("rt"));
    assert_int_equal(mkdir(dir, 0755), 0);
    const char *path = fmt("%s/%s", dir, name);
    limn_status st = limn_mesh_write(ctx, a, path, format);
    if (st)
        print_error("%s\n", limn_context_message(ctx));
    assert_int_equal(st, LIMN_OK);
    b = read_ok(path);
    size_t nv = limn_mesh_vertex_count(a), nf = limn_mesh_face_count(a);
    assert_int_equal(limn_mesh_vertex_count(b), nv);
    assert_int_equal(limn_mesh_face_count(b), nf);
    assert_memory_equal(limn_mesh_positions(a), limn_mesh_positions(b), nv * 3 * sizeof(double));
    assert_memory_equal(limn_mesh_face_offsets(a), limn_mesh_face_offsets(b),
                        (nf + 1) * sizeof(uint32_t));
    assert_memory_equal(limn_mesh_face_indices(a), limn_mesh_face_indices(b),
                        limn_mesh_face_offsets(a)[nf] * sizeof(uint32_t));
    if (keeps_colors) {
        assert_non_null(limn_mesh_colors(b));
        assert_memory_equal(limn_mesh_colors(a), limn_mesh_colors(b), nv * 3);
    } else {
        assert_null(limn_mesh_colors(b));
    }
    struct stat sb;
    assert_int_equal(stat(path, &sb), 0);
    assert_int_equal(sb.st_mode & 0777, 0644); /* umask 022 set in setup */
    limn_mesh_destroy(a);
    limn_mesh_destroy(b);
    assert_int_equal(count_entries(dir), 1); /* no temporary file left */
    remove_tree(dir);
    free(dir);
}

static void test_round_trip_obj(void **s) { (void)s; round_trip("rt.obj", LIMN_FORMAT_AUTO, 0, 0); }
static void test_round_trip_ply_le(void **s) { (void)s; round_trip("rt.ply", LIMN_FORMAT_PLY, 1, 0); }
static void test_round_trip_ply_ascii(void **s) { (void)s; round_trip("rt.PLY", LIMN_FORMAT_PLY_ASCII, 1, 0); }
static void test_round_trip_ply_be(void **s) { (void)s; round_trip("rt.ply", LIMN_FORMAT_PLY_BINARY_BE, 1, 0); }
static void test_round_trip_off(void **s) { (void)s; round_trip("rt.off", LIMN_FORMAT_OFF, 0, 0); }
/* a 300-gon needs a uint list count */
static void test_round_trip_big_face(void **s)
{
    (void)s;
    round_trip("big.ply", LIMN_FORMAT_PLY, 1, 300);
    round_trip("big.ply", LIMN_FORMAT_PLY_ASCII, 1, 300);
    round_trip("big.obj", LIMN_FORMAT_OBJ, 0, 300);
    round_trip("big.off", LIMN_FORMAT_OFF, 0, 300);
}

static void test_format_names(void **s)
{
    (void)s;
    limn_format f = LIMN_FORMAT_AUTO;
    assert_true(limn_format_from_name("obj", &f) && f == LIMN_FORMAT_OBJ);
    assert_true(limn_format_from_name("ply", &f) && f == LIMN_FORMAT_PLY);
    assert_true(limn_format_from_name("ply-ascii", &f) && f == LIMN_FORMAT_PLY_ASCII);
    assert_true(limn_format_from_name("ply-be", &f) && f == LIMN_FORMAT_PLY_BINARY_BE);
    assert_true(limn_format_from_name("off", &f) && f == LIMN_FORMAT_OFF);
    assert_true(limn_format_from_name("stl", &f) && f == LIMN_FORMAT_STL);
    assert_false(limn_format_from_name("gltf", &f));
    assert_false(limn_format_from_name(NULL, &f));
    assert_true(limn_format_from_path("a/b.c/Mesh.PLY", &f) && f == LIMN_FORMAT_PLY);
    assert_true(limn_format_from_path("x.Obj", &f) && f == LIMN_FORMAT_OBJ);
    assert_true(limn_format_from_path("x.off", &f) && f == LIMN_FORMAT_OFF);
    assert_false(limn_format_from_path("a.ply/mesh", &f));
    assert_false(limn_format_from_path(".obj", &f));
    assert_true(limn_format_from_path("x.STL", &f) && f == LIMN_FORMAT_STL);
    assert_false(limn_format_from_path("x.glb", &f));
}

/* ----------------------------------------------------------- OBJ features */

static void test_obj_forms(void **s)
{
    (void)s;
    const char *path = write_text(
        "forms.obj",
        "# comment\r\nmtllib x.mtl\r\no thing\r\nv 0 0 0\r\nv 1 0 0 1.0\r\n"
        "v 1 1 0 0.5 0.5 0.5\r\n\r\n   v 0 1 0\r\nvt 0 0\r\nvn 0 0 1\r\ng grp\r\ns off\r\n"
        "usemtl m\r\nf 1/1/1 2/1/1 3/1/1\r\nf -4//1 -2//1 -1//1\r\nf 1/1 3/1 \\\r\n  4/1\r\n"
        "l 1 2\r\np 1\r\nt crease 2/1/0 1 2 1.0\r\nf\t2 3 4");
    limn_mesh *m = read_ok(path);
    assert_int_equal(limn_mesh_vertex_count(m), 4);
    assert_int_equal(limn_mesh_face_count(m), 4);
    const uint32_t want[] = {0, 1, 2, 0, 2, 3, 0, 2, 3, 1, 2, 3};
    assert_memory_equal(limn_mesh_face_indices(m), want, sizeof want);
    assert_true(limn_mesh_positions(m)[4 * 3 - 2] == 1.0);
    limn_mesh_destroy(m);
}

static void test_ply_variants(void **s)
{
    (void)s;
    /* elements out of order, an unknown element with a list, extra vertex
       properties (scalar and list), extra face properties, vertex_index,
       types in both spellings, a tristrips element with degenerate steps */
    unsigned char b[2048];
    size_t n = 0;
    const char *h = "ply\nformat binary_big_endian 1.0\ncomment c\nobj_info o\n"
                    "element face 1\nproperty int16 flags\nproperty list uint8 uint vertex_index\n"
                    "property list uchar float uv\n"
                    "element material 2\nproperty list int short name\nproperty double k\n"
                    "element vertex 5\nproperty uchar confidence\nproperty float32 x\n"
                    "property list uchar int8 junk\nproperty short y\nproperty float64 z\n"
                    "element tristrips 1\nproperty list int int vertex_indices\nend_header\n";
    memcpy(b, h, strlen(h));
    n = strlen(h);
#define PUT(v, k) for (int i_ = (k) - 1; i_ >= 0; i_--) b[n++] = (unsigned char)((uint64_t)(v) >> (8 * i_))
    PUT(7, 2); PUT(3, 1); PUT(4, 4); PUT(0, 4); PUT(2, 4); PUT(1, 1); PUT(0x3f800000, 4);
    for (int k = 0; k < 2; k++) { PUT(2, 4); PUT(1, 2); PUT(2, 2); PUT(0, 8); }
    for (int v = 0; v < 5; v++) {
        PUT(9, 1);
        float fx = (float)v + 0.5f;
        uint32_t u;
        memcpy(&u, &fx, 4);
        PUT(u, 4); PUT(v, 1); for (int i = 0; i < v; i++) PUT(0xff, 1);
        PUT(-v, 2);
        double dz = v * 0.1;
        uint64_t w;
        memcpy(&w, &dz, 8);
        PUT(w, 8);
    }
    /* strip 0 1 2 3 | 4 1 1 0 3 */
    int32_t strip[] = {0, 1, 2, 3, -1, 4, 1, 1, 0, 3};
    PUT(10, 4);
    for (int i = 0; i < 10; i++) PUT((uint32_t)strip[i], 4);
#undef PUT
    limn_mesh *m = read_ok(write_bytes("variants.ply", b, n));
    assert_int_equal(limn_mesh_vertex_count(m), 5);
    const double *p = limn_mesh_positions(m);
    assert_true(p[3 * 4] == 4.5 && p[3 * 4 + 1] == -4.0 && p[3 * 4 + 2] == 4 * 0.1);
    /* face 4 0 2; strips: (0 1 2) (2 1 3); (4 1 1) and (1 1 0) dropped, (1 0 3) */
    const uint32_t want[] = {4, 0, 2, 0, 1, 2, 2, 1, 3, 1, 0, 3};
    assert_int_equal(limn_mesh_face_count(m), 4);
    assert_memory_equal(limn_mesh_face_indices(m), want, sizeof want);
    assert_null(limn_mesh_colors(m));
    limn_mesh_destroy(m);
}

/* --------------------------------------------------------- malformed input */

/* One malformed file: its name, its text and the start of the message. */
struct bad_case {
    const char *name, *text, *message;
};

/* Each file of the table must fail to read as a format error. */
static void expect_format_errors(const struct bad_case *c, size_t n)
{
    for (size_t i = 0; i < n; i++)
        expect_fail(write_text(c[i].name, c[i].text), LIMN_ERR_FORMAT, c[i].message);
}

/* three vertices that a face may reference */
#define V3 "v 0 0 0\nv 1 0 0\nv 0 1 0\n"

static void test_bad_obj(void **s)
{
    (void)s;
    static const struct bad_case cases[] = {
        {"idx.obj", V3 "# c\nf 1 2 12\n",
         "idx.obj:5: face references vertex 12 but only 3 vertices are defined"},
        {"neg.obj", V3 "f -1 -2 -4\n",
         "neg.obj:4: face references vertex -4 but only 3 vertices are defined"},
        {"zero.obj", V3 "f 0 1 2\n", "zero.obj:4: face references vertex 0"},
        {"two.obj", V3 "f 1 2\n", "two.obj:4: face has 2 vertices (at least 3 needed)"},
        {"tok.obj", V3 "f 1 2 3x\n", "tok.obj:4: face: '3x' is not a vertex reference"},
        {"num.obj", "v 0 0 0\nv 1 abc 0\n",
         "num.obj:2: vertex 2: coordinate 'abc' is not a number"},
        {"short.obj", "v 0 0\n", "short.obj:1: vertex 1 has 2 coordinates (3 needed)"},
        {"nan.obj", "v 0 0 0\nv nan 0 0\n", "nan.obj:2: vertex 2: coordinate 'nan' is not finite"},
        {"inf.obj", "v 0 1e999 0\n", "inf.obj:1: vertex 1: coordinate '1e999' is not finite"},
        {"novert.obj", "# nothing\n\ng x\n", "novert.obj: the file defines no vertices"},
    };
    expect_format_errors(cases, sizeof cases / sizeof cases[0]);
}

/* A binary LE header for a vertex (float x,y,z) and face (list uchar int) file. */
static size_t ply_le(unsigned char *b, const char *counts_and_props, unsigned nv)
{
    int n = sprintf((char *)b, "ply\nformat binary_little_endian 1.0\nelement vertex %u\n"
                               "property float x\nproperty float y\nproperty float z\n%s"
                               "end_header\n", nv, counts_and_props);
    memset(b + n, 0, 12 * nv);
    return (size_t)n + 12 * nv;
}

static void test_bad_ply(void **s)
{
    (void)s;
    unsigned char b[4096];
    size_t n = ply_le(b, "element face 2\nproperty list uchar int vertex_indices\n", 3);
    b[n++] = 3; memset(b + n, 0, 12); n += 12;
    b[n++] = 3; memset(b + n, 0, 5); n += 5; /* truncated in face 1's list */
    expect_fail(write_bytes("trunc.ply", b, n), LIMN_ERR_FORMAT,
                "trunc.ply: byte 218: face 1: list count 3 is larger than the rest of the file");
    n = ply_le(b, "element face 2\nproperty list uchar int vertex_indices\nproperty int flags\n", 3);
    b[n++] = 3; memset(b + n, 0, 16); n += 16;
    b[n++] = 3; memset(b + n, 0, 14); n += 14; /* truncated in face 1's flags */
    expect_fail(write_bytes("trunc2.ply", b, n), LIMN_ERR_FORMAT,
                "trunc2.ply: byte 254: face 1: the file ends early (truncated)");

    /* counts far larger than the file: refused before any allocation */
    n = ply_le(b, "element face 1000000000000000000\nproperty list uchar int vertex_indices\n", 3);
    clock_t t0 = clock();
    expect_fail(write_bytes("huge.ply", b, n), LIMN_ERR_FORMAT,
                "huge.ply: the header declares 1000000000000000000 'face' records");
    assert_true((double)(clock() - t0) / CLOCKS_PER_SEC < 0.5);
    n = sprintf((char *)b, "ply\nformat ascii 1.0\nelement vertex 5000000000\nproperty float x\n"
                           "property float y\nproperty float z\nend_header\n0 0 0\n");
    expect_fail(write_bytes("hugev.ply", b, n), LIMN_ERR_FORMAT, "hugev.ply: too many vertices");

    n = sprintf((char *)b, "ply\nformat binary_middle_endian 1.0\nelement vertex 0\nend_header\n");
    expect_fail(write_bytes("fmt.ply", b, n), LIMN_ERR_FORMAT, "fmt.ply:2: bad format line");
    n = sprintf((char *)b, "ply\nformat ascii 2.0\nend_header\n");
    expect_fail(write_bytes("ver.ply", b, n), LIMN_ERR_FORMAT,
                "ver.ply:2: unsupported PLY version '2.0'");
    n = sprintf((char *)b, "ply\nformat ascii 1.0\nelement face 0\n"
                           "property list uchar int vertex_indices\nend_header\n");
    expect_fail(write_bytes("nov.ply", b, n), LIMN_ERR_FORMAT,
                "nov.ply: the header has no 'vertex' element");
    n = sprintf((char *)b, "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                           "property float y\nend_header\n0 0\n");
    expect_fail(write_bytes("noz.ply", b, n), LIMN_ERR_FORMAT,
                "noz.ply: the 'vertex' element has no 'z' property");
    n = sprintf((char *)b, "ply\nformat ascii 1.0\nelement vertex 1\nproperty flt x\nend_header\n");
    expect_fail(write_bytes("type.ply", b, n), LIMN_ERR_FORMAT,
                "type.ply:4: unknown property type 'flt'");
    n = sprintf((char *)b, "ply\nformat ascii 1.0\nelement vertex 1\n");
    expect_fail(write_bytes("noend.ply", b, n), LIMN_ERR_FORMAT,
                "noend.ply:3: the header has no end_header line");
    expect_fail(write_text("magic.ply", "PLY\n"), LIMN_ERR_FORMAT, "magic.ply:1: not a PLY file");

    /* list counts: negative (char count), absurd (int count) */
    n = ply_le(b, "element face 1\nproperty list char int vertex_indices\n", 3);
    b[n++] = 0xfd; memset(b + n, 0, 12); n += 12;
    expect_fail(write_bytes("negc.ply", b, n), LIMN_ERR_FORMAT, "face 0: list count -3 is negative");
    n = ply_le(b, "element face 1\nproperty list int int vertex_indices\n", 3);
    memcpy(b + n, "\x00\xca\x9a\x3b", 4); n += 4; memset(b + n, 0, 12); n += 12;
    expect_fail(write_bytes("absc.ply", b, n), LIMN_ERR_FORMAT,
                "face 0: list count 1000000000 is larger than the rest of the file");
    n = ply_le(b, "element face 1\nproperty list uchar int vertex_indices\n", 3);
    b[n++] = 3; memcpy(b + n, "\0\0\0\0\1\0\0\0\3\0\0\0", 12); n += 12;
    expect_fail(write_bytes("range.ply", b, n), LIMN_ERR_FORMAT,
                "face 0: references vertex 3 but only 3 vertices are defined");
    n = ply_le(b, "element face 1\nproperty list uchar int vertex_indices\n", 3);
    b[n++] = 2; memset(b + n, 0, 8); n += 8;
    expect_fail(write_bytes("f2.ply", b, n), LIMN_ERR_FORMAT,
                "face 0: face has 2 vertices (at least 3 needed)");
    n = ply_le(b, "", 2);
    memcpy(b + n - 4, "\0\0\xc0\x7f", 4); /* NaN */
    expect_fail(write_bytes("nan.ply", b, n), LIMN_ERR_FORMAT, "vertex 1: a coordinate is not finite");

    /* ascii */
    expect_fail(write_text("a.ply", "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\n"
                                    "property float y\nproperty float z\nend_header\n0 0 0\n1 x 1\n"),
                LIMN_ERR_FORMAT, "a.ply:9: vertex 1: coordinate 'x' is not a number");
    expect_fail(write_text("al.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                                     "property float y\nproperty float z\nelement face 1\n"
                                     "property list uchar int vertex_indices\nend_header\n"
                                     "0 0 0\n1 1 1\n2 2 2\n-3 0 1 2\n"),
                LIMN_ERR_FORMAT, "al.ply:13: face 0: -3 is out of range for type uchar");
}

static void test_bad_off(void **s)
{
    (void)s;
    static const struct bad_case cases[] = {
        {"trunc.off", "OFF\n3 1 0\n0.000000 0 0\n1.000000 0 0\n0.000000 1 0\n",
         "trunc.off:5: the file ends after 0 of 1 faces"},
        {"truncv.off", "OFF\n# c\n3 0 0\n0.00000000000000 0 0\n1 0 0.0000000\n",
         "truncv.off:5: the file ends after 2 of 3 vertices"},
        {"neg.off", "OFF\n-3 1 0\n", "neg.off:2: invalid counts: -3 vertices, 1 faces"},
        {"big.off", "OFF 100000000 1 0\n0 0 0\n",
         "big.off:1: the header declares 100000000 vertices and 1 faces"},
        {"cnt.off", "OFF\n3 one 0\n", "cnt.off:2: expected the counts 'vertices faces [edges]'"},
        {"idx.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n",
         "idx.off:6: face 0 references vertex 3 but only 3 vertices"},
        {"few.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4 0 1 2\n",
         "few.off:6: face 0 declares 4 vertices but lists 3"},
        {"hdr.off", "PLY\n", "hdr.off:1: not an OFF file"},
        {"4d.off", "4OFF\n", "4d.off:1: 4OFF and nOFF"},
    };
    expect_format_errors(cases, sizeof cases / sizeof cases[0]);
    /* accepted: counts on the header line, COFF colours, comments, face colours */
    limn_mesh *m = read_ok(write_text("ok.off", "COFF 3 1 # tri\n0 0 0 255 0 0 255\n1 0 0 0 0 0 0\n"
                                                "\n0 1 0 1 1 1 1\n3 0 1 2 0.5 0.5 0.5\n"));
    assert_int_equal(limn_mesh_face_count(m), 1);
    limn_mesh_destroy(m);
}

static void test_bad_files(void **s)
{
    (void)s;
    expect_fail(tmp_path("mesh.3ds"), LIMN_ERR_ARGUMENT, "mesh.3ds");
    assert_non_null(strstr(limn_context_message(ctx), ".obj, .ply, .off, .stl"));
    expect_fail(tmp_path("noext"), LIMN_ERR_ARGUMENT, "accepted: .obj, .ply, .off, .stl");
    expect_fail(tmp_path("missing.obj"), LIMN_ERR_IO,
                fmt("cannot open %s: No such file or directory", tmp_path("missing.obj")));
    expect_fail(write_text("empty.ply", ""), LIMN_ERR_FORMAT, "empty.ply: the file is empty");
    expect_fail(write_text("empty.obj", ""), LIMN_ERR_FORMAT, "empty.obj: the file is empty");
    expect_fail(write_text("empty.off", ""), LIMN_ERR_FORMAT, "empty.off: the file is empty");
    mkdir(tmp_path("dir.obj"), 0755);
    expect_fail(tmp_path("dir.obj"), LIMN_ERR_IO, "it is a directory");
}

/* ------------------------------------------------------------ writer safety */

/* Writer tests run in an empty subdirectory so that leftovers are visible. */
static const char *wdir;
static const char *wpath(const char *name) { return fmt("%s/%s", wdir, name); }

static int writer_setup(void **state)
{
    (void)state;
    wdir = strdup(tmp_path("w"));
    return mkdir(wdir, 0755);
}

static int writer_teardown(void **state)
{
    (void)state;
    remove_tree(wdir);
    free((void *)wdir);
    return 0;
}

static void test_write_missing_dir(void **s)
{
    (void)s;
    limn_mesh *m = sample_mesh(0);
    const char *path = wpath("nodir/out.obj");
    assert_int_equal(limn_mesh_write(ctx, m, path, LIMN_FORMAT_AUTO), LIMN_ERR_IO);
    assert_non_null(strstr(limn_context_message(ctx), path));
    assert_non_null(strstr(limn_context_message(ctx), "No such file or directory"));
    assert_int_equal(access(path, F_OK), -1);
    /* a parent that is a regular file */
    write_text("w/regular", "x");
    path = wpath("regular/out.ply");
    assert_int_equal(limn_mesh_write(ctx, m, path, LIMN_FORMAT_AUTO), LIMN_ERR_IO);
    assert_non_null(strstr(limn_context_message(ctx), "Not a directory"));
    /* a read-only directory (only meaningful when not root) */
    if (geteuid() != 0) {
        mkdir(wpath("ro"), 0555);
        assert_int_equal(limn_mesh_write(ctx, m, wpath("ro/out.off"), LIMN_FORMAT_AUTO),
                         LIMN_ERR_IO);
        assert_int_equal(count_entries(wpath("ro")), 0);
    }
    assert_int_equal(limn_mesh_write(ctx, m, wpath("out.stl"), LIMN_FORMAT_AUTO),
                     LIMN_ERR_ARGUMENT);
    assert_int_equal(limn_mesh_write(ctx, m, wdir, LIMN_FORMAT_OBJ), LIMN_ERR_IO);
    limn_mesh_destroy(m);
    remove_tree(wpath("ro"));
    unlink(wpath("regular"));
    assert_int_equal(count_entries(wdir), 0);
}

static void test_write_replaces(void **s)
{
    (void)s;
    limn_mesh *m = sample_mesh(0);
    const char *path = write_text("w/replace.obj", "old content\n");
    assert_int_equal(limn_mesh_write(ctx, m, path, LIMN_FORMAT_AUTO), LIMN_OK);
    size_t n;
    char *text = test_slurp(path, &n);
    assert_non_null(text);
    assert_non_null(strstr(text, "# limn: 12 vertices, 4 faces\nv 0.10000000000000001 "));
    assert_null(strstr(text, "old content"));
    free(text);
    assert_int_equal(count_entries(wdir), 1);
    limn_mesh_destroy(m);
    unlink(path);
}

/* A write that fails half way (file size limit) leaves the old file and no
   temporary file. */
static void test_write_fails_midway(void **s)
{
    (void)s;
    size_t nv = 20000;
    double *pos = calloc(3 * nv, sizeof(double));
    uint32_t off[1] = {0}, none[1] = {0};
    for (size_t i = 0; i < 3 * nv; i++)
        pos[i] = 1.0 / (double)(i + 3);
    limn_mesh *m = NULL;
    assert_int_equal(limn_mesh_create(ctx, nv, pos, 0, off, none, &m), LIMN_OK);
    free(pos);
    const char *path = write_text("w/keep.ply", "old\n");
    struct rlimit old, small;
    assert_int_equal(getrlimit(RLIMIT_FSIZE, &old), 0);
    small = old;
    small.rlim_cur = 65536;
    void (*prev)(int) = signal(SIGXFSZ, SIG_IGN);
    assert_int_equal(setrlimit(RLIMIT_FSIZE, &small), 0);
    limn_format formats[] = {LIMN_FORMAT_PLY, LIMN_FORMAT_PLY_ASCII, LIMN_FORMAT_OBJ,
                             LIMN_FORMAT_OFF};
    limn_status st[4];
    for (int i = 0; i < 4; i++)
        st[i] = limn_mesh_write(ctx, m, path, formats[i]);
    setrlimit(RLIMIT_FSIZE, &old);
    signal(SIGXFSZ, prev);
    for (int i = 0; i < 4; i++)
        assert_int_equal(st[i], LIMN_ERR_IO);
    assert_non_null(strstr(limn_context_message(ctx), "cannot write"));
    assert_non_null(strstr(limn_context_message(ctx), "keep.ply: File too large"));
    size_t n;
    char *text = test_slurp(path, &n);
    assert_string_equal(text, "old\n");
    free(text);
    assert_int_equal(count_entries(wdir), 1);
    limn_mesh_destroy(m);
    unlink(path);
}

TEST_MAIN(setup, teardown, cmocka_unit_test(test_real_spot), cmocka_unit_test(test_real_suzanne),
          cmocka_unit_test(test_real_knight), cmocka_unit_test(test_real_bunny),
          cmocka_unit_test(test_real_igea), cmocka_unit_test(test_real_tristrips),
          cmocka_unit_test(test_real_all_stats), cmocka_unit_test(test_round_trip_obj),
          cmocka_unit_test(test_round_trip_ply_le), cmocka_unit_test(test_round_trip_ply_ascii),
          cmocka_unit_test(test_round_trip_ply_be), cmocka_unit_test(test_round_trip_off),
          cmocka_unit_test(test_round_trip_big_face), cmocka_unit_test(test_format_names),
          cmocka_unit_test(test_obj_forms), cmocka_unit_test(test_ply_variants),
          cmocka_unit_test(test_bad_obj), cmocka_unit_test(test_bad_ply),
          cmocka_unit_test(test_bad_off), cmocka_unit_test(test_bad_files),
          cmocka_unit_test_setup_teardown(test_write_missing_dir, writer_setup, writer_teardown),
          cmocka_unit_test_setup_teardown(test_write_replaces, writer_setup, writer_teardown),
          cmocka_unit_test_setup_teardown(test_write_fails_midway, writer_setup, writer_teardown))
