/* SPDX-License-Identifier: MIT */
/* The options every mesh command shares (interpolate, subdivide and the
   series commands): their table entries, their parser, and the loop that
   hands the rest to the command's own options. */
#ifndef LIMN_CLI_ARGS_H
#define LIMN_CLI_ARGS_H

#include "cli.h"

typedef struct cli_args {
    const char *cmd;          /* "denoise" etc. */
    const char *help;
    const char *inputs[2];
    int input_count, inputs_wanted;
    const char *output, *report, *device, *fallback;
    limn_format in_format, out_format;
    const char *formats;      /* the names a bad --format lists (NULL: no stl) */
    limn_scheme *scheme;      /* where --scheme and --alpha go (NULL: none) */
    double *alpha;
    int quiet, overwrite_input;
    int per_rank;             /* --per-rank-output (under mpirun) */
    cli_repair repair;        /* --no-repair, --drop-duplicate-faces (cli.h) */
    int host_threads;         /* --host-threads N (0: the default) */
    limn_output_precision precision; /* --output-precision (interpolate, subdivide) */
    limn_write_report written;       /* the error of the output as staged, when wrote */
    int wrote;
    limn_output_set *staged; /* outputs staged before the command's finish (a sliced
                                run's mesh, bands, morph frames): it commits them
                                with the report; or NULL */
} cli_args;

/* The long options cli_args_parse takes itself (cli_options tables); each
   command's table says which of them it has: render has no scheme, alpha,
   device or format; interpolate and subdivide add fallback, smooth, denoise
   and interpolate per-rank-output. */
#define CLI_ARGS_BASE_OPTIONS                                                                  \
    CLI_FLAG("help"), CLI_VALUE("output"), CLI_VALUE("report"), CLI_VALUE("input-format"),     \
        CLI_FLAG("overwrite-input"), CLI_FLAG("quiet"), CLI_VALUE("host-threads"),             \
        CLI_REPAIR_OPTIONS
#define CLI_ARGS_OPTIONS                                                                       \
    CLI_ARGS_BASE_OPTIONS, CLI_VALUE("scheme"), CLI_VALUE("alpha"), CLI_VALUE("device"),       \
        CLI_VALUE("format")

/* What a command's own option handler returns for an argument that is none
   of its options (cli_args_parse then refuses it as unknown). */
enum { CLI_OWN_UNKNOWN = -2 };
/* Handles argv[*i], an option cli_args_parse does not take: returns 0,
   an exit status, or CLI_OWN_UNKNOWN. Takes a value with cli_args_value
   (or cli_args_int, cli_args_positive), which advance *i. */
typedef int (*cli_own_fn)(cli_args *a, void *user, int argc, char **argv, int *i);

/* cli_options over longopts (short options "ho:q"), then every argument in
   order: the shared options (-h, -o, --scheme, --alpha, --device,
   --fallback, --report, --format, --input-format, --overwrite-input,
   --per-rank-output, -q, --host-threads, the repair policy), up to inputs_wanted positional
   INPUTs, and the command's own through own (may be NULL). Returns 0, -1
   (help printed on rank 0: exit status 0) or an exit status; under mpirun
   the same on every rank (cli_mpi_root_rc: a rank out of memory stops all). */
int cli_args_parse(cli_args *a, const struct option *longopts, int argc, char **argv,
                   cli_own_fn own, void *user);

/* "--opt value": the value, or NULL after the usage error "OPT needs a value". */
const char *cli_args_value(cli_args *a, int argc, char **argv, int *i);
/* An integer value in [min, max] ("OPT V must be at least MIN", "OPT V: at
   most MAX"); 0 or an exit status. The value text is argv[*i] after it. */
int cli_args_int(cli_args *a, int argc, char **argv, int *i, int min, int max, int *out);
/* A number value; 0 or an exit status. */
int cli_args_number(cli_args *a, int argc, char **argv, int *i, double *out);
/* A number value above 0 ("OPT V must be positive"); 0 or an exit status. */
int cli_args_positive(cli_args *a, int argc, char **argv, int *i, double *out);
/* v as one of names[0..n-1]: its index, or -1 after the usage error
   "OPT 'V' is not one of NAME, NAME, ...". */
int cli_args_choice(cli_args *a, const char *opt, const char *v, const char *const *names, int n);

/* A command's own option in a table read by cli_args_own: a flag sets
   *target to `min`; the others take a value (an integer in [min, max] by
   cli_args_int, a number, a positive number, a byte size). */
typedef enum cli_own_kind {
    CLI_OWN_FLAG,
    CLI_OWN_INT,
    CLI_OWN_NUMBER,
    CLI_OWN_POSITIVE,
    CLI_OWN_SIZE
} cli_own_kind;
typedef struct cli_own_option {
    const char *name; /* "--steps" */
    cli_own_kind kind;
    void *target;     /* int (FLAG, INT), double (NUMBER, POSITIVE), size_t (SIZE) */
    int min, max;
} cli_own_option;
/* argv[*i] when it is one of the n options of t: 0 or an exit status;
   CLI_OWN_UNKNOWN when it is none of them. */
int cli_args_own(cli_args *a, int argc, char **argv, int *i, const cli_own_option *t, size_t n);

/* After parsing: the INPUTs and -o were given; 0 or an exit status. */
int cli_args_required(cli_args *a);
/* --per-rank-output is refused without several MPI ranks; 0 or an exit status. */
int cli_args_check_per_rank(cli_args *a);
/* Before any work: the mesh output (and surface, when not NULL) has a known
   format and is not the input, the report is not the input either, and all
   can be written (cli_check_output, cli_check_outputs); 0 or an exit status. */
int cli_args_check_meshes(cli_args *a, const char *surface);
/* Sets the context's memory cap (the reader's too), host threads, device and fallback,
   then with load reads and repairs INPUT into *mesh (cli_load_mesh). */
limn_status cli_args_open(cli_args *a, limn_context *ctx, size_t max_memory, int load,
                          limn_mesh **mesh);
/* Stages the mesh output in set: with --per-rank-output this rank's piece
   at cli_mpi_rank_path(OUTPUT), else mesh (when not NULL) at OUTPUT. */
limn_status cli_args_stage_mesh(cli_args *a, limn_context *ctx, limn_output_set *set,
                                const limn_mesh *mesh, const limn_mesh *piece);
/* Stages mesh as path with --output-precision; the output's error is kept
   for the report when path is the output. */
limn_status cli_args_stage_output(cli_args *a, limn_context *ctx, limn_output_set *set,
                                  const limn_mesh *mesh, const char *path);
/* The text report's line on the output's float32 error (nothing for doubles). */
void cli_args_print_written(const cli_args *a);
/* A report's first keys (json_begin): command, input, target (the second
   input, when there is one), output, vertices, faces; NULL when out of memory. */
json_out *cli_args_report(const cli_args *a, size_t vertices, size_t faces);

#endif
