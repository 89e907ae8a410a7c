/* SPDX-License-Identifier: MIT */
/* limn texture: procedural Perlin texture through the interpolation (seed 000 §5). */
#include "cli_series.h"

#include <ctype.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>

static const char *const help =
    "usage: limn texture INPUT -o OUTPUT.ply --colors '#hex,#hex,...' [--levels N]\n"
    "                    [--seed S] [--frequency F] [options]\n"
    "\n"
    "Colours a mesh with procedural noise (Lai & Cheng (2011), 'Fast Mesh\n"
    "Interpolation and Mesh Decomposition with Applications', section 5):\n"
    "INPUT (G_0) is refined N\n"
    "times into G_1..G_N; on G_i's vertices improved Perlin noise f(2^i p)/2^i is\n"
    "interpolated (the scalar interpolation with G_i's limit operator), carried to\n"
    "G_N by subdivision and summed there, normalised to [0, 1] and mapped through\n"
    "the uniform cubic B-spline that interpolates the colours in order (values\n"
    "clamped to the colours' per-channel range). Writes G_N with its vertices on\n"
    "the limit surface and per-vertex colours (PLY). Deterministic for a seed.\n"
    "\n"
    "  -o, --output FILE      PLY file to write (binary; --format ply-ascii, ply-be)\n"
    "  --colors LIST          comma-separated #rrggbb (or #rgb) colours, at least one\n"
    "  --levels N             refinement levels, 0..8                    [3]\n"
    "  --seed S               shuffles the noise's permutation           [1]\n"
    "  --frequency F          noise cells across the bbox diagonal on G_0 [4]\n"
    "  --tol T                tolerance of each level's interpolation, relative\n"
    "                         to the level's largest noise value         [1e-6]\n"
    "  --max-memory SIZE      refuse when the predicted peak is larger (512M, 4G)\n"
    "                         [three quarters of physical memory]; under mpirun\n"
    "                         a rank's limit (default: that over the node's ranks)\n"
    SERIES_HELP
    "  --input-format F / --overwrite-input / -q\n"
    SERIES_HELP_EXIT;

#define MAX_COLORS 256

static int hexval(int ch)
{
    return isdigit(ch) ? ch - '0' : isxdigit(ch) ? tolower(ch) - 'a' + 10 : -1;
}

/* "#rrggbb,#rgb,..." -> rgb triples; 0 and a message on error. */
static int parse_colors(const char *text, uint8_t *rgb, size_t *count, char *why, size_t wn)
{
    *count = 0;
    const char *p = text;
    for (;;) {
        while (*p == ' ')
            p++;
        const char *start = p;
        if (*p == '#')
            p++;
        const char *h = p;
        while (*p && *p != ',' && *p != ' ')
            p++;
        size_t len = (size_t)(p - h);
        int ok = len == 6 || len == 3;
        for (size_t i = 0; ok && i < len; i++)
            ok = hexval((unsigned char)h[i]) >= 0;
        if (!ok) {
            snprintf(why, wn, "'%.*s' is not a colour like #1a2b3c or #abc", (int)(p - start),
                     start);
            return 0;
        }
        if (*count == MAX_COLORS) {
            snprintf(why, wn, "more than %d colours", MAX_COLORS);
            return 0;
        }
        for (int c = 0; c < 3; c++) {
            int v = len == 6 ? 16 * hexval((unsigned char)h[2 * c]) + hexval((unsigned char)h[2 * c + 1])
                             : 17 * hexval((unsigned char)h[c]);
            rgb[3 * *count + (size_t)c] = (uint8_t)v;
        }
        ++*count;
        while (*p == ' ')
            p++;
        if (!*p)
            return 1;
        if (*p != ',') {
            snprintf(why, wn, "unexpected '%c' in the colour list", *p);
            return 0;
        }
        p++;
    }
}

typedef struct extra {
    limn_texture_options t;
    uint8_t rgb[3 * MAX_COLORS];
    size_t out[2]; /* the surface's vertices and faces */
    const char *colors;
} extra;

static void json_extra(json_out *j, void *user)
{
    extra *e = user;
    json_integer(j, "levels", e->t.levels);
    json_string(j, "colors", e->colors);
    json_integer(j, "seed", (long long)e->t.seed);
    json_number(j, "frequency", e->t.frequency);
    json_number(j, "tolerance", e->t.tolerance);
    json_integer(j, "output_vertices", (long long)e->out[0]);
    json_integer(j, "output_faces", (long long)e->out[1]);
}

static void print_extra(void *user)
{
    extra *e = user;
    fprintf(stderr, "  %d levels, %zu colours, seed %llu: %zu vertices and %zu faces written\n",
            e->t.levels, e->t.color_count, (unsigned long long)e->t.seed, e->out[0],
            e->out[1]);
}

