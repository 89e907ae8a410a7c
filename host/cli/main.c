/* limn: command dispatch. */
#include "cli.h"

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
            "  info INPUT [--json]       counts, boundaries, non-manifold elements, bbox\n"
            "  devices                   the OpenCL devices limn can use\n"
            "\n"
            "Run 'limn COMMAND --help' for a command's options. Formats: OBJ, PLY, OFF.\n");
}

int main(int argc, char **argv)
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
    if (strcmp(cmd, "--help") == 0 || strcmp(cmd, "-h") == 0 || strcmp(cmd, "help") == 0) {
        usage(stdout);
        return 0;
    }
    if (strcmp(cmd, "--version") == 0) {
        printf("limn %d.%d.%d\n", LIMN_VERSION_MAJOR, LIMN_VERSION_MINOR, LIMN_VERSION_PATCH);
        return 0;
    }
    fprintf(stderr, "limn: unknown command '%s'\n\n", cmd);
    usage(stderr);
    return EXIT_USAGE;
}
