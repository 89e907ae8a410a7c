/* SPDX-License-Identifier: MIT */
/* limn morph: frames from FROM to TO by seed 000 eq. 9, or the linear blend. */
#include "cli_series.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static const char *const help =
    "usage: limn morph FROM TO -o 'frames/f%04d.ply' [--frames F] [--m M] [--p P]\n"
    "                  [--linear] [options]\n"
    "\n"
    "Writes F frames morphing FROM into TO (same faces, same vertex order) by\n"
    "eq. 9 of Lai & Cheng (2011), 'Fast Mesh Interpolation and Mesh\n"
    "Decomposition with Applications': Q_0 = FROM,\n"
    "Q_{k+1} = TO + p sum_{i=0..m} (E - A)^i A (Q_k - TO),\n"
    "computed with m + 1 stencil products per frame (A: the limit operator of the\n"
    "shared topology). Frame 0 is FROM; the frames approach TO geometrically\n"
    "(the smooth part of the difference fades by p per frame, detail faster), so\n"
    "the last frame is near TO, not exactly TO. --linear writes the linear blend\n"
    "(1 - t) FROM + t TO, t = k / (F - 1), for comparison. The report has each\n"
    "frame's volume (closed meshes), area, flipped faces (normals turned more\n"
    "than 90 degrees from FROM's) and mean distance to TO.\n"
    "\n"
    "  -o, --output PATTERN   frame file names with one %d conversion (%04d etc.)\n"
    "  --frames F             frames written, F >= 2                    [30]\n"
    "  --m M                  highest term of eq. 9, M >= 0              [2]\n"
    "  --p P                  speed, 0 < P < 1 (smaller is faster)       [0.8]\n"
    "  --linear               the linear blend instead\n"
    SERIES_HELP
    "  --format F / --input-format F / --overwrite-input / -q\n"
    "\n"
    "Every frame is staged whole and all appear together with the report at the\n"
    "end, or none does (an existing file keeps its bytes). Under 'mpirun -np N'\n"
    "on two files every rank reads its slices\n"
    "of FROM and TO and writes its share of every frame (no rank holds a mesh);\n"
    "else the products are distributed and rank 0 writes the frames.\n"
    "Exit status: 0 success, 1 failure, 2 bad usage.\n";

typedef struct pattern {
    char *prefix, *suffix;
    int zero, width;
} pattern;

/* Accepts exactly one conversion %d / %Nd / %0Nd (and %% for a percent
   sign): 1, or 0 with why, or -1 when out of memory. */
static int parse_pattern(const char *text, pattern *p, char *why, size_t why_size)
{
    size_t len = strlen(text);
    p->prefix = calloc(len + 1, 1);
    p->suffix = calloc(len + 1, 1);
    if (!p->prefix || !p->suffix)
        return -1;
    int conversions = 0;
    char *dst = p->prefix;
    for (size_t i = 0; i < len; i++) {
        if (text[i] != '%') {
            *dst++ = text[i];
            continue;
        }
        if (text[i + 1] == '%') {
            *dst++ = '%';
            i++;
            continue;
        }
        size_t j = i + 1;
        int zero = 0, width = 0;
        if (text[j] == '0')
            zero = 1, j++;
        while (text[j] >= '0' && text[j] <= '9' && width < 100)
            width = 10 * width + (text[j++] - '0');
        if (text[j] != 'd' && text[j] != 'i' && text[j] != 'u') {
            snprintf(why, why_size, "'%s' has a conversion other than %%d at character %zu",
                     text, i + 1);
            return 0;
        }
        if (++conversions > 1) {
            snprintf(why, why_size, "'%s' has more than one %%d conversion", text);
            return 0;
        }
        if (width > 32) {
            snprintf(why, why_size, "'%s': field width %d is too wide", text, width);
            return 0;
        }
        p->zero = zero;
        p->width = width;
        dst = p->suffix;
        i = j;
    }
    if (conversions != 1) {
        snprintf(why, why_size,
                 "'%s' needs exactly one %%d-style conversion for the frame number (e.g. "
                 "'frames/f%%04d.ply')",
                 text);
        return 0;
    }
    return 1;
}

static void frame_name(const pattern *p, int k, char *buf, size_t size)
{
    if (p->zero)
        snprintf(buf, size, "%s%0*d%s", p->prefix, p->width, k, p->suffix);
    else
        snprintf(buf, size, "%s%*d%s", p->prefix, p->width, k, p->suffix);
}

