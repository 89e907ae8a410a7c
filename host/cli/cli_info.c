/* limn info: what a mesh is made of, as text or JSON on stdout. */
#include "cli.h"

#include <string.h>

static const char *const help =
    "usage: limn info INPUT [--json] [--input-format F] [--no-repair]\n"
    "                       [--drop-duplicate-faces]\n"
    "\n"
    "Prints vertex, face and edge counts, face kinds, boundary loops, components,\n"
    "non-manifold elements, the Euler characteristic, the bounding box and the\n"
    "scheme 'auto' would choose, of the mesh as the other commands see it: after\n"
    "the repair step, whose changes are printed as warnings.\n"
    CLI_REPAIR_HELP;

int cli_info(int argc, char **argv)
{
    const char *input = NULL;
    int json = 0;
    limn_format fmt = LIMN_FORMAT_AUTO;
    cli_repair repair = {0, 0};
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
    limn_context *ctx = limn_context_create();
    if (!ctx)
        return EXIT_FAILURE_RUN;
    limn_mesh *mesh = NULL;
    limn_mesh_info in;
    limn_status st = cli_load_mesh("info", ctx, input, fmt, &repair, 0, &mesh);
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
        printf("{\"file\": \"%s\", \"vertices\": %zu, \"faces\": %zu, \"edges\": %zu, "
               "\"referenced_vertices\": %zu, \"triangles\": %zu, \"quads\": %zu, "
               "\"other_faces\": %zu, \"max_face_size\": %zu, \"max_valence\": %zu, "
               "\"boundary_edges\": %zu, \"boundary_loops\": %zu, \"components\": %zu, "
               "\"nonmanifold_edges\": %zu, \"nonmanifold_vertices\": %zu, "
               "\"inconsistent_orientation_edges\": %zu, \"euler_characteristic\": %ld, "
               "\"bbox\": [[%.17g, %.17g, %.17g], [%.17g, %.17g, %.17g]], "
               "\"bbox_diagonal\": %.17g, \"auto_scheme\": \"%s\"}\n",
               input, in.vertices, in.faces, in.edges, in.referenced_vertices, in.triangles,
               in.quads, in.other_faces, in.max_face_size, in.max_valence, in.boundary_edges,
               in.boundary_loops, in.components, in.nonmanifold_edges, in.nonmanifold_vertices,
               in.inconsistent_edges, in.euler_characteristic, in.bbox_min[0], in.bbox_min[1],
               in.bbox_min[2], in.bbox_max[0], in.bbox_max[1], in.bbox_max[2], in.bbox_diagonal,
               scheme);
    } else {
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
               input, in.vertices, in.referenced_vertices, in.faces, in.triangles, in.quads,
               in.other_faces, in.max_face_size, in.edges, in.max_valence, in.boundary_edges,
               in.boundary_loops, in.components,
               in.nonmanifold_edges || in.nonmanifold_vertices ? "NO" : "yes",
               in.nonmanifold_edges, in.nonmanifold_vertices, in.inconsistent_edges,
               in.euler_characteristic, in.bbox_min[0], in.bbox_min[1], in.bbox_min[2],
               in.bbox_max[0], in.bbox_max[1], in.bbox_max[2], in.bbox_diagonal, scheme);
    }
    limn_mesh_destroy(mesh);
    limn_context_destroy(ctx);
    return 0;
}
