/* SPDX-License-Identifier: MIT */
/* limn interpolate: solve for the control mesh, write it and a report. */
#include "cli_args.h"

#include <limits.h>
#include <stdlib.h>
#include <string.h>

static const char *const help =
    "usage: limn interpolate INPUT -o OUTPUT [options]\n"
    "\n"
    "Computes the control mesh P whose subdivision limit surface passes through\n"
    "every vertex of INPUT (same faces, same vertex order) and writes it.\n"
    "\n"
    "  -o, --output FILE      control mesh to write (.obj, .ply binary, .off, .stl)\n"
    "  --scheme S             auto (Loop for triangle meshes, else Catmull-Clark),\n"
    "                         loop or catmark                        [auto]\n"
    "  --alpha A              Catmull-Clark alpha in [0, 1]; 0 is the standard\n"
    "                         surface (OpenSubdiv's), 0.5 avoids the singular\n"
    "                         valence-3 case                          [0]\n"
    "  --tol T                stop when max |M - A P| <= T * bbox diagonal [1e-6]\n"
    "  --max-iter N           iteration cap                            [1000]\n"
    "  --report FILE.json     also write the report as JSON\n"
    "  --device SPEC          reference | opencl | opencl:P.D | opencl:NAME\n"
    "                         (default: LIMN_DEVICE etc., then the first device)\n"
    "  --fallback reference   when the OpenCL device cannot be used, run on the\n"
    "                         reference backend instead, with a warning\n"
    "                         (default: LIMN_FALLBACK, else none: fail)\n"
    "  --format F             output format: obj, ply, ply-ascii, ply-be, off, stl\n"
    "  --output-precision P   double (default, lossless) or float: PLY positions as\n"
    "                         float32; the report gives the error as written\n"
    "  --input-format F       input format, when the extension does not say\n"
    "  --surface FILE         also refine P and write its subdivision surface\n"
    "  --levels K             refinement levels of the surface, 0..16    [2]\n"
    "  --limit                put the surface's finest vertices on the limit\n"
    "                         surface: vertex i of it is then M_i to --tol\n"
    "  --max-memory SIZE      refuse, before any work, when the predicted peak\n"
    "                         memory (of the solve, or of the surface) exceeds\n"
    "                         SIZE (bytes, or with K, M, G suffix)   [3/4 of RAM]\n"
    CLI_REPAIR_HELP
    CLI_HOST_THREADS_HELP
    "  --method M             auto (the fastest measured: chebyshev),\n"
    "                         paper (the seeds' iteration, the reference),\n"
    "                         weighted, chebyshev (one fused step a product),\n"
    "                         cg (Jacobi-preconditioned CG),\n"
    "                         sgs (CG with symmetric Gauss-Seidel: fewest\n"
    "                         products)                                 [auto]\n"
    "  --precision P          auto (float from 200,000 vertices), double, or\n"
    "                         float: corrections iterated in float, residuals\n"
    "                         and the stop test in double (not cg, sgs)  [auto]\n"
    "  --no-reorder           keep the input vertex order inside the solve\n"
    "                         (default: RCM for paper, weighted)\n"
    "  --overwrite-input      allow OUTPUT to be the INPUT file\n"
    "  -q, --quiet            no summary and no progress on stderr\n"
    CLI_MPI_HELP
    CLI_PATHS_HELP
    "\n"
    "Under 'mpirun -np N' (N > 1) the vertices are split across the ranks (README\n"
    "\"MPI\"): rank 0 reads INPUT and writes OUTPUT, the same bits as one process.\n"
    "Exit status: 0 success, 1 failure (nothing written), 2 bad usage.\n";

typedef struct args {
    cli_args a; /* a.inputs[0] is INPUT */
    const char *surface;
    limn_interpolate_options opt;
    limn_subdivide_options sub;
    int levels_given;
    size_t estimated_bytes; /* limn_interpolate_estimate's, for the report */
} args;

