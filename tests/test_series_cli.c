/* SPDX-License-Identifier: MIT */
/*
 * The series subcommands as a user meets them: bad options and bad inputs
 * give a message, exit status 2 (usage) or 1 (failure) and write nothing;
 * good runs write what the README says (band files and energy JSON, frames,
 * PLY colours, a PNG that decodes) and reports with the shared keys.
 */
#include "shell.h"
#include "support.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmocka.h>

static char spot[512];

static int setup(void **s)
{
    (void)s;
    if (test_scratch_make("series", NULL) != 0)
        return -1;
    snprintf(spot, sizeof spot, "%s/spot_control_mesh.obj", getenv("LIMN_TEST_DATA"));
    return 0;
}

/* Runs `limn ARGS` (with %s replaced by the temporary directory) and captures
   stdout+stderr; returns the exit status. */
static int limn(const char *fmt, ...)
{
    char args[4096];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(args, sizeof args, fmt, ap);
    va_end(ap);
    return test_in_dir(test_text, sizeof test_text, test_dir, "'%s' %s", getenv("LIMN_BIN"), args);
}

/* Nothing but the inputs (in_*) and the frames directory is in the directory. */
static void nothing_written(const char *what)
{
    char cmd[512];
    snprintf(cmd, sizeof cmd, "cd '%s' && find . -type f ! -name 'in_*' | grep -q .", test_dir);
    if (system(cmd) == 0) {
        snprintf(cmd, sizeof cmd, "cd '%s' && find . -type f >&2", test_dir);
        (void)system(cmd);
        fail_msg("%s: a failed run left files behind", what);
    }
}

static void expect(int rc, int status, const char *message, const char *what)
{
    if (rc != status || !strstr(test_text, message))
        fail_msg("%s: exit %d (want %d), output:\n%s\nwanted: %s", what, rc, status, test_text,
                 message);
    nothing_written(what);
}

static void write_in(const char *name, const char *content)
{
    assert_int_equal(test_write_text(test_join(test_dir, name), content), 0);
}

static void bad_usage(void **s)
{
    (void)s;
    struct {
        const char *args, *message;
        int status;
    } cases[] = {
        {"bands '%s' -o b", "--count N is required", 2},
        {"bands '%s' -o b --count -1", "--count -1 must be at least 0", 2},
        {"bands '%s' -o b --count 3 --frobnicate", "unknown option '--frobnicate'", 2},
        {"bands '%s' --count 3", "no output given", 2},
        {"smooth '%s' -o out.ply", "--terms N is required", 2},
        {"smooth '%s' -o out.ply --terms 0", "--terms 0 must be at least 1", 2},
        {"smooth '%s' -o out.xyz --terms 2", "cannot tell the format", 2},
        {"denoise '%s' -o out.ply --m -1", "--m -1 must be at least 0", 2},
        {"denoise '%s' -o out.ply --steps 0", "--steps 0 must be at least 1", 2},
        {"denoise '%s' -o out.ply --m two", "--m expects an integer", 2},
        {"denoise '%s' -o out.ply --products 0", "--products 0 must be at least 1", 2},
        {"denoise '%s' -o out.ply --products 65", "--products 65: at most 64", 2},
        {"denoise '%s' -o out.ply --products 4 --m 1", "give one or the other", 2},
        {"denoise '%s' -o out.ply --alpha 3", "--alpha 3 is outside [0, 1]", 2},
        {"denoise '%s' -o out.ply --scheme butterfly", "is not one of auto, loop, catmark", 2},
        {"denoise '%s' -o out.ply --device cuda", "unknown device 'cuda'", 2},
        {"denoise '%s' -o out.ply --scheme loop", "Loop subdivision needs triangles", 1},
        {"denoise '%s' -o out.ply --preserve-features --m 2", "takes neither --m nor --steps", 2},
        {"denoise '%s' -o out.ply --preserve-features --steps 2", "takes neither --m", 2},
        {"denoise '%s' -o out.ply --preserve-features --products 4", "nor --products", 2},
        {"denoise '%s' -o out.ply --sigma-r 0.3", "need --preserve-features", 2},
        {"denoise '%s' -o out.ply --preserve-features --sigma-r 0", "must be positive", 2},
        {"denoise '%s' -o out.ply --preserve-features --normal-steps 0", "must be at least 1", 2},
        {"denoise '%s' -o out.ply --preserve-features --tangential 2", "must lie in [0, 1]", 2},
        {"denoise '%s' -o out.ply --preserve-features --crease-angle 180", "[0, 180)", 2},
        {"denoise '%s' -o out.ply --crease-angle 20", "need --preserve-features", 2},
        {"sharpen '%s' -o out.ply --to 3", "--from M and --to N are required", 2},
        {"sharpen '%s' -o out.ply --from 3 --to 1", "--to 1 is below --from 3", 2},
        {"morph '%s' -o 'f%%04d.ply'", "two meshes are needed", 2},
        {"morph '%s' '%s' -o f.ply", "exactly one %d-style conversion", 2},
        {"morph '%s' '%s' -o 'f%%d_%%d.ply'", "more than one %d conversion", 2},
        {"morph '%s' '%s' -o 'f%%s.ply'", "conversion other than %d", 2},
        {"morph '%s' '%s' -o 'f%%04d.ply' --p 1.5", "--p 1.5 must lie strictly between 0 and 1", 2},
        {"morph '%s' '%s' -o 'f%%04d.ply' --frames 1", "--frames 1 must be at least 2", 2},
        {"morph '%s' '%s' -o 'nodir/f%%04d.ply'", "directory 'nodir' does not exist", 1},
        {"texture '%s' -o t.ply", "--colors '#hex,#hex,...' is required", 2},
        {"texture '%s' -o t.ply --colors '#12345g'", "is not a colour", 2},
        {"texture '%s' -o t.ply --colors '#123456;#000000'", "is not a colour", 2},
        {"texture '%s' -o t.obj --colors '#123456'", "vertex colours are written in PLY only", 2},
        {"texture '%s' -o t.ply --colors '#123456' --levels 9", "--levels 9: at most 8", 2},
        {"texture '%s' -o t.ply --colors '#123456' --seed -4", "--seed expects", 2},
        {"render '%s' -o r.png --size 0x10", "--size '0x10' is not WIDTHxHEIGHT", 2},
        {"render '%s' -o r.png --view abc", "--view 'abc' is not AZIMUTH,ELEVATION", 2},
        {"render '%s' -o r.png --view 10,100", "--view '10,100'", 2},
        {"render '%s' -o r.jpg", "must end in .png", 2},
        {"render '%s' -o r.png --scheme loop", "unknown option '--scheme'", 2},
        {"render '%s' -o r.png --up w", "--up 'w' is not x, y or z", 2},
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        int rc = limn(cases[i].args, spot, spot);
        expect(rc, cases[i].status, cases[i].message, cases[i].args);
    }
    /* help goes to stdout with status 0 */
    static const char *cmds[] = {"bands", "smooth", "denoise", "sharpen", "morph", "texture",
                                 "render"};
    for (size_t i = 0; i < sizeof cmds / sizeof *cmds; i++) {
        assert_int_equal(limn("%s --help", cmds[i]), 0);
        assert_non_null(strstr(test_text, "usage: limn"));
    }
}

