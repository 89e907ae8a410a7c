/* SPDX-License-Identifier: MIT */
/* The shared options of the mesh commands and the loop over the arguments. */
#include "cli_args.h"

#include <stdlib.h>
#include <string.h>

const char *cli_args_value(cli_args *a, int argc, char **argv, int *i)
{
    const char *opt = argv[*i];
    const char *v = cli_value(argc, argv, i);
    if (!v)
        cli_usage_error(a->cmd, "%s needs a value", opt);
    return v;
}

int cli_args_int(cli_args *a, int argc, char **argv, int *i, int min, int max, int *out)
{
    const char *opt = argv[*i];
    const char *v = cli_args_value(a, argc, argv, i);
    if (!v || !cli_parse_int(opt, v, out))
        return EXIT_USAGE;
    if (*out < min)
        return cli_usage_error(a->cmd, "%s %s must be at least %d", opt, v, min);
    if (*out > max)
        return cli_usage_error(a->cmd, "%s %s: at most %d", opt, v, max);
    return 0;
}

int cli_args_number(cli_args *a, int argc, char **argv, int *i, double *out)
{
    const char *opt = argv[*i];
    const char *v = cli_args_value(a, argc, argv, i);
    return v && cli_parse_double(opt, v, out) ? 0 : EXIT_USAGE;
}

int cli_args_positive(cli_args *a, int argc, char **argv, int *i, double *out)
{
    const char *opt = argv[*i];
    int rc = cli_args_number(a, argc, argv, i, out);
    if (!rc && !(*out > 0))
        rc = cli_usage_error(a->cmd, "%s %s must be positive", opt, argv[*i]);
    return rc;
}

/* --format / --input-format F. */
static int format_arg(cli_args *a, const char *opt, const char *v)
{
    limn_format f;
    if (!limn_format_from_name(v, &f))
        return cli_usage_error(a->cmd, "%s '%s' is not one of %s", opt, v,
                               a->formats ? a->formats : "obj, ply, ply-ascii, ply-be, off");
    if (opt[2] == 'f')
        a->out_format = f;
    else
        a->in_format = f;
    return 0;
}

/* --scheme S / --alpha A, into the command's options. */
static int scheme_arg(cli_args *a, const char *opt, const char *v)
{
    if (opt[2] == 's')
        return cli_parse_scheme(a->cmd, v, a->scheme) ? 0 : EXIT_USAGE;
    if (!cli_parse_double(opt, v, a->alpha))
        return EXIT_USAGE;
    if (!(*a->alpha >= 0 && *a->alpha <= 1))
        return cli_usage_error(a->cmd, "--alpha %s is outside [0, 1]", v);
    return 0;
}

/* --output-precision float|double. */
static int precision_arg(cli_args *a, int argc, char **argv, int *i)
{
    const char *v = cli_args_value(a, argc, argv, i);
    if (!v)
        return EXIT_USAGE;
    if (strcmp(v, "float") == 0 || strcmp(v, "double") == 0) {
        a->precision = v[0] == 'f' ? LIMN_OUTPUT_FLOAT : LIMN_OUTPUT_DOUBLE;
        return 0;
    }
    return cli_usage_error(a->cmd, "--output-precision '%s' is not one of float, double", v);
}

/* --output-precision float needs PLY: refused before any work. */
static int check_precision(const cli_args *a, const char *path)
{
    limn_format f = a->out_format;
    if (a->precision != LIMN_OUTPUT_FLOAT || !path ||
        (f == LIMN_FORMAT_AUTO && !limn_format_from_path(path, &f)))
        return 0;
    if (f == LIMN_FORMAT_PLY || f == LIMN_FORMAT_PLY_ASCII || f == LIMN_FORMAT_PLY_BINARY_BE)
        return 0;
    return cli_usage_error(a->cmd, "--output-precision float is for PLY output only, and %s is "
                                   "%s (doubles, lossless)",
                           path, f == LIMN_FORMAT_OBJ ? "OBJ" : f == LIMN_FORMAT_OFF ? "OFF" : "STL");
}

/* The shared options that take a value: 0 or an exit status when argv[*i]
   is one of them, CLI_OWN_UNKNOWN when not. */
static int value_arg(cli_args *a, int argc, char **argv, int *i)
{
    const char *s = argv[*i];
    if (strcmp(s, "--output-precision") == 0) /* only in interpolate's and subdivide's tables */
        return precision_arg(a, argc, argv, i);
    static const char *const names[] = {"-o",       "--output",   "--device", "--fallback",
                                        "--report", "--format",   "--input-format",
                                        "--scheme", "--alpha"};
    size_t k = 0, n = sizeof names / sizeof *names;
    while (k < n && strcmp(s, names[k]) != 0)
        k++;
    if (k == n || (k >= 7 && !a->scheme)) /* no --scheme, --alpha: render */
        return CLI_OWN_UNKNOWN;
    const char *v = cli_args_value(a, argc, argv, i);
    if (!v)
        return EXIT_USAGE;
    const char **to[] = {&a->output, &a->output, &a->device, &a->fallback, &a->report};
    if (k < 5)
        *to[k] = v;
    return k < 5 ? 0 : k < 7 ? format_arg(a, s, v) : scheme_arg(a, s, v);
}