typedef struct morph_state {
    limn_context *ctx;
    series_cli *c;
    pattern pat;
    size_t name_size;
    char *name;
    limn_mesh *frame;
    int frames, m, linear;
    double p, write_seconds;
    double *volume, *area, *distance;
    size_t *flipped;
} morph_state;

/* A frame's measures for the report. */
static void record(void *user, const limn_morph_frame *f)
{
    morph_state *s = user;
    s->volume[f->index] = f->volume;
    s->area[f->index] = f->area;
    s->flipped[f->index] = f->flipped_faces;
    s->distance[f->index] = f->mean_distance_to_target;
}

static limn_status write_frame(void *user, const limn_morph_frame *f)
{
    morph_state *s = user;
    double t = cli_now();
    memcpy(limn_mesh_positions_mutable(s->frame), f->positions,
           3 * limn_mesh_vertex_count(s->frame) * sizeof(double));
    frame_name(&s->pat, f->index, s->name, s->name_size);
    limn_status st = limn_output_set_add_mesh(s->ctx, s->c->a.staged, s->frame, s->name,
                                              s->c->a.out_format);
    record(s, f);
    s->write_seconds += cli_now() - t;
    return st;
}

/* Frame k's file name (on slices every rank writes its share of it). */
static const char *name_of(void *user, int k)
{
    morph_state *s = user;
    frame_name(&s->pat, k, s->name, s->name_size);
    return s->name;
}

static void json_extra(json_out *j, void *user)
{
    morph_state *s = user;
    json_string(j, "method", s->linear ? "linear" : "series");
    json_integer(j, "frames", s->frames);
    if (!s->linear) {
        json_integer(j, "m", s->m);
        json_number(j, "p", s->p);
    }
    json_array_begin(j, "per_frame");
    for (int k = 0; k < s->frames; k++) {
        json_element_object_begin(j);
        json_integer(j, "frame", k);
        json_number(j, "volume", s->volume[k]);
        json_number(j, "area", s->area[k]);
        json_integer(j, "flipped_faces", (long long)s->flipped[k]);
        json_number(j, "mean_rel_distance_to_target", s->distance[k]);
        json_object_end(j);
    }
    json_array_end(j);
    if (isnan(s->volume[0]))
        json_string(j, "volume_note", "not defined: the mesh is not closed");
}

static void print_extra(void *user)
{
    morph_state *s = user;
    size_t most = 0;
    double vmin = INFINITY, vmax = -INFINITY;
    for (int k = 0; k < s->frames; k++) {
        most = s->flipped[k] > most ? s->flipped[k] : most;
        vmin = fmin(vmin, s->volume[k]);
        vmax = fmax(vmax, s->volume[k]);
    }
    fprintf(stderr, "  %d frames (%s%s), last frame's mean distance to TO %.3g of the bbox "
                    "diagonal, at most %zu flipped faces in a frame\n",
            s->frames, s->linear ? "linear blend" : "series, eq. 9", "", s->distance[s->frames - 1],
            most);
    if (!isnan(s->volume[0]))
        fprintf(stderr, "  volume: first %.6g, last %.6g, range %.6g .. %.6g\n", s->volume[0],
                s->volume[s->frames - 1], vmin, vmax);
    else
        fprintf(stderr, "  volume not defined (the mesh is not closed)\n");
}

static int own_option(cli_args *a, void *user, int argc, char **argv, int *i)
{
    limn_morph_options *mo = user;
    const char *s = argv[*i];
    const cli_own_option own[] = {
        {"--linear", CLI_OWN_FLAG, &mo->linear, 1, 0},
        {"--frames", CLI_OWN_INT, &mo->frames, 2, 1000000},
        {"--m", CLI_OWN_INT, &mo->m, 0, INT_MAX},
        {"--p", CLI_OWN_NUMBER, &mo->p, 0, 0},
    };
    int rc = cli_args_own(a, argc, argv, i, own, sizeof own / sizeof *own);
    if (!rc && strcmp(s, "--p") == 0 && !(mo->p > 0 && mo->p < 1))
        rc = cli_usage_error(a->cmd, "--p %s must lie strictly between 0 and 1", argv[*i]);
    return rc;
}

