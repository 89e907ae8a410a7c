/* SPDX-License-Identifier: MIT */
/*
 * `mpirun -np N limn denoise --preserve-features` (issue 16 item 4): on 2,
 * 3 and 5 ranks, on slices (no rank holding the whole mesh:
 * limn_mpi_mesh_denoise_features), the very bytes of one process, with and
 * without --keep-volume, on noisy CAD-like meshes (tests/cad_shapes.c:
 * a bevelled cube of triangles, a chamfered puck of quads) and the shared
 * fandisk when ../shared/meshes is there; a bad input gives one message,
 * exit status 1 and nothing written; an input that cannot be sliced is
 * refused (status 2). A separate file: test_mpi_cli.c is at its size limit
 * (the launcher, shared with test_mpi_cli.c and test_mpi_cli_refine.c: mpi_cli.c).
 */
#include "cad_shapes.h"
#include "mpi_cli.h"
#include "noise.h"
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
    return test_scratch_make("mpi_cli_features", NULL);
}

static const char *at(const char *name) { return test_join(test_dir, name); }

/* shape's mesh with seeded noise of 0.3 mean edges, written to path. */
static void write_noisy(cad_shape shape, int n, int triangles, uint64_t seed, const char *path)
{
    limn_context *ctx = limn_context_create();
    limn_mesh *m = cad_shape_mesh(ctx, shape, n, triangles);
    assert_non_null(m);
    test_gaussian_noise(m, 0.3 * test_mean_edge(m), seed);
    assert_int_equal(limn_mesh_write(ctx, m, path, LIMN_FORMAT_AUTO), LIMN_OK);
    limn_mesh_destroy(m);
    limn_context_destroy(ctx);
}

/* One process, then 2, 3 and 5 ranks: the same bytes, on slices. */
static void same_on_ranks(const char *path, const char *extra)
{
    char args[4096], input[1024];
    snprintf(input, sizeof input, "%s", path); /* test_join's buffers rotate */
    snprintf(args, sizeof args, "denoise '%s' -o '%s' --preserve-features %s -q", input,
             at("one.ply"), extra);
    if (mpi_cli_run(0, args) != 0)
        fail_msg("%s", test_text);
    for (int ranks = 2; ranks <= 5; ranks += ranks == 3 ? 2 : 1) {
        remove(at("many.ply"));
        snprintf(args, sizeof args,
                 "denoise '%s' -o '%s' --preserve-features %s --report '%s' -q", input,
                 at("many.ply"), extra, at("many.json"));
        if (mpi_cli_run(ranks, args) != 0)
            fail_msg("%d ranks: %s", ranks, test_text);
        if (!test_same_bytes(at("one.ply"), at("many.ply")))
            fail_msg("%s %s on %d ranks: not the single process's bytes", input, extra, ranks);
        assert_true(mpi_cli_report_sliced(at("many.json")));
    }
}

static void features_same(void **s)
{
    (void)s;
    write_noisy(CAD_BEVELLED_CUBE, 6, 1, 1601, at("bevel.ply"));
    write_noisy(CAD_PART, 6, 0, 1602, at("puck.obj"));
    static const char *const extras[] = {"", "--keep-volume",
                                         "--normal-steps 3 --vertex-steps 4 --outer-steps 3 "
                                         "--sigma-r 0.5 --tangential 0"};
    for (int e = 0; e < 3; e++) {
        same_on_ranks(at("bevel.ply"), extras[e]);
        same_on_ranks(at("puck.obj"), extras[e]);
    }
    if (test_shared_meshes()) {
        char path[1024];
        snprintf(path, sizeof path, "%s", test_shared_path("small/fandisk_quads.off"));
        same_on_ranks(path, "--keep-volume");
    }
}

/* A bad input (a face naming a vertex the file lacks), --keep-volume on an
   open mesh: one message, status 1, nothing written; stdout as the output
   (no slices) refused before anything runs. */
static void features_errors(void **s)
{
    (void)s;
    char args[4096];
    assert_int_equal(test_write_text(at("broken.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"
                                                       "f 1 3 9\n"),
                     0);
    snprintf(args, sizeof args, "denoise '%s' -o '%s' --preserve-features", at("broken.obj"),
             at("bad.ply"));
    assert_int_equal(mpi_cli_run(3, args), 1);
    assert_int_equal(mpi_cli_count(test_text, "limn denoise: error:"), 1);
    assert_false(test_file_exists(at("bad.ply")));
    assert_int_equal(test_write_text(at("open.obj"), "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                                     "v 2 0 0\nv 2 1 0\nf 1 2 3 4\nf 2 5 6 3\n"),
                     0);
    snprintf(args, sizeof args, "denoise '%s' -o '%s' --preserve-features --keep-volume",
             at("open.obj"), at("bad.ply"));
    assert_int_equal(mpi_cli_run(3, args), 1);
    assert_int_equal(mpi_cli_count(test_text, "limn denoise: error:"), 1);
    assert_int_equal(mpi_cli_count(test_text, "keeping the volume needs a closed mesh"), 1);
    assert_false(test_file_exists(at("bad.ply")));
    snprintf(args, sizeof args, "denoise '%s' -o - --preserve-features", at("open.obj"));
    assert_int_equal(mpi_cli_run(2, args), 2);
    assert_int_equal(mpi_cli_count(test_text, "on slices only"), 1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(features_same),
                                       cmocka_unit_test(features_errors)};
    return cmocka_run_group_tests(tests, setup, test_scratch_teardown);
}
