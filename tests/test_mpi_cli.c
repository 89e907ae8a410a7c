/* SPDX-License-Identifier: MIT */
/*
 * `mpirun -np N limn ...` as a user meets it (2 and 3 ranks; bands, denoise
 * and sharpen also 5): interpolate (--precision float too), bands, smooth,
 * denoise (eq. 8 and the default SURE form, on slices and the root path),
 * sharpen and morph write the very bytes of one process (paper iteration
 * and series: every row is summed in the same order), weighted, cg and sgs
 * agree to 1e-12 with the same iteration count; --per-rank-output writes
 * one piece per rank; a bad input gives one message, exit status 1 on every
 * rank, no output and no hang; commands that do not run distributed refuse;
 * the same bytes with either partition (LIMN_MPI_PARTITION=sfc | scotch).
 * Meshes: generated with several components, boundaries and an isolated
 * vertex, and shared real meshes when ../shared/meshes is there.
 * subdivide and texture: test_mpi_cli_refine.c; denoise --preserve-features:
 * test_mpi_cli_features.c (the launcher of all three: mpi_cli.c).
 */
#include "mpi_cli.h"
#include "shell.h"
#include "support.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmocka.h>

static int setup(void **s)
{
    (void)s;
    return test_scratch_make("mpi_cli", NULL);
}

static const char *at(const char *name) { return test_join(test_dir, name); }

static int report_iterations(const char *path)
{
    FILE *f = fopen(path, "r");
    assert_non_null(f);
    char buf[1 << 14];
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    buf[n] = '\0';
    fclose(f);
    const char *k = strstr(buf, "\"iterations\":");
    assert_non_null(k);
    return atoi(k + strlen("\"iterations\":"));
}

/* Both outputs read back; the largest coordinate difference over the scale. */
static double difference(const char *a, const char *b)
{
    limn_context *ctx = limn_context_create();
    limn_mesh *ma = NULL, *mb = NULL;
    assert_int_equal(limn_mesh_read(ctx, a, LIMN_FORMAT_AUTO, &ma), LIMN_OK);
    assert_int_equal(limn_mesh_read(ctx, b, LIMN_FORMAT_AUTO, &mb), LIMN_OK);
    size_t n3 = 3 * limn_mesh_vertex_count(ma);
    assert_int_equal(n3, 3 * limn_mesh_vertex_count(mb));
    double worst = 0, scale = 0;
    for (size_t i = 0; i < n3; i++) {
        worst = fmax(worst, fabs(limn_mesh_positions(ma)[i] - limn_mesh_positions(mb)[i]));
        scale = fmax(scale, fabs(limn_mesh_positions(ma)[i]));
    }
    limn_mesh_destroy(ma);
    limn_mesh_destroy(mb);
    limn_context_destroy(ctx);
    return worst / (scale > 0 ? scale : 1);
}

/* interpolate with `opts` on one process and on `ranks`: same bytes (exact)
   or 1e-12 and the same iteration count. */
static void interpolate_same(const char *input, const char *opts, int ranks, int exact)
{
    char args[2048];
    const char *one = at("one.ply"), *many = at("many.ply");
    snprintf(args, sizeof args, "interpolate '%s' -o '%s' --report '%s' %s -q", input, one,
             at("one.json"), opts);
    if (mpi_cli_run(0, args) != 0)
        fail_msg("one process: %s", test_text);
    snprintf(args, sizeof args, "interpolate '%s' -o '%s' --report '%s' %s", input, many,
             at("many.json"), opts);
    int rc = mpi_cli_run(ranks, args);
    if (rc != 0) {
        fputs(test_text, stderr); /* whole: cmocka's message is cut short */
        fail_msg("%d ranks: exit status %d", ranks, rc);
    }
    /* rank 0 printed the summary once, with every rank's line */
    assert_int_equal(mpi_cli_count(test_text, "  device: "), 1);
    char line[32];
    snprintf(line, sizeof line, "rank %d:", ranks - 1);
    assert_non_null(strstr(test_text, line));
    assert_int_equal(report_iterations(at("one.json")), report_iterations(at("many.json")));
    if (exact)
        assert_true(test_same_bytes(one, many));
    double d = difference(one, many);
    const char *base = strrchr(input, '/');
    printf("  %s %s, %d ranks: %s, max difference %.2g of the scale\n", base ? base + 1 : input,
           opts, ranks, exact ? "same bytes" : "close", d);
    assert_true(d <= 1e-12);
}

