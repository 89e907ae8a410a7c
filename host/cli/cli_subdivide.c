/* SPDX-License-Identifier: MIT */
/* limn subdivide: refine a control mesh into its subdivision surface. */
#include "cli_args.h"

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
    "  --format F, --input-format F, --output-precision P, --overwrite-input, -q\n"
    "                         (as in interpolate)\n"
    "Under mpirun (several ranks) on a .ply/.obj/.off file every rank reads its\n"
    "slice, refines its share and writes its part of OUTPUT (the same bytes);\n"
    "--max-memory is then a rank's limit (default: 3/4 of RAM over the ranks on\n"
    "the node) against a rank's share of the estimate; --fallback is not applied.\n"
    CLI_REPAIR_HELP
    CLI_HOST_THREADS_HELP
    CLI_PATHS_HELP;

static int own_option(cli_args *a, void *user, int argc, char **argv, int *i)
{
    limn_subdivide_options *o = user;
    const char *s = argv[*i], *v;
    const cli_own_option own[] = {
        {"--limit", CLI_OWN_FLAG, &o->limit, 1, 0},
        {"--max-memory", CLI_OWN_SIZE, &o->max_memory, 0, 0},
    };
    int rc = cli_args_own(a, argc, argv, i, own, sizeof own / sizeof *own);
    if (rc != CLI_OWN_UNKNOWN || strcmp(s, "--levels") != 0)
        return rc;
    if (!(v = cli_args_value(a, argc, argv, i)))
        return EXIT_USAGE;
    if (!cli_parse_int(s, v, &o->levels))
        return EXIT_USAGE;
    if (o->levels < 0 || o->levels > 16)
        return cli_usage_error(a->cmd, "--levels %s is outside 0..16", v);
    return 0;
}

/* load, write, total */
static limn_status write_report(limn_context *ctx, const cli_args *a,
                                const limn_subdivide_report *r, const double sec[3],
                                limn_output_set *set)
{
    json_out *j = cli_args_report(a, r->input_vertices, r->input_faces);
    if (!j)
        return cli_error(LIMN_ERR_MEMORY, "out of memory for the report");
    json_integer(j, "output_vertices", (long long)r->vertices);
    json_integer(j, "output_faces", (long long)r->faces);
    json_string(j, "scheme", limn_scheme_name(r->scheme));
    json_number(j, "alpha", r->alpha);
    json_integer(j, "levels", r->levels);
    json_bool(j, "limit", r->limit);
    json_integer(j, "stencil_nonzeros", (long long)r->stencil_nonzeros);
    json_integer(j, "estimated_bytes", (long long)r->estimated_bytes);
    json_integer(j, "peak_rss_bytes", (long long)cli_peak_rss());
    json_string(j, "device", r->device);
    cli_mpi_json(j);
    json_object_begin(j, "seconds");
    json_number(j, "load", sec[0]);
    json_number(j, "plan", r->seconds_plan);
    json_number(j, "apply", r->seconds_apply);
    json_number(j, "limit", r->seconds_limit);
    json_number(j, "write", sec[1]);
    json_number(j, "total", sec[2]);
    json_object_end(j);
    return json_stage(ctx, j, a->report, set);
}

static void print_summary(const cli_args *a, const limn_subdivide_report *r, const double sec[3])
{
    fprintf(stderr,
            "limn subdivide: %s -> %s\n"
            "  %zu vertices, %zu faces -> %zu vertices, %zu faces (%s, alpha %g, %d levels%s)\n"
            "  device: %s\n"
            "  seconds: load %.3f, plan %.3f, apply %.3f, limit %.3f, write %.3f; peak "
            "memory %.1f MiB (estimated %.1f)\n",
            a->inputs[0], a->output, r->input_vertices, r->input_faces, r->vertices, r->faces,
            limn_scheme_name(r->scheme), r->alpha, r->levels, r->limit ? ", limit positions" : "",
            r->device, sec[0], r->seconds_plan, r->seconds_apply, r->seconds_limit, sec[1],
            (double)cli_peak_rss() / (1 << 20), (double)r->estimated_bytes / (1 << 20));
}

/* Refines; a device failure runs again on the reference backend when that
   is allowed. */
static limn_status refine(limn_context *ctx, const cli_args *a, const limn_mesh *mesh,
                          const limn_subdivide_options *o, limn_mesh **surface,
                          limn_subdivide_report *r)
{
    limn_status st = LIMN_OK;
    for (int attempt = 0; attempt < 2; attempt++) {
        cli_progress_enable(ctx, a->quiet);
        st = limn_subdivide(ctx, mesh, o, surface, r);
        cli_progress_done();
        cli_print_warnings("subdivide", ctx);
        if (!st || !cli_fall_back("subdivide", ctx, &st))
            break;
    }
    return st;
}

