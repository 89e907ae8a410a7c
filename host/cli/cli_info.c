/* SPDX-License-Identifier: MIT */
/* limn info: what a mesh is made of, as text or JSON on stdout. */
#include "cli.h"

#include <string.h>

static const char *const help =
    "usage: limn info INPUT [--json] [--input-format F] [--max-memory SIZE]\n"
    "                       [--no-repair] [--drop-duplicate-faces] [--host-threads N]\n"
    "\n"
    "Prints vertex, face and edge counts, face kinds, boundary loops, components,\n"
    "non-manifold elements, the Euler characteristic, the bounding box and the\n"
    "scheme 'auto' would choose, of the mesh as the other commands see it: after\n"
    "the repair step, whose changes are printed as warnings. --json prints one line\n"
    "of JSON. A pipe or device is read only with --input-format; reading stops\n"
    "beyond --max-memory (default three quarters of physical memory).\n"
    CLI_REPAIR_HELP
    CLI_HOST_THREADS_HELP;

static limn_status print_json(limn_context *ctx, const char *input, const limn_mesh_info *in,
                              const char *scheme)
{
    json_out *j = json_begin_line();
    if (!j)
        return cli_error(LIMN_ERR_MEMORY, "out of memory writing JSON");
    json_string(j, "file", input);
    const struct { const char *key; size_t value; } counts[] = {
        {"vertices", in->vertices},
        {"faces", in->faces},
        {"edges", in->edges},
        {"referenced_vertices", in->referenced_vertices},
        {"triangles", in->triangles},
        {"quads", in->quads},
        {"other_faces", in->other_faces},
        {"max_face_size", in->max_face_size},
        {"max_valence", in->max_valence},
        {"boundary_edges", in->boundary_edges},
        {"boundary_loops", in->boundary_loops},
        {"components", in->components},
        {"nonmanifold_edges", in->nonmanifold_edges},
        {"nonmanifold_vertices", in->nonmanifold_vertices},
        {"inconsistent_orientation_edges", in->inconsistent_edges},
    };
    for (size_t i = 0; i < sizeof counts / sizeof *counts; i++)
        json_integer(j, counts[i].key, (long long)counts[i].value);
    json_integer(j, "euler_characteristic", in->euler_characteristic);
    json_array_begin(j, "bbox");
    for (int c = 0; c < 2; c++) {
        const double *corner = c ? in->bbox_max : in->bbox_min;
        json_element_array_begin(j);
        for (int k = 0; k < 3; k++)
            json_element_number(j, corner[k]);
        json_array_end(j);
    }
    json_array_end(j);
    json_number(j, "bbox_diagonal", in->bbox_diagonal);
    json_string(j, "auto_scheme", scheme);
    return json_print(ctx, j, stdout);
}

static void print_text(const char *input, const limn_mesh_info *in, const char *scheme)
{
    printf("%s\n"
           "  vertices   %zu (%zu used by faces)\n"
           "  faces      %zu (%zu triangles, %zu quads, %zu other; largest %zu sides)\n"
           "  edges      %zu (max valence %zu)\n"
           "  boundary   %zu edges in %zu loops\n"
           "  components %zu\n"
           "  manifold   %s (%zu non-manifold edges, %zu non-manifold vertices, %zu edges "
           "with inconsistent orientation)\n"
           "  euler      %ld\n"
           "  bbox       [%g %g %g] - [%g %g %g], diagonal %g\n"
           "  scheme     %s (for --scheme auto)\n",
           input, in->vertices, in->referenced_vertices, in->faces, in->triangles, in->quads,
           in->other_faces, in->max_face_size, in->edges, in->max_valence, in->boundary_edges,
           in->boundary_loops, in->components,
           in->nonmanifold_edges || in->nonmanifold_vertices ? "NO" : "yes",
           in->nonmanifold_edges, in->nonmanifold_vertices, in->inconsistent_edges,
           in->euler_characteristic, in->bbox_min[0], in->bbox_min[1], in->bbox_min[2],
           in->bbox_max[0], in->bbox_max[1], in->bbox_max[2], in->bbox_diagonal, scheme);
}