static void bad_inputs(void **s)
{
    (void)s;
    /* same vertex count, one face differs */
    write_in("in_a.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                         "f 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n");
    write_in("in_b.obj", "v 0 0 0\nv 2 0 0\nv 0 2 0\nv 0 0 2\n"
                         "f 1 3 2\nf 1 2 4\nf 2 4 3\nf 3 1 4\n");
    write_in("in_c.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    assert_int_equal(system("true"), 0);
    char a[300], b[300], c[300];
    snprintf(a, sizeof a, "%s/in_a.obj", test_dir);
    snprintf(b, sizeof b, "%s/in_b.obj", test_dir);
    snprintf(c, sizeof c, "%s/in_c.obj", test_dir);
    expect(limn("morph '%s' '%s' -o 'f%%03d.ply' --frames 4", a, b), 1,
           "FROM and TO differ in topology: face 2 is (1 2 3) in FROM but (1 3 2) in TO",
           "morph, one face differs");
    expect(limn("morph '%s' '%s' -o 'f%%03d.ply' --frames 4 --linear", a, c), 1,
           "FROM has 4 vertices, TO has 3", "morph, vertex counts differ");
    /* an open mesh has no volume to keep */
    expect(limn("denoise '%s' -o out.ply --keep-volume", c), 1, "needs a closed mesh",
           "denoise --keep-volume, open mesh");
    /* missing input, and a malformed one */
    expect(limn("denoise in_missing.obj -o out.ply"), 1, "in_missing.obj", "missing input");
    write_in("in_bad.obj", "v 0 0 0\nv 1 0 0\nf 1 2 7\n");
    expect(limn("bands in_bad.obj -o b --count 2"), 1, "in_bad.obj", "malformed input");
    /* an existing output survives a failed run untouched */
    write_in("in_keep.ply", "KEEP");
    assert_int_equal(limn("denoise '%s' -o in_keep.ply --keep-volume", c), 1);
    FILE *f = fopen(strcat(strcpy(test_text, test_dir), "/in_keep.ply"), "rb");
    char buf[8] = "";
    assert_non_null(f);
    assert_int_equal(fread(buf, 1, sizeof buf, f), 4);
    fclose(f);
    assert_memory_equal(buf, "KEEP", 4);
    /* the input is never overwritten */
    expect(limn("smooth in_a.obj -o in_a.obj --terms 2"), 2, "is the input file",
           "output = input");
}

static char *slurp(const char *name)
{
    char path[300];
    snprintf(path, sizeof path, "%s/%s", test_dir, name);
    FILE *f = fopen(path, "rb");
    if (!f)
        fail_msg("%s was not written", name);
    static char buf[1 << 17];
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    buf[n] = '\0';
    fclose(f);
    return buf;
}

static void has_keys(const char *json, const char *const *keys, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (!strstr(json, keys[i]))
            fail_msg("report lacks %s:\n%s", keys[i], json);
}

static const char *const shared_keys[] = {
    "\"vertices\": 188", "\"faces\": 180", "\"scheme\": \"catmark\"", "\"alpha\": 0",
    "\"device\": ", "\"products\": ", "\"seconds\": {", "\"load\": ", "\"topology\": ",
    "\"stencil\": ", "\"compute\": ", "\"write\": ", "\"total\": "};

static void clean(void)
{
    char cmd[256];
    snprintf(cmd, sizeof cmd, "cd '%s' && rm -rf ./*", test_dir);
    assert_int_equal(system(cmd), 0);
}

static void good_runs(void **s)
{
    (void)s;
    clean();
    /* bands: N band files, the remainder, the energy JSON */
    assert_int_equal(limn("bands '%s' -o sp --count 3 --report rep.json", spot), 0);
    for (int i = 0; i < 3; i++) {
        char name[32];
        snprintf(name, sizeof name, "sp_band%d.ply", i);
        slurp(name);
    }
    slurp("sp_remainder.ply");
    const char *energy = slurp("sp_energy.json");
    static const char *const ekeys[] = {"\"bands\": [", "\"remainder\": ", "\"input_energy\": ",
                                        "\"max_rel_sum_error\": "};
    has_keys(energy, ekeys, 4);
    double err = strtod(strstr(energy, "\"max_rel_sum_error\": ") + 21, NULL);
    assert_true(err <= 1e-12);
    const char *rep = slurp("rep.json");
    has_keys(rep, shared_keys, sizeof shared_keys / sizeof *shared_keys);
    assert_non_null(strstr(rep, "\"products\": 3"));
    assert_int_equal(limn("info sp_band0.ply --json"), 0);
    assert_non_null(strstr(test_text, "\"vertices\": 188, \"faces\": 180"));

    /* denoise: volume change in the report */
    assert_int_equal(limn("denoise '%s' -o dn.ply --m 2 --steps 3 --report dn.json", spot), 0);
    assert_non_null(strstr(test_text, "volume"));
    rep = slurp("dn.json");
    has_keys(rep, shared_keys, sizeof shared_keys / sizeof *shared_keys);
    static const char *const dkeys[] = {"\"m\": 2", "\"steps\": 3", "\"products\": 9",
                                        "\"volume_input\": ", "\"volume_output\": ",
                                        "\"volume_change\": ", "\"closed\": true"};
    has_keys(rep, dkeys, sizeof dkeys / sizeof *dkeys);
    assert_int_equal(limn("denoise '%s' -o dk.ply --keep-volume -q --report dk.json", spot), 0);
    assert_string_equal(test_text, "");
    double change = strtod(strstr(slurp("dk.json"), "\"volume_change\": ") + 17, NULL);
    assert_true(change > -1e-9 && change < 1e-9);
    /* the default form: SURE, 12 products, the volume of a closed mesh kept */
    assert_int_equal(limn("denoise '%s' -o ds.ply -q --report ds.json", spot), 0);
    rep = slurp("ds.json");
    static const char *const skeys[] = {"\"form\": \"sure\"", "\"degree\": 12",
                                        "\"products\": 12", "\"sigma_estimate\": ",
                                        "\"keep_volume\": true"};
    has_keys(rep, skeys, sizeof skeys / sizeof *skeys);
    change = strtod(strstr(rep, "\"volume_change\": ") + 17, NULL);
    assert_true(change > -1e-9 && change < 1e-9);
    assert_non_null(strstr(slurp("dn.json"), "\"form\": \"paper\""));
    /* denoise --preserve-features: its options in the report, W's products counted (adaptive
     * rounds: the first takes --normal-steps 4, the second half of it, 4 + 2; then the
     * crease pass, 3 + 2; without it 6) */
    assert_int_equal(limn("denoise '%s' -o df.ply --preserve-features --normal-steps 4 "
                          "--outer-steps 2 --keep-volume -q --report df.json",
                          spot),
                     0);
    rep = slurp("df.json");
    static const char *const fkeys[] = {"\"preserve_features\": true", "\"normal_steps\": 4",
                                        "\"outer_steps\": 2", "\"products\": 11",
                                        "\"adaptive\": true", "\"crease_angle\": 30",
                                        "\"volume_change\": "};
    has_keys(rep, fkeys, sizeof fkeys / sizeof *fkeys);
    change = strtod(strstr(rep, "\"volume_change\": ") + 17, NULL);
    assert_true(change > -1e-9 && change < 1e-9);
    assert_int_equal(limn("denoise '%s' -o df.ply --preserve-features --normal-steps 4 "
                          "--outer-steps 2 --crease-angle 0 -q --report df.json",
                          spot),
                     0);
    rep = slurp("df.json");
    static const char *const nkeys[] = {"\"products\": 6", "\"crease_angle\": 0"};
    has_keys(rep, nkeys, sizeof nkeys / sizeof *nkeys);

    /* smooth and sharpen */
    assert_int_equal(limn("smooth '%s' -o sm.obj --terms 2 -q", spot), 0);
    assert_int_equal(limn("sharpen '%s' -o sh.off --from 1 --to 2 --steps 2 -q --report sh.json",
                          spot),
                     0);
    assert_non_null(strstr(slurp("sh.json"), "\"products\": 4"));

    /* morph: every frame, per-frame report */
    assert_int_equal(system(strcat(strcat(strcpy(test_text, "mkdir "), test_dir), "/frames")), 0);
    assert_int_equal(limn("morph '%s' sm.obj -o 'frames/q%%03d.ply' --frames 5 --report m.json",
                          spot),
                     0);
    for (int k = 0; k < 5; k++) {
        char name[32];
        snprintf(name, sizeof name, "frames/q%03d.ply", k);
        slurp(name);
    }
    rep = slurp("m.json");
    static const char *const mkeys[] = {"\"method\": \"series\"", "\"per_frame\": [",
                                        "\"frame\": 4", "\"flipped_faces\": 0",
                                        "\"mean_rel_distance_to_target\": ", "\"products\": 12"};
    has_keys(rep, mkeys, sizeof mkeys / sizeof *mkeys);
    assert_int_equal(limn("morph '%s' sm.obj -o 'frames/l%%d.ply' --frames 3 --linear -q "
                          "--report l.json",
                          spot),
                     0);
    assert_non_null(strstr(slurp("l.json"), "\"method\": \"linear\""));
    slurp("frames/l2.ply");

    /* texture: a PLY with colours, the same bytes twice */
    assert_int_equal(
        limn("texture '%s' -o t1.ply --levels 1 --colors '#102040,#f0c080,#803010' -q", spot), 0);
    assert_int_equal(
        limn("texture '%s' -o t2.ply --levels 1 --colors '#102040,#f0c080,#803010' -q "
             "--device reference",
             spot),
        0);
    assert_int_equal(limn("info t1.ply --json"), 0);
    char cmd[4096];
    snprintf(cmd, sizeof cmd, "cmp -s '%s/t1.ply' '%s/t2.ply'", test_dir, test_dir);
    assert_int_equal(system(cmd), 0);
    assert_non_null(strstr(slurp("t1.ply"), "property uchar red"));

    /* render: a PNG that decodes to the right size, mesh in the middle */
    assert_int_equal(limn("render t1.ply -o r.png --size 120x90 --view 150,10 --report r.json"),
                     0);
    assert_non_null(strstr(slurp("r.json"), "\"vertex_colors\": true"));
    if (system("python3 -c 'import zlib' 2>/dev/null") == 0) {
        snprintf(cmd, sizeof cmd,
                 "python3 -c \"\n"
                 "import struct, zlib, sys\n"
                 "d = open('%s/r.png', 'rb').read()\n"
                 "assert d[:8] == bytes([137, 80, 78, 71, 13, 10, 26, 10])\n"
                 "i, idat = 8, b''\n"
                 "while i < len(d):\n"
                 "    n, = struct.unpack('>I', d[i:i+4]); t = d[i+4:i+8]; c = d[i+8:i+8+n]\n"
                 "    assert zlib.crc32(t + c) == struct.unpack('>I', d[i+8+n:i+12+n])[0]\n"
                 "    if t == b'IHDR': w, h = struct.unpack('>II', c[:8]); assert c[8:10] == bytes([8, 2])\n"
                 "    if t == b'IDAT': idat += c\n"
                 "    i += 12 + n\n"
                 "raw = zlib.decompress(idat)\n"
                 "assert (w, h) == (120, 90) and len(raw) == h * (3 * w + 1), (w, h, len(raw))\n"
                 "\"",
                 test_dir);
        if (system(cmd) != 0)
            fail_msg("the PNG does not decode");
    } else {
        printf("  (python3 not found: PNG decoding not checked)\n");
    }
    clean();
}

TEST_MAIN(setup, test_scratch_teardown, cmocka_unit_test(bad_usage), cmocka_unit_test(bad_inputs),
          cmocka_unit_test(good_runs))
