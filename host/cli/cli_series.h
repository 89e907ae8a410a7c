/* SPDX-License-Identifier: MIT */
/* Pieces shared by the series subcommands (bands, smooth, denoise, sharpen,
   morph, texture, render): common options, loading, reports. */
#ifndef LIMN_CLI_SERIES_H
#define LIMN_CLI_SERIES_H

#include "cli_args.h"

/* The help lines of the series commands' shared options, and the last line. */
#define SERIES_HELP                                                                            \
    "  --scheme S             auto, loop or catmark                  [auto]\n"                  \
    "  --alpha A              Catmull-Clark alpha in [0, 1]           [0]\n"                    \
    "  --report FILE.json     also write the report as JSON\n"                                 \
    "  --device SPEC          reference | opencl | opencl:P.D | opencl:NAME\n"                 \
    CLI_HOST_THREADS_HELP
#define SERIES_HELP_EXIT "\nExit status: 0 success, 1 failure (nothing written), 2 bad usage.\n"

typedef struct series_cli {
    cli_args a;               /* the shared options (cli_args.h) */
    limn_series_options opt;  /* --scheme, --alpha */
    limn_mesh *piece;         /* --per-rank-output: this rank's piece; series_cli_finish frees */
    int sliced;               /* the run was on slices: the mesh is written already */
} series_cli;

/* The defaults, with --scheme and --alpha going to c->opt. */
void series_cli_init(series_cli *c, const char *cmd, const char *help, int inputs_wanted);

/* Checks inputs and output after parsing; 0 or an exit status. mesh_output:
   the output is a mesh (its format must be known, it is not an input and it
   can be written: cli_check_outputs, as the report always). */
int series_cli_check(series_cli *c, int mesh_output);

/* Creates the context, sets the device, reads the input meshes (under
   mpirun: on rank 0 only, and a failure there stops every rank). */
limn_status series_cli_load(series_cli *c, limn_context **ctx, limn_mesh **meshes);

/* Destroys what series_cli_load made (the meshes, then the context). */
void series_cli_unload(limn_context *ctx, limn_mesh **meshes);

typedef struct series_seconds {
    double load, write, total, t0;
} series_seconds;

/* Writes a filtered mesh (timed) and the shared report and summary; the
   command adds its keys and lines through the callbacks (may be NULL). */
typedef struct series_extra {
    void (*json)(json_out *j, void *user);
    void (*print)(void *user);
    void *user;
} series_extra;
int series_cli_finish(series_cli *c, limn_context *ctx, limn_status st, const limn_mesh *result,
                      const limn_series_report *r, series_seconds *s, const series_extra *x);

/* A command that filters one mesh into one (smooth, denoise, sharpen,
   texture): run makes *out from in (progress shown around it); after a run
   that gave a mesh, measure (may be NULL) fills the command's report keys
   and returns a failure of its own, and *displacement (when not NULL) is
   the mean displacement (series_mean_displacement; left as it was when the
   meshes cannot be compared); x reports them. */
typedef struct series_filter {
    limn_status (*run)(series_cli *c, limn_context *ctx, const limn_mesh *in, limn_mesh **out,
                       limn_series_report *r, void *user);
    limn_status (*measure)(limn_context *ctx, const limn_mesh *in, const limn_mesh *out,
                           const limn_series_report *r, void *user);
    double *displacement;
    series_extra x;
    /* may be NULL: the filter as a distributed-mesh call; under several
       ranks on a file input (cli_mpi_sliced) it runs on slices, no rank
       holding the whole mesh, and measure is not called */
    const cli_series_call *sliced;
} series_filter;
/* Loads the input, runs the filter, writes the result and the report, prints
   the summary (series_cli_finish); returns the exit status. With f->sliced
   under several ranks on a file: every rank reads its slice, filters and
   writes its share (cli_mpi_series_sliced), then the report (rank 0). */
int series_cli_filter(series_cli *c, const series_filter *f);
/* The mean distance from in to out relative to the bbox diagonal. */
limn_status series_mean_displacement(limn_context *ctx, const limn_mesh *in, const limn_mesh *out,
                                     const limn_series_report *r, double *value);

#endif
