/* SPDX-License-Identifier: MIT */
/* limn bands: a mesh as bands of its series, one mesh per band. */
#include "cli_series.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char *const help =
    "usage: limn bands INPUT --count N -o PREFIX [options]\n"
    "\n"
    "Splits INPUT (M) into the bands of its series (eq. 6 of Lai & Cheng (2011),\n"
    "'Fast Mesh Interpolation and Mesh Decomposition with Applications'):\n"
    "band i = (E - A)^i A M for i = 0..N-1, and the remainder (E - A)^N M;\n"
    "bands and remainder sum back to M. Band 0 (the limit points) is the overall\n"
    "shape, higher bands are finer detail.\n"
    "Writes PREFIX_band0.ply .. PREFIX_band{N-1}.ply and PREFIX_remainder.ply:\n"
    "each has INPUT's faces and the band's vectors as its vertex positions (band 0\n"
    "looks like a smoothed INPUT; higher bands are small offsets around the\n"
    "origin); and PREFIX_energy.json: each band's energy sum_v |band_i(v)|^2.\n"
    "\n"
    "  -o, --output PREFIX    prefix of the files written\n"
    "  --count N              number of bands, N >= 0\n"
    "  --format F             mesh format: ply (default), ply-ascii, ply-be, obj, off\n"
    SERIES_HELP
    "  --input-format F / --overwrite-input / -q\n"
    SERIES_HELP_EXIT;

typedef struct extra {
    int count;
    double *energy, input_energy, max_sum_error;
    char **names;
    const char *energy_path;
} extra;

static void json_energy(json_out *j, const extra *e)
{
    json_integer(j, "count", e->count);
    json_number(j, "input_energy", e->input_energy);
    json_array_begin(j, "bands");
    for (int i = 0; i < e->count; i++)
        json_element_number(j, e->energy[i]);
    json_array_end(j);
    json_number(j, "remainder", e->energy[e->count]);
    json_number(j, "max_rel_sum_error", e->max_sum_error);
}

static void json_extra(json_out *j, void *user)
{
    extra *e = user;
    json_energy(j, e);
    json_string(j, "energy_file", e->energy_path);
}

static void print_extra(void *user)
{
    extra *e = user;
    fprintf(stderr, "  %d bands + remainder written (%s ... %s), energy in %s\n", e->count,
            e->names[0], e->names[e->count], e->energy_path);
    fprintf(stderr, "  energy:");
    for (int i = 0; i <= e->count && i < 8; i++)
        fprintf(stderr, " %.3g", e->energy[i] / (e->input_energy > 0 ? e->input_energy : 1.0));
    fprintf(stderr, "%s (of the input's), bands + remainder = input to %.2g\n",
            e->count >= 8 ? " ..." : "", e->max_sum_error);
}

static const char *extension(limn_format f)
{
    return f == LIMN_FORMAT_OBJ ? "obj" : f == LIMN_FORMAT_OFF ? "off" : "ply";
}

static int own_option(cli_args *a, void *user, int argc, char **argv, int *i)
{
    extra *e = user;
    if (strcmp(argv[*i], "--count") != 0)
        return CLI_OWN_UNKNOWN;
    int rc = cli_args_int(a, argc, argv, i, 0, INT_MAX, &e->count);
    if (!rc && e->count > 10000)
        rc = cli_usage_error(a->cmd, "--count %s: at most 10000 bands", argv[*i]);
    return rc;
}

/* PREFIX_band0.EXT .. PREFIX_remainder.EXT, PREFIX_energy.json in e->names
   (e->count + 2 of them, freed by free_names); 0 or an exit status. */
static int make_names(const series_cli *c, extra *e)
{
    size_t plen = strlen(c->a.output) + 32;
    const char *ext = extension(c->a.out_format);
    e->names = calloc((size_t)e->count + 2, sizeof *e->names);
    for (int i = 0; e->names && i <= e->count + 1; i++) {
        e->names[i] = malloc(plen);
        if (!e->names[i])
            break;
        if (i < e->count)
            snprintf(e->names[i], plen, "%s_band%d.%s", c->a.output, i, ext);
        else if (i == e->count)
            snprintf(e->names[i], plen, "%s_remainder.%s", c->a.output, ext);
        else
            snprintf(e->names[i], plen, "%s_energy.json", c->a.output);
    }
    if (!e->names || !e->names[e->count + 1]) {
        fprintf(stderr, "limn bands: error: out of memory\n");
        return EXIT_FAILURE_RUN;
    }
    e->energy_path = e->names[e->count + 1];
    return 0;
}