/* --method M / --precision P. */
static int choice_option(args *x, const char *opt, const char *v)
{
    static const char *const methods[] = {"auto", "paper", "weighted", "chebyshev", "cg", "sgs"};
    static const limn_method method_values[] = {LIMN_METHOD_AUTO,      LIMN_METHOD_PAPER,
                                                LIMN_METHOD_WEIGHTED,  LIMN_METHOD_CHEBYSHEV,
                                                LIMN_METHOD_CG,        LIMN_METHOD_SGS};
    static const char *const precisions[] = {"auto", "double", "float"};
    static const limn_precision precision_values[] = {
        LIMN_PRECISION_AUTO, LIMN_PRECISION_DOUBLE, LIMN_PRECISION_FLOAT};
    int method = strcmp(opt, "--method") == 0;
    int k = method ? cli_args_choice(&x->a, opt, v, methods, 6)
                   : cli_args_choice(&x->a, opt, v, precisions, 3);
    if (k < 0)
        return EXIT_USAGE;
    if (method)
        x->opt.method = method_values[k];
    else
        x->opt.precision = precision_values[k];
    return 0;
}

static int own_option(cli_args *a, void *user, int argc, char **argv, int *i)
{
    args *x = user;
    const char *s = argv[*i], *v;
    const cli_own_option own[] = {
        {"--tol", CLI_OWN_POSITIVE, &x->opt.tolerance, 0, 0},
        {"--max-iter", CLI_OWN_INT, &x->opt.max_iterations, 1, INT_MAX},
        {"--limit", CLI_OWN_FLAG, &x->sub.limit, 1, 0},
        {"--no-reorder", CLI_OWN_FLAG, &x->opt.reorder, 0, 0},
        {"--max-memory", CLI_OWN_SIZE, &x->sub.max_memory, 0, 0},
    };
    int rc = cli_args_own(a, argc, argv, i, own, sizeof own / sizeof *own);
    if (rc != CLI_OWN_UNKNOWN)
        return rc;
    if (strcmp(s, "--surface") != 0 && strcmp(s, "--levels") != 0 && strcmp(s, "--method") != 0 &&
        strcmp(s, "--precision") != 0)
        return CLI_OWN_UNKNOWN;
    if (!(v = cli_args_value(a, argc, argv, i)))
        return EXIT_USAGE;
    if (strcmp(s, "--surface") == 0) {
        x->surface = v;
    } else if (strcmp(s, "--levels") == 0) {
        if (!cli_parse_int(s, v, &x->sub.levels))
            return EXIT_USAGE;
        if (x->sub.levels < 0 || x->sub.levels > 16)
            return cli_usage_error(a->cmd, "--levels %s is outside 0..16", v);
        x->levels_given = 1;
    } else {
        return choice_option(x, s, v);
    }
    return 0;
}

/* After parsing: what the options need of each other, then the outputs. */
static int check(args *x)
{
    int rc = cli_args_required(&x->a);
    if (rc)
        return rc;
    if (x->opt.precision == LIMN_PRECISION_FLOAT &&
        (x->opt.method == LIMN_METHOD_CG || x->opt.method == LIMN_METHOD_SGS))
        return cli_usage_error("interpolate", "--precision float runs the chebyshev, paper or "
                                              "weighted iteration; cg and sgs run in double");
    if ((x->levels_given || x->sub.limit) && !x->surface)
        return cli_usage_error("interpolate", "--levels and --limit need --surface FILE");
    rc = cli_args_check_per_rank(&x->a);
    return rc ? rc : cli_args_check_meshes(&x->a, x->surface);
}

/* 0, -1 (help printed: exit status 0) or an exit status. */
static int parse(int argc, char **argv, args *x)
{
    x->a.cmd = "interpolate";
    x->a.help = help;
    x->a.inputs_wanted = 1;
    x->a.formats = "obj, ply, ply-ascii, ply-be, off, stl";
    limn_interpolate_options_default(&x->opt);
    x->a.scheme = &x->opt.scheme;
    x->a.alpha = &x->opt.alpha;
    limn_subdivide_options_default(&x->sub);
    x->sub.levels = 2;
    static const struct option longopts[] = {
        CLI_ARGS_OPTIONS,          CLI_VALUE("output-precision"), CLI_VALUE("tol"),        CLI_VALUE("max-iter"),
        CLI_VALUE("fallback"),     CLI_VALUE("surface"),    CLI_VALUE("levels"),
        CLI_FLAG("limit"),         CLI_VALUE("max-memory"), CLI_VALUE("method"),
        CLI_VALUE("precision"),    CLI_FLAG("no-reorder"),  CLI_FLAG("per-rank-output"),
        CLI_OPTIONS_END};
    int rc = cli_args_parse(&x->a, longopts, argc, argv, own_option, x);
    return rc ? rc : check(x);
}

