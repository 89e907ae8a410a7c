/* SPDX-License-Identifier: MIT */
/* Shared CLI pieces: option values, errors, progress, output checks. */
#include "cli.h"

#include <errno.h>
#include <limits.h>
#include <locale.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

/* The CLI's own message (cli_error); "" when none is recorded. */
static char cli_own_message[2048];

limn_status cli_error(limn_status status, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(cli_own_message, sizeof cli_own_message, fmt, ap);
    va_end(ap);
    return status;
}

const char *cli_message(const limn_context *ctx)
{
    if (cli_own_message[0] || !ctx)
        return cli_own_message;
    return limn_context_message(ctx);
}

int cli_locale_enter(cli_locale *s)
{
    /* glibc hands out its static C locale here: no allocation, cheap per call */
    locale_t c = newlocale(LC_ALL_MASK, "C", (locale_t)0);
    s->c = NULL;
    s->prev = NULL;
    if (c == (locale_t)0)
        return 0;
    s->c = (void *)c;
    s->prev = (void *)uselocale(c);
    return 1;
}

void cli_locale_leave(cli_locale *s)
{
    if (!s->c)
        return;
    int e = errno; /* what the call in the C locale said is the caller's to see */
    uselocale((locale_t)s->prev);
    freelocale((locale_t)s->c);
    s->c = NULL;
    errno = e;
}

double cli_strtod(const char *text, char **end)
{
    cli_locale s;
    cli_locale_enter(&s); /* leave is a no-op when it could not */
    errno = 0;
    double v = strtod(text, end);
    cli_locale_leave(&s); /* keeps strtod's ERANGE */
    return v;
}

/* The command running (cli_options), for the messages of cli_parse_*. */
static const char *current_command;

void cli_set_command(const char *cmd) { current_command = cmd; }

int cli_usage_error(const char *cmd, const char *fmt, ...)
{
    if (cli_mpi_rank() != 0) /* under mpirun: printed once, by rank 0 */
        return EXIT_USAGE;
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "limn %s: error: ", cmd);
    vfprintf(stderr, fmt, ap);
    fprintf(stderr, " (see 'limn %s --help')\n", cmd);
    va_end(ap);
    return EXIT_USAGE;
}

const char *cli_value(int argc, char **argv, int *i)
{
    if (*i + 1 >= argc)
        return NULL;
    return argv[++*i];
}

/* "limn CMD: error: OPT expects WHAT, got 'TEXT' (see ...)", a usage error. */
static void value_error(const char *opt, const char *what, const char *text)
{
    if (current_command)
        cli_usage_error(current_command, "%s expects %s, got '%s'", opt, what, text);
    else if (cli_mpi_rank() == 0)
        fprintf(stderr, "limn: error: %s expects %s, got '%s'\n", opt, what, text);
}

int cli_parse_double(const char *opt, const char *text, double *out)
{
    char *end;
    double v = cli_strtod(text, &end); /* "0.5" whatever the locale */
    if (end == text || *end || errno == ERANGE || !isfinite(v)) {
        value_error(opt, "a number", text);
        return 0;
    }
    *out = v;
    return 1;
}

int cli_parse_int(const char *opt, const char *text, int *out)
{
    char *end;
    errno = 0;
    long v = strtol(text, &end, 10);
    if (end == text || *end || errno == ERANGE || v < INT_MIN || v > INT_MAX) {
        value_error(opt, "an integer", text);
        return 0;
    }
    *out = (int)v;
    return 1;
}

int cli_fail(const char *cmd, limn_context *ctx, limn_status st)
{
    if (cli_mpi_rank() == 0)
        fprintf(stderr, "limn %s: error: %s\n", cmd, cli_message(ctx));
    cli_own_message[0] = '\0';
    return st == LIMN_ERR_ARGUMENT ? EXIT_USAGE : EXIT_FAILURE_RUN;
}

void cli_print_warnings(const char *cmd, limn_context *ctx)
{
    const char *w = cli_mpi_rank() == 0 ? limn_context_warnings(ctx) : "";
    while (*w) {
        const char *nl = strchr(w, '\n');
        int len = nl ? (int)(nl - w) : (int)strlen(w);
        fprintf(stderr, "limn %s: warning: %.*s\n", cmd, len, w);
        w += len + (nl != NULL);
    }
}

static int progress_shown;