/* The name buffer and the per-frame arrays; 0 or an exit status. */
static int allocate(morph_state *ms, const char *output, int frames)
{
    ms->name_size = strlen(output) + 64;
    ms->name = malloc(ms->name_size);
    ms->volume = calloc((size_t)frames, sizeof *ms->volume);
    ms->area = calloc((size_t)frames, sizeof *ms->area);
    ms->distance = calloc((size_t)frames, sizeof *ms->distance);
    ms->flipped = calloc((size_t)frames, sizeof *ms->flipped);
    if (!ms->name || !ms->volume || !ms->area || !ms->distance || !ms->flipped) {
        fprintf(stderr, "limn morph: error: out of memory\n");
        return EXIT_FAILURE_RUN;
    }
    return 0;
}

static void release(morph_state *ms)
{
    free(ms->pat.prefix);
    free(ms->pat.suffix);
    free(ms->name);
    free(ms->volume);
    free(ms->area);
    free(ms->distance);
    free(ms->flipped);
}

/* The frames' directory exists (checked on frame 0's name); 0 or 1. */
static int check_directory(const char *name)
{
    char *dir = strdup(name);
    char *slash = dir ? strrchr(dir, '/') : NULL;
    struct stat sb;
    int rc = 0;
    if (slash && slash != dir) {
        *slash = '\0';
        if (stat(dir, &sb) != 0 || !S_ISDIR(sb.st_mode)) {
            fprintf(stderr, "limn morph: error: the frames' directory '%s' does not exist\n",
                    dir);
            rc = EXIT_FAILURE_RUN;
        }
    }
    free(dir);
    return rc;
}

/* The frames' names: a known format, distinct, not an input, in a
   directory; 0 or an exit status. Leaves frame 0's name in ms->name. */
static int check_frames(series_cli *c, morph_state *ms)
{
    frame_name(&ms->pat, 0, ms->name, ms->name_size);
    char *second = malloc(ms->name_size);
    if (!second) {
        fprintf(stderr, "limn morph: error: out of memory\n");
        return EXIT_FAILURE_RUN;
    }
    frame_name(&ms->pat, 1, second, ms->name_size);
    int same = strcmp(second, ms->name) == 0;
    free(second);
    if (same)
        return cli_usage_error(c->a.cmd, "-o '%s' gives every frame the same name", c->a.output);
    for (int k = 0; k < 2; k++) {
        int rc = cli_check_output(c->a.cmd, c->a.inputs[k], ms->name, c->a.out_format,
                                  c->a.overwrite_input);
        if (rc)
            return rc;
    }
    for (int k = 0; k < ms->frames && !c->a.overwrite_input; k++) {
        frame_name(&ms->pat, k, ms->name, ms->name_size);
        if (cli_same_file(ms->name, c->a.inputs[0]) || cli_same_file(ms->name, c->a.inputs[1]))
            return cli_usage_error(c->a.cmd, "frame %d would overwrite the input '%s'", k,
                                   ms->name);
    }
    return check_directory(ms->name);
}

/* Everything about the output pattern, before any work; 0 or an exit status. */
static int check(series_cli *c, morph_state *ms)
{
    char why[512];
    int parsed = parse_pattern(c->a.output, &ms->pat, why, sizeof why);
    if (parsed < 0) {
        fprintf(stderr, "limn morph: error: out of memory\n");
        return EXIT_FAILURE_RUN;
    }
    if (!parsed)
        return cli_usage_error(c->a.cmd, "-o %s", why);
    int rc = allocate(ms, c->a.output, ms->frames);
    if (!rc)
        rc = check_frames(c, ms);
    if (!rc && c->a.out_format == LIMN_FORMAT_AUTO)
        limn_format_from_path(ms->name, &c->a.out_format);
    return rc;
}

/* The end of both paths: the report staged with the frames, all committed
   together (series_cli_finish), and the summary; the exit status. */
static int finish(series_cli *c, limn_status st, limn_series_report *r, series_seconds *s,
                  morph_state *ms)
{
    r->seconds_compute -= ms->write_seconds;
    s->write = ms->write_seconds;
    series_extra x = {json_extra, print_extra, ms};
    return series_cli_finish(c, ms->ctx, st, NULL, r, s, &x);
}

/* Under mpirun on two input files: every rank reads its slices of FROM and
   TO and writes its share of every frame (cli_mpi_morph_sliced). */
