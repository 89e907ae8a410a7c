/* SPDX-License-Identifier: MIT */
/* Shared option handling, loading and reports of the series subcommands. */
#include "cli_series.h"

#include <stdlib.h>
#include <string.h>

void series_cli_init(series_cli *c, const char *cmd, const char *help, int inputs_wanted)
{
    memset(c, 0, sizeof *c);
    c->a.cmd = cmd;
    c->a.help = help;
    c->a.inputs_wanted = inputs_wanted;
    limn_series_options_default(&c->opt);
    c->a.scheme = &c->opt.scheme;
    c->a.alpha = &c->opt.alpha;
}

int series_cli_check(series_cli *c, int mesh_output)
{
    int rc = cli_args_check_per_rank(&c->a);
    if (!rc)
        rc = cli_args_required(&c->a);
    if (rc)
        return rc;
    for (int k = 0; k < c->a.input_count; k++) {
        if (mesh_output) {
            int rc = cli_check_output(c->a.cmd, c->a.inputs[k], c->a.output, c->a.out_format,
                                      c->a.overwrite_input);
            if (rc)
                return rc;
        }
        if (c->a.report && !c->a.overwrite_input && cli_same_file(c->a.report, c->a.inputs[k]))
            return cli_usage_error(c->a.cmd, "--report '%s' is the input file", c->a.report);
    }
    /* the output of bands and morph is a prefix or a pattern, not a file */
    const char *outputs[] = {mesh_output ? c->a.output : NULL, c->a.report};
    return cli_check_outputs(c->a.cmd, outputs, 2);
}

limn_status series_cli_load(series_cli *c, limn_context **ctx, limn_mesh **meshes)
{
    *ctx = limn_context_create();
    if (!*ctx) {
        fprintf(stderr, "limn %s: error: out of memory\n", c->a.cmd);
        return LIMN_ERR_MEMORY;
    }
    limn_status st = cli_set_host_threads(*ctx, c->a.host_threads);
    if (!st)
        st = limn_context_set_device(*ctx, c->a.device);
    c->a.quiet |= cli_mpi_rank() != 0; /* under mpirun rank 0 prints */
    cli_mpi_set_per_rank(c->a.per_rank);
    for (int k = 0; !st && cli_mpi_rank() == 0 && k < c->a.input_count; k++) {
        st = cli_load_mesh(c->a.cmd, *ctx, c->a.inputs[k], c->a.in_format, &c->a.repair, 1, c->a.quiet,
                           &meshes[k]);
    }
    return cli_mpi_agree(*ctx, st);
}

void series_cli_unload(limn_context *ctx, limn_mesh **meshes)
{
    limn_mesh_destroy(meshes[0]);
    limn_mesh_destroy(meshes[1]);
    limn_context_destroy(ctx);
}

static json_out *series_json_begin(const series_cli *c, const limn_series_report *r)
{
    json_out *j = cli_args_report(&c->a, r->vertices, r->faces);
    if (!j)
        return NULL;
    json_string(j, "scheme", limn_scheme_name(r->scheme));
    json_number(j, "alpha", r->alpha);
    json_string(j, "device", r->device);
    json_integer(j, "stencil_nonzeros", (long long)r->stencil_nonzeros);
    json_integer(j, "products", r->products);
    json_number(j, "bbox_diagonal", r->bbox_diagonal);
    cli_mpi_json(j);
    return j;
}

static limn_status series_json_stage(limn_context *ctx, json_out *j, const series_cli *c,
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
    return json_stage(ctx, j, c->a.report, set);
}

static void series_print_head(const series_cli *c, const limn_series_report *r)
{
    fprintf(stderr, "limn %s: %s%s%s -> %s\n", c->a.cmd, c->a.inputs[0], c->a.input_count > 1 ? " to " : "",
            c->a.input_count > 1 ? c->a.inputs[1] : "", c->a.output);
    fprintf(stderr, "  vertices %zu, faces %zu, scheme %s, alpha %g, %lld stencil products\n",
            r->vertices, r->faces, limn_scheme_name(r->scheme), r->alpha, r->products);
    fprintf(stderr, "  device: %s\n", r->device);
}

