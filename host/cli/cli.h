/* SPDX-License-Identifier: MIT */
/* The limn command line: one file per subcommand, glue over the library. */
#ifndef LIMN_CLI_H
#define LIMN_CLI_H

#include "limn.h"
#include <stdio.h>

enum { EXIT_USAGE = 2, EXIT_FAILURE_RUN = 1 };

int cli_interpolate(int argc, char **argv);
int cli_info(int argc, char **argv);
int cli_devices(int argc, char **argv);
int cli_subdivide(int argc, char **argv);
int cli_bands(int argc, char **argv);
int cli_smooth(int argc, char **argv);
int cli_denoise(int argc, char **argv);
int cli_sharpen(int argc, char **argv);
int cli_morph(int argc, char **argv);
int cli_texture(int argc, char **argv);
int cli_render(int argc, char **argv);

/* Strict number parsing for options; print a usage error naming the option. */
int cli_parse_double(const char *opt, const char *text, double *out);
int cli_parse_int(const char *opt, const char *text, int *out);
/* "auto" | "loop" | "catmark"; prints a usage error otherwise. */
int cli_parse_scheme(const char *cmd, const char *text, limn_scheme *out);
/* Bytes with an optional K, M, G or T suffix (powers of 1024). */
int cli_parse_size(const char *opt, const char *text, size_t *out);
/* Checks an output path before any work: its format is known (from format
   or the extension) and it is not the input file. Returns 0 or an exit status. */
int cli_check_output(const char *cmd, const char *input, const char *output, limn_format format,
                     int overwrite_input);
/* The repair policy of every command that reads a mesh (README "Meshes limn
   accepts"): --no-repair refuses faces that use a vertex twice instead of
   repairing them; --drop-duplicate-faces removes later copies of a face. */
typedef struct cli_repair {
    int off;
    int drop_duplicates;
} cli_repair;
#define CLI_REPAIR_HELP                                                                        \
    "  --no-repair            refuse faces that use a vertex twice (default:\n"                \
    "                         repair them, with a warning saying what changed)\n"              \
    "  --drop-duplicate-faces remove later copies of a face (default: keep\n"                 \
    "                         them; their edges are sharp)\n"
/* Where outputs go (README "Command line"). */
#define CLI_PATHS_HELP                                                                         \
    "\n"                                                                                      \
    "INPUT '-' is standard input (with --input-format); an output '-' is standard\n"         \
    "output (a mesh with --format). Files appear whole or not at all; a symlink's\n"        \
    "target is replaced; '-', FIFOs and devices are written last, straight through.\n"
/* 1 when arg is a repair option (recorded in *r), else 0. */
int cli_repair_arg(const char *arg, cli_repair *r);
/* Reads path, prints its warnings, repairs the mesh by the policy (printing
   what was changed as "limn CMD: warning: ..."), and with need_faces refuses a
   mesh that has (or is left with) no faces. On failure *out is NULL and the
   context holds the message. */
limn_status cli_load_mesh(const char *cmd, limn_context *ctx, const char *path,
                          limn_format format, const cli_repair *r, int need_faces,
                          limn_mesh **out);
/* After a failed operation: when the failure came from the OpenCL device and
   the fallback is allowed (--fallback reference, LIMN_FALLBACK), switches to
   the reference backend, prints the warning, sets *st to LIMN_OK and returns
   1 (run the operation again); else returns 0. */
int cli_fall_back(const char *cmd, limn_context *ctx, limn_status *st);
/* Fails before any work (exit status 1, message printed) when the output
   cannot be written (atomic_file_check): a missing or unwritable directory,
   a directory, a name too long, a rename the directory would not allow.
   Returns 0 or 1. */
int cli_check_writable(const char *cmd, const char *output);
/* cli_check_writable of each non-NULL output, after refusing (exit status 2)
   two that go to standard output. Returns 0 or an exit status. */
