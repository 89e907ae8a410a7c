/* SPDX-License-Identifier: MIT */
/* limn denoise: seed 000 eq. 8, with the volume change reported; or with
   --preserve-features limn_denoise_features (docs/series.md). */
#include "cli_series.h"

#include <limits.h>
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
    "  --preserve-features    keep sharp edges: filter the face normals with a\n"
    "                         bilateral face operator rebuilt from the current\n"
    "                         normals before each product, then fit the vertices\n"
    "                         to them (Zheng et al. 2011, Sun et al. 2007, with a\n"
    "                         tangential pull); for CAD-like meshes. Takes:\n"
    "    --normal-steps T     face-operator products a round, T >= 1      [10]\n"
    "    --vertex-steps V     vertex-fit sweeps a round, V >= 1           [10]\n"
    "    --outer-steps K      rounds of filter-then-fit, K >= 1            [2]\n"
    "    --sigma-r R          normal range kernel width, R > 0          [0.35]\n"
    "    --tangential U       tangential pull in [0, 1]                 [0.25]\n"
    "                         (not with --m or --steps; --keep-volume works too)\n"
    SERIES_HELP
    "  --format F / --input-format F / --overwrite-input / -q\n"
    CLI_MPI_HELP
    SERIES_HELP_EXIT;

typedef struct extra {
    int m, steps, keep_volume;
    int preserve, feature_given, series_given; /* --preserve-features; its options; --m etc. */
    limn_feature_options fo;
    cli_series_measures v;    /* volumes and areas (on slices: cli_mpi_series_sliced's) */
    double mean_displacement;
} extra;

static void json_extra(json_out *j, void *user)
{
    extra *e = user;
    json_bool(j, "preserve_features", e->preserve);
    if (e->preserve) {
        json_integer(j, "normal_steps", e->fo.normal_steps);
        json_integer(j, "vertex_steps", e->fo.vertex_steps);
        json_integer(j, "outer_steps", e->fo.outer_steps);
        json_number(j, "sigma_r", e->fo.sigma_r);
        json_number(j, "tangential", e->fo.tangential);
    } else {
        json_integer(j, "m", e->m);
        json_integer(j, "steps", e->steps);
    }
    json_bool(j, "keep_volume", e->keep_volume);
    const cli_series_measures *v = &e->v;
    if (v->measured) { /* on success always: on slices too */
        json_bool(j, "closed", v->closed);
        json_number(j, "volume_input", v->closed ? v->volume_in : NAN);
        json_number(j, "volume_output", v->closed ? v->volume_out : NAN);
        json_number(j, "volume_change",
                    v->closed ? (v->volume_out - v->volume_in) / v->volume_in : NAN);
        if (!v->closed)
            json_string(j, "volume_note", "not defined: the mesh is not closed");
        json_number(j, "area_input", v->area_in);
        json_number(j, "area_output", v->area_out);
    }
    json_number(j, "mean_rel_displacement", e->mean_displacement);
}

static void print_extra(void *user)
{
    extra *e = user;
    const cli_series_measures *v = &e->v;
    if (e->preserve)
        fprintf(stderr,
                "  features kept: %d x (%d normal products, %d vertex sweeps), sigma_r %g, "
                "mean displacement %.3g of the bbox diagonal\n",
                e->fo.outer_steps, e->fo.normal_steps, e->fo.vertex_steps, e->fo.sigma_r,
                e->mean_displacement);
    else
        fprintf(stderr, "  m %d, %d steps%s, mean displacement %.3g of the bbox diagonal\n",
                e->m, e->steps, e->keep_volume ? ", volume kept" : "", e->mean_displacement);
    if (v->closed)
        fprintf(stderr, "  volume %.6g -> %.6g (%+.3f%%), area %.6g -> %.6g\n", v->volume_in,
                v->volume_out, 100.0 * (v->volume_out - v->volume_in) / v->volume_in, v->area_in,
                v->area_out);
    else
        fprintf(stderr, "  volume not defined (the mesh is not closed); area %.6g -> %.6g\n",
                v->area_in, v->area_out);
}