static void interpolate_generated(void **s)
{
    (void)s;
    mpi_cli_write_inputs();
    for (int ranks = 2; ranks <= 3; ranks++) {
        interpolate_same(at("tri.obj"), "--method paper", ranks, 1);
        interpolate_same(at("tri.obj"), "--method weighted", ranks, 0);
        interpolate_same(at("tri.obj"), "--method cg", ranks, 0);
        interpolate_same(at("tri.obj"), "--method chebyshev", ranks, 1);
        interpolate_same(at("quad.obj"), "--alpha 0.5", ranks, 1);
        interpolate_same(at("quad.obj"), "--alpha 0.5 --method weighted", ranks, 0);
        interpolate_same(at("quad.obj"), "--alpha 0.5 --method cg", ranks, 0);
        interpolate_same(at("tri.obj"), "--precision float", ranks, 1);
        interpolate_same(at("tri.obj"), "--method sgs", ranks, 0);
        interpolate_same(at("quad.obj"), "--alpha 0.5 --method sgs", ranks, 0);
        interpolate_same(at("quad.obj"), "--alpha 0.5 --precision float --method paper", ranks,
                         1);
    }
}

static void interpolate_shared(void **s)
{
    (void)s;
    if (!test_shared_meshes())
        skip();
    char path[4096];
    snprintf(path, sizeof path, "%s", test_shared_path("medium/bun_zipper.ply"));
    interpolate_same(path, "", 2, 1);
    interpolate_same(path, "--method weighted", 3, 0);
    snprintf(path, sizeof path, "%s", test_shared_path("small/suzanne.obj"));
    interpolate_same(path, "", 3, 1);
}

static void series_same(void **s)
{
    (void)s;
    mpi_cli_write_inputs();
    /* smooth, denoise and sharpen on a file input: slices (limn_mpi_mesh_smooth
       etc.), the single process's bytes (--keep-volume: denoise_volume_same) */
    static const char *cmds[] = {"smooth '%s' -o '%s' --terms 4 -q",
                                 "denoise '%s' -o '%s' --m 2 --steps 3 -q",
                                 "sharpen '%s' -o '%s' --from 1 --to 3 --steps 2 -q"};
    static const char *inputs[] = {"quad.obj", "tri.obj"};
    for (int k = 0; k < 3; k++)
        for (int ranks = 2; ranks <= 3; ranks++) {
            char args[1024];
            char in[4200];
            snprintf(in, sizeof in, "%s", at(inputs[(k + ranks) % 2]));
            snprintf(args, sizeof args, cmds[k], in, at("s1.ply"));
            assert_int_equal(mpi_cli_run(0, args), 0);
            snprintf(args, sizeof args, cmds[k], in, at("s2.ply"));
            strcat(args, " --report '");
            strcat(args, at("s2.json"));
            strcat(args, "'");
            if (mpi_cli_run(ranks, args) != 0)
                fail_msg("%s", test_text);
            assert_true(test_same_bytes(at("s1.ply"), at("s2.ply")));
            assert_true(mpi_cli_report_sliced(at("s2.json")));
        }
    /* morph on slices (both inputs files): every frame the same bytes, the
       same per-frame measures in the report; the series and the blend */
    char args[1024];
    snprintf(args, sizeof args, "denoise '%s' -o '%s' --steps 6 -q", at("quad.obj"), at("to.ply"));
    assert_int_equal(mpi_cli_run(0, args), 0);
    snprintf(args, sizeof args, "mkdir -p '%s' '%s'", at("f1"), at("f2"));
    assert_int_equal(system(args), 0);
    for (int linear = 0; linear <= 1; linear++)
        for (int ranks = 2; ranks <= 5; ranks += ranks == 3 ? 2 : 1) {
            const char *how = linear ? "--linear" : "";
            snprintf(args, sizeof args,
                     "morph '%s' '%s' -o '%s/f%%d.ply' --frames 3 %s --report '%s' -q",
                     at("quad.obj"), at("to.ply"), at("f1"), how, at("m1.json"));
            assert_int_equal(mpi_cli_run(0, args), 0);
            snprintf(args, sizeof args,
                     "morph '%s' '%s' -o '%s/f%%d.ply' --frames 3 %s --report '%s' -q",
                     at("quad.obj"), at("to.ply"), at("f2"), how, at("m2.json"));
            if (mpi_cli_run(ranks, args) != 0)
                fail_msg("%s", test_text);
            for (int k = 0; k < 3; k++) {
                char a[64], b[64];
                snprintf(a, sizeof a, "f1/f%d.ply", k);
                snprintf(b, sizeof b, "f2/f%d.ply", k);
                assert_true(test_same_bytes(at(a), at(b)));
            }
            assert_true(mpi_cli_report_sliced(at("m2.json")));
            size_t n1 = 0, n2 = 0;
            char *r1 = test_slurp(at("m1.json"), &n1), *r2 = test_slurp(at("m2.json"), &n2);
            assert_non_null(r1);
            assert_non_null(r2);
            char *p1 = strstr(r1, "\"per_frame\""), *p2 = strstr(r2, "\"per_frame\"");
            assert_non_null(p1);
            assert_non_null(p2);
            size_t l1 = strcspn(p1, "]"), l2 = strcspn(p2, "]");
            assert_int_equal(l1, l2);
            assert_memory_equal(p1, p2, l1);
            free(r1);
            free(r2);
        }
}