/* The shared flags and the positional INPUTs: 0, -1 (help), an exit status
   or CLI_OWN_UNKNOWN. */
static int flag_arg(cli_args *a, const char *s)
{
    if (strcmp(s, "-h") == 0 || strcmp(s, "--help") == 0) {
        if (cli_mpi_rank() == 0)
            fputs(a->help, stdout);
        return -1;
    }
    if (strcmp(s, "--overwrite-input") == 0)
        a->overwrite_input = 1;
    else if (strcmp(s, "--per-rank-output") == 0) /* only in the tables of the distributed */
        a->per_rank = 1;
    else if (strcmp(s, "-q") == 0 || strcmp(s, "--quiet") == 0)
        a->quiet = 1;
    else if (cli_repair_arg(s, &a->repair))
        ; /* the repair policy, applied when the mesh is read (cli_load_mesh) */
    else if (s[0] == '-' && s[1])
        return CLI_OWN_UNKNOWN;
    else if (a->input_count < a->inputs_wanted)
        a->inputs[a->input_count++] = s;
    else
        return cli_usage_error(a->cmd, "unexpected argument '%s'", s);
    return 0;
}

int cli_args_parse(cli_args *a, const struct option *longopts, int argc, char **argv,
                   cli_own_fn own, void *user)
{
    int rc = cli_options(a->cmd, longopts, "ho:q", &argc, &argv);
    for (int i = 1; !rc && i < argc; i++) {
        if (strcmp(argv[i], "--host-threads") == 0) {
            const char *v = cli_args_value(a, argc, argv, &i);
            rc = v ? cli_parse_host_threads(a->cmd, v, &a->host_threads) : EXIT_USAGE;
            continue;
        }
        rc = value_arg(a, argc, argv, &i);
        if (rc == CLI_OWN_UNKNOWN)
            rc = flag_arg(a, argv[i]);
        if (rc == CLI_OWN_UNKNOWN)
            rc = own ? own(a, user, argc, argv, &i) : CLI_OWN_UNKNOWN;
        if (rc == CLI_OWN_UNKNOWN)
            rc = cli_usage_error(a->cmd, "unknown option '%s'", argv[i]);
    }
    return cli_mpi_root_rc(rc);
}

int cli_args_own(cli_args *a, int argc, char **argv, int *i, const cli_own_option *t, size_t n)
{
    const char *opt = argv[*i], *v;
    for (size_t k = 0; k < n; k++) {
        if (strcmp(opt, t[k].name) != 0)
            continue;
        switch (t[k].kind) {
        case CLI_OWN_FLAG:
            *(int *)t[k].target = t[k].min;
            return 0;
        case CLI_OWN_INT:
            return cli_args_int(a, argc, argv, i, t[k].min, t[k].max, t[k].target);
        case CLI_OWN_NUMBER:
            return cli_args_number(a, argc, argv, i, t[k].target);
        case CLI_OWN_POSITIVE:
            return cli_args_positive(a, argc, argv, i, t[k].target);
        case CLI_OWN_SIZE:
            v = cli_args_value(a, argc, argv, i);
            return v && cli_parse_size(opt, v, t[k].target) ? 0 : EXIT_USAGE;
        }
    }
    return CLI_OWN_UNKNOWN;
}

int cli_args_choice(cli_args *a, const char *opt, const char *v, const char *const *names, int n)
{
    char list[256] = "";
    for (int k = 0; k < n; k++) {
        if (strcmp(v, names[k]) == 0)
            return k;
        size_t len = strlen(list);
        snprintf(list + len, sizeof list - len, "%s%s", k ? ", " : "", names[k]);
    }
    cli_usage_error(a->cmd, "%s '%s' is not one of %s", opt, v, list);
    return -1;
}

int cli_args_required(cli_args *a)
{
    if (a->input_count < a->inputs_wanted)
        return cli_usage_error(a->cmd, a->inputs_wanted == 2 ? "two meshes are needed (FROM TO)"
                                                             : "no INPUT mesh given");
    if (!a->output)
        return cli_usage_error(a->cmd, "no output given (-o OUTPUT)");
    return 0;
}

int cli_args_check_per_rank(cli_args *a)
{
    if (a->per_rank && cli_mpi_ranks() == 1)
        return cli_usage_error(a->cmd, "--per-rank-output needs several MPI ranks (mpirun -np "
                                       "N limn %s ...)",
                               a->cmd);
    return 0;
}