static void free_names(extra *e)
{
    for (int i = 0; e->names && i <= e->count + 1; i++)
        free(e->names[i]);
    free(e->names);
}

/* The file names, checked before any work: none is the input, all can be
   written. 0 or an exit status. */
static int check_names(const series_cli *c, const extra *e)
{
    for (int i = 0; i <= e->count + 1; i++)
        if (!c->a.overwrite_input && cli_same_file(c->a.inputs[0], e->names[i]))
            return cli_usage_error(c->a.cmd,
                                   "output '%s' is the input file; refusing to overwrite it",
                                   e->names[i]);
    return cli_check_outputs(c->a.cmd, (const char *const *)e->names, e->count + 2);
}

/* The bands of in into bands[(count + 1) * n3] and e->energy, and how
   exactly they sum back to the input. */
static limn_status compute(series_cli *c, limn_context *ctx, const limn_mesh *in, double *bands,
                           extra *e, limn_series_report *r)
{
    cli_progress_enable(ctx, c->a.quiet);
    limn_status st = cli_mpi_ranks() > 1
                         ? cli_mpi_bands(ctx, in, &c->opt, e->count, bands, e->energy, r)
                         : limn_bands(ctx, in, &c->opt, e->count, bands, e->energy, r);
    cli_progress_done();
    if (st || !in) /* under mpirun: the root has the input and the bands */
        return st;
    size_t n3 = 3 * limn_mesh_vertex_count(in);
    const double *m = limn_mesh_positions(in);
    for (size_t k = 0; k < n3; k++) {
        double sum = 0.0;
        for (int i = 0; i <= e->count; i++)
            sum += bands[(size_t)i * n3 + k];
        e->max_sum_error = fmax(e->max_sum_error, fabs(sum - m[k]));
        e->input_energy += m[k] * m[k];
    }
    e->max_sum_error /= r->bbox_diagonal > 0 ? r->bbox_diagonal : 1.0;
    return LIMN_OK;
}

/* The energy file staged in set (rank 0). */
static limn_status stage_energy(series_cli *c, limn_context *ctx, const extra *e,
                                const limn_series_report *r, limn_output_set *set)
{
    json_out *j = json_begin();
    if (!j)
        return cli_error(LIMN_ERR_MEMORY, "out of memory for %s", e->energy_path);
    json_string(j, "input", c->a.inputs[0]);
    json_string(j, "scheme", limn_scheme_name(r->scheme));
    json_number(j, "alpha", r->alpha);
    json_energy(j, e);
    return json_stage(ctx, j, e->energy_path, set);
}

/* Each band as in's faces with the band's vectors as positions, then the
   energy file, staged in set: they appear with the report, or none does. */
static limn_status stage_bands(series_cli *c, limn_context *ctx, const limn_mesh *in,
                               const double *bands, const extra *e, const limn_series_report *r,
                               limn_output_set *set)
{
    size_t n3 = 3 * limn_mesh_vertex_count(in);
    limn_mesh *band = NULL;
    limn_status st = limn_mesh_copy(ctx, in, &band);
    for (int i = 0; !st && i <= e->count; i++) {
        memcpy(limn_mesh_positions_mutable(band), bands + (size_t)i * n3, n3 * sizeof *bands);
        st = limn_output_set_add_mesh(ctx, set, band, e->names[i], c->a.out_format);
    }
    limn_mesh_destroy(band);
    return st ? st : stage_energy(c, ctx, e, r, set);
}

/* Under several ranks on a file input (cli_mpi_sliced): every rank reads its
   slice, computes and writes its share of every band (no rank holding the
   mesh); rank 0 writes the energy file and the report. */