/* A closed input of two components: the cube (quads) and the icosahedron. */
static void write_closed(const char *path)
{
    limn_context *ctx = limn_context_create();
    limn_mesh *parts[2] = {test_mesh_cube(ctx), test_mesh_icosahedron(ctx)};
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    size_t base = 0;
    for (int k = 0; k < 2; k++) {
        const double *p = limn_mesh_positions(parts[k]);
        for (size_t i = 0; i < limn_mesh_vertex_count(parts[k]); i++)
            fprintf(f, "v %.17g %.17g %.17g\n", p[3 * i] + 5.0 * k, p[3 * i + 1], p[3 * i + 2]);
        const uint32_t *off = limn_mesh_face_offsets(parts[k]);
        const uint32_t *idx = limn_mesh_face_indices(parts[k]);
        for (size_t fc = 0; fc < limn_mesh_face_count(parts[k]); fc++) {
            fprintf(f, "f");
            for (uint32_t c = off[fc]; c < off[fc + 1]; c++)
                fprintf(f, " %zu", (size_t)idx[c] + 1 + base);
            fprintf(f, "\n");
        }
        base += limn_mesh_vertex_count(parts[k]);
        limn_mesh_destroy(parts[k]);
    }
    assert_int_equal(fclose(f), 0);
    limn_context_destroy(ctx);
}

/* The text of key's value in the report at path ("" when absent). */
static void report_value(const char *path, const char *key, char *out, size_t cap)
{
    size_t n = 0;
    char *text = test_slurp(path, &n), *k = text ? strstr(text, key) : NULL;
    size_t len = k ? strcspn(k, ",\n}") : 0;
    snprintf(out, cap, "%.*s", (int)len, k ? k : "");
    free(text);
}

/* denoise on slices, eq. 8 and the default form, --keep-volume too: the
   single process's bytes and the same volumes, areas and noise estimate in
   the report (to the last digit); --keep-volume on an open mesh: its
   message once, status 1, nothing written; the default form on the root
   path (standard input): the same bytes. */