static void print_summary(limn_context *ctx, const args *x, const limn_report *r,
                          const double sec[3])
{
    int threads;
    const char *threads_source;
    limn_context_threads(ctx, &threads, &threads_source);
    fprintf(stderr,
            "limn interpolate: %s -> %s\n"
            "  vertices %zu, faces %zu, scheme %s, alpha %g, method %s, precision %s, vertex "
            "order %s\n"
            "  iterations %d, max error %.3g, mean error %.3g (relative to the bbox diagonal "
            "%.6g)\n"
            "  device: %s; threads %d (%s)\n"
            "  seconds: load %.3f, opencl setup %.3f, topology %.3f, stencil %.3f, solve %.3f "
            "(%.3g per iteration), write %.3f\n",
            x->a.inputs[0], x->a.output, r->vertices, r->faces, limn_scheme_name(r->scheme), r->alpha,
            r->method, r->precision ? r->precision : "double", r->reordered ? "rcm" : "input",
            r->iterations,
            r->max_rel_error, r->mean_rel_error, r->bbox_diagonal, r->device, threads,
            threads_source, sec[0],
            r->seconds_opencl_platform + r->seconds_opencl_context + r->seconds_opencl_build +
                r->seconds_opencl_kernels,
            r->seconds_topology, r->seconds_stencil, r->seconds_solve,
            r->seconds_solve / (r->iterations + 1), sec[1]);
}

static limn_status write_report(limn_context *ctx, const args *x, const limn_report *r,
                                const limn_subdivide_report *sr, const double sec[3],
                                limn_output_set *set)
{
    json_out *j = cli_args_report(&x->a, r->vertices, r->faces);
    if (!j)
        return cli_error(LIMN_ERR_MEMORY, "out of memory for the report");
    json_string(j, "scheme", limn_scheme_name(r->scheme));
    json_number(j, "alpha", r->alpha);
    json_string(j, "method", r->method);
    json_integer(j, "iterations", r->iterations);
    json_number(j, "products", r->products);
    json_string(j, "method_reason", r->method_reason ? r->method_reason : "");
    json_string(j, "precision", r->precision ? r->precision : "double");
    json_string(j, "precision_reason", r->precision_reason ? r->precision_reason : "");
    json_number(j, "products_float", r->products_float);
    if (strcmp(r->method, "weighted") == 0)
        json_number(j, "omega", r->omega);
    if (strcmp(r->method, "chebyshev") == 0) {
        json_number(j, "spectrum_lower", r->spectrum_lower);
        json_integer(j, "restarts", r->restarts);
    }
    json_number(j, "tolerance", x->opt.tolerance);
    json_number(j, "max_rel_error", r->max_rel_error);
    json_number(j, "mean_rel_error", r->mean_rel_error);
    json_number(j, "max_abs_error", r->max_abs_error);
    json_number(j, "mean_abs_error", r->mean_abs_error);
    json_number(j, "bbox_diagonal", r->bbox_diagonal);
    json_integer(j, "stencil_nonzeros", (long long)r->stencil_nonzeros);
    json_string(j, "vertex_order", r->reordered ? "rcm" : "input");
    json_string(j, "device", r->device);
    int threads;
    const char *threads_source;
    limn_context_threads(ctx, &threads, &threads_source);
    json_integer(j, "threads", threads);
    json_string(j, "threads_source", threads_source);
    if (!limn_context_host_threads(ctx, &threads, &threads_source)) {
        json_integer(j, "host_threads", threads);
        json_string(j, "host_threads_source", threads_source);
    }
    if (sr) {
        json_string(j, "surface", x->surface);
        json_integer(j, "surface_vertices", (long long)sr->vertices);
        json_integer(j, "surface_faces", (long long)sr->faces);
        json_integer(j, "levels", sr->levels);
        json_bool(j, "limit", sr->limit);
    }
    json_integer(j, "estimated_bytes", (long long)x->estimated_bytes);
    json_integer(j, "peak_rss_bytes", (long long)cli_peak_rss());
    cli_mpi_json(j);
    json_object_begin(j, "seconds");
    json_number(j, "load", sec[0]);
    json_number(j, "topology", r->seconds_topology);
    json_number(j, "stencil", r->seconds_stencil);
    json_number(j, "solve", r->seconds_solve);
    json_number(j, "iterations", r->seconds_iterations);
    json_number(j, "solve_finish", r->seconds_solve_finish);
    json_number(j, "opencl_setup", r->seconds_opencl_platform + r->seconds_opencl_context +
                                       r->seconds_opencl_build + r->seconds_opencl_kernels);
    if (sr)
        json_number(j, "surface", sr->seconds_plan + sr->seconds_apply + sr->seconds_limit);
    json_number(j, "write", sec[1]);
    json_number(j, "total", sec[2]);
    json_object_end(j);
    json_object_begin(j, "opencl_setup");
    json_number(j, "platform", r->seconds_opencl_platform);
    json_number(j, "context", r->seconds_opencl_context);
    json_number(j, "build", r->seconds_opencl_build);
    json_number(j, "kernels", r->seconds_opencl_kernels);
    json_object_end(j);
    return json_stage(ctx, j, x->a.report, set);
}



