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

/* JSON report writer: keys in the order they are added. */
typedef struct json_out json_out;
json_out *json_begin(void);
void json_string(json_out *j, const char *key, const char *value);
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
/* Writes the document atomically; frees j in any case. */
limn_status json_commit(limn_context *ctx, json_out *j, const char *path);

#endif
