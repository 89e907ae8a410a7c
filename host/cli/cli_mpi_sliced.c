/* SPDX-License-Identifier: MIT */
/*
 * The commands on slices under mpirun (cli.h "cli_mpi_sliced"): every rank
 * reads and repairs its slice of the input file, computes its share of a
 * distributed mesh (include/limn_mpi.h) and writes its part of the output,
 * no rank holding the mesh whole. Every job is one skeleton (run_sliced:
 * the read, the call, its warnings and figures) around the command's call.
 */
#include "cli_mpi.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int cli_mpi_sliced(const char *input, limn_format in_format, const char *output, int per_rank)
{
    if (cli_mpi_ranks() == 1 || per_rank || strcmp(input, "-") == 0 || strcmp(output, "-") == 0)
        return 0;
    limn_format f;
    if (!limn_format_from_path(input, &f) || (in_format != LIMN_FORMAT_AUTO && in_format != f))
        return 0;
    return f == LIMN_FORMAT_PLY || f == LIMN_FORMAT_OBJ || f == LIMN_FORMAT_OFF;
}

/* Every rank's slice of input, repaired by the command's policy. */
static limn_status read_sliced(limn_context *ctx, const cli_sliced_job *job,
                               limn_mpi_mesh **mesh)
{
    const char *cmd = job->cmd, *input = job->input;
    const cli_repair *repair = job->repair;
    limn_status st = limn_mpi_mesh_read(ctx, MPI_COMM_WORLD, input, job->in_format, mesh);
    cli_print_warnings(cmd, ctx);
    if (st)
        return st;
    limn_repair_options o;
    limn_repair_options_default(&o);
    o.repeated_vertices = !repair->off;
    o.duplicate_faces = repair->drop_duplicates;
    o.sub_meshes = job->rows;
    limn_repair_report rep = {.size = sizeof rep};
    st = limn_mpi_mesh_repair(ctx, *mesh, &o, &rep);
    cli_print_warnings(cmd, ctx);
    if (!st && limn_mpi_mesh_face_total(*mesh) == 0)
        st = cli_no_faces(cmd, input, rep.faces_before);
    return st;
}

/* A command's own part of a sliced job: fn on the slices read (in[1] the
   second input's, else NULL) with the options of a distributed mesh; user
   holds its arguments and takes its results. */
typedef struct sliced_call {
    limn_status (*fn)(limn_context *ctx, limn_mpi_mesh *const in[2], void *user,
                      const limn_mpi_options *mo, limn_mpi_result *res);
    void *user;
    const char *second; /* morph's TO, read and repaired as job->input is; else NULL */
    int gather_load;    /* every rank's load seconds to the root (the report's) */
} sliced_call;

/* The skeleton of every sliced job: job->input's slice (and call->second's)
   read and repaired, seconds[0] the time it took; then call->fn on it, its
   warnings printed and every rank's statistics collected. in: the slices
   read (the caller destroys them). */
static limn_status run_sliced(limn_context *ctx, const cli_sliced_job *job,
                              const sliced_call *call, limn_mpi_mesh *in[2], double seconds[2])
{
    double t0 = MPI_Wtime();
    limn_status st = read_sliced(ctx, job, &in[0]);
    if (!st && call->second) {
        cli_sliced_job second = *job;
        second.input = call->second;
        second.rows = 0; /* the rows are the first input's */
        st = read_sliced(ctx, &second, &in[1]);
    }
    seconds[0] = MPI_Wtime() - t0;
    if (call->gather_load)
        cli_mpi_gather_load(seconds[0]);
    limn_mpi_options mo;
    limn_mpi_options_default(&mo);
    mo.keep_piece = 0; /* --per-rank-output never runs on slices */
    limn_mpi_result res = {.size = sizeof res, .stats.size = sizeof res.stats};
    cli_mpi_mark_sliced();
    if (st)
        return st;
    st = call->fn(ctx, in, call->user, &mo, &res);
    cli_print_warnings(job->cmd, ctx);
    cli_mpi_collect(&res);
    limn_mpi_result_free(&res);
    return st;
}

/* mesh written to job->output in parallel (when st is LIMN_OK), staged in
   job->stage when there is one; seconds[1] the time it took. */
static limn_status write_sliced(limn_context *ctx, const cli_sliced_job *job, limn_status st,
                                const limn_mpi_mesh *mesh, limn_write_report *written,
                                double seconds[2])
{
    double t1 = MPI_Wtime();
    if (!st && job->stage)
        st = limn_mpi_output_set_add_mesh(ctx, job->stage, mesh, job->output, job->out_format,
                                          job->write, written);
    else if (!st)
        st = limn_mpi_mesh_write(ctx, mesh, job->output, job->out_format, job->write, written);
    seconds[1] = MPI_Wtime() - t1;
    return st;
}

