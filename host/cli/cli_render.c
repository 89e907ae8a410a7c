/* SPDX-License-Identifier: MIT */
/* limn render: a headless PNG picture of a mesh. */
#include "cli_series.h"

#include <ctype.h>
#include <stdlib.h>
#include <string.h>

static const char *const help =
    "usage: limn render INPUT -o OUTPUT.png [--view AZ,EL] [--size WxH] [options]\n"
    "\n"
    "Draws INPUT into a PNG without any display: orthographic view, z-buffer,\n"
    "Lambert shading (one light from the upper left plus ambient, two-sided),\n"
    "vertex colours when the mesh has them (PLY), 2x2 supersampling.\n"
    "\n"
    "  -o, --output FILE      PNG file to write\n"
    "  --view AZ,EL           azimuth and elevation in degrees          [30,20]\n"
    "                         (0,0 looks from +z with y up; see --up)\n"
    "  --size WxH             picture size in pixels                    [400x300]\n"
    "  --up AXIS              x, y or z: the axis drawn upwards          [y]\n"
    "  --flat                 flat shading (face normals) instead of smooth\n"
    "  --supersample N        samples per pixel side, 1..4               [2]\n"
    "  --color #rrggbb        surface colour when the mesh has none\n"
    "  --background #rrggbb   background colour                          [#ffffff]\n"
    "  --report FILE.json     also write a JSON report\n"
    "  --input-format F / --overwrite-input / -q\n"
    CLI_HOST_THREADS_HELP
    SERIES_HELP_EXIT;

static int parse_hex_color(const char *v, uint8_t rgb[3])
{
    if (*v == '#')
        v++;
    if (strlen(v) != 6)
        return 0;
    for (int i = 0; i < 6; i++)
        if (!isxdigit((unsigned char)v[i]))
            return 0;
    for (int c = 0; c < 3; c++) {
        char b[3] = {v[2 * c], v[2 * c + 1], 0};
        rgb[c] = (uint8_t)strtol(b, NULL, 16);
    }
    return 1;
}

/* --view AZ,EL; 0 or an exit status. */
static int view_option(cli_args *a, const char *v, limn_render_options *o)
{
    char *end, *end2;
    /* C locale: under de_DE strtod would read "30,20" as 30.2 */
    double az = cli_strtod(v, &end), el = 0;
    if (end == v || *end != ',' || (el = cli_strtod(end + 1, &end2), end2 == end + 1) || *end2 ||
        !(el >= -90 && el <= 90) || !(az > -1e6 && az < 1e6))
        return cli_usage_error(a->cmd,
                               "--view '%s' is not AZIMUTH,ELEVATION in degrees (elevation in "
                               "-90..90), e.g. 30,20",
                               v);
    o->azimuth = az;
    o->elevation = el;
    return 0;
}

/* --size WxH; 0 or an exit status. */
static int size_option(cli_args *a, const char *v, limn_render_options *o)
{
    char *end, *end2;
    long w = strtol(v, &end, 10), h = 0;
    if (end == v || (*end != 'x' && *end != 'X') ||
        (h = strtol(end + 1, &end2, 10), end2 == end + 1) || *end2 || w < 1 || h < 1 ||
        w > 8192 || h > 8192)
        return cli_usage_error(a->cmd, "--size '%s' is not WIDTHxHEIGHT in 1..8192", v);
    o->width = (int)w;
    o->height = (int)h;
    return 0;
}

static int own_option(cli_args *a, void *user, int argc, char **argv, int *i)
{
    limn_render_options *o = user;
    const char *s = argv[*i], *v;
    const cli_own_option own[] = {
        {"--flat", CLI_OWN_FLAG, &o->flat, 1, 0},
        {"--supersample", CLI_OWN_INT, &o->supersample, 1, 4},
    };
    int rc = cli_args_own(a, argc, argv, i, own, sizeof own / sizeof *own);
    if (rc != CLI_OWN_UNKNOWN)
        return rc;
    if (strcmp(s, "--view") != 0 && strcmp(s, "--size") != 0 && strcmp(s, "--up") != 0 &&
        strcmp(s, "--color") != 0 && strcmp(s, "--background") != 0)
        return CLI_OWN_UNKNOWN;
    if (!(v = cli_args_value(a, argc, argv, i)))
        return EXIT_USAGE;
    if (strcmp(s, "--view") == 0)
        return view_option(a, v, o);
    if (strcmp(s, "--size") == 0)
        return size_option(a, v, o);
    if (strcmp(s, "--up") == 0) {
        if (strlen(v) != 1 || !strchr("xyzXYZ", v[0]))
            return cli_usage_error(a->cmd, "--up '%s' is not x, y or z", v);
        o->up_axis = tolower((unsigned char)v[0]) - 'x';
        return 0;
    }
    if (!parse_hex_color(v, strcmp(s, "--color") == 0 ? o->color : o->background))
        return cli_usage_error(a->cmd, "%s '%s' is not a colour like #1a2b3c", s, v);
    return 0;
}

/* After the shared checks: a .png output that is not the input and can be
   written; 0 or an exit status. */