/* Solves (on one process, or distributed under mpirun), then refines the
   surface on rank 0. A device failure runs again on the reference backend
   when that is allowed (one process only: under MPI a rank's device falls
   back when it opens, see --fallback). */
static limn_status solve(args *x, limn_context *ctx, const limn_mesh *mesh, limn_mesh **control,
                         limn_mesh **surface, limn_mesh **piece, limn_report *r,
                         limn_subdivide_report *sr)
{
    limn_status st = LIMN_OK;
    for (int attempt = 0; attempt < 2; attempt++) {
        cli_progress_enable(ctx, x->a.quiet);
        if (cli_mpi_ranks() > 1)
            st = cli_mpi_interpolate(ctx, mesh, &x->opt, control, r, x->a.per_rank ? piece : NULL);
        else
            st = limn_interpolate(ctx, mesh, &x->opt, control, r);
        cli_progress_done();
        cli_print_warnings("interpolate", ctx);
        if (!st && x->surface && *control) {
            x->sub.scheme = r->scheme;
            cli_progress_enable(ctx, x->a.quiet);
            st = limn_subdivide(ctx, *control, &x->sub, surface, sr);
            cli_progress_done();
            cli_print_warnings("interpolate", ctx);
        }
        if (!st || cli_mpi_ranks() > 1 || !cli_fall_back("interpolate", ctx, &st))
            break;
        limn_mesh_destroy(*control);
        *control = NULL;
    }
    return st;
}

/* Under several ranks on a file input (cli_mpi_sliced): every rank reads,
   repairs, solves and writes its share, none holding the whole mesh; the
   report after the mesh (rank 0). */
static int interpolate_sliced(args *x)
{
    limn_context *ctx = cli_sliced_context("interpolate");
    if (!ctx)
        return EXIT_FAILURE_RUN;
    int root = cli_mpi_rank() == 0, rc = 0;
    limn_report r = {.size = sizeof r};
    limn_write_report wr = {.size = sizeof wr};
    limn_write_options wo;
    limn_write_options_default(&wo);
    wo.precision = x->a.precision;
    /* the mesh is staged in the set with the report: it appears only if both could be made */
    limn_output_set *set = NULL;
    double sec[3] = {0, 0, 0}, t0 = cli_now();
    limn_status st = cli_mpi_agree(ctx, cli_args_open(&x->a, ctx, x->sub.max_memory, 0, NULL));
    if (!st)
        st = cli_mpi_agree(ctx, limn_output_set_create(ctx, &set));
    cli_sliced_job job = {"interpolate",   x->a.inputs[0], x->a.output, &x->a.repair,
                          x->a.in_format, x->a.out_format, &wo,        1, set};
    if (!st) {
        cli_progress_enable(ctx, x->a.quiet);
        st = cli_mpi_interpolate_sliced(ctx, &job, &x->opt, &r, &wr, sec);
        cli_progress_done();
    }
    sec[2] = cli_now() - t0;
    cli_mpi_note_memory();
    x->a.written = wr;
    x->a.wrote = !st;
    if (!st && root && x->a.report)
        st = write_report(ctx, x, &r, NULL, sec, set);
    st = cli_commit_outputs(ctx, st, set);
    if (st)
        rc = cli_fail("interpolate", ctx, st);
    else if (!x->a.quiet) {
        print_summary(ctx, x, &r, sec);
        cli_args_print_written(&x->a);
        cli_mpi_print();
    }
    limn_context_destroy(ctx);
    return rc;
}