/* --seed S: a non-negative integer. */
static int seed_option(cli_args *a, const char *v, extra *e)
{
    char *end;
    errno = 0;
    unsigned long long seed = strtoull(v, &end, 10);
    if (end == v || *end || errno || v[0] == '-')
        return cli_usage_error(a->cmd, "--seed expects a non-negative integer, got '%s'", v);
    e->t.seed = seed;
    return 0;
}

static int own_option(cli_args *a, void *user, int argc, char **argv, int *i)
{
    extra *e = user;
    const char *s = argv[*i], *v;
    const cli_own_option own[] = {
        {"--levels", CLI_OWN_INT, &e->t.levels, 0, 8},
        {"--tol", CLI_OWN_POSITIVE, &e->t.tolerance, 0, 0},
        {"--frequency", CLI_OWN_POSITIVE, &e->t.frequency, 0, 0},
        {"--max-memory", CLI_OWN_SIZE, &e->t.max_memory, 0, 0},
    };
    int rc = cli_args_own(a, argc, argv, i, own, sizeof own / sizeof *own);
    if (rc != CLI_OWN_UNKNOWN)
        return rc;
    if (strcmp(s, "--colors") != 0 && strcmp(s, "--colours") != 0 && strcmp(s, "--seed") != 0)
        return CLI_OWN_UNKNOWN;
    if (!(v = cli_args_value(a, argc, argv, i)))
        return EXIT_USAGE;
    if (strcmp(s, "--seed") == 0)
        return seed_option(a, v, e);
    char why[256];
    if (!parse_colors(v, e->rgb, &e->t.color_count, why, sizeof why))
        return cli_usage_error(a->cmd, "--colors: %s", why);
    e->colors = v;
    return 0;
}

/* After the shared checks: colours given, a PLY output. */
static int check(series_cli *c, const extra *e)
{
    if (!e->colors)
        return cli_usage_error(c->a.cmd, "--colors '#hex,#hex,...' is required");
    int rc = series_cli_check(c, 1);
    if (rc)
        return rc;
    limn_format f = c->a.out_format;
    if (f == LIMN_FORMAT_AUTO)
        limn_format_from_path(c->a.output, &f);
    if (f != LIMN_FORMAT_PLY && f != LIMN_FORMAT_PLY_ASCII && f != LIMN_FORMAT_PLY_BINARY_BE)
        return cli_usage_error(c->a.cmd, "'%s': vertex colours are written in PLY only",
                               c->a.output);
    return 0;
}

/* On several ranks texture runs on slices only: file input and output. */
static int sliced_only(series_cli *c)
{
    if (cli_mpi_ranks() < 2 ||
        cli_mpi_sliced(c->a.inputs[0], c->a.in_format, c->a.output, c->a.per_rank))
        return 0;
    if (cli_mpi_rank() == 0)
        cli_usage_error(c->a.cmd, "on several MPI ranks the input and the output must be "
                        ".ply, .obj or .off files (not standard input or output)");
    return EXIT_USAGE;
}

static limn_status run(series_cli *c, limn_context *ctx, const limn_mesh *in, limn_mesh **out,
                       limn_series_report *r, void *user)
{
    extra *e = user;
    e->t.colors = e->rgb;
    e->t.series = c->opt;
    return limn_texture(ctx, in, &e->t, out, r);
}

static limn_status measure(limn_context *ctx, const limn_mesh *in, const limn_mesh *out,
                           const limn_series_report *r, void *user)
{
    (void)ctx, (void)in, (void)r;
    extra *e = user;
    e->out[0] = limn_mesh_vertex_count(out);
    e->out[1] = limn_mesh_face_count(out);
    return LIMN_OK;
}

int cli_texture(int argc, char **argv)
{
    series_cli c;
    series_cli_init(&c, "texture", help, 1);
    extra e;
    memset(&e, 0, sizeof e);
    limn_texture_options_default(&e.t);
    static const struct option longopts[] = {
        CLI_ARGS_OPTIONS,     CLI_VALUE("colors"), CLI_VALUE("colours"), CLI_VALUE("frequency"),
        CLI_VALUE("levels"),  CLI_VALUE("max-memory"), CLI_VALUE("seed"), CLI_VALUE("tol"),
        CLI_OPTIONS_END};
    int rc = cli_args_parse(&c.a, longopts, argc, argv, own_option, &e);
    if (rc)
        return rc < 0 ? 0 : rc;
    if ((rc = cli_mpi_root_rc(check(&c, &e))))
        return rc;
    if ((rc = sliced_only(&c)))
        return rc;
    e.t.colors = e.rgb;
    /* on slices the surface's counts come back through call (no measure runs) */
    cli_series_call call = {.kind = CLI_SERIES_TEXTURE, .texture = &e.t, .out_counts = e.out};
    series_filter f = {run, measure, NULL, {json_extra, print_extra, &e}, &call};
    return series_cli_filter(&c, &f);
}
