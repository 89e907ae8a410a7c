/* SPDX-License-Identifier: MIT */
/* Pieces shared by the series subcommands (bands, smooth, denoise, sharpen,
   morph, texture, render): common options, loading, reports. */
#ifndef LIMN_CLI_SERIES_H
#define LIMN_CLI_SERIES_H

#include "cli.h"

typedef struct series_cli {
    const char *cmd;          /* "denoise" etc. */
    const char *help;
    const char *inputs[2];
    int input_count, inputs_wanted;
    const char *output, *report, *device;
    limn_format in_format, out_format;
    limn_series_options opt;
    int quiet, overwrite_input;
    cli_repair repair;        /* --no-repair, --drop-duplicate-faces (cli.h) */
    int per_rank;             /* --per-rank-output (smooth, denoise; under mpirun) */
    limn_mesh *piece;         /* this rank's piece for it; series_cli_finish frees */
} series_cli;

/* The long options series_cli_arg takes (cli_options tables): render has
   no scheme, alpha, device or format; smooth and denoise add
   per-rank-output. */
#define SERIES_BASE_OPTIONS                                                                    \
    CLI_FLAG("help"), CLI_VALUE("output"), CLI_VALUE("report"), CLI_VALUE("input-format"),     \
        CLI_FLAG("overwrite-input"), CLI_FLAG("quiet"), CLI_REPAIR_OPTIONS
#define SERIES_OPTIONS                                                                         \
    SERIES_BASE_OPTIONS, CLI_VALUE("scheme"), CLI_VALUE("alpha"), CLI_VALUE("device"),         \
        CLI_VALUE("format")
#define SERIES_SHORT "ho:q"

enum { SERIES_ARG_NOT_MINE = 0, SERIES_ARG_TAKEN = 1, SERIES_ARG_EXIT = 2 };

/*
 * Handles argv[*i] if it is one of the shared options (-h, -o, --scheme,
 * --alpha, --device, --report, --format, --input-format, --overwrite-input,
 * -q) or a positional INPUT. Returns SERIES_ARG_TAKEN, SERIES_ARG_NOT_MINE,
 * or SERIES_ARG_EXIT with *rc the exit status (-1: help printed, exit 0).
 */
int series_cli_arg(series_cli *c, int argc, char **argv, int *i, int *rc);
/* Checks inputs and output after parsing; 0 or an exit status. mesh_output:
   the output is a mesh (its format must be known, it is not an input and it
   can be written: cli_check_outputs, as the report always). */
int series_cli_check(series_cli *c, int mesh_output);
/* "--opt value" for the command's own options: the value or NULL after a
   usage error. */
const char *series_cli_value(series_cli *c, int argc, char **argv, int *i);
/* Integer / number options with a lower bound; 0 on success or exit status. */
int series_cli_int(series_cli *c, const char *opt, const char *text, int min, int *out);
int series_cli_number(series_cli *c, const char *opt, const char *text, double *out);

/* Creates the context, sets the device, reads the input meshes (under
   mpirun: on rank 0 only, and a failure there stops every rank). */
limn_status series_cli_load(series_cli *c, limn_context **ctx, limn_mesh **meshes);

typedef struct series_seconds {
    double load, write, total, t0;
} series_seconds;

/* The report's shared keys (command, input, output, vertices, faces, scheme,
   alpha, device, stencil_nonzeros, products, bbox_diagonal). */
json_out *series_json_begin(const series_cli *c, const limn_series_report *r);
/* The seconds object, then the report staged in set (see json_stage). */
limn_status series_json_stage(limn_context *ctx, json_out *j, const series_cli *c,
                              const limn_series_report *r, const series_seconds *s,
                              limn_output_set *set);
/* The seconds object, then writes the report atomically. */
limn_status series_json_finish(limn_context *ctx, json_out *j, const series_cli *c,
                               const limn_series_report *r, const series_seconds *s);
/* The summary's first lines on stderr. */
void series_print_head(const series_cli *c, const limn_series_report *r);
void series_print_seconds(const limn_series_report *r, const series_seconds *s);

/* Writes a filtered mesh (timed) and the shared report and summary; the
   command adds its keys and lines through the callbacks (may be NULL). */
typedef struct series_extra {
    void (*json)(json_out *j, void *user);
    void (*print)(void *user);
    void *user;
} series_extra;
int series_cli_finish(series_cli *c, limn_context *ctx, limn_status st, const limn_mesh *result,
                      const limn_series_report *r, series_seconds *s, const series_extra *x);

#endif