/* The surface and the report (rank 0's) staged, then committed together. */
static int finish(limn_context *ctx, cli_args *a, limn_status st, const limn_mesh *surface,
                  const limn_subdivide_report *r, double sec[3], double t0)
{
    limn_output_set *set = a->staged; /* on slices: it holds the surface already */
    a->staged = NULL;
    if (!st && !set)
        st = limn_output_set_create(ctx, &set);
    if (!st && surface) {
        double t1 = cli_now();
        st = cli_args_stage_output(a, ctx, set, surface, a->output);
        sec[1] = cli_now() - t1;
    }
    sec[2] = cli_now() - t0;
    cli_mpi_note_memory();
    if (!st && a->report && cli_mpi_rank() == 0)
        st = write_report(ctx, a, r, sec, set);
    st = cli_commit_outputs(ctx, st, set);
    int rc = st ? cli_fail("subdivide", ctx, st) : 0;
    if (!st && !a->quiet) {
        print_summary(a, r, sec);
        cli_mpi_print();
        cli_args_print_written(a);
    }
    return rc;
}

/* Under mpirun on a file: every rank reads its slice, refines its share and
   writes its part of the surface (limn_mpi_mesh_subdivide); rank 0 reports. */
static int run_sliced(cli_args *a, const limn_subdivide_options *o)
{
    limn_context *ctx = cli_sliced_context(a->cmd);
    if (!ctx)
        return EXIT_FAILURE_RUN;
    double sec[3] = {0, 0, 0}, t0 = cli_now();
    limn_status st = cli_set_host_threads(ctx, a->host_threads);
    if (!st)
        st = limn_context_set_device(ctx, a->device);
    a->quiet |= cli_mpi_rank() != 0; /* under mpirun rank 0 prints */
    st = cli_mpi_agree(ctx, st);
    if (!st) /* the surface staged there, to appear with the report (finish) */
        st = cli_mpi_agree(ctx, limn_output_set_create(ctx, &a->staged));
    limn_write_options wo;
    limn_write_options_default(&wo);
    wo.precision = a->precision;
    cli_sliced_job job = {a->cmd,       a->inputs[0],  a->output, &a->repair,
                          a->in_format, a->out_format, &wo,       0,
                          a->staged};
    limn_subdivide_report r = {.size = sizeof r};
    limn_write_report wr = {.size = sizeof wr};
    double io[2] = {0, 0};
    if (!st) {
        cli_progress_enable(ctx, a->quiet);
        st = cli_mpi_subdivide_sliced(ctx, &job, o, &r, &wr, io);
        cli_progress_done();
    }
    sec[0] = io[0];
    sec[1] = io[1];
    a->written = wr;
    a->wrote = !st;
    int rc = finish(ctx, a, st, NULL, &r, sec, t0);
    limn_context_destroy(ctx);
    return rc;
}

static int run(cli_args *a, const limn_subdivide_options *o)
{
    if (cli_mpi_ranks() > 1) {
        if (cli_mpi_sliced(a->inputs[0], a->in_format, a->output, 0))
            return run_sliced(a, o);
        if (cli_mpi_rank() == 0)
            cli_usage_error(a->cmd, "on several MPI ranks the input and the output must be "
                            ".ply, .obj or .off files (not standard input or output)");
        return EXIT_USAGE;
    }

    limn_context *ctx = cli_context(a->cmd);
    if (!ctx)
        return EXIT_FAILURE_RUN;
    limn_mesh *mesh = NULL, *surface = NULL;
    limn_subdivide_report r = {.size = sizeof r};
    double sec[3] = {0, 0, 0}, t0 = cli_now();
    limn_status st = cli_args_open(a, ctx, o->max_memory, 1, &mesh);
    sec[0] = cli_now() - t0;
    if (!st)
        st = refine(ctx, a, mesh, o, &surface, &r);
    /* the surface and the report are both complete before either appears */
    int rc = finish(ctx, a, st, surface, &r, sec, t0);
    limn_mesh_destroy(mesh);
    limn_mesh_destroy(surface);
    limn_context_destroy(ctx);
    return rc;
}

int cli_subdivide(int argc, char **argv)
{
    cli_args a = {.cmd = "subdivide", .help = help, .inputs_wanted = 1,
                  .formats = "obj, ply, ply-ascii, ply-be, off, stl"};
    limn_subdivide_options o;
    limn_subdivide_options_default(&o);
    a.scheme = &o.scheme;
    a.alpha = &o.alpha;
    static const struct option longopts[] = {
        CLI_ARGS_OPTIONS,  CLI_VALUE("output-precision"), CLI_VALUE("fallback"),   CLI_VALUE("levels"),
        CLI_FLAG("limit"), CLI_VALUE("max-memory"), CLI_OPTIONS_END};
    int rc = cli_args_parse(&a, longopts, argc, argv, own_option, &o);
    if (rc)
        return rc < 0 ? 0 : rc;
    rc = cli_args_required(&a);
    if (!rc)
        rc = cli_args_check_meshes(&a, NULL);
    return rc ? rc : run(&a, &o);
}
