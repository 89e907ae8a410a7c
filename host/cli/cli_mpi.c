/* SPDX-License-Identifier: MIT */
/*
 * limn under mpirun (built with LIMN_MPI). main() calls cli_mpi_main when an
 * MPI launcher started the process; with one rank everything runs exactly as
 * without MPI. With several, interpolate, bands, smooth, denoise, sharpen and
 * morph run distributed (include/limn_mpi.h): the root (rank 0) reads, writes and
 * prints, every rank computes its share, and every failure is agreed on so
 * that all ranks exit with the same status and the message is printed once.
 * On file inputs, interpolate, smooth, denoise, sharpen, bands and morph
 * run on slices instead, and subdivide and texture only there (cli_mpi_sliced): every rank reads, computes
 * and writes its share of a distributed mesh, none holding it whole.
 * The other commands refuse to run on several ranks.
 */
#include "cli.h"

#include <limn_mpi.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif

static struct {
    int rank, size;
    int per_rank;               /* --per-rank-output was given */
    limn_mpi_stats *all;        /* root: every rank's figures of the last call */
    long long *rss;             /* root: every rank's peak resident bytes (cli_mpi_note_memory) */
    int sliced;                 /* the last call ran on slices: no rank held the whole mesh */
    double *load;               /* root: every rank's seconds reading and repairing its slice
                                   (distributed meshes only) */
} g = {0, 1, 0, NULL, NULL, 0, NULL};

