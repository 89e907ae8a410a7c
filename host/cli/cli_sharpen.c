/* SPDX-License-Identifier: MIT */
/* limn sharpen: T_{k+1} = T_k + sum_{i=m..n} (E - A)^i T_k (seed 000 §6). */
#include "cli_series.h"

#include <limits.h>
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
    SERIES_HELP
    "  --format F / --input-format F / --overwrite-input / -q\n"
    CLI_MPI_HELP
    SERIES_HELP_EXIT;

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

static int own_option(cli_args *a, void *user, int argc, char **argv, int *i)
{
    extra *e = user;
    const cli_own_option own[] = {
        {"--from", CLI_OWN_INT, &e->from, 0, INT_MAX},
        {"--to", CLI_OWN_INT, &e->to, 0, INT_MAX},
        {"--steps", CLI_OWN_INT, &e->steps, 1, INT_MAX},
    };
    return cli_args_own(a, argc, argv, i, own, sizeof own / sizeof *own);
}

static limn_status run(series_cli *c, limn_context *ctx, const limn_mesh *in, limn_mesh **out,
                       limn_series_report *r, void *user)
{
    extra *e = user;
    if (e->from == 0 && !c->a.quiet)
        fprintf(stderr, "limn sharpen: warning: --from 0 adds the mesh itself: it is scaled "
                        "by 2 about the origin\n");
    if (cli_mpi_ranks() > 1)
        return cli_mpi_sharpen(ctx, in, &c->opt, e->from, e->to, e->steps, out, r, &c->piece);
    return limn_sharpen(ctx, in, &c->opt, e->from, e->to, e->steps, out, r);
}

int cli_sharpen(int argc, char **argv)
{
    series_cli c;
    series_cli_init(&c, "sharpen", help, 1);
    extra e = {.from = -1, .to = -1, .steps = 1};
    static const struct option longopts[] = {
        CLI_ARGS_OPTIONS,   CLI_FLAG("per-rank-output"), CLI_VALUE("from"), CLI_VALUE("to"),
        CLI_VALUE("steps"), CLI_OPTIONS_END};
    int rc = cli_args_parse(&c.a, longopts, argc, argv, own_option, &e);
    if (rc)
        return rc < 0 ? 0 : rc;
    if (e.from < 0 || e.to < 0)
        return cli_usage_error(c.a.cmd, "--from M and --to N are required");
    if (e.to < e.from)
        return cli_usage_error(c.a.cmd, "--to %d is below --from %d", e.to, e.from);
    rc = cli_mpi_root_rc(series_cli_check(&c, 1));
    if (rc)
        return rc;
    cli_series_call call = {
        .kind = CLI_SERIES_SHARPEN, .from = e.from, .to = e.to, .steps = e.steps};
    series_filter f = {run, NULL, &e.mean_displacement, {json_extra, print_extra, &e}, &call};
    return series_cli_filter(&c, &f);
}
