/* SPDX-License-Identifier: MIT */
/*
 * limn under mpirun (built with LIMN_MPI). main() calls cli_mpi_main when an
 * MPI launcher started the process; with one rank everything runs exactly as
 * without MPI. With several, interpolate, bands, smooth, denoise, sharpen and
 * morph run distributed (include/limn_mpi.h): the root (rank 0) reads, writes and
 * prints, every rank computes its share, and every failure is agreed on so
 * that all ranks exit with the same status and the message is printed once.
 * On file inputs, interpolate, smooth, denoise, sharpen, bands and morph
 * run on slices instead, and subdivide and texture only there
 * (cli_mpi_sliced.c): every rank reads, computes and writes its share of a
 * distributed mesh, none holding it whole.
 * The other commands refuse to run on several ranks.
 */
#include "cli_mpi.h"

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
    if (g.size > 1) {
        /* the parse is the same on every rank but for memory: a rank that
           ran out (its message said) stops them all */
        int failed = rc > 0, any = 0;
        MPI_Bcast(&rc, 1, MPI_INT, 0, MPI_COMM_WORLD);
        MPI_Allreduce(&failed, &any, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
        if (rc == 0 && any)
            rc = EXIT_FAILURE_RUN;
    }
    return rc;
}

void cli_mpi_set_per_rank(int on) { g.per_rank = on; }
int cli_mpi_per_rank(void) { return g.per_rank; }

/* Every rank's bytes of mine gathered into a new array on rank 0 (NULL on
   the others). Rank 0 out of memory: no gather (the others' sends would not
   fit), NULL, and the summary and report go without these figures (said). */
static void *gather_to_root(const void *mine, size_t bytes)
{
    void *all = g.rank == 0 ? calloc((size_t)g.size, bytes) : NULL;
    int room = g.rank != 0 || all;
    MPI_Bcast(&room, 1, MPI_INT, 0, MPI_COMM_WORLD);
    if (!room) {
        fprintf(stderr, "limn: warning: out of memory for the ranks' figures: the summary and "
                        "the report leave them out\n");
        return NULL;
    }
    /* homogeneous ranks: the figures travel as bytes */
    MPI_Gather(mine, (int)bytes, MPI_BYTE, all, all ? (int)bytes : 0, MPI_BYTE, 0,
               MPI_COMM_WORLD);
    return all;
}

void cli_mpi_collect(const limn_mpi_result *res)
{
    free(g.all);
    g.all = gather_to_root(&res->stats, sizeof res->stats);
}

void cli_mpi_mark_sliced(void) { g.sliced = 1; }

void cli_mpi_gather_load(double seconds)
{
    free(g.load);
    g.load = gather_to_root(&seconds, sizeof seconds);
}

static limn_mpi_options options(void)
{
    limn_mpi_options o;
    limn_mpi_options_default(&o);
    o.keep_piece = g.per_rank;
    return o;
}

/* The end of every call on the root path: every rank's figures to the
   root, this rank's piece into *piece (when not NULL), res freed; st. */
static limn_status gathered(limn_status st, limn_mpi_result *res, limn_mesh **piece)
{
    cli_mpi_collect(res);
    if (piece) {
        *piece = res->piece;
        res->piece = NULL;
    }
    limn_mpi_result_free(res);
    return st;
}

limn_status cli_mpi_interpolate(limn_context *ctx, const limn_mesh *mesh,
                                const limn_interpolate_options *o, limn_mesh **control,
                                limn_report *r, limn_mesh **piece)
{
    limn_mpi_options mo = options();
    limn_mpi_result res = {.size = sizeof res, .stats.size = sizeof res.stats};
    return gathered(limn_interpolate_mpi(ctx, MPI_COMM_WORLD, mesh, o, control, r, &mo, &res),
                    &res, piece);
}

limn_status cli_mpi_smooth(limn_context *ctx, const limn_mesh *mesh,
                           const limn_series_options *o, int terms, limn_mesh **out,
                           limn_series_report *r, limn_mesh **piece)
{
    limn_mpi_options mo = options();
    limn_mpi_result res = {.size = sizeof res, .stats.size = sizeof res.stats};
    return gathered(limn_smooth_mpi(ctx, MPI_COMM_WORLD, mesh, o, terms, out, r, &mo, &res),
                    &res, piece);
}

limn_status cli_mpi_denoise(limn_context *ctx, const limn_mesh *mesh,
                            const limn_series_options *o, int m, int steps, int keep_volume,
                            limn_mesh **out, limn_series_report *r, limn_mesh **piece)
{
    limn_mpi_options mo = options();
    limn_mpi_result res = {.size = sizeof res, .stats.size = sizeof res.stats};
    return gathered(limn_denoise_mpi(ctx, MPI_COMM_WORLD, mesh, o, m, steps, keep_volume, out, r,
                                     &mo, &res),
                    &res, piece);
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
    return gathered(limn_denoise_sure_mpi(ctx, MPI_COMM_WORLD, mesh, o, products, *keep_volume,
                                          out, sigma, r, &mo, &res),
                    &res, piece);
}

limn_status cli_mpi_sharpen(limn_context *ctx, const limn_mesh *mesh,
                            const limn_series_options *o, int from, int to, int steps,
                            limn_mesh **out, limn_series_report *r, limn_mesh **piece)
{
    limn_mpi_options mo = options();
    limn_mpi_result res = {.size = sizeof res, .stats.size = sizeof res.stats};
    return gathered(
        limn_sharpen_mpi(ctx, MPI_COMM_WORLD, mesh, o, from, to, steps, out, r, &mo, &res), &res,
        piece);
}

limn_status cli_mpi_bands(limn_context *ctx, const limn_mesh *mesh, const limn_series_options *o,
                          int count, double *bands, double *energy, limn_series_report *r)
{
    limn_mpi_options mo = options();
    mo.keep_piece = 0;
    limn_mpi_result res = {.size = sizeof res, .stats.size = sizeof res.stats};
    return gathered(
        limn_bands_mpi(ctx, MPI_COMM_WORLD, mesh, o, count, bands, energy, r, &mo, &res), &res,
        NULL);
}

limn_status cli_mpi_morph(limn_context *ctx, const limn_mesh *from, const limn_mesh *to,
                          const limn_morph_options *o, limn_morph_frame_fn fn, void *user,
                          limn_series_report *r)
{
    limn_mpi_options mo = options();
    mo.keep_piece = 0;
    limn_mpi_result res = {.size = sizeof res, .stats.size = sizeof res.stats};
    return gathered(limn_morph_mpi(ctx, MPI_COMM_WORLD, from, to, o, fn, user, r, &mo, &res),
                    &res, NULL);
}

void cli_mpi_note_memory(void)
{
    if (g.size == 1)
        return;
    free(g.rss);
    long long mine = (long long)cli_peak_rss();
    g.rss = gather_to_root(&mine, sizeof mine);
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
