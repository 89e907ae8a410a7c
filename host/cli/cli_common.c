/* SPDX-License-Identifier: MIT */
/* Shared CLI pieces: option values, errors, progress, JSON reports. */
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
    uselocale((locale_t)s->prev);
    freelocale((locale_t)s->c);
    s->c = NULL;
}

double cli_strtod(const char *text, char **end)
{
    cli_locale s;
    int entered = cli_locale_enter(&s);
    errno = 0;
    double v = strtod(text, end);
    int e = errno; /* ERANGE is the caller's to see */
    if (entered)
        cli_locale_leave(&s);
    errno = e;
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

/* ------------------------------------------------------------------- JSON */

struct json_out {
    char *text;
    size_t len, cap;
    int depth;
    int need_comma;
    int failed;
    int compact;    /* one line (limn info --json) instead of one key per line */
};

static void put(json_out *j, const char *s, size_t n)
{
    if (j->failed)
        return;
    if (j->len + n + 1 > j->cap) {
        size_t cap = (j->cap ? j->cap * 2 : 1024) + n;
        char *t = realloc(j->text, cap);
        if (!t) {
            j->failed = 1;
            return;
        }
        j->text = t;
        j->cap = cap;
    }
    memcpy(j->text + j->len, s, n);
    j->len += n;
    j->text[j->len] = '\0';
}

static void puts_(json_out *j, const char *s) { put(j, s, strlen(s)); }

/* Length of the valid UTF-8 sequence at p (RFC 3629: no overlong forms, no
   surrogates, nothing past U+10FFFF), or 0 when the byte starts none. */
static size_t utf8_length(const unsigned char *p)
{
    unsigned char c = p[0];
    size_t n;
    unsigned char lo = 0x80, hi = 0xBF; /* range of the second byte */
    if (c < 0x80)
        return 1;
    if (c >= 0xC2 && c <= 0xDF)
        n = 2;
    else if (c >= 0xE0 && c <= 0xEF) {
        n = 3;
        lo = c == 0xE0 ? 0xA0 : 0x80;
        hi = c == 0xED ? 0x9F : 0xBF;
    } else if (c >= 0xF0 && c <= 0xF4) {
        n = 4;
        lo = c == 0xF0 ? 0x90 : 0x80;
        hi = c == 0xF4 ? 0x8F : 0xBF;
    } else
        return 0;
    if (p[1] < lo || p[1] > hi)
        return 0;
    for (size_t i = 2; i < n; i++)
        if (p[i] < 0x80 || p[i] > 0xBF)
            return 0;
    return n;
}

/* A JSON string (RFC 8259): quotes, backslashes and control characters
   escaped; a byte that is not valid UTF-8 (a file name from another
   encoding) becomes U+FFFD, so the document always parses. */
static void put_string(json_out *j, const char *v)
{
    puts_(j, "\"");
    for (const unsigned char *p = (const unsigned char *)v; *p;) {
        char esc[8];
        size_t n = utf8_length(p);
        const char *named = *p == '"'    ? "\\\""
                            : *p == '\\' ? "\\\\"
                            : *p == '\n' ? "\\n"
                            : *p == '\t' ? "\\t"
                            : *p == '\r' ? "\\r"
                            : *p == '\b' ? "\\b"
                            : *p == '\f' ? "\\f"
                                         : NULL;
        if (named) {
            puts_(j, named);
        } else if (*p < 0x20) {
            snprintf(esc, sizeof esc, "\\u%04x", *p);
            puts_(j, esc);
        } else if (n == 0) {
            puts_(j, "\\ufffd");
            n = 1;
        } else {
            put(j, (const char *)p, n);
        }
        p += n ? n : 1;
    }
    puts_(j, "\"");
}

/* Comma, then a new line and indentation (or one space when compact). */
static void element(json_out *j)
{
    if (j->need_comma)
        puts_(j, j->compact ? ", " : ",");
    if (!j->compact) {
        puts_(j, "\n");
        for (int i = 0; i < j->depth; i++)
            puts_(j, "  ");
    }
    j->need_comma = 1;
}

static void key(json_out *j, const char *k)
{
    element(j);
    put_string(j, k);
    puts_(j, ": ");
}

/* A closing bracket on its own line (or right after the last value). */
static void close_(json_out *j, const char *bracket)
{
    j->depth--;
    if (!j->compact) {
        puts_(j, "\n");
        for (int i = 0; i < j->depth; i++)
            puts_(j, "  ");
    }
    puts_(j, bracket);
    j->need_comma = 1;
}

static void open_(json_out *j, const char *bracket)
{
    puts_(j, bracket);
    j->depth++;
    j->need_comma = 0;
}

static json_out *begin(int compact)
{
    json_out *j = calloc(1, sizeof *j);
    if (j) {
        j->compact = compact;
        open_(j, "{");
        json_string(j, "limn_version", limn_version());
    }
    return j;
}

json_out *json_begin(void) { return begin(0); }
json_out *json_begin_line(void) { return begin(1); }

void json_string(json_out *j, const char *k, const char *v)
{
    key(j, k);
    put_string(j, v ? v : "");
}

/* The shortest of %.15g / %.17g that reads back to v, with a '.' whatever
   the locale (the C locale for this thread, only here); null if not finite. */
static void put_number(json_out *j, double v)
{
    char buf[64] = "null";
    if (isfinite(v)) {
        cli_locale loc;
        int entered = cli_locale_enter(&loc);
        snprintf(buf, sizeof buf, "%.15g", v);
        if (strtod(buf, NULL) != v)
            snprintf(buf, sizeof buf, "%.17g", v);
        if (entered)
            cli_locale_leave(&loc);
        else if (strchr(buf, ','))
            *strchr(buf, ',') = '.'; /* no C locale object: mend the decimal comma */
    }
    puts_(j, buf);
}

void json_number(json_out *j, const char *k, double v)
{
    key(j, k);
    put_number(j, v);
}

void json_integer(json_out *j, const char *k, long long v)
{
    char buf[32];
    key(j, k);
    snprintf(buf, sizeof buf, "%lld", v);
    puts_(j, buf);
}

void json_bool(json_out *j, const char *k, int v)
{
    key(j, k);
    puts_(j, v ? "true" : "false");
}

void json_object_begin(json_out *j, const char *k)
{
    key(j, k);
    open_(j, "{");
}

void json_object_end(json_out *j) { close_(j, "}"); }

void json_array_begin(json_out *j, const char *k)
{
    key(j, k);
    open_(j, "[");
}

void json_array_end(json_out *j) { close_(j, "]"); }

void json_element_number(json_out *j, double v)
{
    element(j);
    put_number(j, v);
}

void json_element_object_begin(json_out *j)
{
    element(j);
    open_(j, "{");
}

void json_element_array_begin(json_out *j)
{
    element(j);
    open_(j, "[");
}

limn_status json_print(limn_context *ctx, json_out *j, FILE *f)
{
    (void)ctx; /* the messages are the CLI's own (cli_error) */
    limn_status st = LIMN_OK;
    while (j->depth > 0)
        json_object_end(j);
    puts_(j, "\n");
    if (j->failed)
        st = cli_error(LIMN_ERR_MEMORY, "out of memory writing JSON");
    else if (fwrite(j->text, 1, j->len, f) != j->len || fflush(f) != 0)
        st = cli_error(LIMN_ERR_IO, "cannot write JSON: %s", strerror(errno));
    free(j->text);
    free(j);
    return st;
}

limn_status json_stage(limn_context *ctx, json_out *j, const char *path, limn_output_set *set)
{
    limn_status st = LIMN_OK;
    while (j->depth > 0)
        json_object_end(j);
    puts_(j, "\n");
    if (j->failed)
        st = cli_error(LIMN_ERR_MEMORY, "out of memory writing the report %s", path);
    else
        st = limn_output_set_add_bytes(ctx, set, path, j->text, j->len);
    free(j->text);
    free(j);
    return st;
}

limn_status json_commit(limn_context *ctx, json_out *j, const char *path)
{
    limn_output_set *set = NULL;
    limn_status st = limn_output_set_create(ctx, &set);
    if (st) {
        free(j->text);
        free(j);
        return st;
    }
    st = json_stage(ctx, j, path, set);
    if (!st)
        st = limn_output_set_commit(ctx, set);
    limn_output_set_destroy(set);
    return st;
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

int cli_check_writable(const char *cmd, const char *output)
{
    limn_context *ctx = limn_context_create();
    if (!ctx)
        return EXIT_FAILURE_RUN;
    limn_status st = limn_output_check(ctx, output, NULL);
    /* every refusal here is the run's failure (1), a usage error or not */
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

limn_status cli_load_mesh(const char *cmd, limn_context *ctx, const char *path,
                          limn_format format, const cli_repair *r, int need_faces,
                          limn_mesh **out)
{
    limn_status st;
    if (strcmp(path, "-") != 0)
        st = limn_mesh_read(ctx, path, format, out);
    else if (format == LIMN_FORMAT_AUTO)
        st = cli_error(LIMN_ERR_ARGUMENT,
                       "reading standard input ('-') needs --input-format (obj, ply, off, "
                       "stl), since there is no extension to tell the format (a file named "
                       "'-' is ./-)");
    else
        st = limn_mesh_read_stream(ctx, stdin, "standard input", format, out);
    cli_print_warnings(cmd, ctx);
    if (st)
        return st;
    limn_repair_options o;
    limn_repair_options_default(&o);
    if (r) {
        o.repeated_vertices = !r->off;
        o.duplicate_faces = r->drop_duplicates;
    }
    limn_repair_report rep = {.size = sizeof rep};
    st = limn_mesh_repair(ctx, *out, &o, &rep);
    cli_print_warnings(cmd, ctx);
    if (!st && need_faces && limn_mesh_face_count(*out) == 0)
        st = rep.faces_before
                 ? cli_error(LIMN_ERR_TOPOLOGY,
                                     "%s: no faces are left after the repair (all %zu were "
                                     "degenerate): nothing to %s",
                                     path, rep.faces_before, cmd)
                 : cli_error(LIMN_ERR_TOPOLOGY,
                                     "%s: the mesh has no faces (a point cloud?): nothing to %s",
                                     path, cmd);
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