/* ---------------------------------------------------- interpolate, subdivide */

/* A job whose result is one mesh: its options, its report, the result. */
typedef struct mesh_job {
    const void *o; /* limn_interpolate_options, limn_subdivide_options */
    void *r;       /* limn_report, limn_subdivide_report */
    limn_mpi_mesh *out;
} mesh_job;

static limn_status interpolate_fn(limn_context *ctx, limn_mpi_mesh *const in[2], void *user,
                                  const limn_mpi_options *mo, limn_mpi_result *res)
{
    mesh_job *j = user;
    return limn_mpi_mesh_interpolate(ctx, in[0], j->o, &j->out, j->r, mo, res);
}

static limn_status subdivide_fn(limn_context *ctx, limn_mpi_mesh *const in[2], void *user,
                                const limn_mpi_options *mo, limn_mpi_result *res)
{
    mesh_job *j = user;
    return limn_mpi_mesh_subdivide(ctx, in[0], j->o, &j->out, j->r, mo, res);
}

/* call's job (a mesh_job) on the slices, then its result written; the
   input destroyed before the write when drop_input (subdivide: the surface
   is all that is left). */
static limn_status mesh_result(limn_context *ctx, const cli_sliced_job *job,
                               const sliced_call *call, int drop_input,
                               limn_write_report *written, double seconds[2])
{
    mesh_job *j = call->user;
    limn_mpi_mesh *in[2] = {NULL, NULL};
    limn_status st = run_sliced(ctx, job, call, in, seconds);
    if (drop_input) {
        limn_mpi_mesh_destroy(in[0]);
        in[0] = NULL;
    }
    st = write_sliced(ctx, job, st, j->out, written, seconds);
    limn_mpi_mesh_destroy(in[0]);
    limn_mpi_mesh_destroy(j->out);
    return st;
}

limn_status cli_mpi_interpolate_sliced(limn_context *ctx, const cli_sliced_job *job,
                                       const limn_interpolate_options *o, limn_report *r,
                                       limn_write_report *written, double seconds[2])
{
    mesh_job j = {o, r, NULL};
    sliced_call call = {interpolate_fn, &j, NULL, 1};
    return mesh_result(ctx, job, &call, 0, written, seconds);
}

limn_status cli_mpi_subdivide_sliced(limn_context *ctx, const cli_sliced_job *job,
                                     const limn_subdivide_options *o, limn_subdivide_report *r,
                                     limn_write_report *written, double seconds[2])
{
    mesh_job j = {o, r, NULL};
    sliced_call call = {subdivide_fn, &j, NULL, 0};
    return mesh_result(ctx, job, &call, 1, written, seconds);
}

/* ----------------------------------------------------------------- series */

/* The default denoise form on a distributed mesh; keep_volume < 0: kept
   when the mesh is closed (limn_mpi_mesh_measure). */
static limn_status denoise_sure_sliced(limn_context *ctx, const limn_mpi_mesh *mesh,
                                       const limn_series_options *o, const cli_series_call *c,
                                       limn_mpi_mesh **out, limn_series_report *r,
                                       const limn_mpi_options *mo, limn_mpi_result *res)
{
    int keep = c->keep_volume;
    if (keep < 0) {
        limn_mesh_measures a = {.size = sizeof a};
        limn_status st = limn_mpi_mesh_measure(ctx, mesh, &a);
        if (st)
            return st;
        keep = a.closed;
    }
    if (c->kept)
        *c->kept = keep;
    return limn_mpi_mesh_denoise_sure(ctx, mesh, o, c->products, keep, out, c->sigma, r, mo,
                                      res);
}

/* texture on a distributed mesh: its options with the call's series options. */
static limn_status texture_call(limn_context *ctx, const limn_mpi_mesh *mesh,
                                const limn_series_options *o, const cli_series_call *c,
                                limn_mpi_mesh **out, limn_series_report *r,
                                const limn_mpi_options *mo, limn_mpi_result *res)
{
    limn_texture_options t = *c->texture;
    t.series = *o;
    limn_status st = limn_mpi_mesh_texture(ctx, mesh, &t, out, r, mo, res);
    if (!st && c->out_counts) {
        c->out_counts[0] = limn_mpi_mesh_vertex_total(*out);
        c->out_counts[1] = limn_mpi_mesh_face_total(*out);
    }
    return st;
}

typedef struct series_job {
    const limn_series_options *o;
    const cli_series_call *call;
    limn_series_report *r;
    limn_mpi_mesh *out;
} series_job;