static int check(const cli_args *a)
{
    const char *dot = strrchr(a->output, '.');
    if (!dot || (strcmp(dot, ".png") != 0 && strcmp(dot, ".PNG") != 0))
        return cli_usage_error(a->cmd, "the output '%s' must end in .png", a->output);
    if (!a->overwrite_input && cli_same_file(a->inputs[0], a->output))
        return cli_usage_error(a->cmd, "output '%s' is the input file", a->output);
    const char *picture[] = {a->output};
    return cli_check_outputs(a->cmd, picture, 1);
}

/* load, render, write, total */
typedef struct render_seconds {
    double load, draw, write, t0;
} render_seconds;

static limn_status stage_report(limn_context *ctx, const cli_args *a, const limn_mesh *mesh,
                                const limn_render_options *o, const render_seconds *sec,
                                limn_output_set *set)
{
    json_out *j = cli_args_report(a, limn_mesh_vertex_count(mesh), limn_mesh_face_count(mesh));
    if (!j)
        return cli_error(LIMN_ERR_MEMORY, "out of memory for the report");
    json_integer(j, "width", o->width);
    json_integer(j, "height", o->height);
    json_number(j, "azimuth", o->azimuth);
    json_number(j, "elevation", o->elevation);
    json_string(j, "up", o->up_axis == 0 ? "x" : o->up_axis == 1 ? "y" : "z");
    json_string(j, "shading", o->flat ? "flat" : "smooth");
    json_bool(j, "vertex_colors", limn_mesh_colors(mesh) != NULL);
    json_object_begin(j, "seconds");
    json_number(j, "load", sec->load);
    json_number(j, "render", sec->draw);
    json_number(j, "write", sec->write);
    json_number(j, "total", cli_now() - sec->t0);
    json_object_end(j);
    return json_stage(ctx, j, a->report, set);
}

/* Draws the mesh and writes the picture and the report, staged and made to
   appear together (a failure leaves an existing picture as it was). */
static limn_status draw(limn_context *ctx, const cli_args *a, const limn_mesh *mesh,
                        const limn_render_options *o, uint8_t *rgb, render_seconds *sec)
{
    double t = cli_now();
    limn_status st = limn_render(ctx, mesh, o, rgb);
    sec->draw = cli_now() - t;
    if (st)
        return st;
    t = cli_now();
    limn_output_set *set = NULL;
    st = limn_output_set_create(ctx, &set);
    if (!st)
        st = limn_output_set_add_png(ctx, set, a->output, o->width, o->height, rgb);
    sec->write = cli_now() - t;
    if (!st && a->report)
        st = stage_report(ctx, a, mesh, o, sec, set);
    return cli_commit_outputs(ctx, st, set);
}

static int run(series_cli *c, const limn_render_options *o)
{
    render_seconds sec = {.t0 = cli_now()};
    limn_context *ctx = NULL;
    limn_mesh *in[2] = {NULL, NULL};
    uint8_t *rgb = NULL;
    int rc = 0;
    limn_status st = series_cli_load(c, &ctx, in);
    sec.load = cli_now() - sec.t0;
    if (!st && !(rgb = malloc(3 * (size_t)o->width * (size_t)o->height))) {
        fprintf(stderr, "limn render: error: out of memory for a %dx%d picture\n", o->width,
                o->height);
        series_cli_unload(ctx, in);
        return EXIT_FAILURE_RUN;
    }
    if (!st)
        st = draw(ctx, &c->a, in[0], o, rgb, &sec);
    if (st)
        rc = ctx ? cli_fail(c->a.cmd, ctx, st) : EXIT_FAILURE_RUN;
    else if (!c->a.quiet)
        fprintf(stderr,
                "limn render: %s -> %s\n  %dx%d, view %g,%g, %s shading%s; seconds: load %.3f, "
                "render %.3f, write %.3f\n",
                c->a.inputs[0], c->a.output, o->width, o->height, o->azimuth, o->elevation,
                o->flat ? "flat" : "smooth", limn_mesh_colors(in[0]) ? ", vertex colours" : "",
                sec.load, sec.draw, sec.write);
    free(rgb);
    series_cli_unload(ctx, in);
    return rc;
}

int cli_render(int argc, char **argv)
{
    series_cli c;
    series_cli_init(&c, "render", help, 1);
    c.a.scheme = NULL; /* no --scheme, --alpha */
    c.a.alpha = NULL;
    limn_render_options o;
    limn_render_options_default(&o);
    static const struct option longopts[] = {
        CLI_ARGS_BASE_OPTIONS, CLI_FLAG("flat"),        CLI_VALUE("view"),
        CLI_VALUE("size"),     CLI_VALUE("up"),         CLI_VALUE("supersample"),
        CLI_VALUE("color"),    CLI_VALUE("background"), CLI_OPTIONS_END};
    int rc = cli_args_parse(&c.a, longopts, argc, argv, own_option, &o);
    if (rc)
        return rc < 0 ? 0 : rc;
    rc = series_cli_check(&c, 0);
    if (!rc)
        rc = check(&c.a);
    return rc ? rc : run(&c, &o);
}
