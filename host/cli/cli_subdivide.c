/* SPDX-License-Identifier: MIT */
/* limn subdivide: refine a control mesh into its subdivision surface. */
#include "cli.h"

#include <stdlib.h>
#include <string.h>

static const char *const help =
    "usage: limn subdivide INPUT -o OUTPUT --levels K [options]\n"
    "\n"
    "Refines INPUT uniformly K times (Catmull-Clark: quads after the first step;\n"
    "Loop: triangles). Vertex i of INPUT is vertex i of OUTPUT; then come one\n"
    "vertex per face (Catmull-Clark) and one per edge of each level.\n"
    "\n"
    "  -o, --output FILE      surface to write (.obj, .ply binary, .off, .stl)\n"
    "  --levels K             refinement levels, 0..16                  [1]\n"
    "  --limit                move the finest vertices onto the limit surface\n"
    "  --scheme S             auto | loop | catmark                     [auto]\n"
    "  --alpha A              Catmull-Clark alpha of the first step     [0]\n"
    "  --max-memory SIZE      refuse when the predicted peak exceeds SIZE\n"
    "                         (bytes, or with K, M, G suffix) [3/4 of RAM]\n"
    "  --report FILE.json     also write the report as JSON\n"
    "  --device SPEC          reference | opencl | opencl:P.D | opencl:NAME\n"
    "  --fallback reference   run on the reference backend when OpenCL fails\n"
    "  --format F, --input-format F, --overwrite-input, -q (as in interpolate)\n"
    CLI_REPAIR_HELP
    CLI_PATHS_HELP;

