/* SPDX-License-Identifier: MIT */
#include "mpi_cli.h"
#include "shell.h"
#include "support.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

static const char *at(const char *name) { return test_join(test_dir, name); }

/* Under the sanitizers the ranks run without LeakSanitizer: its
   stop-the-world tracer segfaults at exit while Open MPI's and PoCL's
   threads wind down ("Tracer caught signal 11 ... LeakSanitizer has
   encountered a fatal error", google/sanitizers#1353) - seen three times in
   a row on a loaded CI machine, after limn had written its output. The same
   code's leaks are still checked: by the one-process runs here and by
   test_mpi (the MPI layer in process, 2 and 3 ranks). Memory errors and
   undefined behaviour still fail the ranks. */
int mpi_cli_run(int ranks, const char *args)
{
    char cmd[8192];
    const char *asan = getenv("ASAN_OPTIONS");
    char no_leaks[512] = "";
    if (asan)
        snprintf(no_leaks, sizeof no_leaks, "ASAN_OPTIONS='%s:detect_leaks=0' ", asan);
    if (ranks > 0)
        snprintf(cmd, sizeof cmd, "%stimeout 300 %s %d '%s' %s 2>&1", no_leaks,
                 getenv("LIMN_MPIEXEC"), ranks, getenv("LIMN_BIN"), args);
    else
        snprintf(cmd, sizeof cmd, "'%s' %s 2>&1", getenv("LIMN_BIN"), args);
    return test_run(test_text, sizeof test_text, cmd);
}

size_t mpi_cli_count(const char *hay, const char *needle)
{
    size_t n = 0;
    for (const char *p = strstr(hay, needle); p; p = strstr(p + 1, needle))
        n++;
    return n;
}

int mpi_cli_report_sliced(const char *path)
{
    size_t n = 0;
    char *text = test_slurp(path, &n);
    int yes = text && strstr(text, "\"distributed_mesh\": true") != NULL;
    free(text);
    return yes;
}

void mpi_cli_write_inputs(void)
{
    limn_context *ctx = limn_context_create();
    limn_mesh *grid = test_mesh_grid(ctx, 40, 30, 1), *quads = test_mesh_grid(ctx, 40, 30, 0);
    limn_mesh *ico = test_mesh_icosahedron(ctx), *cube = test_mesh_cube(ctx);
    /* two components each: an OBJ by hand (the grid, then the closed piece) */
    const limn_mesh *pairs[2][2] = {{grid, ico}, {quads, cube}};
    const char *names[2] = {"tri.obj", "quad.obj"};
    for (int k = 0; k < 2; k++) {
        FILE *f = fopen(at(names[k]), "w");
        assert_non_null(f);
        size_t base = 0;
        for (int part = 0; part < 2; part++) {
            const limn_mesh *m = pairs[k][part];
            const double *p = limn_mesh_positions(m);
            for (size_t i = 0; i < limn_mesh_vertex_count(m); i++)
                fprintf(f, "v %.17g %.17g %.17g\n", p[3 * i] + 50.0 * part, p[3 * i + 1],
                        p[3 * i + 2]);
            if (part == 0) {
                fprintf(f, "v -5 -5 0\n"); /* isolated */
                base++;
            }
            const uint32_t *off = limn_mesh_face_offsets(m), *idx = limn_mesh_face_indices(m);
            for (size_t fc = 0; fc < limn_mesh_face_count(m); fc++) {
                fprintf(f, "f");
                for (uint32_t c = off[fc]; c < off[fc + 1]; c++)
                    fprintf(f, " %zu", (size_t)idx[c] + 1 + (part ? base : 0));
                fprintf(f, "\n");
            }
            base += limn_mesh_vertex_count(m);
        }
        assert_int_equal(fclose(f), 0);
    }
    limn_mesh_destroy(grid);
    limn_mesh_destroy(quads);
    limn_mesh_destroy(ico);
    limn_mesh_destroy(cube);
    limn_context_destroy(ctx);
}
