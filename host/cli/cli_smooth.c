/* SPDX-License-Identifier: MIT */
/* limn smooth: the partial sum of the first N bands of the series. */
#include "cli_series.h"

#include <string.h>

static const char *const help =
    "usage: limn smooth INPUT -o OUTPUT --terms N [options]\n"
    "\n"
    "Writes the partial sum of the first N bands of INPUT's series,\n"
    "sum_{i<N} (E - A)^i A M = (E - (E - A)^N) M: N = 1 gives the limit points\n"
    "(the smoothest), larger N keeps more detail and tends to INPUT.\n"
    "\n"
    "  -o, --output FILE      mesh to write (.obj, .ply binary, .off)\n"
    "  --terms N              number of bands summed, N >= 1\n"
    "  --scheme S             auto, loop or catmark                  [auto]\n"
    "  --alpha A              Catmull-Clark alpha in [0, 1]           [0]\n"
    "  --report FILE.json     also write the report as JSON\n"
    "  --device SPEC          reference | opencl | opencl:P.D | opencl:NAME\n"
    "  --format F / --input-format F / --overwrite-input / -q\n"
    CLI_MPI_HELP
    "\n"
    "Exit status: 0 success, 1 failure (nothing written), 2 bad usage.\n";

typedef struct extra {
    int terms;
    double mean_displacement;
} extra;

static void json_extra(json_out *j, void *user)
{
    extra *e = user;
    json_integer(j, "terms", e->terms);
    json_number(j, "mean_rel_displacement", e->mean_displacement);
}

static void print_extra(void *user)
{
    extra *e = user;
    fprintf(stderr, "  %d terms, mean displacement %.3g of the bbox diagonal\n", e->terms,
            e->mean_displacement);
}

int cli_smooth(int argc, char **argv)
{
    series_cli c = {.cmd = "smooth", .help = help, .inputs_wanted = 1};
    limn_series_options_default(&c.opt);
    extra e = {.terms = 0};
    static const struct option longopts[] = {
        SERIES_OPTIONS, CLI_FLAG("per-rank-output"), CLI_VALUE("terms"), CLI_OPTIONS_END};
    int orc = cli_options(c.cmd, longopts, SERIES_SHORT, &argc, &argv);
    if (orc)
        return orc;
    for (int i = 1; i < argc; i++) {
        int rc, k = series_cli_arg(&c, argc, argv, &i, &rc);
        if (k == SERIES_ARG_EXIT)
            return rc < 0 ? 0 : rc;
        if (k == SERIES_ARG_TAKEN)
            continue;
        if (strcmp(argv[i], "--terms") == 0) {
            const char *v = series_cli_value(&c, argc, argv, &i);
            if (!v || (rc = series_cli_int(&c, "--terms", v, 1, &e.terms)) != 0)
                return v ? rc : EXIT_USAGE;
        } else {
            return cli_usage_error(c.cmd, "unknown option '%s'", argv[i]);
        }
    }
    if (e.terms == 0)
        return cli_usage_error(c.cmd, "--terms N is required");
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
        st = cli_mpi_ranks() > 1
                 ? cli_mpi_smooth(ctx, in[0], &c.opt, e.terms, &out, &r, &c.piece)
                 : limn_smooth(ctx, in[0], &c.opt, e.terms, &out, &r);
        cli_progress_done();
    }
    limn_mesh_comparison cmp = {.size = sizeof cmp};
    if (!st && out && limn_mesh_compare(ctx, in[0], out, &cmp) == LIMN_OK)
        e.mean_displacement = cmp.mean_distance / (r.bbox_diagonal > 0 ? r.bbox_diagonal : 1.0);
    series_extra x = {json_extra, print_extra, &e};
    rc = series_cli_finish(&c, ctx, st, out, &r, &s, &x);
    limn_mesh_destroy(in[0]);
    limn_mesh_destroy(out);
    limn_context_destroy(ctx);
    return rc;
}
