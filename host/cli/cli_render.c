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
    "\n"
    "Exit status: 0 success, 1 failure (nothing written), 2 bad usage.\n";

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

int cli_render(int argc, char **argv)
{
    series_cli c = {.cmd = "render", .help = help, .inputs_wanted = 1};
    limn_render_options o;
    limn_render_options_default(&o);
    static const struct option longopts[] = {
        SERIES_BASE_OPTIONS, CLI_FLAG("flat"), CLI_VALUE("view"), CLI_VALUE("size"), CLI_VALUE("up"),
        CLI_VALUE("supersample"), CLI_VALUE("color"), CLI_VALUE("background"), CLI_OPTIONS_END};
    int orc = cli_options(c.cmd, longopts, SERIES_SHORT, &argc, &argv);
    if (orc)
        return orc;
    for (int i = 1; i < argc; i++) {
        const char *s = argv[i], *v;
        if (strcmp(s, "--scheme") == 0 || strcmp(s, "--alpha") == 0 ||
            strcmp(s, "--device") == 0 || strcmp(s, "--format") == 0)
            return cli_usage_error(c.cmd, "unknown option '%s'", s);
        int rc, k = series_cli_arg(&c, argc, argv, &i, &rc);
        if (k == SERIES_ARG_EXIT)
            return rc < 0 ? 0 : rc;
        if (k == SERIES_ARG_TAKEN)
            continue;
        if (strcmp(s, "--flat") == 0) {
            o.flat = 1;
            continue;
        }
        if (strcmp(s, "--view") != 0 && strcmp(s, "--size") != 0 && strcmp(s, "--up") != 0 &&
            strcmp(s, "--supersample") != 0 && strcmp(s, "--color") != 0 &&
            strcmp(s, "--background") != 0)
            return cli_usage_error(c.cmd, "unknown option '%s'", s);
        if (!(v = series_cli_value(&c, argc, argv, &i)))
            return EXIT_USAGE;
        if (strcmp(s, "--view") == 0) {
            char *end, *end2;
            /* C locale: under de_DE strtod would read "30,20" as 30.2 */
            double az = cli_strtod(v, &end), el = 0;
            if (end == v || *end != ',' || (el = cli_strtod(end + 1, &end2), end2 == end + 1) ||
                *end2 || !(el >= -90 && el <= 90) || !(az > -1e6 && az < 1e6))
                return cli_usage_error(c.cmd,
                                       "--view '%s' is not AZIMUTH,ELEVATION in degrees "
                                       "(elevation in -90..90), e.g. 30,20",
                                       v);
            o.azimuth = az;
            o.elevation = el;
        } else if (strcmp(s, "--size") == 0) {
            char *end, *end2;
            long w = strtol(v, &end, 10), h = 0;
            if (end == v || (*end != 'x' && *end != 'X') ||
                (h = strtol(end + 1, &end2, 10), end2 == end + 1) || *end2 || w < 1 || h < 1 ||
                w > 8192 || h > 8192)
                return cli_usage_error(c.cmd, "--size '%s' is not WIDTHxHEIGHT in 1..8192", v);
            o.width = (int)w;
            o.height = (int)h;
        } else if (strcmp(s, "--up") == 0) {
            if (strlen(v) != 1 || !strchr("xyzXYZ", v[0]))
                return cli_usage_error(c.cmd, "--up '%s' is not x, y or z", v);
            o.up_axis = tolower((unsigned char)v[0]) - 'x';
        } else if (strcmp(s, "--supersample") == 0) {
            if ((rc = series_cli_int(&c, s, v, 1, &o.supersample)))
                return rc;
            if (o.supersample > 4)
                return cli_usage_error(c.cmd, "--supersample %s: at most 4", v);
        } else {
            uint8_t *dst = strcmp(s, "--color") == 0 ? o.color : o.background;
            if (!parse_hex_color(v, dst))
                return cli_usage_error(c.cmd, "%s '%s' is not a colour like #1a2b3c", s, v);
        }
    }
    int rc = series_cli_check(&c, 0);
    if (rc)
        return rc;
    const char *dot = strrchr(c.output, '.');
    if (!dot || (strcmp(dot, ".png") != 0 && strcmp(dot, ".PNG") != 0))
        return cli_usage_error(c.cmd, "the output '%s' must end in .png", c.output);
    if (!c.overwrite_input && cli_same_file(c.inputs[0], c.output))
        return cli_usage_error(c.cmd, "output '%s' is the input file", c.output);
    const char *picture[] = {c.output};
    if ((rc = cli_check_outputs(c.cmd, picture, 1)))
        return rc;

    double t0 = cli_now(), load, draw = 0, write = 0;
    limn_context *ctx = NULL;
    limn_mesh *in[2] = {NULL, NULL};
    uint8_t *rgb = NULL;
    limn_status st = series_cli_load(&c, &ctx, in);
    load = cli_now() - t0;
    if (!st && !(rgb = malloc(3 * (size_t)o.width * (size_t)o.height))) {
        fprintf(stderr, "limn render: error: out of memory for a %dx%d picture\n", o.width, o.height);
        limn_mesh_destroy(in[0]);
        limn_context_destroy(ctx);
        return EXIT_FAILURE_RUN;
    }
    if (!st) {
        double t = cli_now();
        st = limn_render(ctx, in[0], &o, rgb);
        draw = cli_now() - t;
    }
    if (!st) {
        double t = cli_now();
        st = limn_png_write(ctx, c.output, o.width, o.height, rgb);
        write = cli_now() - t;
    }
    if (!st && c.report) {
        json_out *j = json_begin();
        if (!j) {
            st = LIMN_ERR_MEMORY;
        } else {
            json_string(j, "command", "render");
            json_string(j, "input", c.inputs[0]);
            json_string(j, "output", c.output);
            json_integer(j, "vertices", (long long)limn_mesh_vertex_count(in[0]));
            json_integer(j, "faces", (long long)limn_mesh_face_count(in[0]));
            json_integer(j, "width", o.width);
            json_integer(j, "height", o.height);
            json_number(j, "azimuth", o.azimuth);
            json_number(j, "elevation", o.elevation);
            json_string(j, "up", o.up_axis == 0 ? "x" : o.up_axis == 1 ? "y" : "z");
            json_string(j, "shading", o.flat ? "flat" : "smooth");
            json_bool(j, "vertex_colors", limn_mesh_colors(in[0]) != NULL);
            json_object_begin(j, "seconds");
            json_number(j, "load", load);
            json_number(j, "render", draw);
            json_number(j, "write", write);
            json_number(j, "total", cli_now() - t0);
            json_object_end(j);
            st = json_commit(ctx, j, c.report);
        }
        if (st)
            remove(c.output);
    }
    if (st)
        rc = ctx ? cli_fail(c.cmd, ctx, st) : EXIT_FAILURE_RUN;
    else if (!c.quiet)
        fprintf(stderr,
                "limn render: %s -> %s\n  %dx%d, view %g,%g, %s shading%s; seconds: load %.3f, "
                "render %.3f, write %.3f\n",
                c.inputs[0], c.output, o.width, o.height, o.azimuth, o.elevation,
                o.flat ? "flat" : "smooth", limn_mesh_colors(in[0]) ? ", vertex colours" : "",
                load, draw, write);
    free(rgb);
    limn_mesh_destroy(in[0]);
    limn_context_destroy(ctx);
    return rc;
}