static int run_sliced(series_cli *c, limn_morph_options *mo, morph_state *ms)
{
    series_seconds s = {.t0 = cli_now()};
    limn_series_report r = {.size = sizeof r};
    ms->ctx = cli_sliced_context("morph");
    if (!ms->ctx)
        return EXIT_FAILURE_RUN;
    limn_status st = cli_set_host_threads(ms->ctx, c->a.host_threads);
    if (!st)
        st = limn_context_set_device(ms->ctx, c->a.device);
    c->a.quiet |= cli_mpi_rank() != 0; /* under mpirun rank 0 prints */
    st = cli_mpi_agree(ms->ctx, st);
    if (!st) /* every frame staged there, to appear with the report */
        st = cli_mpi_agree(ms->ctx, limn_output_set_create(ms->ctx, &c->a.staged));
    mo->series = c->opt;
    /* frames written with the defaults, as limn_mesh_write writes them */
    cli_sliced_job job = {c->a.cmd,       c->a.inputs[0],  c->a.output, &c->a.repair,
                          c->a.in_format, c->a.out_format, NULL,        1,
                          c->a.staged};
    cli_morph_sink sink = {name_of, record, ms, 0.0};
    double sec[2] = {0, 0};
    if (!st) {
        cli_progress_enable(ms->ctx, c->a.quiet);
        st = cli_mpi_morph_sliced(ms->ctx, &job, c->a.inputs[1], mo, &sink, &r, sec);
        cli_progress_done();
    }
    ms->write_seconds = sink.write_seconds;
    s.load = sec[0];
    c->sliced = 1;
    int rc = finish(c, st, &r, &s, ms);
    limn_context_destroy(ms->ctx);
    return rc;
}

/* Loads FROM and TO, stages the frames as they come, then the report, and
   commits them together; the summary; the exit status. */
static int run(series_cli *c, limn_morph_options *mo, morph_state *ms)
{
    if (cli_mpi_ranks() > 1 &&
        cli_mpi_sliced(c->a.inputs[0], c->a.in_format, c->a.output, c->a.per_rank) &&
        cli_mpi_sliced(c->a.inputs[1], c->a.in_format, c->a.output, c->a.per_rank))
        return run_sliced(c, mo, ms);
    series_seconds s = {.t0 = cli_now()};
    limn_mesh *in[2] = {NULL, NULL};
    limn_series_report r = {.size = sizeof r};
    limn_status st = series_cli_load(c, &ms->ctx, in);
    s.load = cli_now() - s.t0;
    mo->series = c->opt;
    if (!st && in[0]) /* rank 0 writes the frames */
        st = limn_mesh_copy(ms->ctx, in[0], &ms->frame);
    if (!st && in[0])
        st = limn_output_set_create(ms->ctx, &c->a.staged);
    if (!st) {
        cli_progress_enable(ms->ctx, c->a.quiet);
        st = cli_mpi_ranks() > 1
                 ? cli_mpi_morph(ms->ctx, in[0], in[1], mo, write_frame, ms, &r)
                 : limn_morph(ms->ctx, in[0], in[1], mo, write_frame, ms, &r);
        cli_progress_done();
    }
    int rc = finish(c, st, &r, &s, ms);
    limn_mesh_destroy(ms->frame);
    series_cli_unload(ms->ctx, in);
    return rc;
}

int cli_morph(int argc, char **argv)
{
    series_cli c;
    series_cli_init(&c, "morph", help, 2);
    limn_morph_options mo;
    limn_morph_options_default(&mo);
    static const struct option longopts[] = {
        CLI_ARGS_OPTIONS, CLI_VALUE("frames"), CLI_FLAG("linear"), CLI_VALUE("m"),
        CLI_VALUE("p"),   CLI_OPTIONS_END};
    int rc = cli_args_parse(&c.a, longopts, argc, argv, own_option, &mo);
    if (rc)
        return rc < 0 ? 0 : rc;
    rc = cli_mpi_root_rc(series_cli_check(&c, 0));
    if (rc)
        return rc;
    morph_state ms = {
        .c = &c, .frames = mo.frames, .m = mo.m, .p = mo.p, .linear = mo.linear};
    /* under mpirun rank 0's checks decide for every rank */
    rc = cli_mpi_root_rc(check(&c, &ms));
    if (!rc)
        rc = run(&c, &mo, &ms);
    release(&ms);
    return rc;
}