/* The filter of the job's call on a distributed mesh. */
static limn_status series_fn(limn_context *ctx, limn_mpi_mesh *const in[2], void *user,
                             const limn_mpi_options *mo, limn_mpi_result *res)
{
    series_job *j = user;
    const limn_series_options *o = j->o;
    const cli_series_call *c = j->call;
    const limn_mpi_mesh *mesh = in[0];
    switch (c->kind) {
    case CLI_SERIES_SMOOTH:
        return limn_mpi_mesh_smooth(ctx, mesh, o, c->terms, &j->out, j->r, mo, res);
    case CLI_SERIES_TEXTURE:
        return texture_call(ctx, mesh, o, c, &j->out, j->r, mo, res);
    case CLI_SERIES_DENOISE:
        if (c->features)
            return limn_mpi_mesh_denoise_features(ctx, mesh, c->features, &j->out, j->r, mo, res);
        if (c->products)
            return denoise_sure_sliced(ctx, mesh, o, c, &j->out, j->r, mo, res);
        return limn_mpi_mesh_denoise(ctx, mesh, o, c->m, c->steps, c->keep_volume, &j->out, j->r,
                                     mo, res);
    default:
        return limn_mpi_mesh_sharpen(ctx, mesh, o, c->from, c->to, c->steps, &j->out, j->r, mo,
                                     res);
    }
}

/* The mean distance between the vertex blocks of a and b (the same blocks)
   over diag, as series_mean_displacement gives it, the sum over the ranks. */