static void denoise_volume_same(void **s)
{
    (void)s;
    mpi_cli_write_inputs();
    write_closed(at("closed.obj"));
    static const char *keys[] = {"\"closed\"",      "\"volume_input\"", "\"volume_output\"",
                                 "\"area_input\"",  "\"area_output\"",  "\"keep_volume\"",
                                 "\"sigma_estimate\""};
    /* eq. 8, then the default form (SURE: volume kept on a closed mesh by default; its
       other cases in process, test_mpi_denoise, which is lighter under the sanitizers) */
    static const char *cases[][2] = {{"closed.obj", "--m 2 --steps 3 --keep-volume"},
                                     {"closed.obj", "--m 2 --steps 3"},
                                     {"quad.obj", "--m 2 --steps 3"},
                                     {"closed.obj", ""},
                                     {"quad.obj", "--products 5"}};
    for (int c = 0; c < 5; c++)
        for (int ranks = 2; ranks <= 5; ranks += ranks == 3 ? 2 : 1) {
            char args[2048];
            snprintf(args, sizeof args,
                     "denoise '%s' -o '%s' %s --report '%s' -q", at(cases[c][0]), at("v1.ply"),
                     cases[c][1], at("v1.json"));
            assert_int_equal(mpi_cli_run(0, args), 0);
            snprintf(args, sizeof args,
                     "denoise '%s' -o '%s' %s --report '%s' -q", at(cases[c][0]), at("v2.ply"),
                     cases[c][1], at("v2.json"));
            if (mpi_cli_run(ranks, args) != 0)
                fail_msg("%s", test_text);
            assert_true(test_same_bytes(at("v1.ply"), at("v2.ply")));
            assert_true(mpi_cli_report_sliced(at("v2.json")));
            for (size_t k = 0; k < sizeof keys / sizeof *keys; k++) {
                char a[128], b[128];
                report_value(at("v1.json"), keys[k], a, sizeof a);
                report_value(at("v2.json"), keys[k], b, sizeof b);
                assert_true(a[0] != '\0' || (k == 6 && c < 3)); /* eq. 8: no estimate */
                assert_string_equal(a, b);
            }
        }
    char args[2048];
    snprintf(args, sizeof args, "denoise '%s' -o '%s' --m 2 --steps 3 --keep-volume",
             at("quad.obj"), at("open1.ply"));
    assert_int_equal(mpi_cli_run(0, args), 1);
    const char *why = strstr(test_text, "keeping the volume needs a closed mesh");
    assert_non_null(why);
    char one[512];
    snprintf(one, sizeof one, "%.*s", (int)strcspn(why, "\n"), why);
    snprintf(args, sizeof args, "denoise '%s' -o '%s' --m 2 --steps 3 --keep-volume",
             at("quad.obj"), at("open2.ply"));
    assert_int_equal(mpi_cli_run(3, args), 1);
    assert_int_equal(mpi_cli_count(test_text, "limn denoise: error:"), 1);
    assert_int_equal(mpi_cli_count(test_text, one), 1); /* the same edge counts */
    assert_false(test_file_exists(at("open2.ply")));
    /* the default form: the same refusal of an open mesh's --keep-volume */
    snprintf(args, sizeof args, "denoise '%s' -o '%s' --keep-volume", at("quad.obj"),
             at("open3.ply"));
    assert_int_equal(mpi_cli_run(5, args), 1);
    assert_int_equal(mpi_cli_count(test_text, "keeping the volume needs a closed mesh"), 1);
    assert_false(test_file_exists(at("open3.ply")));
    /* and on the root path (standard input: limn_denoise_sure_mpi): the same bytes */
    snprintf(args, sizeof args, "denoise '%s' -o '%s' -q", at("closed.obj"), at("v1.ply"));
    assert_int_equal(mpi_cli_run(0, args), 0);
    for (int ranks = 2; ranks <= 5; ranks += 3) {
        snprintf(args, sizeof args, "denoise - --input-format obj -o '%s' -q < '%s'",
                 at("v2.ply"), at("closed.obj"));
        if (mpi_cli_run(ranks, args) != 0)
            fail_msg("%s", test_text);
        assert_true(test_same_bytes(at("v1.ply"), at("v2.ply")));
    }
}

/* bands (every band, the remainder and the energy file; on slices) and
   sharpen: the single process's bytes on 2, 3 and 5 ranks. */
static void bands_sharpen_same(void **s)
{
    (void)s;
    mpi_cli_write_inputs();
    static const char *files[] = {"_band0.ply", "_band1.ply", "_remainder.ply", "_energy.json"};
    for (int ranks = 2; ranks <= 5; ranks += ranks == 3 ? 2 : 1) {
        char args[1024], a[64], b[64];
        snprintf(args, sizeof args, "bands '%s' -o '%s' --count 2 -q", at("tri.obj"), at("b1"));
        assert_int_equal(mpi_cli_run(0, args), 0);
        snprintf(args, sizeof args, "bands '%s' -o '%s' --count 2 --report '%s'", at("tri.obj"),
                 at("b2"), at("b2.json"));
        if (mpi_cli_run(ranks, args) != 0)
            fail_msg("%s", test_text);
        assert_int_equal(mpi_cli_count(test_text, "bands + remainder written"), 1);
        assert_true(mpi_cli_report_sliced(at("b2.json"))); /* limn_mpi_mesh_bands */
        for (int k = 0; k < 4; k++) {
            snprintf(a, sizeof a, "b1%s", files[k]);
            snprintf(b, sizeof b, "b2%s", files[k]);
            assert_true(test_same_bytes(at(a), at(b)));
        }
        snprintf(args, sizeof args, "sharpen '%s' -o '%s' --from 1 --to 2 --steps 2 -q",
                 at("quad.obj"), at("s1.ply"));
        assert_int_equal(mpi_cli_run(0, args), 0);
        snprintf(args, sizeof args, "sharpen '%s' -o '%s' --from 1 --to 2 --steps 2 -q",
                 at("quad.obj"), at("s2.ply"));
        if (mpi_cli_run(ranks, args) != 0)
            fail_msg("%s", test_text);
        assert_true(test_same_bytes(at("s1.ply"), at("s2.ply")));
        printf("  bands --count 2 and sharpen, %d ranks: same bytes\n", ranks);
    }
    /* a failure reaches every rank: one message, nothing written */
    assert_int_equal(test_write_text(at("broken.obj"), "v 0 0 0\nv 1 0 0\nf 1 2 7\n"), 0);
    char args[1024];
    snprintf(args, sizeof args, "bands '%s' -o '%s' --count 2", at("broken.obj"), at("bad"));
    assert_int_equal(mpi_cli_run(3, args), 1);
    assert_int_equal(mpi_cli_count(test_text, "limn bands: error:"), 1);
    assert_false(test_file_exists(at("bad_band0.ply")));
    assert_false(test_file_exists(at("bad_energy.json")));
}

