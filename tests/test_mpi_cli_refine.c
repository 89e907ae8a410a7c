/* SPDX-License-Identifier: MIT */
/*
 * `mpirun -np N limn subdivide | texture` on slices (limn_mpi_mesh_subdivide,
 * limn_mpi_mesh_texture): on 2, 3 and 5 ranks, Loop and Catmull-Clark, the
 * very bytes of one process: subdivide with --limit, texture with every
 * option (levels, seed, frequency, tol, colours in both spellings, the
 * output formats, the scheme and alpha). A bad input and a singular level
 * give one message, exit status 1 and nothing written; standard output is
 * refused. The generated inputs and the launcher: mpi_cli.c (as
 * test_mpi_cli.c, of which these cases were part).
 */
#include "mpi_cli.h"
#include "shell.h"
#include "support.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

static int setup(void **s)
{
    (void)s;
    return test_scratch_make("mpi_cli_refine", NULL);
}

static const char *at(const char *name) { return test_join(test_dir, name); }

/* `limn CMD INPUT -o OUT OPTIONS` for each (input, options) of runs, on one
   process, then on 2, 3 and 5 ranks: on slices, the summary (the line
   holding summary) printed once, the single process's bytes. */
static void same_on_ranks(const char *cmd, const char *const (*runs)[2], size_t n,
                          const char *summary, const char *what)
{
    for (int ranks = 2; ranks <= 5; ranks += ranks == 3 ? 2 : 1) {
        for (size_t k = 0; k < n; k++) {
            char args[1024];
            snprintf(args, sizeof args, "%s '%s' -o '%s' %s -q", cmd, at(runs[k][0]),
                     at("one.ply"), runs[k][1]);
            if (mpi_cli_run(0, args) != 0)
                fail_msg("%s", test_text);
            snprintf(args, sizeof args, "%s '%s' -o '%s' %s --report '%s'", cmd, at(runs[k][0]),
                     at("many.ply"), runs[k][1], at("many.json"));
            if (mpi_cli_run(ranks, args) != 0)
                fail_msg("%s", test_text);
            assert_int_equal(mpi_cli_count(test_text, summary), 1);
            assert_true(mpi_cli_report_sliced(at("many.json")));
            assert_true(test_same_bytes(at("one.ply"), at("many.ply")));
        }
        printf("  %s (%s), %d ranks: same bytes\n", cmd, what, ranks);
    }
}

/* `limn CMD ... OPTIONS` on a bad input (a face naming a vertex the file
   lacks) on 3 ranks: one message, status 1, nothing written; standard output
   as the output (no slices): refused, status 2, said once. */
static void refusals(const char *cmd, const char *options)
{
    char args[1024], error[64];
    assert_int_equal(test_write_text(at("broken.obj"), "v 0 0 0\nv 1 0 0\nf 1 2 7\n"), 0);
    snprintf(args, sizeof args, "%s '%s' -o '%s' %s", cmd, at("broken.obj"), at("bad.ply"),
             options);
    assert_int_equal(mpi_cli_run(3, args), 1);
    snprintf(error, sizeof error, "limn %s: error:", cmd);
    assert_int_equal(mpi_cli_count(test_text, error), 1);
    assert_false(test_file_exists(at("bad.ply")));
    snprintf(args, sizeof args, "%s '%s' -o - --format ply %s", cmd, at("quad.obj"), options);
    assert_int_equal(mpi_cli_run(2, args), 2);
    assert_int_equal(mpi_cli_count(test_text, "standard input or output"), 1);
}

static void subdivide_same(void **s)
{
    (void)s;
    mpi_cli_write_inputs();
    static const char *const runs[][2] = {{"tri.obj", "--levels 2 --limit"},
                                          {"tri.obj", "--levels 1 --scheme catmark"},
                                          {"quad.obj", "--levels 2 --limit --alpha 0.5"}};
    same_on_ranks("subdivide", runs, sizeof runs / sizeof *runs, " faces -> ",
                  "Loop, Catmull-Clark, --limit");
    refusals("subdivide", "--levels 1");
}

static void texture_same(void **s)
{
    (void)s;
    mpi_cli_write_inputs();
    static const char *const runs[][2] = {
        {"tri.obj", "--levels 2 --colors '#ff0000,#00ff00,#0000ff'"},
        {"tri.obj", "--levels 2 --seed 9 --frequency 2.5 --tol 1e-8 --colours '#abc,#123456'"},
        {"quad.obj", "--levels 1 --alpha 0.5 --colors '#102030' --format ply-ascii"},
        {"quad.obj", "--levels 2 --alpha 0.5 --scheme catmark --colors '#f00,#0f0,#00f,#fff' "
                     "--format ply-be"},
        {"tri.obj", "--levels 0 --scheme catmark --alpha 0.5 --colors '#000,#fff'"}};
    same_on_ranks("texture", runs, sizeof runs / sizeof *runs, "vertices and",
                  "Loop, Catmull-Clark, every option");
    refusals("texture", "--colors '#fff'");
    /* Catmull-Clark with alpha 0 on these meshes: a level's interpolation stalls */
    char args[1024];
    snprintf(args, sizeof args, "texture '%s' -o '%s' --colors '#fff' --levels 1",
             at("quad.obj"), at("bad.ply"));
    int one = mpi_cli_run(0, args);
    static char single[sizeof test_text];
    snprintf(single, sizeof single, "%s", test_text);
    assert_int_equal(mpi_cli_run(3, args), one);
    if (one) {
        assert_int_equal(mpi_cli_count(test_text, "limn texture: error:"), 1);
        const char *line = strstr(test_text, "limn texture: error:");
        size_t len = strcspn(line, "\n");
        char want[1024];
        snprintf(want, sizeof want, "%.*s", (int)len, line);
        assert_non_null(strstr(single, want)); /* the single process's message */
        assert_false(test_file_exists(at("bad.ply")));
    }
}

int main(void)
{
    if (!getenv("LIMN_MPIEXEC") || !getenv("LIMN_BIN"))
        return 77;
    const struct CMUnitTest tests[] = {cmocka_unit_test(subdivide_same),
                                       cmocka_unit_test(texture_same)};
    return cmocka_run_group_tests(tests, setup, test_scratch_teardown);
}