static double block_displacement(const limn_mpi_mesh *a, const limn_mpi_mesh *b, double diag)
{
    const double *p = limn_mpi_mesh_positions(a), *q = limn_mpi_mesh_positions(b);
    double sum = 0.0, all = 0.0;
    for (size_t i = 0; i < limn_mpi_mesh_vertex_count(a); i++) {
        double d[3] = {p[3 * i] - q[3 * i], p[3 * i + 1] - q[3 * i + 1],
                       p[3 * i + 2] - q[3 * i + 2]};
        sum += sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    }
    MPI_Allreduce(&sum, &all, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
    size_t n = limn_mpi_mesh_vertex_total(a);
    return n ? all / (double)n / (diag > 0 ? diag : 1.0) : 0.0;
}

/* The input's measures and the result's volume and area, as cli_denoise.c's
   measure takes them from the whole meshes (the same bits). */
static limn_status measure_sliced(limn_context *ctx, const limn_mpi_mesh *in,
                                  const limn_mpi_mesh *out, cli_series_measures *m)
{
    limn_mesh_measures a = {.size = sizeof a};
    limn_status st = limn_mpi_mesh_measure(ctx, in, &a);
    if (!st)
        st = limn_mpi_mesh_volume_area(ctx, out, &m->volume_out, &m->area_out);
    if (st)
        return st;
    m->measured = 1;
    m->closed = a.closed;
    m->volume_in = a.volume;
    m->area_in = a.area;
    return LIMN_OK;
}

limn_status cli_mpi_series_sliced(limn_context *ctx, const cli_sliced_job *job,
                                  const limn_series_options *o, const cli_series_call *call,
                                  limn_series_report *r, limn_write_report *written,
                                  double *displacement, double seconds[2])
{
    series_job j = {o, call, r, NULL};
    sliced_call sc = {series_fn, &j, NULL, 0};
    limn_mpi_mesh *in[2] = {NULL, NULL};
    cli_sliced_job rows = *job; /* texture and --preserve-features build no rows from it */
    rows.rows = call->kind != CLI_SERIES_TEXTURE && !call->features;
    limn_status st = run_sliced(ctx, &rows, &sc, in, seconds);
    if (!st && call->kind != CLI_SERIES_TEXTURE) /* texture: another mesh, no displacement */
        *displacement = block_displacement(in[0], j.out, r->bbox_diagonal);
    if (!st && call->measures)
        st = measure_sliced(ctx, in[0], j.out, call->measures);
    st = write_sliced(ctx, job, st, j.out, written, seconds);
    limn_mpi_mesh_destroy(in[0]);
    limn_mpi_mesh_destroy(j.out);
    return st;
}

/* ------------------------------------------------------------------ bands */

/* The input's energy (sum of its squared coordinates in input order) and
   the largest |sum of the bands - input| over the blocks, as cli_bands.c's
   compute gives them: the sum passed from rank to rank, the maximum exact. */
static void bands_check(const limn_mpi_mesh *mesh, limn_mpi_mesh *const *bands, int count,
                        cli_bands_out *out)
{
    int rank = cli_mpi_rank(), size = cli_mpi_ranks();
    double sum = 0.0, worst = 0.0;
    if (rank > 0)
        MPI_Recv(&sum, 1, MPI_DOUBLE, rank - 1, 0, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    const double *m = limn_mpi_mesh_positions(mesh);
    for (size_t k = 0; k < 3 * limn_mpi_mesh_vertex_count(mesh); k++) {
        double s = 0.0;
        for (int i = 0; i <= count; i++)
            s += limn_mpi_mesh_positions(bands[i])[k];
        worst = fmax(worst, fabs(s - m[k]));
        sum += m[k] * m[k];
    }
    if (rank + 1 < size)
        MPI_Send(&sum, 1, MPI_DOUBLE, rank + 1, 0, MPI_COMM_WORLD);
    MPI_Bcast(&sum, 1, MPI_DOUBLE, size - 1, MPI_COMM_WORLD);
    MPI_Allreduce(&worst, &out->max_sum_error, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
    out->input_energy = sum;
}

typedef struct bands_job {
    const limn_series_options *o;
    int count;
    limn_mpi_mesh **bands; /* count + 1 */
    double *energy;
    limn_series_report *r;
} bands_job;

static limn_status bands_fn(limn_context *ctx, limn_mpi_mesh *const in[2], void *user,
                            const limn_mpi_options *mo, limn_mpi_result *res)
{
    bands_job *j = user;
    return limn_mpi_mesh_bands(ctx, in[0], j->o, j->count, j->bands, j->energy, j->r, mo, res);
}

/* Every band written in parallel to its path, staged in job->stage. */
static limn_status write_bands(limn_context *ctx, const cli_sliced_job *job,
                               limn_mpi_mesh *const *bands, int count, char *const *paths)
{
    limn_status st = LIMN_OK;
    for (int i = 0; !st && i <= count; i++)
        st = limn_mpi_output_set_add_mesh(ctx, job->stage, bands[i], paths[i], job->out_format,
                                          job->write, NULL);
    return st;
}

limn_status cli_mpi_bands_sliced(limn_context *ctx, const cli_sliced_job *job,
                                 const limn_series_options *o, int count, cli_bands_out *out,
                                 limn_series_report *r, double seconds[2])
{
    limn_mpi_mesh **bands = calloc((size_t)count + 1, sizeof *bands);
    limn_status st = cli_mpi_agree(ctx, bands ? LIMN_OK
                                              : cli_error(LIMN_ERR_MEMORY, "out of memory"));
    if (st) {
        free(bands);
        return st;
    }
    bands_job j = {o, count, bands, out->energy, r};
    sliced_call call = {bands_fn, &j, NULL, 0};
    limn_mpi_mesh *in[2] = {NULL, NULL};
    st = run_sliced(ctx, job, &call, in, seconds);
    if (!st)
        bands_check(in[0], bands, count, out);
    double t1 = MPI_Wtime();
    if (!st)
        st = write_bands(ctx, job, bands, count, out->paths);
    seconds[1] = MPI_Wtime() - t1;
    for (int i = 0; i <= count; i++)
        limn_mpi_mesh_destroy(bands[i]);
    free(bands);
    limn_mpi_mesh_destroy(in[0]);
    return st;
}

/* ------------------------------------------------------------------ morph */

/* limn_mpi_mesh_morph's frames to the CLI's sink (every rank). */
typedef struct morph_job {
    const cli_sliced_job *job;
    const limn_morph_options *o;
    cli_morph_sink *sink;
    limn_series_report *r;
    limn_context *ctx;
} morph_job;

static limn_status sliced_frame(void *user, const limn_mpi_mesh *frame, const limn_morph_frame *f)
{
    morph_job *m = user;
    double t = MPI_Wtime();
    const char *name = m->sink->name(m->sink->user, f->index);
    limn_status st = limn_mpi_output_set_add_mesh(m->ctx, m->job->stage, frame, name,
                                                  m->job->out_format, m->job->write, NULL);
    m->sink->record(m->sink->user, f);
    m->sink->write_seconds += MPI_Wtime() - t;
    return st;
}

static limn_status morph_fn(limn_context *ctx, limn_mpi_mesh *const in[2], void *user,
                            const limn_mpi_options *mo, limn_mpi_result *res)
{
    morph_job *m = user;
    return limn_mpi_mesh_morph(ctx, in[0], in[1], m->o, sliced_frame, m, m->r, mo, res);
}

limn_status cli_mpi_morph_sliced(limn_context *ctx, const cli_sliced_job *job,
                                 const char *to_path, const limn_morph_options *o,
                                 cli_morph_sink *sink, limn_series_report *r, double seconds[2])
{
    morph_job m = {job, o, sink, r, ctx};
    sliced_call call = {morph_fn, &m, to_path, 0};
    limn_mpi_mesh *in[2] = {NULL, NULL};
    limn_status st = run_sliced(ctx, job, &call, in, seconds);
    seconds[1] = sink->write_seconds;
    limn_mpi_mesh_destroy(in[0]);
    limn_mpi_mesh_destroy(in[1]);
    return st;
}