/* Every rank reads its slice of the file and each phase of the slice reader
   parses the header: a header warning is still printed once, by rank 0;
   so are the repair's (counted over the ranks). */
static void warnings_once(void **s)
{
    (void)s;
    const char *in = at("extra_property.ply");
    assert_int_equal(test_write_text(in, "ply\nformat ascii 1.0\nelement vertex 4\n"
                                         "property float x\nproperty float y\n"
                                         "property float z\nproperty float confidence\n"
                                         "element face 2\n"
                                         "property list uchar int vertex_indices\n"
                                         "end_header\n0 0 0 1\n1 0 0 1\n1 1 0 1\n"
                                         "0 1 0.2 1\n3 0 1 2\n3 0 2 3\n"),
                     0);
    char args[2048];
    snprintf(args, sizeof args, "interpolate '%s' -o '%s'", in, at("extra_many.ply"));
    if (mpi_cli_run(2, args) != 0)
        fail_msg("2 ranks: %s", test_text);
    assert_int_equal(mpi_cli_count(test_text, "vertex property dropped"), 1);
    snprintf(args, sizeof args, "interpolate '%s' -o '%s' -q", in, at("extra_one.ply"));
    assert_int_equal(mpi_cli_run(0, args), 0);
    assert_true(test_same_bytes(at("extra_one.ply"), at("extra_many.ply")));
    /* the repair's warnings on slices (a duplicate face at the other end of
       the file, a fin, an unused vertex): one process's words, said once */
    const char *bad = at("kept.obj");
    assert_int_equal(test_write_text(bad, "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\n"
                                          "v 5 5 5\nf 1 2 3\nf 1 3 4\nf 1 3 5\nf 2 3 4\n"
                                          "f 1 2 5\nf 3 2 1\n"),
                     0);
    static const char *said[] = {"duplicate face", "non-manifold edge", "non-manifold vert",
                                 "used by no face"};
    char one[4][512];
    snprintf(args, sizeof args, "smooth '%s' -o '%s' --terms 2", bad, at("kept1.ply"));
    assert_int_equal(mpi_cli_run(0, args), 0);
    for (int k = 0; k < 4; k++) {
        const char *w = strstr(test_text, said[k]);
        assert_non_null(w);
        while (w > test_text && w[-1] != '\n')
            w--;
        snprintf(one[k], sizeof one[k], "%.*s", (int)strcspn(w, "\n"), w);
    }
    snprintf(args, sizeof args, "smooth '%s' -o '%s' --terms 2", bad, at("kept3.ply"));
    if (mpi_cli_run(3, args) != 0)
        fail_msg("%s", test_text);
    for (int k = 0; k < 4; k++)
        assert_int_equal(mpi_cli_count(test_text, one[k]), 1);
    assert_true(test_same_bytes(at("kept1.ply"), at("kept3.ply")));
}