int cli_info(int argc, char **argv)
{
    const char *input = NULL;
    int json = 0;
    limn_format fmt = LIMN_FORMAT_AUTO;
    cli_repair repair = {.counts_only = 1}; /* the counts alone: no topology */
    size_t max_memory = 0;
    int host_threads = 0;
    static const struct option longopts[] = {
        CLI_FLAG("help"),        CLI_FLAG("json"),         CLI_VALUE("input-format"),
        CLI_VALUE("max-memory"), CLI_VALUE("host-threads"), CLI_REPAIR_OPTIONS, CLI_OPTIONS_END};
    int orc = cli_options("info", longopts, "h", &argc, &argv);
    if (orc)
        return orc;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "-h") == 0 || strcmp(argv[i], "--help") == 0) {
            fputs(help, stdout);
            return 0;
        } else if (strcmp(argv[i], "--json") == 0) {
            json = 1;
        } else if (cli_repair_arg(argv[i], &repair)) {
        } else if (strcmp(argv[i], "--input-format") == 0) {
            const char *v = cli_value(argc, argv, &i);
            if (!v || !limn_format_from_name(v, &fmt))
                return cli_usage_error("info", "--input-format needs one of obj, ply, off, stl");
        } else if (strcmp(argv[i], "--host-threads") == 0) {
            const char *v = cli_value(argc, argv, &i);
            if (!v || cli_parse_host_threads("info", v, &host_threads))
                return v ? EXIT_USAGE : cli_usage_error("info", "--host-threads needs a value");
        } else if (strcmp(argv[i], "--max-memory") == 0) {
            const char *v = cli_value(argc, argv, &i);
            if (!v)
                return cli_usage_error("info", "--max-memory needs a size such as 512M or 4G");
            if (!cli_parse_size("--max-memory", v, &max_memory))
                return EXIT_USAGE;
        } else if (argv[i][0] == '-' && argv[i][1]) {
            return cli_usage_error("info", "unknown option '%s'", argv[i]);
        } else if (!input) {
            input = argv[i];
        } else {
            return cli_usage_error("info", "unexpected argument '%s'", argv[i]);
        }
    }
    if (!input)
        return cli_usage_error("info", "no INPUT mesh given");
    limn_context *ctx = cli_context("info");
    if (!ctx)
        return EXIT_FAILURE_RUN;
    limn_context_set_max_memory(ctx, max_memory);
    limn_mesh *mesh = NULL;
    limn_mesh_info in = {.size = sizeof in};
    limn_context_set_host_threads(ctx, host_threads); /* 1..64 (parsed) or 0: the default */
    limn_status st = cli_load_mesh("info", ctx, input, fmt, &repair, 0, 0, &mesh);
    if (!st)
        st = limn_mesh_info_compute(ctx, mesh, &in);
    if (st) {
        int rc = cli_fail("info", ctx, st);
        limn_mesh_destroy(mesh);
        limn_context_destroy(ctx);
        return rc;
    }
    const char *scheme = in.faces > 0 && in.quads == 0 && in.other_faces == 0 ? "loop" : "catmark";
    if (json) {
        st = print_json(ctx, input, &in, scheme);
    } else {
        cli_locale loc; /* "%g" with a '.', as in the files, whatever the locale */
        int entered = cli_locale_enter(&loc);
        print_text(input, &in, scheme);
        if (entered)
            cli_locale_leave(&loc);
    }
    if (st) {
        int rc = cli_fail("info", ctx, st);
        limn_mesh_destroy(mesh);
        limn_context_destroy(ctx);
        return rc;
    }
    limn_mesh_destroy(mesh);
    limn_context_destroy(ctx);
    return 0;
}
