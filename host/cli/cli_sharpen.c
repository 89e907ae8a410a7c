/* SPDX-License-Identifier: MIT */
/* limn sharpen: T_{k+1} = T_k + sum_{i=m..n} (E - A)^i T_k (seed 000 §6). */
#include "cli_series.h"

#include <string.h>

static const char *const help =
    "usage: limn sharpen INPUT -o OUTPUT --from M --to N [--steps K] [options]\n"
    "\n"
    "Adds high-frequency detail (Lai & Cheng (2011), 'Fast Mesh Interpolation\n"
    "and Mesh Decomposition with Applications', section 6): T_0 = INPUT,\n"
    "T_{k+1} = T_k + sum_{i=M..N} (E - A)^i T_k, K times (N K stencil products).\n"
    "Terms with larger i are finer detail; M = 0 adds T itself (doubles the mesh\n"
    "about the origin), so M >= 1 is the useful range.\n"
    "\n"
    "  -o, --output FILE      mesh to write (.obj, .ply binary, .off)\n"
    "  --from M, --to N       the terms added, 0 <= M <= N\n"
    "  --steps K              iterations, K >= 1                         [1]\n"
    "  --scheme S             auto, loop or catmark                  [auto]\n"
    "  --alpha A              Catmull-Clark alpha in [0, 1]           [0]\n"
    "  --report FILE.json     also write the report as JSON\n"
    "  --device SPEC          reference | opencl | opencl:P.D | opencl:NAME\n"
    "  --format F / --input-format F / --overwrite-input / -q\n"
    "\n"
    "Exit status: 0 success, 1 failure (nothing written), 2 bad usage.\n";

typedef struct extra {
    int from, to, steps;
    double mean_displacement;
} extra;

static void json_extra(json_out *j, void *user)
{
    extra *e = user;
    json_integer(j, "from", e->from);
    json_integer(j, "to", e->to);
    json_integer(j, "steps", e->steps);
    json_number(j, "mean_rel_displacement", e->mean_displacement);
}

static void print_extra(void *user)
{
    extra *e = user;
    fprintf(stderr, "  terms %d..%d, %d steps, mean displacement %.3g of the bbox diagonal\n",
            e->from, e->to, e->steps, e->mean_displacement);
}

int cli_sharpen(int argc, char **argv)
{
    series_cli c = {.cmd = "sharpen", .help = help, .inputs_wanted = 1};
    limn_series_options_default(&c.opt);
    extra e = {.from = -1, .to = -1, .steps = 1};
    static const struct option longopts[] = {
        SERIES_OPTIONS, CLI_VALUE("from"), CLI_VALUE("to"), CLI_VALUE("steps"), CLI_OPTIONS_END};
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
        int *target = strcmp(s, "--from") == 0    ? &e.from
                      : strcmp(s, "--to") == 0    ? &e.to
                      : strcmp(s, "--steps") == 0 ? &e.steps
                                                  : NULL;
        if (!target)
            return cli_usage_error(c.cmd, "unknown option '%s'", s);
        const char *v = series_cli_value(&c, argc, argv, &i);
        if (!v)
            return EXIT_USAGE;
        rc = series_cli_int(&c, s, v, target == &e.steps ? 1 : 0, target);
        if (rc)
            return rc;
    }
    if (e.from < 0 || e.to < 0)
        return cli_usage_error(c.cmd, "--from M and --to N are required");
    if (e.to < e.from)
        return cli_usage_error(c.cmd, "--to %d is below --from %d", e.to, e.from);
    int rc = series_cli_check(&c, 1);
    if (rc)
        return rc;
    series_seconds s = {.t0 = cli_now()};
    limn_context *ctx = NULL;
    limn_mesh *in[2] = {NULL, NULL}, *out = NULL;
    limn_series_report r = {.size = sizeof r};
    limn_status st = series_cli_load(&c, &ctx, in);
    s.load = cli_now() - s.t0;
    if (!st) {
        if (e.from == 0 && !c.quiet)
            fprintf(stderr, "limn sharpen: warning: --from 0 adds the mesh itself: it is scaled "
                            "by 2 about the origin\n");
        cli_progress_enable(ctx, c.quiet);
        st = limn_sharpen(ctx, in[0], &c.opt, e.from, e.to, e.steps, &out, &r);
        cli_progress_done();
    }
    limn_mesh_comparison cmp = {.size = sizeof cmp};
    if (!st && limn_mesh_compare(ctx, in[0], out, &cmp) == LIMN_OK)
        e.mean_displacement = cmp.mean_distance / (r.bbox_diagonal > 0 ? r.bbox_diagonal : 1.0);
    series_extra x = {json_extra, print_extra, &e};
    rc = series_cli_finish(&c, ctx, st, out, &r, &s, &x);
    limn_mesh_destroy(in[0]);
    limn_mesh_destroy(out);
    limn_context_destroy(ctx);
    return rc;
}