static void per_rank(void **s)
{
    (void)s;
    mpi_cli_write_inputs();
    char args[1024];
    snprintf(args, sizeof args, "interpolate '%s' -o '%s' --per-rank-output -q", at("tri.obj"),
             at("piece.ply"));
    if (mpi_cli_run(3, args) != 0)
        fail_msg("%s", test_text);
    assert_false(test_file_exists(at("piece.ply"))); /* the pieces instead */
    limn_context *ctx = limn_context_create();
    size_t total = 0;
    for (int r = 0; r < 3; r++) {
        char name[64];
        snprintf(name, sizeof name, "piece.r%d.ply", r);
        limn_mesh *m = NULL;
        assert_int_equal(limn_mesh_read(ctx, at(name), LIMN_FORMAT_AUTO, &m), LIMN_OK);
        total += limn_mesh_vertex_count(m);
        assert_true(limn_mesh_face_count(m) > 0);
        limn_mesh_destroy(m);
    }
    /* owned vertices once each, plus the ring around each piece */
    assert_true(total > 41 * 31 + 1 + 12);
    limn_context_destroy(ctx);
    /* one process refuses the option */
    assert_int_equal(mpi_cli_run(0, args), 2);
    assert_non_null(strstr(test_text, "--per-rank-output needs several MPI ranks"));
}

/* The ranks of a node take the matching OpenCL devices in turn (local rank %
   count). Two ICD entries naming PoCL make two platforms of one CPU device
   each: ranks 0, 1, 2 must take 0.0, 1.0, 0.0, and still give the same bytes. */
static void device_per_rank(void **s)
{
    (void)s;
    FILE *icd = fopen("/etc/OpenCL/vendors/pocl.icd", "r");
    if (!icd)
        skip();
    char lib[512] = "";
    if (!fgets(lib, sizeof lib, icd))
        lib[0] = '\0';
    fclose(icd);
    lib[strcspn(lib, "\r\n")] = '\0';
    char cmd[2048];
    snprintf(cmd, sizeof cmd, "mkdir -p '%s' && printf '%%s\\n' '%s' > '%s' && cp '%s' '%s'",
             at("icd"), lib, at("icd/a.icd"), at("icd/a.icd"), at("icd/b.icd"));
    assert_int_equal(system(cmd), 0);
    mpi_cli_write_inputs();
    char args[2048];
    snprintf(args, sizeof args, "interpolate '%s' -o '%s' -q", at("quad.obj"), at("one.ply"));
    assert_int_equal(mpi_cli_run(0, args), 0);
    snprintf(args, sizeof args, "interpolate '%s' -o '%s' --report '%s' -q", at("quad.obj"),
             at("many.ply"), at("many.json"));
    setenv("OCL_ICD_VENDORS", at("icd"), 1);
    int rc = mpi_cli_run(3, args);
    unsetenv("OCL_ICD_VENDORS");
    if (rc != 0)
        fail_msg("%s", test_text);
    assert_true(test_same_bytes(at("one.ply"), at("many.ply")));
    FILE *f = fopen(at("many.json"), "r");
    assert_non_null(f);
    size_t n = fread(test_text, 1, sizeof test_text - 1, f);
    test_text[n] = '\0';
    fclose(f);
    static const char *want[3] = {"device 0.0", "device 1.0", "device 0.0"};
    const char *at_rank = test_text;
    for (int r = 0; r < 3; r++) {
        char key[32];
        snprintf(key, sizeof key, "\"rank\": %d", r);
        at_rank = strstr(at_rank, key);
        assert_non_null(at_rank);
        const char *dev = strstr(at_rank, "\"device\"");
        assert_non_null(dev);
        const char *end = strchr(dev + 10, '}');
        assert_non_null(end);
        const char *hit = strstr(dev, want[r]);
        if (!hit || hit > end)
            fail_msg("rank %d should have taken %s: %.200s", r, want[r], dev);
    }
}

/* The default partition (the Hilbert curve) and PT-Scotch's give the single
   process's bytes on 2, 3 and 5 ranks (the rows do not depend on the parts);
   an unknown LIMN_MPI_PARTITION is one error, status 2, nothing written. */
