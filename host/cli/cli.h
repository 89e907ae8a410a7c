/* SPDX-License-Identifier: MIT */
/* The limn command line: one file per subcommand, glue over the library. */
#ifndef LIMN_CLI_H
#define LIMN_CLI_H

#include <getopt.h>
#include <limn.h>
#include <stdio.h>

/* The CLI is a client of the public API only (include/limn.h, limn_mpi.h):
   it builds against an installed prefix (tests/test_cli_installed.sh). */

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
int cli_bench(int argc, char **argv);

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
    int counts_only; /* not an option: the command reads only the counts (info) */
} cli_repair;
#define CLI_REPAIR_HELP                                                                        \
    "  --no-repair            refuse faces that use a vertex twice (default:\n"                \
    "                         repair them, with a warning saying what changed)\n"              \
    "  --drop-duplicate-faces remove later copies of a face (default: keep\n"                 \
    "                         them; their edges are sharp)\n"
/* --host-threads N (every command that reads a mesh, and bench): limn's own
   host threads (reading, topology, stencil rows, writing), 1..CLI_HOST_THREADS_MAX;
   the output bytes are the same for any N. */
#define CLI_HOST_THREADS_MAX 64
#define CLI_HOST_THREADS_HELP                                                                  \
    "  --host-threads N       threads of limn's own host work (reading, topology,\n"          \
    "                         stencil rows, writing), 1..64; same bytes for any N\n"        \
    "                         (default: the OpenCL thread count, else the cores\n"         \
    "                         of the process's CPU binding)\n"
/* "--host-threads V": V as an integer in 1..CLI_HOST_THREADS_MAX, or a usage
   error naming it (exit status 2 returned); 0 on success. */
int cli_parse_host_threads(const char *cmd, const char *text, int *out);
/* limn_context_set_host_threads when n > 0 (0: the default, nothing set). */
limn_status cli_set_host_threads(limn_context *ctx, int n);
/* Where outputs go (README "Command line"). */
#define CLI_PATHS_HELP                                                                         \
    "\n"                                                                                      \
    "INPUT '-' is standard input (with --input-format); an output '-' is standard\n"         \
    "output (a mesh with --format). Files appear whole or not at all; a symlink's\n"        \
    "target is replaced; '-', FIFOs and devices are written last, straight through.\n"
/* 1 when arg is a repair option (recorded in *r), else 0. */
int cli_repair_arg(const char *arg, cli_repair *r);
/* The refusal of a mesh with no faces to CMD: none left after the repair
   (faces_before > 0 of them, all degenerate) or none in the file. */
limn_status cli_no_faces(const char *cmd, const char *path, size_t faces_before);
/* Reads path, prints its warnings, repairs the mesh by the policy (printing
   what was changed as "limn CMD: warning: ..."), and with need_faces refuses a
   mesh that has (or is left with) no faces. Unless quiet, the read and the
   repair (with its topology) show progress on a terminal. On failure *out is
   NULL and the context holds the message. */
limn_status cli_load_mesh(const char *cmd, limn_context *ctx, const char *path,
                          limn_format format, const cli_repair *r, int need_faces, int quiet,
                          limn_mesh **out);
/* After a failed operation: when the failure came from the OpenCL device and
   the fallback is allowed (--fallback reference, LIMN_FALLBACK), switches to
   the reference backend, prints the warning, sets *st to LIMN_OK and returns
   1 (run the operation again); else returns 0. */
int cli_fall_back(const char *cmd, limn_context *ctx, limn_status *st);
/* limn_context_create, or NULL after "limn CMD: error: out of memory". */
limn_context *cli_context(const char *cmd);
/* The same under mpirun on slices, collective: a context on every rank, or
   NULL on every rank after rank 0 said that one ran out of memory (a rank
   that returned alone would leave the others waiting). */
limn_context *cli_sliced_context(const char *cmd);
/* Fails before any work (exit status 1, message printed) when the output
   cannot be written (limn_output_check): a missing or unwritable directory,
   a directory, a name too long, a rename the directory would not allow.
   Returns 0 or 1. */
int cli_check_writable(const char *cmd, const char *output);
/* cli_check_writable of each non-NULL output, after refusing (exit status 2)
   two that go to standard output. Returns 0 or an exit status. */
int cli_check_outputs(const char *cmd, const char *const *outputs, int n);
/* Peak resident memory of this process so far, in bytes. */
size_t cli_peak_rss(void);
/* Every command first passes its arguments through cli_options: getopt_long
   over the command's long options (longopts, ending with a zeroed entry;
   flag and val are ignored) and short ones (shortopts, getopt's syntax, e.g.
   "ho:q"). "--opt=value", "--opt value" and an unambiguous prefix of opt all
   become "--opt" "value" in the new *argc / *argv (kept until the next call),
   in the order given, for the command's own parser and messages. An option
   that is none of them is refused here: "unknown option '--tl'; did you mean
   --tol?" (the nearest long option at edit distance 2 or less), exit status
   2. Also names the command for the messages of cli_parse_*. Returns 0 or an
   exit status. */