static int run_sliced(series_cli *c, extra *e)
{
    series_seconds s = {.t0 = cli_now()};
    limn_context *ctx = cli_sliced_context("bands");
    if (!ctx)
        return EXIT_FAILURE_RUN;
    e->energy = calloc((size_t)e->count + 1, sizeof *e->energy);
    limn_status st = e->energy ? cli_set_host_threads(ctx, c->a.host_threads)
                               : cli_error(LIMN_ERR_MEMORY, "out of memory");
    if (!st)
        st = limn_context_set_device(ctx, c->a.device);
    c->a.quiet |= cli_mpi_rank() != 0; /* under mpirun rank 0 prints */
    st = cli_mpi_agree(ctx, st);
    limn_write_options wo;
    limn_write_options_default(&wo);
    wo.precision = c->a.precision;
    if (!st) /* every band staged there, to appear with the energy file and the report */
        st = cli_mpi_agree(ctx, limn_output_set_create(ctx, &c->a.staged));
    cli_sliced_job job = {c->a.cmd,       c->a.inputs[0],  NULL, &c->a.repair,
                          c->a.in_format, c->a.out_format, &wo,  1,
                          c->a.staged};
    limn_series_report r = {.size = sizeof r};
    cli_bands_out out = {e->names, e->energy, 0.0, 0.0};
    double sec[2] = {0, 0};
    if (!st) {
        cli_progress_enable(ctx, c->a.quiet);
        st = cli_mpi_bands_sliced(ctx, &job, &c->opt, e->count, &out, &r, sec);
        cli_progress_done();
    }
    e->input_energy = out.input_energy;
    e->max_sum_error = out.max_sum_error / (r.bbox_diagonal > 0 ? r.bbox_diagonal : 1.0);
    if (!st && cli_mpi_rank() == 0)
        st = stage_energy(c, ctx, e, &r, c->a.staged);
    st = cli_mpi_agree(ctx, st);
    s.load = sec[0];
    s.write = sec[1];
    c->sliced = 1;
    series_extra x = {json_extra, print_extra, e};
    int rc = series_cli_finish(c, ctx, st, NULL, &r, &s, &x);
    free(e->energy);
    limn_context_destroy(ctx);
    return rc;
}

/* Loads, computes and writes (every file staged, appearing together at the
   finish); the exit status. */
static int run(series_cli *c, extra *e)
{
    if (cli_mpi_ranks() > 1 && cli_mpi_sliced(c->a.inputs[0], c->a.in_format, c->a.output, 0))
        return run_sliced(c, e);
    series_seconds s = {.t0 = cli_now()};
    limn_context *ctx = NULL;
    limn_mesh *in[2] = {NULL, NULL};
    limn_series_report r = {.size = sizeof r};
    double *bands = NULL;
    limn_status st = series_cli_load(c, &ctx, in);
    s.load = cli_now() - s.t0;
    size_t n3 = in[0] ? 3 * limn_mesh_vertex_count(in[0]) : 0; /* under mpirun: the root's */
    e->energy = calloc((size_t)e->count + 1, sizeof *e->energy);
    if (!st && (n3 / 3 > ((size_t)1 << 40) / 24 / ((size_t)e->count + 1) || !e->energy ||
                (in[0] && !(bands = malloc(((size_t)e->count + 1) * n3 * sizeof *bands)))))
        st = cli_error(LIMN_ERR_MEMORY, "out of memory for %d bands of %zu vertices",
                       e->count + 1, n3 / 3);
    if (ctx)
        st = cli_mpi_agree(ctx, st);
    if (!st)
        st = compute(c, ctx, in[0], bands, e, &r);
    double t = cli_now();
    if (!st && in[0]) /* rank 0 writes */
        st = limn_output_set_create(ctx, &c->a.staged);
    if (!st && in[0])
        st = stage_bands(c, ctx, in[0], bands, e, &r, c->a.staged);
    s.write = cli_now() - t;
    series_extra x = {json_extra, print_extra, e};
    int rc = series_cli_finish(c, ctx, st, NULL, &r, &s, &x);
    free(bands);
    free(e->energy);
    series_cli_unload(ctx, in);
    return rc;
}

int cli_bands(int argc, char **argv)
{
    series_cli c;
    series_cli_init(&c, "bands", help, 1);
    extra e = {.count = -1};
    static const struct option longopts[] = {CLI_ARGS_OPTIONS, CLI_VALUE("count"),
                                             CLI_OPTIONS_END};
    int rc = cli_args_parse(&c.a, longopts, argc, argv, own_option, &e);
    if (rc)
        return rc < 0 ? 0 : rc;
    if (e.count < 0)
        return cli_usage_error(c.a.cmd, "--count N is required");
    if ((rc = cli_mpi_root_rc(series_cli_check(&c, 0))))
        return rc;
    if (c.a.out_format == LIMN_FORMAT_AUTO)
        c.a.out_format = LIMN_FORMAT_PLY;
    rc = make_names(&c, &e);
    if (!rc)
        rc = check_names(&c, &e);
    rc = cli_mpi_root_rc(rc); /* under mpirun: the root decides */
    if (!rc)
        rc = run(&c, &e);
    free_names(&e);
    return rc;
}