static void show_progress(void *user, const char *stage, double fraction)
{
    (void)user;
    if (fraction < 0)
        fraction = 0;
    if (fraction > 1)
        fraction = 1;
    fprintf(stderr, "\r  %-10s %3d%%", stage, (int)(100 * fraction + 0.5));
    fflush(stderr);
    progress_shown = 1;
}

void cli_progress_enable(limn_context *ctx, int quiet)
{
    if (!quiet && isatty(STDERR_FILENO) && cli_mpi_rank() == 0)
        limn_context_set_progress(ctx, show_progress, NULL);
}

void cli_progress_done(void)
{
    if (progress_shown) {
        fprintf(stderr, "\r%30s\r", "");
        progress_shown = 0;
    }
}

int cli_same_file(const char *a, const char *b)
{
    struct stat sa, sb;
    /* standard input or output is never a file of the command line */
    if (!strcmp(a, "-") || !strcmp(b, "-") || stat(a, &sa) != 0 || stat(b, &sb) != 0)
        return 0;
    return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

limn_status cli_commit_outputs(limn_context *ctx, limn_status st, limn_output_set *set)
{
    /* under mpirun: every rank's outputs are staged before any appears */
    st = cli_mpi_agree(ctx, st);
    if (!st && set)
        st = limn_output_set_commit(ctx, set);
    limn_output_set_destroy(set); /* drops whatever was not committed */
    return st;
}

double cli_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int cli_parse_scheme(const char *cmd, const char *text, limn_scheme *out)
{
    if (strcmp(text, "auto") == 0)
        *out = LIMN_SCHEME_AUTO;
    else if (strcmp(text, "loop") == 0)
        *out = LIMN_SCHEME_LOOP;
    else if (strcmp(text, "catmark") == 0 || strcmp(text, "catmull-clark") == 0)
        *out = LIMN_SCHEME_CATMARK;
    else {
        cli_usage_error(cmd, "--scheme '%s' is not one of auto, loop, catmark", text);
        return 0;
    }
    return 1;
}

int cli_parse_size(const char *opt, const char *text, size_t *out)
{
    char *end;
    double v = cli_strtod(text, &end);
    double unit = 1;
    if (end != text && *end && !end[1]) {
        switch (*end) {
        case 'k': case 'K': unit = 1024.0; end++; break;
        case 'm': case 'M': unit = 1024.0 * 1024; end++; break;
        case 'g': case 'G': unit = 1024.0 * 1024 * 1024; end++; break;
        case 't': case 'T': unit = 1024.0 * 1024 * 1024 * 1024; end++; break;
        default: break;
        }
    }
    if (end == text || *end || errno == ERANGE || !(v > 0) || v * unit >= 1.8e19) {
        value_error(opt, "a size such as 512M or 4G", text);
        return 0;
    }
    *out = (size_t)(v * unit);
    return 1;
}

int cli_check_output(const char *cmd, const char *input, const char *output, limn_format format,
                     int overwrite_input)
{
    limn_format f;
    if (format == LIMN_FORMAT_AUTO && limn_output_is_stdout(output))
        return cli_usage_error(cmd, "writing a mesh to standard output ('%s') needs --format, "
                                    "since there is no extension to tell it",
                               output);
    if (format == LIMN_FORMAT_AUTO && !limn_format_from_path(output, &f))
        return cli_usage_error(cmd,
                               "cannot tell the format of '%s' from its extension: use .obj, "
                               ".ply or .off, or --format",
                               output);
    if (!overwrite_input && cli_same_file(input, output))
        return cli_usage_error(cmd,
                               "output '%s' is the input file; refusing to overwrite it (use "
                               "--overwrite-input if you mean it)",
                               output);
    return 0;
}

limn_context *cli_context(const char *cmd)
{
    limn_context *ctx = limn_context_create();
    if (!ctx)
        fprintf(stderr, "limn %s: error: out of memory\n", cmd);
    return ctx;
}

limn_context *cli_sliced_context(const char *cmd)
{
    limn_context *ctx = limn_context_create();
    limn_status st =
        cli_mpi_agree(ctx, ctx ? LIMN_OK : cli_error(LIMN_ERR_MEMORY, "out of memory"));
    if (!st)
        return ctx;
    cli_fail(cmd, ctx, st);
    limn_context_destroy(ctx);
    return NULL;
}

int cli_check_writable(const char *cmd, const char *output)
{
    limn_context *ctx = cli_context(cmd);
    if (!ctx)
        return EXIT_FAILURE_RUN;
    limn_status st = limn_output_check(ctx, output, NULL);
    /* every refusal here is the run's failure (1), a usage error or not; one
       for want of memory is this rank's alone (under mpirun): said here */
    if (st == LIMN_ERR_MEMORY && cli_mpi_rank() != 0)
        fprintf(stderr, "limn %s: error: %s\n", cmd, cli_message(ctx));
    int rc = st ? (cli_fail(cmd, ctx, st), EXIT_FAILURE_RUN) : 0;
    limn_context_destroy(ctx);
    return rc;
}

int cli_check_outputs(const char *cmd, const char *const *outputs, int n)
{
    const char *first = NULL;
    for (int i = 0; i < n; i++) {
        if (!outputs[i])
            continue;
        if (limn_output_is_stdout(outputs[i])) {
            if (first)
                return cli_usage_error(cmd,
                                       "'%s' and '%s' both go to standard output; at most one "
                                       "output can",
                                       first, outputs[i]);
            first = outputs[i];
        }
    }
    for (int i = 0; i < n; i++) {
        int rc = outputs[i] ? cli_check_writable(cmd, outputs[i]) : 0;
        if (rc)
            return rc;
    }
    return 0;
}

size_t cli_peak_rss(void)
{
    struct rusage ru;
    if (getrusage(RUSAGE_SELF, &ru) != 0)
        return 0;
    return (size_t)ru.ru_maxrss * 1024;
}

int cli_repair_arg(const char *arg, cli_repair *r)
{
    if (strcmp(arg, "--no-repair") == 0)
        r->off = 1;
    else if (strcmp(arg, "--repair") == 0)
        r->off = 0;
    else if (strcmp(arg, "--drop-duplicate-faces") == 0)
        r->drop_duplicates = 1;
    else
        return 0;
    return 1;
}

limn_status cli_no_faces(const char *cmd, const char *path, size_t faces_before)
{
    if (faces_before)
        return cli_error(LIMN_ERR_TOPOLOGY,
                         "%s: no faces are left after the repair (all %zu were degenerate): "
                         "nothing to %s",
                         path, faces_before, cmd);
    return cli_error(LIMN_ERR_TOPOLOGY,
                     "%s: the mesh has no faces (a point cloud?): nothing to %s", path, cmd);
}

limn_status cli_load_mesh(const char *cmd, limn_context *ctx, const char *path,
                          limn_format format, const cli_repair *r, int need_faces, int quiet,
                          limn_mesh **out)
{
    limn_status st;
    cli_progress_enable(ctx, quiet);
    if (strcmp(path, "-") != 0)
        st = limn_mesh_read(ctx, path, format, out);
    else if (format == LIMN_FORMAT_AUTO)
        st = cli_error(LIMN_ERR_ARGUMENT,
                       "reading standard input ('-') needs --input-format (obj, ply, off, "
                       "stl), since there is no extension to tell the format (a file named "
                       "'-' is ./-)");
    else
        st = limn_mesh_read_stream(ctx, stdin, "standard input", format, out);
    cli_progress_done();
    cli_print_warnings(cmd, ctx);
    if (st) {
        limn_context_set_progress(ctx, NULL, NULL);
        return st;
    }
    limn_repair_options o;
    limn_repair_options_default(&o);
    if (r) {
        o.repeated_vertices = !r->off;
        o.duplicate_faces = r->drop_duplicates;
        o.keep_topology = !r->counts_only;
    }
    limn_repair_report rep = {.size = sizeof rep};
    st = limn_mesh_repair(ctx, *out, &o, &rep);
    cli_progress_done();
    limn_context_set_progress(ctx, NULL, NULL); /* the caller's stages enable their own */
    cli_print_warnings(cmd, ctx);
    if (!st && need_faces && limn_mesh_face_count(*out) == 0)
        st = cli_no_faces(cmd, path, rep.faces_before);
    if (st) {
        limn_mesh_destroy(*out);
        *out = NULL;
    }
    return st;
}

int cli_fall_back(const char *cmd, limn_context *ctx, limn_status *st)
{
    if (limn_context_fall_back(ctx, *st) != LIMN_OK)
        return 0;
    cli_print_warnings(cmd, ctx);
    *st = LIMN_OK;
    return 1;
}