int cli_subdivide(int argc, char **argv)
{
    const char *input = NULL, *output = NULL, *report = NULL, *device = NULL, *fallback = NULL;
    limn_format in_format = LIMN_FORMAT_AUTO, out_format = LIMN_FORMAT_AUTO;
    limn_subdivide_options o;
    limn_subdivide_options_default(&o);
    int quiet = 0, overwrite_input = 0;
    cli_repair repair = {0, 0};
    static const struct option longopts[] = {
        CLI_FLAG("help"), CLI_VALUE("output"), CLI_VALUE("scheme"), CLI_VALUE("alpha"),
        CLI_VALUE("device"), CLI_VALUE("fallback"), CLI_VALUE("format"), CLI_VALUE("input-format"),
        CLI_VALUE("levels"), CLI_FLAG("limit"), CLI_VALUE("max-memory"), CLI_FLAG("overwrite-input"),
        CLI_FLAG("quiet"), CLI_VALUE("report"), CLI_REPAIR_OPTIONS, CLI_OPTIONS_END};
    int orc = cli_options("subdivide", longopts, "ho:q", &argc, &argv);
    if (orc)
        return orc;
    for (int i = 1; i < argc; i++) {
        const char *s = argv[i], *v = NULL;
#define VALUE()                                                                                \
    do {                                                                                       \
        if (!(v = cli_value(argc, argv, &i)))                                                  \
            return cli_usage_error("subdivide", "%s needs a value", s);                        \
    } while (0)
        if (strcmp(s, "-h") == 0 || strcmp(s, "--help") == 0) {
            fputs(help, stdout);
            return 0;
        } else if (strcmp(s, "-o") == 0 || strcmp(s, "--output") == 0) {
            VALUE();
            output = v;
        } else if (strcmp(s, "--levels") == 0) {
            VALUE();
            if (!cli_parse_int(s, v, &o.levels))
                return EXIT_USAGE;
            if (o.levels < 0 || o.levels > 16)
                return cli_usage_error("subdivide", "--levels %s is outside 0..16", v);
        } else if (strcmp(s, "--limit") == 0) {
            o.limit = 1;
        } else if (strcmp(s, "--scheme") == 0) {
            VALUE();
            if (!cli_parse_scheme("subdivide", v, &o.scheme))
                return EXIT_USAGE;
        } else if (strcmp(s, "--alpha") == 0) {
            VALUE();
            if (!cli_parse_double(s, v, &o.alpha))
                return EXIT_USAGE;
            if (!(o.alpha >= 0 && o.alpha <= 1))
                return cli_usage_error("subdivide", "--alpha %s is outside [0, 1]", v);
        } else if (strcmp(s, "--max-memory") == 0) {
            VALUE();
            if (!cli_parse_size(s, v, &o.max_memory))
                return EXIT_USAGE;
        } else if (strcmp(s, "--report") == 0) {
            VALUE();
            report = v;
        } else if (strcmp(s, "--device") == 0) {
            VALUE();
            device = v;
        } else if (strcmp(s, "--fallback") == 0) {
            VALUE();
            fallback = v;
        } else if (strcmp(s, "--format") == 0 || strcmp(s, "--input-format") == 0) {
            VALUE();
            limn_format f;
            if (!limn_format_from_name(v, &f))
                return cli_usage_error("subdivide",
                                       "%s '%s' is not one of obj, ply, ply-ascii, ply-be, off, stl", s,
                                       v);
            if (s[2] == 'f')
                out_format = f;
            else
                in_format = f;
        } else if (strcmp(s, "--overwrite-input") == 0) {
            overwrite_input = 1;
        } else if (cli_repair_arg(s, &repair)) {
        } else if (strcmp(s, "-q") == 0 || strcmp(s, "--quiet") == 0) {
            quiet = 1;
        } else if (s[0] == '-' && s[1]) {
            return cli_usage_error("subdivide", "unknown option '%s'", s);
        } else if (!input) {
            input = s;
        } else {
            return cli_usage_error("subdivide", "unexpected argument '%s'", s);
        }
#undef VALUE
    }
    if (!input)
        return cli_usage_error("subdivide", "no INPUT mesh given");
    if (!output)
        return cli_usage_error("subdivide", "no output given (-o OUTPUT)");
    int rc = cli_check_output("subdivide", input, output, out_format, overwrite_input);
    if (!rc && report)
        rc = cli_check_output("subdivide", input, report, LIMN_FORMAT_OBJ, overwrite_input);
    const char *outputs[] = {output, report};
    if (!rc)
        rc = cli_check_outputs("subdivide", outputs, 2);
    if (rc)
        return rc;

    limn_context *ctx = limn_context_create();
    if (!ctx)
        return EXIT_FAILURE_RUN;
    limn_context_set_max_memory(ctx, o.max_memory); /* the reader's cap too */
    limn_mesh *mesh = NULL, *surface = NULL;
    limn_subdivide_report r = {.size = sizeof r};
    double sec[3] = {0, 0, 0}, t0 = cli_now();
    limn_status st = limn_context_set_device(ctx, device);
    if (!st && fallback)
        st = limn_context_set_fallback(ctx, fallback);
    if (!st)
        st = cli_load_mesh("subdivide", ctx, input, in_format, &repair, 1, &mesh);
    sec[0] = cli_now() - t0;
    /* a device failure runs again on the reference backend when that is allowed */
    for (int attempt = 0; !st && attempt < 2; attempt++) {
        cli_progress_enable(ctx, quiet);
        st = limn_subdivide(ctx, mesh, &o, &surface, &r);
        cli_progress_done();
        cli_print_warnings("subdivide", ctx);
        if (!st || !cli_fall_back("subdivide", ctx, &st))
            break;
    }
    /* the surface and the report are both complete before either appears */
    limn_output_set *set = NULL;
    if (!st)
        st = limn_output_set_create(ctx, &set);
    if (!st) {
        double t1 = cli_now();
        st = limn_output_set_add_mesh(ctx, set, surface, output, out_format);
        sec[1] = cli_now() - t1;
        sec[2] = cli_now() - t0;
    }
    if (!st && report) {
        json_out *j = json_begin();
        json_string(j, "command", "subdivide");
        json_string(j, "input", input);
        json_string(j, "output", output);
        json_integer(j, "vertices", (long long)r.input_vertices);
        json_integer(j, "faces", (long long)r.input_faces);
        json_integer(j, "output_vertices", (long long)r.vertices);
        json_integer(j, "output_faces", (long long)r.faces);
        json_string(j, "scheme", limn_scheme_name(r.scheme));
        json_number(j, "alpha", r.alpha);
        json_integer(j, "levels", r.levels);
        json_bool(j, "limit", r.limit);
        json_integer(j, "stencil_nonzeros", (long long)r.stencil_nonzeros);
        json_integer(j, "estimated_bytes", (long long)r.estimated_bytes);
        json_integer(j, "peak_rss_bytes", (long long)cli_peak_rss());
        json_string(j, "device", r.device);
        json_object_begin(j, "seconds");
        json_number(j, "load", sec[0]);
        json_number(j, "plan", r.seconds_plan);
        json_number(j, "apply", r.seconds_apply);
        json_number(j, "limit", r.seconds_limit);
        json_number(j, "write", sec[1]);
        json_number(j, "total", sec[2]);
        json_object_end(j);
        st = json_stage(ctx, j, report, set);
    }
    st = cli_commit_outputs(ctx, st, set);
    if (st)
        rc = cli_fail("subdivide", ctx, st);
    else if (!quiet)
        fprintf(stderr,
                "limn subdivide: %s -> %s\n"
                "  %zu vertices, %zu faces -> %zu vertices, %zu faces (%s, alpha %g, %d levels%s)\n"
                "  device: %s\n"
                "  seconds: load %.3f, plan %.3f, apply %.3f, limit %.3f, write %.3f; peak "
                "memory %.1f MiB (estimated %.1f)\n",
                input, output, r.input_vertices, r.input_faces, r.vertices, r.faces,
                limn_scheme_name(r.scheme), r.alpha, r.levels, r.limit ? ", limit positions" : "",
                r.device, sec[0], r.seconds_plan, r.seconds_apply, r.seconds_limit, sec[1],
                (double)cli_peak_rss() / (1 << 20), (double)r.estimated_bytes / (1 << 20));
    limn_mesh_destroy(mesh);
    limn_mesh_destroy(surface);
    limn_context_destroy(ctx);
    return rc;
}