int cli_mpi_launched(void)
{
    /* Open MPI, MPICH / Hydra (PMI), PMIx launchers */
    static const char *vars[] = {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK", "PMI_RANK"};
    for (size_t k = 0; k < sizeof vars / sizeof *vars; k++)
        if (getenv(vars[k]))
            return 1;
    return 0;
}

int cli_mpi_ranks(void) { return g.size; }
int cli_mpi_rank(void) { return g.rank; }

limn_status cli_mpi_agree(limn_context *ctx, limn_status st)
{
    if (g.size == 1)
        return st;
    /* the lowest failing rank's status and message */
    int key = st ? g.rank : g.size, first;
    MPI_Allreduce(&key, &first, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    if (first == g.size)
        return LIMN_OK;
    int status = (int)st;
    char message[2048] = "";
    if (g.rank == first)
        snprintf(message, sizeof message, "%s", cli_message(ctx));
    MPI_Bcast(&status, 1, MPI_INT, first, MPI_COMM_WORLD);
    MPI_Bcast(message, (int)sizeof message, MPI_CHAR, first, MPI_COMM_WORLD);
    if (g.rank != first)
        cli_error((limn_status)status, "%s", message);
    return (limn_status)status;
}

int cli_mpi_root_rc(int rc)
{
    if (g.size > 1)
        MPI_Bcast(&rc, 1, MPI_INT, 0, MPI_COMM_WORLD);
    return rc;
}

void cli_mpi_set_per_rank(int on) { g.per_rank = on; }
int cli_mpi_per_rank(void) { return g.per_rank; }

/* Every rank's statistics to the root, for the report and the summary. */
static void collect(const limn_mpi_result *res)
{
    free(g.all);
    g.all = NULL;
    if (g.rank == 0)
        g.all = calloc((size_t)g.size, sizeof *g.all);
    limn_mpi_stats mine = res->stats;
    /* homogeneous ranks: the struct travels as bytes */
    MPI_Gather(&mine, (int)sizeof mine, MPI_BYTE, g.all, g.all ? (int)sizeof mine : 0, MPI_BYTE,
               0, MPI_COMM_WORLD);
}

static void adopt_piece(limn_mpi_result *res, limn_mesh **piece)
{
    if (piece) {
        *piece = res->piece;
        res->piece = NULL;
    }
    limn_mpi_result_free(res);
}

static limn_mpi_options options(void)
{
    limn_mpi_options o;
    limn_mpi_options_default(&o);
    o.keep_piece = g.per_rank;
    return o;
}

limn_status cli_mpi_interpolate(limn_context *ctx, const limn_mesh *mesh,
                                const limn_interpolate_options *o, limn_mesh **control,
                                limn_report *r, limn_mesh **piece)
{
    limn_mpi_options mo = options();
    limn_mpi_result res = {.size = sizeof res, .stats.size = sizeof res.stats};
    limn_status st = limn_interpolate_mpi(ctx, MPI_COMM_WORLD, mesh, o, control, r, &mo, &res);
    collect(&res);
    adopt_piece(&res, piece);
    return st;
}

limn_status cli_mpi_smooth(limn_context *ctx, const limn_mesh *mesh,
                           const limn_series_options *o, int terms, limn_mesh **out,
                           limn_series_report *r, limn_mesh **piece)
{
    limn_mpi_options mo = options();
    limn_mpi_result res = {.size = sizeof res, .stats.size = sizeof res.stats};
    limn_status st = limn_smooth_mpi(ctx, MPI_COMM_WORLD, mesh, o, terms, out, r, &mo, &res);
    collect(&res);
    adopt_piece(&res, piece);
    return st;
}

limn_status cli_mpi_denoise(limn_context *ctx, const limn_mesh *mesh,
                            const limn_series_options *o, int m, int steps, int keep_volume,
                            limn_mesh **out, limn_series_report *r, limn_mesh **piece)
{
    limn_mpi_options mo = options();
    limn_mpi_result res = {.size = sizeof res, .stats.size = sizeof res.stats};
    limn_status st = limn_denoise_mpi(ctx, MPI_COMM_WORLD, mesh, o, m, steps, keep_volume, out, r,
                                      &mo, &res);
    collect(&res);
    adopt_piece(&res, piece);
    return st;
}

limn_status cli_mpi_denoise_sure(limn_context *ctx, const limn_mesh *mesh,
                                 const limn_series_options *o, int products, int *keep_volume,
                                 limn_mesh **out, double *sigma, limn_series_report *r,
                                 limn_mesh **piece)
{
    limn_status st = LIMN_OK;
    if (*keep_volume < 0) { /* the default form keeps a closed mesh's volume */
        limn_mesh_measures a = {.size = sizeof a};
        if (cli_mpi_rank() == 0)
            st = limn_mesh_measure(ctx, mesh, &a);
        st = cli_mpi_agree(ctx, st);
        *keep_volume = a.closed;
        MPI_Bcast(keep_volume, 1, MPI_INT, 0, MPI_COMM_WORLD);
    }
    if (st)
        return st;
    limn_mpi_options mo = options();
    limn_mpi_result res = {.size = sizeof res, .stats.size = sizeof res.stats};
    st = limn_denoise_sure_mpi(ctx, MPI_COMM_WORLD, mesh, o, products, *keep_volume, out, sigma,
                               r, &mo, &res);
    collect(&res);
    adopt_piece(&res, piece);
    return st;
}

limn_status cli_mpi_sharpen(limn_context *ctx, const limn_mesh *mesh,
                            const limn_series_options *o, int from, int to, int steps,
                            limn_mesh **out, limn_series_report *r, limn_mesh **piece)
{
    limn_mpi_options mo = options();
    limn_mpi_result res = {.size = sizeof res, .stats.size = sizeof res.stats};
    limn_status st =
        limn_sharpen_mpi(ctx, MPI_COMM_WORLD, mesh, o, from, to, steps, out, r, &mo, &res);
    collect(&res);
    adopt_piece(&res, piece);
    return st;
}

limn_status cli_mpi_bands(limn_context *ctx, const limn_mesh *mesh, const limn_series_options *o,
                          int count, double *bands, double *energy, limn_series_report *r)
{
    limn_mpi_options mo = options();
    mo.keep_piece = 0;
    limn_mpi_result res = {.size = sizeof res, .stats.size = sizeof res.stats};
    limn_status st =
        limn_bands_mpi(ctx, MPI_COMM_WORLD, mesh, o, count, bands, energy, r, &mo, &res);
    collect(&res);
    limn_mpi_result_free(&res);
    return st;
}

limn_status cli_mpi_morph(limn_context *ctx, const limn_mesh *from, const limn_mesh *to,
                          const limn_morph_options *o, limn_morph_frame_fn fn, void *user,
                          limn_series_report *r)
{
    limn_mpi_options mo = options();
    mo.keep_piece = 0;
    limn_mpi_result res = {.size = sizeof res, .stats.size = sizeof res.stats};
    limn_status st = limn_morph_mpi(ctx, MPI_COMM_WORLD, from, to, o, fn, user, r, &mo, &res);
    collect(&res);
    limn_mpi_result_free(&res);
    return st;
}

int cli_mpi_sliced(const char *input, limn_format in_format, const char *output, int per_rank)
{
    if (g.size == 1 || per_rank || strcmp(input, "-") == 0 || strcmp(output, "-") == 0)
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
    limn_repair_report rep = {.size = sizeof rep};
    st = limn_mpi_mesh_repair(ctx, *mesh, &o, &rep);
    cli_print_warnings(cmd, ctx);
    if (!st && limn_mpi_mesh_face_total(*mesh) == 0)
        st = rep.faces_before
                 ? cli_error(LIMN_ERR_TOPOLOGY,
                             "%s: no faces are left after the repair (all %zu were degenerate): "
                             "nothing to %s",
                             input, rep.faces_before, cmd)
                 : cli_error(LIMN_ERR_TOPOLOGY,
                             "%s: the mesh has no faces (a point cloud?): nothing to %s", input,
                             cmd);
    return st;
}

limn_status cli_mpi_interpolate_sliced(limn_context *ctx, const cli_sliced_job *job,
                                       const limn_interpolate_options *o, limn_report *r,
                                       limn_write_report *written, double seconds[2])
{
    limn_mpi_mesh *mesh = NULL, *control = NULL;
    double t0 = MPI_Wtime();
    limn_status st = read_sliced(ctx, job, &mesh);
    seconds[0] = MPI_Wtime() - t0;
    free(g.load);
    g.load = g.rank == 0 ? calloc((size_t)g.size, sizeof *g.load) : NULL;
    MPI_Gather(&seconds[0], 1, MPI_DOUBLE, g.load, 1, MPI_DOUBLE, 0, MPI_COMM_WORLD);
    limn_mpi_options mo = options();
    mo.keep_piece = 0;
    limn_mpi_result res = {.size = sizeof res, .stats.size = sizeof res.stats};
    g.sliced = 1;
    if (!st) {
        st = limn_mpi_mesh_interpolate(ctx, mesh, o, &control, r, &mo, &res);
        cli_print_warnings(job->cmd, ctx);
        collect(&res);
        limn_mpi_result_free(&res);
    }
    double t1 = MPI_Wtime();
    if (!st)
        st = limn_mpi_mesh_write(ctx, control, job->output, job->out_format, job->write,
                                 written);
    seconds[1] = MPI_Wtime() - t1;
    limn_mpi_mesh_destroy(mesh);
    limn_mpi_mesh_destroy(control);
    return st;
}

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

/* The filter of call on a distributed mesh. */
static limn_status series_call(limn_context *ctx, const limn_mpi_mesh *mesh,
                               const limn_series_options *o, const cli_series_call *c,
                               limn_mpi_mesh **out, limn_series_report *r,
                               const limn_mpi_options *mo, limn_mpi_result *res)
{
    switch (c->kind) {
    case CLI_SERIES_SMOOTH:
        return limn_mpi_mesh_smooth(ctx, mesh, o, c->terms, out, r, mo, res);
    case CLI_SERIES_TEXTURE:
        return texture_call(ctx, mesh, o, c, out, r, mo, res);
    case CLI_SERIES_DENOISE:
        if (c->features)
            return limn_mpi_mesh_denoise_features(ctx, mesh, c->features, out, r, mo, res);
        if (c->products)
            return denoise_sure_sliced(ctx, mesh, o, c, out, r, mo, res);
        return limn_mpi_mesh_denoise(ctx, mesh, o, c->m, c->steps, c->keep_volume, out, r, mo,
                                     res);
    default:
        return limn_mpi_mesh_sharpen(ctx, mesh, o, c->from, c->to, c->steps, out, r, mo, res);
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
    limn_mpi_mesh *mesh = NULL, *out = NULL;
    double t0 = MPI_Wtime();
    limn_status st = read_sliced(ctx, job, &mesh);
    seconds[0] = MPI_Wtime() - t0;
    limn_mpi_options mo = options();
    mo.keep_piece = 0;
    limn_mpi_result res = {.size = sizeof res, .stats.size = sizeof res.stats};
    g.sliced = 1;
    if (!st) {
        st = series_call(ctx, mesh, o, call, &out, r, &mo, &res);
        cli_print_warnings(job->cmd, ctx);
        collect(&res);
        limn_mpi_result_free(&res);
    }
    if (!st && call->kind != CLI_SERIES_TEXTURE) /* texture: another mesh, no displacement */
        *displacement = block_displacement(mesh, out, r->bbox_diagonal);
    if (!st && call->measures)
        st = measure_sliced(ctx, mesh, out, call->measures);
    double t1 = MPI_Wtime();
    if (!st)
        st = limn_mpi_mesh_write(ctx, out, job->output, job->out_format, job->write, written);
    seconds[1] = MPI_Wtime() - t1;
    limn_mpi_mesh_destroy(mesh);
    limn_mpi_mesh_destroy(out);
    return st;
}

limn_status cli_mpi_subdivide_sliced(limn_context *ctx, const cli_sliced_job *job,
                                     const limn_subdivide_options *o, limn_subdivide_report *r,
                                     limn_write_report *written, double seconds[2])
{
    limn_mpi_mesh *mesh = NULL, *surface = NULL;
    double t0 = MPI_Wtime();
    limn_status st = read_sliced(ctx, job, &mesh);
    seconds[0] = MPI_Wtime() - t0;
    limn_mpi_options mo = options();
    mo.keep_piece = 0;
    limn_mpi_result res = {.size = sizeof res, .stats.size = sizeof res.stats};
    g.sliced = 1;
    if (!st) {
        st = limn_mpi_mesh_subdivide(ctx, mesh, o, &surface, r, &mo, &res);
        cli_print_warnings(job->cmd, ctx);
        collect(&res);
        limn_mpi_result_free(&res);
    }
    limn_mpi_mesh_destroy(mesh); /* before the write: the surface is all that is left */
    double t1 = MPI_Wtime();
    if (!st)
        st = limn_mpi_mesh_write(ctx, surface, job->output, job->out_format, job->write,
                                 written);
    seconds[1] = MPI_Wtime() - t1;
    limn_mpi_mesh_destroy(surface);
    return st;
}

/* The input's energy (sum of its squared coordinates in input order) and
   the largest |sum of the bands - input| over the blocks, as cli_bands.c's
   compute gives them: the sum passed from rank to rank, the maximum exact. */
static void bands_check(const limn_mpi_mesh *mesh, limn_mpi_mesh *const *bands, int count,
                        cli_bands_out *out)
{
    double sum = 0.0, worst = 0.0;
    if (g.rank > 0)
        MPI_Recv(&sum, 1, MPI_DOUBLE, g.rank - 1, 0, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    const double *m = limn_mpi_mesh_positions(mesh);
    for (size_t k = 0; k < 3 * limn_mpi_mesh_vertex_count(mesh); k++) {
        double s = 0.0;
        for (int i = 0; i <= count; i++)
            s += limn_mpi_mesh_positions(bands[i])[k];
        worst = fmax(worst, fabs(s - m[k]));
        sum += m[k] * m[k];
    }
    if (g.rank + 1 < g.size)
        MPI_Send(&sum, 1, MPI_DOUBLE, g.rank + 1, 0, MPI_COMM_WORLD);
    MPI_Bcast(&sum, 1, MPI_DOUBLE, g.size - 1, MPI_COMM_WORLD);
    MPI_Allreduce(&worst, &out->max_sum_error, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
    out->input_energy = sum;
}

limn_status cli_mpi_bands_sliced(limn_context *ctx, const cli_sliced_job *job,
                                 const limn_series_options *o, int count, cli_bands_out *out,
                                 limn_series_report *r, double seconds[2])
{
    limn_mpi_mesh *mesh = NULL, **bands = calloc((size_t)count + 1, sizeof *bands);
    double t0 = MPI_Wtime();
    limn_status st = cli_mpi_agree(ctx, bands ? LIMN_OK
                                              : cli_error(LIMN_ERR_MEMORY, "out of memory"));
    if (!st)
        st = read_sliced(ctx, job, &mesh);
    seconds[0] = MPI_Wtime() - t0;
    limn_mpi_options mo = options();
    mo.keep_piece = 0;
    limn_mpi_result res = {.size = sizeof res, .stats.size = sizeof res.stats};
    g.sliced = 1;
    if (!st) {
        st = limn_mpi_mesh_bands(ctx, mesh, o, count, bands, out->energy, r, &mo, &res);
        cli_print_warnings(job->cmd, ctx);
        collect(&res);
        limn_mpi_result_free(&res);
    }
    if (!st)
        bands_check(mesh, bands, count, out);
    double t1 = MPI_Wtime();
    int written = 0;
    for (; !st && written <= count; written++)
        st = limn_mpi_mesh_write(ctx, bands[written], out->paths[written], job->out_format,
                                 job->write, NULL);
    for (int i = 0; st && g.rank == 0 && i < written - 1; i++)
        remove(out->paths[i]); /* the bands before the failed one */
    seconds[1] = MPI_Wtime() - t1;
    for (int i = 0; bands && i <= count; i++)
        limn_mpi_mesh_destroy(bands[i]);
    free(bands);
    limn_mpi_mesh_destroy(mesh);
    return st;
}

/* limn_mpi_mesh_morph's frames to the CLI's sink (every rank). */
typedef struct morph_frames {
    limn_context *ctx;
    const cli_sliced_job *job;
    cli_morph_sink *sink;
} morph_frames;

static limn_status sliced_frame(void *user, const limn_mpi_mesh *frame, const limn_morph_frame *f)
{
    morph_frames *m = user;
    double t = MPI_Wtime();
    const char *name = m->sink->name(m->sink->user, f->index);
    limn_status st = limn_mpi_mesh_write(m->ctx, frame, name, m->job->out_format, m->job->write,
                                         NULL);
    m->sink->written += !st;
    m->sink->record(m->sink->user, f);
    m->sink->write_seconds += MPI_Wtime() - t;
    return st;
}

limn_status cli_mpi_morph_sliced(limn_context *ctx, const cli_sliced_job *job,
                                 const char *to_path, const limn_morph_options *o,
                                 cli_morph_sink *sink, limn_series_report *r, double seconds[2])
{
    limn_mpi_mesh *from = NULL, *to = NULL;
    cli_sliced_job tj = *job;
    tj.input = to_path;
    double t0 = MPI_Wtime();
    limn_status st = read_sliced(ctx, job, &from);
    if (!st)
        st = read_sliced(ctx, &tj, &to);
    seconds[0] = MPI_Wtime() - t0;
    limn_mpi_options mo = options();
    mo.keep_piece = 0;
    limn_mpi_result res = {.size = sizeof res, .stats.size = sizeof res.stats};
    g.sliced = 1;
    morph_frames mf = {ctx, job, sink};
    if (!st) {
        st = limn_mpi_mesh_morph(ctx, from, to, o, sliced_frame, &mf, r, &mo, &res);
        cli_print_warnings(job->cmd, ctx);
        collect(&res);
        limn_mpi_result_free(&res);
    }
    seconds[1] = sink->write_seconds;
    limn_mpi_mesh_destroy(from);
    limn_mpi_mesh_destroy(to);
    return st;
}

void cli_mpi_note_memory(void)
{
    if (g.size == 1)
        return;
    free(g.rss);
    g.rss = g.rank == 0 ? calloc((size_t)g.size, sizeof *g.rss) : NULL;
    long long mine = (long long)cli_peak_rss();
    MPI_Gather(&mine, 1, MPI_LONG_LONG, g.rss, 1, MPI_LONG_LONG, 0, MPI_COMM_WORLD);
}

void cli_mpi_json(json_out *j)
{
    if (g.size == 1 || !g.all)
        return;
    json_object_begin(j, "mpi");
    json_integer(j, "ranks", g.size);
    json_bool(j, "distributed_mesh", g.sliced);
    json_integer(j, "edge_cut", (long long)g.all[0].edge_cut);
    json_number(j, "seconds_partition", g.all[0].seconds_partition);
    json_array_begin(j, "per_rank");
    for (int r = 0; r < g.size; r++) {
        const limn_mpi_stats *s = &g.all[r];
        json_element_object_begin(j);
        json_integer(j, "rank", s->rank);
        json_integer(j, "local_rank", s->local_rank);
        json_string(j, "device", s->device);
        json_integer(j, "owned", (long long)s->owned);
        json_integer(j, "ghosts", (long long)s->ghosts);
        json_integer(j, "interior_rows", (long long)s->interior_rows);
        json_integer(j, "neighbours", s->neighbours);
        json_integer(j, "halo_bytes_sent", (long long)s->halo_bytes_sent);
        json_integer(j, "halo_bytes_received", (long long)s->halo_bytes_received);
        json_integer(j, "exchanges", s->exchanges);
        if (g.load)
            json_number(j, "seconds_load", g.load[r]);
        json_number(j, "seconds_partition", s->seconds_partition);
        json_number(j, "seconds_distribute", s->seconds_distribute);
        json_number(j, "seconds_solve", s->seconds_solve);
        json_number(j, "seconds_compute", s->seconds_compute);
        json_number(j, "seconds_halo", s->seconds_halo);
        json_number(j, "seconds_wait", s->seconds_wait);
        json_number(j, "seconds_reduce", s->seconds_reduce);
        if (g.rss)
            json_integer(j, "peak_rss_bytes", g.rss[r]);
        json_object_end(j);
    }
    json_array_end(j);
    json_object_end(j);
}

void cli_mpi_print(void)
{
    if (g.size == 1 || !g.all)
        return;
    fprintf(stderr, "  MPI: %d ranks, edge cut %zu, partition %.3f s (rank 0)\n", g.size,
            g.all[0].edge_cut, g.all[0].seconds_partition);
    for (int r = 0; r < g.size; r++) {
        const limn_mpi_stats *s = &g.all[r];
        double n = s->exchanges > 0 ? (double)s->exchanges : 1.0;
        fprintf(stderr,
                "  rank %d: %zu owned, %zu ghosts, %d neighbours, halo %zu B out / %zu B in per "
                "exchange; per exchange: compute %.3g s, halo %.3g s (waiting %.3g), reduce "
                "%.3g s\n",
                r, s->owned, s->ghosts, s->neighbours, s->halo_bytes_sent,
                s->halo_bytes_received, s->seconds_compute / n, s->seconds_halo / n,
                s->seconds_wait / n, s->seconds_reduce / n);
    }
}

char *cli_mpi_rank_path(const char *path)
{
    /* out.ply -> out.r0003.ply: the extension stays, so the format does */
    int digits = 1;
    for (int n = g.size - 1; n >= 10; n /= 10)
        digits++;
    size_t len = strlen(path) + 32;
    char *out = malloc(len);
    if (!out)
        return NULL;
    const char *slash = strrchr(path, '/'), *dot = strrchr(path, '.');
    if (!dot || (slash && dot < slash))
        dot = path + strlen(path);
    snprintf(out, len, "%.*s.r%0*d%s", (int)(dot - path), path, digits, g.rank, dot);
    return out;
}

static int distributed(const char *cmd)
{
    static const char *names[] = {"interpolate", "bands", "smooth",    "denoise",
                                  "sharpen",     "morph", "subdivide", "texture"};
    for (size_t k = 0; k < sizeof names / sizeof *names; k++)
        if (strcmp(cmd, names[k]) == 0)
            return 1;
    return 0;
}

/* Each rank's peak memory (docs/mpi.md "Memory per rank"): glibc's mmap
   threshold grows to the largest block freed (up to 32 MiB), after which a
   rank's big arrays come from the heap and stay resident when freed in the
   middle of it; every phase then stacks on the last one's holes. A fixed
   threshold gives every big array back at its free. The single process's
   peak does not change with it (measured: 696 MB either way at 2.1M). */
static void fixed_mmap_threshold(void)
{
#ifdef __GLIBC__
    mallopt(M_MMAP_THRESHOLD, 128 * 1024);
    mallopt(M_TRIM_THRESHOLD, 128 * 1024);
#endif
}

int cli_mpi_main(int argc, char **argv, int (*dispatch)(int, char **))
{
    fixed_mmap_threshold();
    MPI_Init(&argc, &argv);
    MPI_Comm_rank(MPI_COMM_WORLD, &g.rank);
    MPI_Comm_size(MPI_COMM_WORLD, &g.size);
    int rc;
    if (g.size == 1) {
        rc = dispatch(argc, argv); /* one rank: exactly the single process */
    } else if (argc < 2 || argv[1][0] == '-' || strcmp(argv[1], "help") == 0) {
        /* usage, --help, --version: rank 0 answers for all */
        rc = g.rank == 0 ? dispatch(argc, argv) : 0;
        MPI_Bcast(&rc, 1, MPI_INT, 0, MPI_COMM_WORLD);
    } else if (!distributed(argv[1])) {
        if (g.rank == 0)
            fprintf(stderr,
                    "limn %s: does not run on several MPI ranks (%d here): run it without "
                    "mpirun; interpolate, bands, smooth, denoise, sharpen, morph, subdivide and "
                    "texture run distributed\n",
                    argv[1], g.size);
        rc = EXIT_USAGE;
    } else {
        rc = dispatch(argc, argv);
        /* every rank leaves with the same status (the root's decides usage errors) */
        int worst = rc;
        MPI_Allreduce(&rc, &worst, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
        rc = worst;
    }
    free(g.all);
    g.all = NULL;
    free(g.rss);
    g.rss = NULL;
    MPI_Finalize();
    return rc;
}
