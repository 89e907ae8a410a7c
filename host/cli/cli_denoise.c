/* SPDX-License-Identifier: MIT */
/* limn denoise: seed 000 eq. 8, with the volume change reported. */
#include "cli_series.h"

#include <math.h>
#include <string.h>

static const char *const help =
    "usage: limn denoise INPUT -o OUTPUT [--m M] [--steps K] [options]\n"
    "\n"
    "Smooths noise away with eq. 8 of Lai & Cheng (2011), 'Fast Mesh\n"
    "Interpolation and Mesh Decomposition with Applications': T_0 = INPUT,\n"
    "T_{k+1} = sum_{i=0..m} (E - A)^i A T_k, K times ((m + 1) K stencil products).\n"
    "Smaller m smooths more; the paper uses m = 2-3 and K = 3-4. Every band gain\n"
    "is at most 1, so the mesh shrinks a little: the volume change is reported\n"
    "(closed meshes; for open ones the volume is not defined).\n"
    "\n"
    "  -o, --output FILE      mesh to write (.obj, .ply binary, .off)\n"
    "  --m M                  highest term of the partial sum, M >= 0   [2]\n"
    "  --steps K              iterations, K >= 1                         [3]\n"
    "  --keep-volume          scale the result about the mean of its vertices\n"
    "                         back to the input's volume (closed meshes only)\n"
    "  --scheme S             auto, loop or catmark                  [auto]\n"
    "  --alpha A              Catmull-Clark alpha in [0, 1]           [0]\n"
    "  --report FILE.json     also write the report as JSON\n"
    "  --device SPEC          reference | opencl | opencl:P.D | opencl:NAME\n"
    "  --format F / --input-format F / --overwrite-input / -q\n"
    CLI_MPI_HELP
    "\n"
    "Exit status: 0 success, 1 failure (nothing written), 2 bad usage.\n";

typedef struct extra {
    int m, steps, keep_volume, closed;
    double volume_in, volume_out, area_in, area_out, mean_displacement;
} extra;

static void json_extra(json_out *j, void *user)
{
    extra *e = user;
    json_integer(j, "m", e->m);
    json_integer(j, "steps", e->steps);
    json_bool(j, "keep_volume", e->keep_volume);
    json_bool(j, "closed", e->closed);
    json_number(j, "volume_input", e->closed ? e->volume_in : NAN);
    json_number(j, "volume_output", e->closed ? e->volume_out : NAN);
    json_number(j, "volume_change", e->closed ? (e->volume_out - e->volume_in) / e->volume_in : NAN);
    if (!e->closed)
        json_string(j, "volume_note", "not defined: the mesh is not closed");
    json_number(j, "area_input", e->area_in);
    json_number(j, "area_output", e->area_out);
    json_number(j, "mean_rel_displacement", e->mean_displacement);
}

static void print_extra(void *user)
{
    extra *e = user;
    fprintf(stderr, "  m %d, %d steps%s, mean displacement %.3g of the bbox diagonal\n", e->m,
            e->steps, e->keep_volume ? ", volume kept" : "", e->mean_displacement);
    if (e->closed)
        fprintf(stderr, "  volume %.6g -> %.6g (%+.3f%%), area %.6g -> %.6g\n", e->volume_in,
                e->volume_out, 100.0 * (e->volume_out - e->volume_in) / e->volume_in, e->area_in,
                e->area_out);
    else
        fprintf(stderr, "  volume not defined (the mesh is not closed); area %.6g -> %.6g\n",
                e->area_in, e->area_out);
}

int cli_denoise(int argc, char **argv)
{
    series_cli c = {.cmd = "denoise", .help = help, .inputs_wanted = 1};
    limn_series_options_default(&c.opt);
    extra e = {.m = 2, .steps = 3};
    static const struct option longopts[] = {
        SERIES_OPTIONS, CLI_FLAG("per-rank-output"), CLI_FLAG("keep-volume"), CLI_VALUE("m"),
        CLI_VALUE("steps"), CLI_OPTIONS_END};
    int orc = cli_options(c.cmd, longopts, SERIES_SHORT, &argc, &argv);
    if (orc)
        return orc;
    for (int i = 1; i < argc; i++) {
        int rc, k = series_cli_arg(&c, argc, argv, &i, &rc);
        if (k == SERIES_ARG_EXIT)
            return rc < 0 ? 0 : rc;
        if (k == SERIES_ARG_TAKEN)
            continue;
        const char *s = argv[i];
        if (strcmp(s, "--m") == 0 || strcmp(s, "--steps") == 0) {
            const char *v = series_cli_value(&c, argc, argv, &i);
            if (!v)
                return EXIT_USAGE;
            rc = series_cli_int(&c, s, v, s[2] == 'm' ? 0 : 1, s[2] == 'm' ? &e.m : &e.steps);
            if (rc)
                return rc;
        } else if (strcmp(s, "--keep-volume") == 0) {
            e.keep_volume = 1;
        } else {
            return cli_usage_error(c.cmd, "unknown option '%s'", s);
        }
    }
    int rc = cli_mpi_root_rc(series_cli_check(&c, 1));
    if (rc)
        return rc;
    series_seconds s = {.t0 = cli_now()};
    limn_context *ctx = NULL;
    limn_mesh *in[2] = {NULL, NULL}, *out = NULL;
    limn_series_report r = {.size = sizeof r};
    limn_status st = series_cli_load(&c, &ctx, in);
    s.load = cli_now() - s.t0;
    if (!st) {
        cli_progress_enable(ctx, c.quiet);
        st = cli_mpi_ranks() > 1 ? cli_mpi_denoise(ctx, in[0], &c.opt, e.m, e.steps,
                                                   e.keep_volume, &out, &r, &c.piece)
                                 : limn_denoise(ctx, in[0], &c.opt, e.m, e.steps, e.keep_volume,
                                                &out, &r);
        cli_progress_done();
    }
    limn_mesh_measures a = {.size = sizeof a}, b = {.size = sizeof b};
    limn_mesh_comparison cmp = {.size = sizeof cmp};
    if (!st && out) /* under mpirun: rank 0 */
        st = limn_mesh_measure(ctx, in[0], &a);
    if (!st && out)
        limn_mesh_volume_area(out, &b.volume, &b.area); /* same topology as the input */
    if (!st && out)
        st = limn_mesh_compare(ctx, in[0], out, &cmp);
    if (!st && out) {
        e.closed = a.closed;
        e.volume_in = a.volume;
        e.volume_out = b.volume;
        e.area_in = a.area;
        e.area_out = b.area;
        e.mean_displacement = cmp.mean_distance / (r.bbox_diagonal > 0 ? r.bbox_diagonal : 1.0);
    }
    series_extra x = {json_extra, print_extra, &e};
    rc = series_cli_finish(&c, ctx, st, out, &r, &s, &x);
    limn_mesh_destroy(in[0]);
    limn_mesh_destroy(out);
    limn_context_destroy(ctx);
    return rc;
}