static void partitions_same(void **s)
{
    (void)s;
    mpi_cli_write_inputs();
    static const char *kinds[] = {"sfc", "scotch"};
    static const int ranks[] = {2, 3, 5};
    for (int k = 0; k < 2; k++) {
        setenv("LIMN_MPI_PARTITION", kinds[k], 1);
        for (int r = 0; r < 3; r++) {
            printf("  LIMN_MPI_PARTITION=%s\n", kinds[k]);
            interpolate_same(at("tri.obj"), "--method paper", ranks[r], 1);
            assert_true(mpi_cli_report_sliced(at("many.json")));
            interpolate_same(at("quad.obj"), "--alpha 0.5", ranks[r], 1);
            assert_true(mpi_cli_report_sliced(at("many.json")));
        }
    }
    setenv("LIMN_MPI_PARTITION", "metis", 1);
    char args[1024];
    snprintf(args, sizeof args, "interpolate '%s' -o '%s'", at("tri.obj"), at("bad.ply"));
    assert_int_equal(mpi_cli_run(3, args), 2); /* an argument error, as a bad option */
    unsetenv("LIMN_MPI_PARTITION");
    assert_int_equal(mpi_cli_count(test_text, "error:"), 1);
    assert_non_null(strstr(test_text, "LIMN_MPI_PARTITION is 'metis'"));
    assert_false(test_file_exists(at("bad.ply")));
}

static void errors(void **s)
{
    (void)s;
    char args[1024];
    /* a missing file and a malformed one: one message, status 1, nothing written */
    snprintf(args, sizeof args, "interpolate '%s' -o '%s'", at("missing.obj"), at("bad.ply"));
    assert_int_equal(mpi_cli_run(3, args), 1);
    assert_int_equal(mpi_cli_count(test_text, "limn interpolate: error:"), 1);
    assert_non_null(strstr(test_text, "missing.obj"));
    assert_false(test_file_exists(at("bad.ply")));
    assert_int_equal(test_write_text(at("broken.obj"), "v 0 0 0\nv 1 0 0\nf 1 2 7\n"), 0);
    snprintf(args, sizeof args, "smooth '%s' -o '%s' --terms 2", at("broken.obj"), at("bad.ply"));
    assert_int_equal(mpi_cli_run(2, args), 1);
    assert_int_equal(mpi_cli_count(test_text, "limn smooth: error:"), 1);
    assert_non_null(strstr(test_text, "broken.obj"));
    assert_false(test_file_exists(at("bad.ply")));
    /* Loop on quads fails on the root while building the operator */
    mpi_cli_write_inputs();
    snprintf(args, sizeof args, "interpolate '%s' -o '%s' --scheme loop", at("quad.obj"),
             at("bad.ply"));
    assert_int_equal(mpi_cli_run(2, args), 1);
    assert_int_equal(mpi_cli_count(test_text, "error:"), 1);
    assert_non_null(strstr(test_text, "Loop"));
    assert_false(test_file_exists(at("bad.ply")));
    /* a usage error, once */
    snprintf(args, sizeof args, "interpolate '%s' -o '%s' --tol -1", at("quad.obj"),
             at("bad.ply"));
    assert_int_equal(mpi_cli_run(3, args), 2);
    assert_int_equal(mpi_cli_count(test_text, "--tol -1 must be positive"), 1);
    /* options the single process refuses: an argument error (status 2), one
       message, nothing written */
    snprintf(args, sizeof args, "interpolate '%s' -o '%s' --method cg --precision float",
             at("quad.obj"), at("bad.ply"));
    assert_int_equal(mpi_cli_run(3, args), 2);
    assert_int_equal(mpi_cli_count(test_text, "precision float runs the chebyshev"), 1);
    assert_false(test_file_exists(at("bad.ply")));
    /* a command that does not run distributed */
    snprintf(args, sizeof args, "info '%s'", at("quad.obj"));
    assert_int_equal(mpi_cli_run(2, args), 2);
    assert_int_equal(mpi_cli_count(test_text, "does not run on several MPI ranks"), 1);
    /* one rank under the launcher: as without it */
    snprintf(args, sizeof args, "info '%s'", at("quad.obj"));
    assert_int_equal(mpi_cli_run(1, args), 0);
}

int main(void)
{
    if (!getenv("LIMN_MPIEXEC") || !getenv("LIMN_BIN"))
        return 77;
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(interpolate_generated), cmocka_unit_test(interpolate_shared),
        cmocka_unit_test(series_same),           cmocka_unit_test(bands_sharpen_same),
        cmocka_unit_test(per_rank),              cmocka_unit_test(warnings_once),
        cmocka_unit_test(device_per_rank),       cmocka_unit_test(errors),
        cmocka_unit_test(denoise_volume_same),   cmocka_unit_test(partitions_same),
    };
    return cmocka_run_group_tests(tests, setup, test_scratch_teardown);
}
