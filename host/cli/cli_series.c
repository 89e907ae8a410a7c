/* SPDX-License-Identifier: MIT */
/* Shared option handling, loading and reports of the series subcommands. */
#include "cli_series.h"

#include <stdlib.h>
#include <string.h>

const char *series_cli_value(series_cli *c, int argc, char **argv, int *i)
{
    const char *opt = argv[*i];
    const char *v = cli_value(argc, argv, i);
    if (!v)
        cli_usage_error(c->cmd, "%s needs a value", opt);
    return v;
}

int series_cli_int(series_cli *c, const char *opt, const char *text, int min, int *out)
{
    if (!cli_parse_int(opt, text, out))
        return EXIT_USAGE;
    if (*out < min)
        return cli_usage_error(c->cmd, "%s %s must be at least %d", opt, text, min);
    return 0;
}

int series_cli_number(series_cli *c, const char *opt, const char *text, double *out)
{
    (void)c;
    return cli_parse_double(opt, text, out) ? 0 : EXIT_USAGE;
}

int series_cli_arg(series_cli *c, int argc, char **argv, int *i, int *rc)
{
    const char *s = argv[*i], *v;
    *rc = 0;
#define VALUE()                                                                                \
    do {                                                                                       \
        if (!(v = series_cli_value(c, argc, argv, i))) {                                       \
            *rc = EXIT_USAGE;                                                                  \
            return SERIES_ARG_EXIT;                                                            \
        }                                                                                      \
    } while (0)
    if (strcmp(s, "-h") == 0 || strcmp(s, "--help") == 0) {
        if (cli_mpi_rank() == 0)
            fputs(c->help, stdout);
        *rc = -1;
        return SERIES_ARG_EXIT;
    } else if (strcmp(s, "-o") == 0 || strcmp(s, "--output") == 0) {
        VALUE();
        c->output = v;
    } else if (strcmp(s, "--scheme") == 0) {
        VALUE();
        if (!cli_parse_scheme(c->cmd, v, &c->opt.scheme)) {
            *rc = EXIT_USAGE;
            return SERIES_ARG_EXIT;
        }
    } else if (strcmp(s, "--alpha") == 0) {
        VALUE();
        if (!cli_parse_double(s, v, &c->opt.alpha)) {
            *rc = EXIT_USAGE;
            return SERIES_ARG_EXIT;
        }
        if (!(c->opt.alpha >= 0 && c->opt.alpha <= 1)) {
            *rc = cli_usage_error(c->cmd, "--alpha %s is outside [0, 1]", v);
            return SERIES_ARG_EXIT;
        }
    } else if (strcmp(s, "--device") == 0) {
        VALUE();
        c->device = v;
    } else if (strcmp(s, "--report") == 0) {
        VALUE();
        c->report = v;
    } else if (strcmp(s, "--format") == 0 || strcmp(s, "--input-format") == 0) {
        VALUE();
        limn_format f;
        if (!limn_format_from_name(v, &f)) {
            *rc = cli_usage_error(c->cmd, "%s '%s' is not one of obj, ply, ply-ascii, ply-be, off",
                                  s, v);
            return SERIES_ARG_EXIT;
        }
        if (s[2] == 'f')
            c->out_format = f;
        else
            c->in_format = f;
    } else if (strcmp(s, "--overwrite-input") == 0) {
        c->overwrite_input = 1;
    } else if (strcmp(s, "--per-rank-output") == 0 &&
               (strcmp(c->cmd, "smooth") == 0 || strcmp(c->cmd, "denoise") == 0)) {
        c->per_rank = 1;
    } else if (strcmp(s, "-q") == 0 || strcmp(s, "--quiet") == 0) {
        c->quiet = 1;
    } else if (cli_repair_arg(s, &c->repair)) {
        /* the repair policy, applied by series_cli_load */
    } else if (s[0] == '-' && s[1]) {
        return SERIES_ARG_NOT_MINE;
    } else if (c->input_count < c->inputs_wanted) {
        c->inputs[c->input_count++] = s;
    } else {
        *rc = cli_usage_error(c->cmd, "unexpected argument '%s'", s);
        return SERIES_ARG_EXIT;
    }
#undef VALUE
    return SERIES_ARG_TAKEN;
}

int series_cli_check(series_cli *c, int mesh_output)
{
    if (c->per_rank && cli_mpi_ranks() == 1)
        return cli_usage_error(c->cmd, "--per-rank-output needs several MPI ranks (mpirun -np "
                                       "N limn %s ...)",
                               c->cmd);
    if (c->input_count < c->inputs_wanted)
        return cli_usage_error(c->cmd, c->inputs_wanted == 2 ? "two meshes are needed (FROM TO)"
                                                             : "no INPUT mesh given");
    if (!c->output)
        return cli_usage_error(c->cmd, "no output given (-o OUTPUT)");
    for (int k = 0; k < c->input_count; k++) {
        if (mesh_output) {
            int rc = cli_check_output(c->cmd, c->inputs[k], c->output, c->out_format,
                                      c->overwrite_input);
            if (rc)
                return rc;
        }
        if (c->report && !c->overwrite_input && cli_same_file(c->report, c->inputs[k]))
            return cli_usage_error(c->cmd, "--report '%s' is the input file", c->report);
    }
    /* the output of bands and morph is a prefix or a pattern, not a file */
    const char *outputs[] = {mesh_output ? c->output : NULL, c->report};
    return cli_check_outputs(c->cmd, outputs, 2);
}