int cli_options(const char *cmd, const struct option *longopts, const char *shortopts, int *argc,
                char ***argv);
void cli_set_command(const char *cmd);
/* Table entries: an option with a value, a flag. */
#define CLI_VALUE(name) {name, required_argument, NULL, 0}
#define CLI_FLAG(name) {name, no_argument, NULL, 0}
#define CLI_OPTIONS_END {NULL, 0, NULL, 0}
#define CLI_REPAIR_OPTIONS                                                                         CLI_FLAG("no-repair"), CLI_FLAG("repair"), CLI_FLAG("drop-duplicate-faces")
/* "--opt value": returns the value or prints an error when it is missing. */
const char *cli_value(int argc, char **argv, int *i);
int cli_usage_error(const char *cmd, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
/* The CLI's own failure messages (the library's stay in the context):
   records the message for the next cli_fail and returns status, for
   `return cli_error(LIMN_ERR_..., ...)`. */
limn_status cli_error(limn_status status, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
/* The message cli_fail would print: the CLI's own when one is recorded, else
   the context's (ctx may be NULL). */
const char *cli_message(const limn_context *ctx);
/* Prints "limn CMD: error: <message>" (cli_message) for a failed call,
   forgets the CLI's own message; returns the exit status. */
int cli_fail(const char *cmd, limn_context *ctx, limn_status st);
void cli_print_warnings(const char *cmd, limn_context *ctx);

/* Progress on a terminal (stderr is a tty and not quiet); silent otherwise. */
void cli_progress_enable(limn_context *ctx, int quiet);
void cli_progress_done(void);

/* Numbers on the command line and in the text the CLI prints use the C
   locale whatever the user's (main() sets it): the calling thread is
   switched (uselocale) and back. cli_locale_enter returns 0, nothing
   changed, when no C locale object can be made (cli_locale_leave is then a
   no-op); cli_locale_leave keeps errno as the call in between left it. */
typedef struct cli_locale {
    void *c, *prev; /* locale_t */
} cli_locale;
int cli_locale_enter(cli_locale *s);
void cli_locale_leave(cli_locale *s);
/* strtod in the C locale (errno is strtod's). */
double cli_strtod(const char *text, char **end);

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
/* The same without the final rename: the report is complete and staged in
   set (limn_output_set_add_bytes); frees j in any case. */
limn_status json_stage(limn_context *ctx, json_out *j, const char *path, limn_output_set *set);
/* Makes set's staged outputs appear (limn_output_set_commit, in order) when
   st is LIMN_OK (on every rank under mpirun), else drops them all; destroys
   set in any case (NULL is fine); returns the first failure. A command
   stages every output first, so a failure writes nothing. */
limn_status cli_commit_outputs(limn_context *ctx, limn_status st, limn_output_set *set);

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
/* Rank 0's exit status on every rank (after parsing: usage errors are its),
   or 1 when another rank failed (ran out of memory) where rank 0 did not. */
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
/* limn_denoise_sure_mpi; *keep_volume < 0: kept when the mesh is closed
   (the root's measure), resolved in place on every rank. */
limn_status cli_mpi_denoise_sure(limn_context *ctx, const limn_mesh *mesh,
                                 const limn_series_options *o, int products, int *keep_volume,
                                 limn_mesh **out, double *sigma, limn_series_report *r,
                                 limn_mesh **piece);
limn_status cli_mpi_sharpen(limn_context *ctx, const limn_mesh *mesh,
                            const limn_series_options *o, int from, int to, int steps,
                            limn_mesh **out, limn_series_report *r, limn_mesh **piece);
/* bands and energy: the root's (NULL elsewhere). */
limn_status cli_mpi_bands(limn_context *ctx, const limn_mesh *mesh, const limn_series_options *o,
                          int count, double *bands, double *energy, limn_series_report *r);
limn_status cli_mpi_morph(limn_context *ctx, const limn_mesh *from, const limn_mesh *to,
                          const limn_morph_options *o, limn_morph_frame_fn fn, void *user,
                          limn_series_report *r);
/* Under several ranks: whether the command can run on slices of its input,
   no rank holding the whole mesh (a .ply, .obj or .off input file, an output
   file, no --per-rank-output). */
int cli_mpi_sliced(const char *input, limn_format in_format, const char *output, int per_rank);
/* What a sliced run reads and writes. */
typedef struct cli_sliced_job {
    const char *cmd, *input, *output;
    const cli_repair *repair;
    limn_format in_format, out_format;
    const limn_write_options *write;
    int rows; /* the command builds rows (interpolate, the series): the repair
                 leaves its sub-meshes for them (limn_repair_options.sub_meshes) */
    limn_output_set *stage; /* takes the outputs (limn_mpi_output_set_add_mesh), to appear
                               with the report; NULL (interpolate, the series,
                               subdivide only): the mesh appears at once */
} cli_sliced_job;
/* interpolate on slices (limn_mpi.h's distributed meshes): every rank reads
   its slice, repairs it, builds its rows, solves and writes its share of the
   output; seconds[0] the load, seconds[1] the write; *written the output's
   error (float32 positions). */
limn_status cli_mpi_interpolate_sliced(limn_context *ctx, const cli_sliced_job *job,
                                       const limn_interpolate_options *o, limn_report *r,
                                       limn_write_report *written, double seconds[2]);
/* The series filters that run on slices, and their arguments. */
typedef enum cli_series_kind {
    CLI_SERIES_SMOOTH,
    CLI_SERIES_DENOISE,
    CLI_SERIES_SHARPEN,
    CLI_SERIES_TEXTURE
} cli_series_kind;
/* The volumes and areas of denoise's report: the input's (closed from its
   edges) and the result's, measured on slices as one process measures them. */
typedef struct cli_series_measures {
    int measured, closed;
    double volume_in, volume_out, area_in, area_out;
} cli_series_measures;
typedef struct cli_series_call {
    cli_series_kind kind;
    int terms, m, steps, from, to, keep_volume;
    int products;                  /* denoise: > 0 the default (SURE) form of this degree */
    double *sigma;                 /* its noise estimate (may be NULL) */
    int *kept;                     /* keep_volume < 0 resolved (closed), may be NULL */
    const limn_feature_options *features; /* denoise: non-NULL for --preserve-features */
    cli_series_measures *measures; /* may be NULL; else filled after the filter */
    const limn_texture_options *texture; /* texture: its options (series from the call's) */
    size_t *out_counts;            /* texture: the surface's vertices and faces (2) */
} cli_series_call;
/* smooth, denoise or sharpen on slices (limn_mpi_mesh_smooth etc.), as
   cli_mpi_interpolate_sliced; *displacement the mean distance from the
   input to the result over the bbox diagonal, summed over the ranks (it may
   differ from one process's figure in the last bits; the mesh does not). */
limn_status cli_mpi_series_sliced(limn_context *ctx, const cli_sliced_job *job,
                                  const limn_series_options *o, const cli_series_call *call,
                                  limn_series_report *r, limn_write_report *written,
                                  double *displacement, double seconds[2]);
/* bands on slices (limn_mpi_mesh_bands): band i written in parallel to
   paths[i] (count + 1 of them, the remainder last), staged in job->stage
   (not NULL), energy (count + 1), the input's energy and
   the largest |sum of the bands - input| (absolute) as the single process
   computes them (the sums passed from rank to rank, the maximum exact). */
typedef struct cli_bands_out {
    char *const *paths;
    double *energy, input_energy, max_sum_error;
} cli_bands_out;
limn_status cli_mpi_bands_sliced(limn_context *ctx, const cli_sliced_job *job,
                                 const limn_series_options *o, int count, cli_bands_out *out,
                                 limn_series_report *r, double seconds[2]);
/* morph on slices (limn_mpi_mesh_morph): FROM is job->input, TO to_path,
   both read and repaired as job says; every frame written in parallel to
   sink->name(user, k) and staged in job->stage (not NULL; job->write: NULL,
   the single process's defaults), then sink->record(user, measures) on
   every rank; sink->write_seconds counted. seconds[0]: the load. */
typedef struct cli_morph_sink {
    const char *(*name)(void *user, int index);
    void (*record)(void *user, const limn_morph_frame *f);
    void *user;
    double write_seconds;
} cli_morph_sink;
limn_status cli_mpi_morph_sliced(limn_context *ctx, const cli_sliced_job *job,
                                 const char *to_path, const limn_morph_options *o,
                                 cli_morph_sink *sink, limn_series_report *r, double seconds[2]);
/* subdivide on slices (limn_mpi_mesh_subdivide): every rank reads its slice,
   refines its share level by level and writes its part of the surface;
   seconds[0] the load, seconds[1] the write. */
limn_status cli_mpi_subdivide_sliced(limn_context *ctx, const cli_sliced_job *job,
                                     const limn_subdivide_options *o, limn_subdivide_report *r,
                                     limn_write_report *written, double seconds[2]);
/* Collective: every rank's peak resident memory so far, to rank 0, for the
   report's per_rank entries. */
void cli_mpi_note_memory(void);
void cli_mpi_json(json_out *j);
void cli_mpi_print(void);
#define CLI_MPI_HELP                                                                           \
    "  --per-rank-output      under mpirun: each rank writes its owned vertices\n"             \
    "                         and their faces to OUTPUT.rN.EXT instead of rank 0\n"           \
    "                         writing OUTPUT\n"

#endif
