/* SPDX-License-Identifier: MIT */
/* limn smooth: the partial sum of the first N bands of the series. */
#include "cli_series.h"

#include <limits.h>
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
    SERIES_HELP
    "  --format F / --input-format F / --overwrite-input / -q\n"
    CLI_MPI_HELP
    SERIES_HELP_EXIT;

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

static int own_option(cli_args *a, void *user, int argc, char **argv, int *i)
{
    extra *e = user;
    const cli_own_option terms = {"--terms", CLI_OWN_INT, &e->terms, 1, INT_MAX};
    return cli_args_own(a, argc, argv, i, &terms, 1);
}

static limn_status run(series_cli *c, limn_context *ctx, const limn_mesh *in, limn_mesh **out,
                       limn_series_report *r, void *user)
{
    extra *e = user;
    if (cli_mpi_ranks() > 1)
        return cli_mpi_smooth(ctx, in, &c->opt, e->terms, out, r, &c->piece);
    return limn_smooth(ctx, in, &c->opt, e->terms, out, r);
}

int cli_smooth(int argc, char **argv)
{
    series_cli c;
    series_cli_init(&c, "smooth", help, 1);
    extra e = {.terms = 0};
    static const struct option longopts[] = {
        CLI_ARGS_OPTIONS, CLI_FLAG("per-rank-output"), CLI_VALUE("terms"), CLI_OPTIONS_END};
    int rc = cli_args_parse(&c.a, longopts, argc, argv, own_option, &e);
    if (rc)
        return rc < 0 ? 0 : rc;
    if (e.terms == 0)
        return cli_usage_error(c.a.cmd, "--terms N is required");
    rc = cli_mpi_root_rc(series_cli_check(&c, 1));
    if (rc)
        return rc;
    cli_series_call call = {.kind = CLI_SERIES_SMOOTH, .terms = e.terms};
    series_filter f = {run, NULL, &e.mean_displacement, {json_extra, print_extra, &e}, &call};
    return series_cli_filter(&c, &f);
}