int cli_check_outputs(const char *cmd, const char *const *outputs, int n);
/* Peak resident memory of this process so far, in bytes. */
size_t cli_peak_rss(void);
/* "--opt value": returns the value or prints an error when it is missing. */
const char *cli_value(int argc, char **argv, int *i);
int cli_usage_error(const char *cmd, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
/* Prints "limn CMD: <message>" for a failed library call; returns exit status. */
int cli_fail(const char *cmd, limn_context *ctx, limn_status st);
void cli_print_warnings(const char *cmd, limn_context *ctx);

/* Progress on a terminal (stderr is a tty and not quiet); silent otherwise. */
void cli_progress_enable(limn_context *ctx, int quiet);
void cli_progress_done(void);

/* Monotonic wall clock in seconds. */
double cli_now(void);

/* Do two paths name the same existing file? */
int cli_same_file(const char *a, const char *b);

/* The JSON writer of every report and of limn info --json: keys in the order
   they are added, the first one "limn_version"; strings escaped per RFC 8259
   (invalid UTF-8 bytes as U+FFFD); numbers in the C locale. */
typedef struct json_out json_out;
json_out *json_begin(void);      /* one key per line (reports) */
json_out *json_begin_line(void); /* the whole document on one line */
void json_string(json_out *j, const char *key, const char *value);
void json_bool(json_out *j, const char *key, int value);
void json_number(json_out *j, const char *key, double value);
void json_integer(json_out *j, const char *key, long long value);
void json_object_begin(json_out *j, const char *key);
void json_object_end(json_out *j);
/* Arrays: json_array_begin, elements, json_array_end. An object element is
   json_element_object_begin ... json_object_end. Non-finite numbers: null. */
void json_array_begin(json_out *j, const char *key);
void json_array_end(json_out *j);
void json_element_number(json_out *j, double value);
void json_element_object_begin(json_out *j);
void json_element_array_begin(json_out *j); /* ends with json_array_end */
/* Writes the document to f (stdout for limn info); frees j in any case. */
limn_status json_print(limn_context *ctx, json_out *j, FILE *f);
/* Writes the document atomically; frees j in any case. */
limn_status json_commit(limn_context *ctx, json_out *j, const char *path);
/* The same without the final rename (see atomic_file_finish): the report is
   complete in af's temporary file; frees j in any case. */
struct atomic_file;
limn_status json_stage(limn_context *ctx, json_out *j, const char *path, struct atomic_file *af);
/* Makes the n staged outputs appear (atomic_file_commit, in order) when st is
   LIMN_OK, else drops them all; returns the first failure. A command stages
   every output first, so a failure writes nothing. */
limn_status cli_commit_outputs(limn_context *ctx, limn_status st, struct atomic_file *staged,
                               int n);

/* ---------------------------------------------------------------------- MPI
 * Under mpirun with several ranks (cli_mpi.c; cli_mpi_none.c without
 * LIMN_MPI: always one rank), interpolate, smooth, denoise and morph run
 * distributed: rank 0 reads, writes and prints; every rank computes its share
 * (include/limn_mpi.h). With one rank everything is as without MPI. */
int cli_mpi_launched(void);   /* an MPI launcher started this process */
/* main(): MPI_Init, the command (refused on several ranks unless distributed),
   the same exit status on every rank, MPI_Finalize. */
int cli_mpi_main(int argc, char **argv, int (*dispatch)(int, char **));
int cli_mpi_ranks(void);      /* 1 without MPI */
int cli_mpi_rank(void);       /* 0 without MPI */
/* Every rank gets the lowest failing rank's status and message (collective). */
limn_status cli_mpi_agree(limn_context *ctx, limn_status st);
/* Rank 0's exit status on every rank (after parsing: usage errors are its). */
int cli_mpi_root_rc(int rc);
/* --per-rank-output: each rank writes its piece to cli_mpi_rank_path(OUTPUT). */
void cli_mpi_set_per_rank(int on);
int cli_mpi_per_rank(void);
/* OUTPUT with ".rNNN" before the extension (this rank's number); caller frees. */
char *cli_mpi_rank_path(const char *path);
/* The distributed calls; *piece (may be NULL): with --per-rank-output, this
   rank's owned vertices and their faces. Every rank's statistics are kept
   for cli_mpi_json (the report's "mpi" object) and cli_mpi_print. */
limn_status cli_mpi_interpolate(limn_context *ctx, const limn_mesh *mesh,
                                const limn_interpolate_options *o, limn_mesh **control,
                                limn_report *r, limn_mesh **piece);
limn_status cli_mpi_smooth(limn_context *ctx, const limn_mesh *mesh,
                           const limn_series_options *o, int terms, limn_mesh **out,
                           limn_series_report *r, limn_mesh **piece);
limn_status cli_mpi_denoise(limn_context *ctx, const limn_mesh *mesh,
                            const limn_series_options *o, int m, int steps, int keep_volume,
                            limn_mesh **out, limn_series_report *r, limn_mesh **piece);
limn_status cli_mpi_morph(limn_context *ctx, const limn_mesh *from, const limn_mesh *to,
                          const limn_morph_options *o, limn_morph_frame_fn fn, void *user,
                          limn_series_report *r);
void cli_mpi_json(json_out *j);
void cli_mpi_print(void);
#define CLI_MPI_HELP                                                                           \
    "  --per-rank-output      under mpirun: each rank writes its owned vertices\n"             \
    "                         and their faces to OUTPUT.rN.EXT instead of rank 0\n"           \
    "                         writing OUTPUT\n"

/* ---------------------------------------------------------------------- MPI
 * Under mpirun with several ranks (cli_mpi.c; cli_mpi_none.c without
 * LIMN_MPI: always one rank), interpolate, smooth, denoise and morph run
 * distributed: rank 0 reads, writes and prints; every rank computes its share
 * (include/limn_mpi.h). With one rank everything is as without MPI. */
int cli_mpi_launched(void);   /* an MPI launcher started this process */
/* main(): MPI_Init, the command (refused on several ranks unless distributed),
   the same exit status on every rank, MPI_Finalize. */
int cli_mpi_main(int argc, char **argv, int (*dispatch)(int, char **));
int cli_mpi_ranks(void);      /* 1 without MPI */
int cli_mpi_rank(void);       /* 0 without MPI */
/* Every rank gets the lowest failing rank's status and message (collective). */
limn_status cli_mpi_agree(limn_context *ctx, limn_status st);
/* Rank 0's exit status on every rank (after parsing: usage errors are its). */
int cli_mpi_root_rc(int rc);
/* --per-rank-output: each rank writes its piece to cli_mpi_rank_path(OUTPUT). */
void cli_mpi_set_per_rank(int on);
int cli_mpi_per_rank(void);
/* OUTPUT with ".rNNN" before the extension (this rank's number); caller frees. */
char *cli_mpi_rank_path(const char *path);
/* The distributed calls; *piece (may be NULL): with --per-rank-output, this
   rank's owned vertices and their faces. Every rank's statistics are kept
   for cli_mpi_json (the report's "mpi" object) and cli_mpi_print. */
limn_status cli_mpi_interpolate(limn_context *ctx, const limn_mesh *mesh,
                                const limn_interpolate_options *o, limn_mesh **control,
                                limn_report *r, limn_mesh **piece);
limn_status cli_mpi_smooth(limn_context *ctx, const limn_mesh *mesh,
                           const limn_series_options *o, int terms, limn_mesh **out,
                           limn_series_report *r, limn_mesh **piece);
limn_status cli_mpi_denoise(limn_context *ctx, const limn_mesh *mesh,
                            const limn_series_options *o, int m, int steps, int keep_volume,
                            limn_mesh **out, limn_series_report *r, limn_mesh **piece);
limn_status cli_mpi_morph(limn_context *ctx, const limn_mesh *from, const limn_mesh *to,
                          const limn_morph_options *o, limn_morph_frame_fn fn, void *user,
                          limn_series_report *r);
void cli_mpi_json(json_out *j);
void cli_mpi_print(void);
#define CLI_MPI_HELP                                                                           \
    "  --per-rank-output      under mpirun: each rank writes its owned vertices\n"             \
    "                         and their faces to OUTPUT.rN.EXT instead of rank 0\n"           \
    "                         writing OUTPUT\n"

#endif