static void series_print_seconds(const limn_series_report *r, const series_seconds *s)
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
    limn_output_set *set = c->a.staged; /* the outputs staged so far (a sliced mesh, bands) */
    c->a.staged = NULL;
    if (!st && !set)
        st = limn_output_set_create(ctx, &set);
    double t = cli_now();
    if (!st && !c->sliced) /* with --per-rank-output every rank: its piece */
        st = cli_args_stage_mesh(&c->a, ctx, set, result, c->piece);
    if (!c->sliced) /* on slices: the parallel write's time */
        s->write = cli_now() - t;
    limn_mesh_destroy(c->piece);
    c->piece = NULL;
    s->total = cli_now() - s->t0;
    if (!st && c->a.report && cli_mpi_rank() == 0) {
        json_out *j = series_json_begin(c, r);
        if (!j) {
            st = cli_error(LIMN_ERR_MEMORY, "out of memory for the report");
        } else {
            if (x && x->json)
                x->json(j, x->user);
            st = series_json_stage(ctx, j, c, r, s, set);
        }
    }
    st = cli_commit_outputs(ctx, st, set);
    if (st)
        return ctx ? cli_fail(c->a.cmd, ctx, st) : EXIT_FAILURE_RUN;
    if (!c->a.quiet) {
        series_print_head(c, r);
        if (x && x->print)
            x->print(x->user);
        series_print_seconds(r, s);
        cli_mpi_print();
    }
    return 0;
}

limn_status series_mean_displacement(limn_context *ctx, const limn_mesh *in, const limn_mesh *out,
                                     const limn_series_report *r, double *value)
{
    limn_mesh_comparison cmp = {.size = sizeof cmp};
    limn_status st = limn_mesh_compare(ctx, in, out, &cmp);
    if (!st)
        *value = cmp.mean_distance / (r->bbox_diagonal > 0 ? r->bbox_diagonal : 1.0);
    return st;
}

/* series_cli_filter on slices (f->sliced, several ranks, a file input). */
static int filter_sliced(series_cli *c, const series_filter *f)
{
    series_seconds s = {.t0 = cli_now()};
    limn_context *ctx = cli_sliced_context(c->a.cmd);
    if (!ctx)
        return EXIT_FAILURE_RUN;
    limn_status st = cli_set_host_threads(ctx, c->a.host_threads);
    if (!st)
        st = limn_context_set_device(ctx, c->a.device);
    c->a.quiet |= cli_mpi_rank() != 0; /* under mpirun rank 0 prints */
    st = cli_mpi_agree(ctx, st);
    if (!st) /* the mesh staged there, to appear with the report (series_cli_finish) */
        st = cli_mpi_agree(ctx, limn_output_set_create(ctx, &c->a.staged));
    limn_write_options wo;
    limn_write_options_default(&wo);
    wo.precision = c->a.precision;
    cli_sliced_job job = {c->a.cmd,       c->a.inputs[0],  c->a.output, &c->a.repair,
                          c->a.in_format, c->a.out_format, &wo,         1,
                          c->a.staged};
    limn_series_report r = {.size = sizeof r};
    limn_write_report wr = {.size = sizeof wr};
    double sec[2] = {0, 0}, unused = 0.0;
    if (!st) {
        cli_progress_enable(ctx, c->a.quiet);
        st = cli_mpi_series_sliced(ctx, &job, &c->opt, f->sliced, &r, &wr,
                                   f->displacement ? f->displacement : &unused, sec);
        cli_progress_done();
    }
    s.load = sec[0];
    s.write = sec[1];
    c->a.written = wr;
    c->a.wrote = !st;
    c->sliced = 1;
    int rc = series_cli_finish(c, ctx, st, NULL, &r, &s, &f->x);
    limn_context_destroy(ctx);
    return rc;
}

int series_cli_filter(series_cli *c, const series_filter *f)
{
    cli_mpi_set_per_rank(c->a.per_rank);
    if (f->sliced && cli_mpi_ranks() > 1 &&
        cli_mpi_sliced(c->a.inputs[0], c->a.in_format, c->a.output, c->a.per_rank))
        return filter_sliced(c, f);
    series_seconds s = {.t0 = cli_now()};
    limn_context *ctx = NULL;
    limn_mesh *in[2] = {NULL, NULL}, *out = NULL;
    limn_series_report r = {.size = sizeof r};
    limn_status st = series_cli_load(c, &ctx, in);
    s.load = cli_now() - s.t0;
    if (!st) {
        cli_progress_enable(ctx, c->a.quiet);
        st = f->run(c, ctx, in[0], &out, &r, f->x.user);
        cli_progress_done();
    }
    if (!st && out && f->measure) /* under mpirun: rank 0 */
        st = f->measure(ctx, in[0], out, &r, f->x.user);
    if (!st && out && f->displacement)
        series_mean_displacement(ctx, in[0], out, &r, f->displacement);
    int rc = series_cli_finish(c, ctx, st, out, &r, &s, &f->x);
    limn_mesh_destroy(out);
    series_cli_unload(ctx, in);
    return rc;
}