limn_status series_cli_load(series_cli *c, limn_context **ctx, limn_mesh **meshes)
{
    *ctx = limn_context_create();
    if (!*ctx) {
        fprintf(stderr, "limn %s: error: out of memory\n", c->cmd);
        return LIMN_ERR_MEMORY;
    }
    limn_status st = limn_context_set_device(*ctx, c->device);
    c->quiet |= cli_mpi_rank() != 0; /* under mpirun rank 0 prints */
    cli_mpi_set_per_rank(c->per_rank);
    for (int k = 0; !st && cli_mpi_rank() == 0 && k < c->input_count; k++) {
        st = cli_load_mesh(c->cmd, *ctx, c->inputs[k], c->in_format, &c->repair, 1,
                           &meshes[k]);
    }
    return cli_mpi_agree(*ctx, st);
}

json_out *series_json_begin(const series_cli *c, const limn_series_report *r)
{
    json_out *j = json_begin();
    if (!j)
        return NULL;
    json_string(j, "command", c->cmd);
    json_string(j, "input", c->inputs[0]);
    if (c->input_count > 1)
        json_string(j, "target", c->inputs[1]);
    json_string(j, "output", c->output);
    json_integer(j, "vertices", (long long)r->vertices);
    json_integer(j, "faces", (long long)r->faces);
    json_string(j, "scheme", limn_scheme_name(r->scheme));
    json_number(j, "alpha", r->alpha);
    json_string(j, "device", r->device);
    json_integer(j, "stencil_nonzeros", (long long)r->stencil_nonzeros);
    json_integer(j, "products", r->products);
    json_number(j, "bbox_diagonal", r->bbox_diagonal);
    cli_mpi_json(j);
    return j;
}

limn_status series_json_finish(limn_context *ctx, json_out *j, const series_cli *c,
                               const limn_series_report *r, const series_seconds *s)
{
    limn_output_set *set = NULL;
    limn_status st = limn_output_set_create(ctx, &set);
    /* frees j in any case (a NULL set is refused, on no context) */
    limn_status staged = series_json_stage(st ? NULL : ctx, j, c, r, s, set);
    if (!st)
        st = staged;
    if (!st)
        st = limn_output_set_commit(ctx, set);
    limn_output_set_destroy(set);
    return st;
}

limn_status series_json_stage(limn_context *ctx, json_out *j, const series_cli *c,
                              const limn_series_report *r, const series_seconds *s,
                              limn_output_set *set)
{
    json_object_begin(j, "seconds");
    json_number(j, "load", s->load);
    json_number(j, "topology", r->seconds_topology);
    json_number(j, "stencil", r->seconds_stencil);
    json_number(j, "compute", r->seconds_compute);
    json_number(j, "write", s->write);
    json_number(j, "total", s->total);
    json_object_end(j);
    return json_stage(ctx, j, c->report, set);
}

void series_print_head(const series_cli *c, const limn_series_report *r)
{
    fprintf(stderr, "limn %s: %s%s%s -> %s\n", c->cmd, c->inputs[0], c->input_count > 1 ? " to " : "",
            c->input_count > 1 ? c->inputs[1] : "", c->output);
    fprintf(stderr, "  vertices %zu, faces %zu, scheme %s, alpha %g, %lld stencil products\n",
            r->vertices, r->faces, limn_scheme_name(r->scheme), r->alpha, r->products);
    fprintf(stderr, "  device: %s\n", r->device);
}

void series_print_seconds(const limn_series_report *r, const series_seconds *s)
{
    fprintf(stderr,
            "  seconds: load %.3f, topology %.3f, stencil %.3f, compute %.3f, write %.3f, total "
            "%.3f\n",
            s->load, r->seconds_topology, r->seconds_stencil, r->seconds_compute, s->write,
            s->total);
}

int series_cli_finish(series_cli *c, limn_context *ctx, limn_status st, const limn_mesh *result,
                      const limn_series_report *r, series_seconds *s, const series_extra *x)
{
    /* the mesh and the report are both complete (staged) before either appears:
       a failure writes nothing and leaves an existing output as it was */
    limn_output_set *set = NULL;
    if (!st)
        st = limn_output_set_create(ctx, &set);
    double t = cli_now();
    if (!st && c->per_rank) { /* every rank: its piece */
        char *path = cli_mpi_rank_path(c->output);
        st = path ? limn_output_set_add_mesh(ctx, set, c->piece, path, c->out_format)
                  : cli_error(LIMN_ERR_MEMORY, "out of memory");
        free(path);
    } else if (!st && result) {
        st = limn_output_set_add_mesh(ctx, set, result, c->output, c->out_format);
    }
    s->write = cli_now() - t;
    limn_mesh_destroy(c->piece);
    c->piece = NULL;
    s->total = cli_now() - s->t0;
    if (!st && c->report && cli_mpi_rank() == 0) {
        json_out *j = series_json_begin(c, r);
        if (!j) {
            st = LIMN_ERR_MEMORY;
        } else {
            if (x && x->json)
                x->json(j, x->user);
            st = series_json_stage(ctx, j, c, r, s, set);
        }
    }
    st = cli_commit_outputs(ctx, st, set);
    if (st)
        return ctx ? cli_fail(c->cmd, ctx, st) : EXIT_FAILURE_RUN;
    if (!c->quiet) {
        series_print_head(c, r);
        if (x && x->print)
            x->print(x->user);
        series_print_seconds(r, s);
        cli_mpi_print();
    }
    return 0;
}
