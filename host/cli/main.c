/* SPDX-License-Identifier: MIT */
/* limn: command dispatch. */
#include "cli.h"

#include <signal.h>
#include <locale.h>
#include <stdio.h>
#include <string.h>

static void usage(FILE *out)
{
    fprintf(out,
            "usage: limn COMMAND [options]\n"
            "\n"
            "commands:\n"
            "  interpolate INPUT -o OUTPUT [--scheme auto|loop|catmark] [--alpha A] [--tol T]\n"
            "              [--max-iter N] [--report FILE.json] [--device SPEC] [-q]\n"
            "      control mesh whose limit surface passes through every vertex of INPUT\n"
            "  subdivide INPUT -o OUTPUT --levels K [--limit] [--scheme S] [--alpha A]\n"
            "              [--max-memory SIZE] [--report FILE.json] [--device SPEC] [-q]\n"
            "      refine a control mesh into its subdivision surface\n"
            "  bands INPUT --count N -o PREFIX      the mesh as bands (E-A)^i A M + remainder\n"
            "  smooth INPUT -o OUTPUT --terms N     partial sum of the first N bands\n"
            "  denoise INPUT -o OUTPUT [--m M] [--steps K] [--keep-volume]\n"
            "      smoothing by Lai & Cheng (2011) eq. 8, volume change reported\n"
            "  sharpen INPUT -o OUTPUT --from M --to N [--steps K]\n"
            "      adds the terms (E-A)^i T, i = M..N\n"
            "  morph FROM TO -o 'frames/f%%04d.ply' [--frames F] [--m M] [--p P] [--linear]\n"
            "      frames from FROM to TO (Lai & Cheng (2011) eq. 9) or the linear blend\n"
            "  texture INPUT -o OUTPUT.ply --colors '#hex,...' [--levels N] [--seed S]\n"
            "      procedural Perlin texture through the interpolation (vertex colours)\n"
            "  render INPUT -o OUTPUT.png [--view AZ,EL] [--size WxH] [--flat]\n"
            "      a shaded picture of a mesh, without a display\n"
            "  info INPUT [--json]       counts, boundaries, non-manifold elements, bbox\n"
            "  devices                   the OpenCL devices limn can use\n"
            "  bench [--vertices N] [--scheme loop|catmark] [--json FILE] [-q]\n"
            "      a whole job on a built mesh of N vertices, timed stage by stage,\n"
            "      against a memory-bandwidth triad on the same device\n"
            "  --version                 print limn's version\n"
            "  --help                    this text\n"
            "\n"
            "Run 'limn COMMAND --help' for a command's options. Formats: OBJ, PLY, OFF, STL.\n");
}

static int dispatch(int argc, char **argv)
{
    if (argc < 2) {
        usage(stderr);
        return EXIT_USAGE;
    }
    const char *cmd = argv[1];
    if (strcmp(cmd, "interpolate") == 0)
        return cli_interpolate(argc - 1, argv + 1);
    if (strcmp(cmd, "info") == 0)
        return cli_info(argc - 1, argv + 1);
    if (strcmp(cmd, "devices") == 0)
        return cli_devices(argc - 1, argv + 1);
    if (strcmp(cmd, "subdivide") == 0)
        return cli_subdivide(argc - 1, argv + 1);
    if (strcmp(cmd, "bench") == 0)
        return cli_bench(argc - 1, argv + 1);
    static const struct {
        const char *name;
        int (*run)(int, char **);
    } series[] = {{"bands", cli_bands},     {"smooth", cli_smooth},   {"denoise", cli_denoise},
                  {"sharpen", cli_sharpen}, {"morph", cli_morph},     {"texture", cli_texture},
                  {"render", cli_render}};
    for (size_t k = 0; k < sizeof series / sizeof *series; k++)
        if (strcmp(cmd, series[k].name) == 0)
            return series[k].run(argc - 1, argv + 1);
    if (strcmp(cmd, "--help") == 0 || strcmp(cmd, "-h") == 0 || strcmp(cmd, "help") == 0) {
        usage(stdout);
        return 0;
    }
    if (strcmp(cmd, "--version") == 0) {
        printf("limn %s\n", limn_version());
        return 0;
    }
    fprintf(stderr, "limn: error: unknown command '%s'\n\n", cmd);
    usage(stderr);
    return EXIT_USAGE;
}

int main(int argc, char **argv)
{
    /* a reader of "-o -" or of a FIFO that goes away is a write error
       (EPIPE, exit status 1, a message), not a silent death by SIGPIPE */
    signal(SIGPIPE, SIG_IGN);
    /* the user's locale, as a real host would have: the library reads and
       writes numbers in the C locale regardless (README "Meshes limn accepts") */
    setlocale(LC_ALL, "");
    /* started by mpirun (a build with LIMN_MPI): MPI_Init and, with several
       ranks, the distributed commands; otherwise no MPI at all */
    if (cli_mpi_launched())
        return cli_mpi_main(argc, argv, dispatch);
    return dispatch(argc, argv);
}