static int own_option(cli_args *a, void *user, int argc, char **argv, int *i)
{
    extra *e = user;
    const cli_own_option own[] = {
        {"--keep-volume", CLI_OWN_FLAG, &e->keep_volume, 1, 0},
        {"--m", CLI_OWN_INT, &e->m, 0, INT_MAX},
        {"--steps", CLI_OWN_INT, &e->steps, 1, INT_MAX},
    };
    const cli_own_option feature[] = {
        {"--preserve-features", CLI_OWN_FLAG, &e->preserve, 1, 0},
        {"--normal-steps", CLI_OWN_INT, &e->fo.normal_steps, 1, INT_MAX},
        {"--vertex-steps", CLI_OWN_INT, &e->fo.vertex_steps, 1, INT_MAX},
        {"--outer-steps", CLI_OWN_INT, &e->fo.outer_steps, 1, INT_MAX},
        {"--sigma-r", CLI_OWN_POSITIVE, &e->fo.sigma_r, 0, 0},
        {"--tangential", CLI_OWN_NUMBER, &e->fo.tangential, 0, 0},
    };
    int volume = strcmp(argv[*i], "--keep-volume") == 0;
    int rc = cli_args_own(a, argc, argv, i, own, sizeof own / sizeof *own);
    if (rc != CLI_OWN_UNKNOWN) {
        e->series_given |= !volume;
        return rc;
    }
    int flag = strcmp(argv[*i], "--preserve-features") == 0;
    rc = cli_args_own(a, argc, argv, i, feature, sizeof feature / sizeof *feature);
    if (rc != CLI_OWN_UNKNOWN && !flag)
        e->feature_given = 1;
    return rc;
}

/* --preserve-features and the options of the other filter exclude each other. */
static int check_mode(const extra *e)
{
    if (e->preserve && e->series_given)
        return cli_usage_error("denoise", "--preserve-features takes neither --m nor --steps");
    if (!e->preserve && e->feature_given)
        return cli_usage_error("denoise", "--normal-steps, --vertex-steps, --outer-steps, "
                                          "--sigma-r and --tangential need --preserve-features");
    if (e->preserve && cli_mpi_ranks() > 1)
        return cli_usage_error("denoise", "--preserve-features does not run on several MPI "
                                          "ranks yet (run it on one process)");
    if (e->preserve && !(e->fo.tangential >= 0.0 && e->fo.tangential <= 1.0))
        return cli_usage_error("denoise", "--tangential %g must lie in [0, 1]", e->fo.tangential);
    return 0;
}

static limn_status run(series_cli *c, limn_context *ctx, const limn_mesh *in, limn_mesh **out,
                       limn_series_report *r, void *user)
{
    extra *e = user;
    if (e->preserve) {
        e->fo.keep_volume = e->keep_volume;
        return limn_denoise_features(ctx, in, &e->fo, out, r);
    }
    if (cli_mpi_ranks() > 1)
        return cli_mpi_denoise(ctx, in, &c->opt, e->m, e->steps, e->keep_volume, out, r,
                               &c->piece);
    return limn_denoise(ctx, in, &c->opt, e->m, e->steps, e->keep_volume, out, r);
}

/* The volume and area before and after, and the displacement. */
static limn_status measure(limn_context *ctx, const limn_mesh *in, const limn_mesh *out,
                           const limn_series_report *r, void *user)
{
    extra *e = user;
    limn_mesh_measures a = {.size = sizeof a};
    limn_status st = limn_mesh_measure(ctx, in, &a);
    if (st)
        return st;
    e->v.measured = 1;
    e->v.closed = a.closed;
    e->v.volume_in = a.volume;
    e->v.area_in = a.area;
    limn_mesh_volume_area(out, &e->v.volume_out, &e->v.area_out); /* same topology as the input */
    (void)r; /* the displacement: series_cli_filter's (f.displacement) */
    return LIMN_OK;
}

int cli_denoise(int argc, char **argv)
{
    series_cli c;
    series_cli_init(&c, "denoise", help, 1);
    extra e = {.m = 2, .steps = 3};
    limn_feature_options_default(&e.fo);
    static const struct option longopts[] = {
        CLI_ARGS_OPTIONS,          CLI_FLAG("per-rank-output"), CLI_FLAG("keep-volume"),
        CLI_VALUE("m"),            CLI_VALUE("steps"),          CLI_FLAG("preserve-features"),
        CLI_VALUE("normal-steps"), CLI_VALUE("vertex-steps"),   CLI_VALUE("outer-steps"),
        CLI_VALUE("sigma-r"),      CLI_VALUE("tangential"),     CLI_OPTIONS_END};
    int rc = cli_args_parse(&c.a, longopts, argc, argv, own_option, &e);
    if (rc)
        return rc < 0 ? 0 : rc;
    rc = cli_mpi_root_rc(check_mode(&e));
    if (rc)
        return rc;
    rc = cli_mpi_root_rc(series_cli_check(&c, 1));
    if (rc)
        return rc;
    /* on slices the volumes are limn_mpi_mesh_measure's (cli_mpi_series_sliced) */
    cli_series_call call = {.kind = CLI_SERIES_DENOISE, .m = e.m, .steps = e.steps,
                            .keep_volume = e.keep_volume, .measures = &e.v};
    series_filter f = {run,  measure, &e.mean_displacement, {json_extra, print_extra, &e},
                       &call};
    return series_cli_filter(&c, &f);
}