int cli_interpolate(int argc, char **argv)
{
    args x = {0};
    int rc = cli_mpi_root_rc(parse(argc, argv, &x));
    if (rc)
        return rc < 0 ? 0 : rc;
    int root = cli_mpi_rank() == 0;
    x.a.quiet |= !root; /* under mpirun rank 0 prints */
    cli_mpi_set_per_rank(x.a.per_rank);
    if (cli_mpi_ranks() > 1 && !x.surface &&
        cli_mpi_sliced(x.a.inputs[0], x.a.in_format, x.a.output, x.a.per_rank))
        return interpolate_sliced(&x);
    limn_context *ctx = limn_context_create();
    if (!ctx) {
        fprintf(stderr, "limn interpolate: error: out of memory\n");
        return EXIT_FAILURE_RUN;
    }
    limn_mesh *mesh = NULL, *control = NULL, *surface = NULL, *piece = NULL;
    limn_report r = {.size = sizeof r};
    limn_subdivide_report sr = {.size = sizeof sr};
    double sec[3] = {0, 0, 0}, t0 = cli_now();
    limn_status st = cli_args_open(&x.a, ctx, x.sub.max_memory, root, &mesh);
    sec[0] = cli_now() - t0;
    if (!st && root)
        st = limn_interpolate_estimate(ctx, mesh, &x.opt, x.sub.max_memory,
                                       &x.estimated_bytes);
    if (!st && root && x.surface) {
        /* refuse an oversize surface before solving */
        size_t v, f, bytes;
        x.sub.scheme = x.opt.scheme;
        x.sub.alpha = x.opt.alpha;
        st = limn_subdivide_estimate(ctx, mesh, &x.sub, &v, &f, &bytes);
    }
    st = cli_mpi_agree(ctx, st); /* a bad input stops every rank, one message */
    if (!st)
        st = solve(&x, ctx, mesh, &control, &surface, &piece, &r, &sr);
    /* every output is complete (staged) before any appears: a failure writes nothing */
    limn_output_set *set = NULL;
    if (!st)
        st = limn_output_set_create(ctx, &set);
    if (!st) {
        double t1 = cli_now();
        st = cli_args_stage_mesh(&x.a, ctx, set, root ? control : NULL, piece);
        if (!st && root && x.surface)
            st = cli_args_stage_output(&x.a, ctx, set, surface, x.surface);
        sec[1] = cli_now() - t1;
        sec[2] = cli_now() - t0;
    }
    cli_mpi_note_memory();
    if (!st && root && x.a.report)
        st = write_report(ctx, &x, &r, x.surface ? &sr : NULL, sec, set);
    st = cli_commit_outputs(ctx, st, set);
    if (st)
        rc = cli_fail("interpolate", ctx, st);
    else if (!x.a.quiet) {
        print_summary(ctx, &x, &r, sec);
        cli_args_print_written(&x.a);
        if (x.surface)
            fprintf(stderr, "  surface: %s, %zu vertices, %zu faces (%d levels%s), %.3f s\n",
                    x.surface, sr.vertices, sr.faces, sr.levels,
                    sr.limit ? ", limit positions" : "",
                    sr.seconds_plan + sr.seconds_apply + sr.seconds_limit);
        cli_mpi_print();
    }
    limn_mesh_destroy(surface);
    limn_mesh_destroy(mesh);
    limn_mesh_destroy(control);
    limn_mesh_destroy(piece);
    limn_context_destroy(ctx);
    return rc;
}