int cli_args_check_meshes(cli_args *a, const char *surface)
{
    const char *in = a->inputs[0];
    int rc = check_precision(a, a->output);
    if (!rc && surface)
        rc = check_precision(a, surface);
    if (!rc)
        rc = cli_check_output(a->cmd, in, a->output, a->out_format, a->overwrite_input);
    if (!rc && surface)
        rc = cli_check_output(a->cmd, in, surface, a->out_format, a->overwrite_input);
    if (!rc && a->report) /* OBJ: no format to check, only that it is not the input */
        rc = cli_check_output(a->cmd, in, a->report, LIMN_FORMAT_OBJ, a->overwrite_input);
    const char *outputs[] = {a->output, surface, a->report};
    return rc ? rc : cli_check_outputs(a->cmd, outputs, 3);
}

limn_status cli_args_open(cli_args *a, limn_context *ctx, size_t max_memory, int load,
                          limn_mesh **mesh)
{
    limn_context_set_max_memory(ctx, max_memory);
    limn_status st = cli_set_host_threads(ctx, a->host_threads);
    if (!st)
        st = limn_context_set_device(ctx, a->device);
    if (!st && a->fallback)
        st = limn_context_set_fallback(ctx, a->fallback);
    if (!st && load)
        st = cli_load_mesh(a->cmd, ctx, a->inputs[0], a->in_format, &a->repair, 1, a->quiet,
                           mesh);
    return st;
}

limn_status cli_args_stage_output(cli_args *a, limn_context *ctx, limn_output_set *set,
                                  const limn_mesh *mesh, const char *path)
{
    limn_write_options o;
    limn_write_options_default(&o);
    o.precision = a->precision;
    limn_write_report r = {.size = sizeof r};
    cli_progress_enable(ctx, a->quiet);
    limn_status st = limn_output_set_add_mesh_with(ctx, set, mesh, path, a->out_format, &o, &r);
    cli_progress_done();
    limn_context_set_progress(ctx, NULL, NULL);
    if (!st && path == a->output) {
        a->written = r;
        a->wrote = 1;
    }
    return st;
}

limn_status cli_args_stage_mesh(cli_args *a, limn_context *ctx, limn_output_set *set,
                                const limn_mesh *mesh, const limn_mesh *piece)
{
    if (a->per_rank) {
        char *path = cli_mpi_rank_path(a->output);
        limn_status st = path ? cli_args_stage_output(a, ctx, set, piece, path)
                              : cli_error(LIMN_ERR_MEMORY, "out of memory");
        free(path);
        return st;
    }
    return mesh ? cli_args_stage_output(a, ctx, set, mesh, a->output) : LIMN_OK;
}

/* The error of the float32 positions written, absolute and relative to the
   bbox diagonal (README "Command line"). */
static void written_json(const cli_args *a, json_out *j)
{
    const limn_write_report *r = &a->written;
    double d = r->bbox_diagonal > 0 ? r->bbox_diagonal : 1;
    json_object_begin(j, "output_precision");
    json_string(j, "precision", a->precision == LIMN_OUTPUT_FLOAT ? "float" : "double");
    json_number(j, "max_error", r->max_error);
    json_number(j, "mean_error", r->mean_error);
    json_number(j, "max_error_relative", r->max_error / d);
    json_number(j, "mean_error_relative", r->mean_error / d);
    json_object_end(j);
}

void cli_args_print_written(const cli_args *a)
{
    const limn_write_report *r = &a->written;
    if (!a->wrote || a->precision != LIMN_OUTPUT_FLOAT)
        return;
    double d = r->bbox_diagonal > 0 ? r->bbox_diagonal : 1;
    fprintf(stderr, "  output: float32 positions, error max %.3g (%.3g of the bbox diagonal), "
                    "mean %.3g\n",
            r->max_error, r->max_error / d, r->mean_error);
}

json_out *cli_args_report(const cli_args *a, size_t vertices, size_t faces)
{
    json_out *j = json_begin();
    if (!j)
        return NULL;
    json_string(j, "command", a->cmd);
    json_string(j, "input", a->inputs[0]);
    if (a->input_count > 1)
        json_string(j, "target", a->inputs[1]);
    json_string(j, "output", a->output);
    json_integer(j, "vertices", (long long)vertices);
    json_integer(j, "faces", (long long)faces);
    if (a->wrote)
        written_json(a, j);
    return j;
}

int cli_parse_host_threads(const char *cmd, const char *text, int *out)
{
    if (!cli_parse_int("--host-threads", text, out))
        return EXIT_USAGE;
    if (*out < 1 || *out > CLI_HOST_THREADS_MAX)
        return cli_usage_error(cmd, "--host-threads %s is outside 1..%d", text,
                               CLI_HOST_THREADS_MAX);
    return 0;
}

limn_status cli_set_host_threads(limn_context *ctx, int n)
{
    return n > 0 ? limn_context_set_host_threads(ctx, n) : LIMN_OK;
}
