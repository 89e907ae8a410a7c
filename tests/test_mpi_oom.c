/* SPDX-License-Identifier: MIT */
/*
 * Memory running out on one rank reaches every rank, with one message, and
 * no rank waits for ever in a collective the failing one never enters
 * (issue 14: "a failure on any rank reaches every rank"). The library's
 * allocations are wrapped at link time (alloc_fail.h: limn is a static
 * library, so its own calls go through the wrappers; PoCL's and MPI's do
 * not): the k-th allocation of one rank fails. Each distributed call below
 * (read and repair, interpolate with the default, sgs and float solves,
 * measure, smooth, sharpen, bands, the default denoise, the
 * feature-preserving one, subdivide with the limit, texture, morph, the
 * MPI-IO write, the split write and read) runs once with nothing failing,
 * counting the allocations of the failing rank (on 2 ranks the last, then
 * rank 0; on more a middle one), then once for every k up to that count.
 * Each run must end alike on every rank: LIMN_ERR_MEMORY with the failing
 * rank's message and no mesh (a write: no file; a split write: no part on
 * any rank), or, where the library works around the failure (a bitmap's
 * fallback to a sort), the bits of the run with nothing failing; and a
 * last run must work as the first. On 2 ranks, then all again with the
 * victim's OpenCL calls failing in turn (cl_fail.h; LIMN_ERR_DEVICE, or
 * _MEMORY). A rank left waiting shows as ctest's
 * timeout. `test_mpi_oom NAME` sweeps only the calls whose name contains
 * NAME (LIMN_OOM_TRACE=1: each run said on stderr).
 */
#include "alloc_fail.h"
#include "cl_fail.h"
#include "mpi_check.h"
#include "mpi_meshes.h"
#include "noise.h"
#include "support.h"

#include "limn_mpi.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

MPI_CHECK_STATE;
static char dir[256];

/* What a call works on: the slices of the input (read and repaired), the
   input's path, the output path of the write, the split files' name. */
typedef struct work {
    const limn_mpi_mesh *mesh;
    const char *in, *out, *split;
} work;

/* A call under test: its status, *out the distributed mesh it makes (NULL
   for none), *value a number it reports (NaN for none). */
typedef limn_status (*call_fn)(limn_context *ctx, const work *w, limn_mpi_mesh **out,
                               double *value);

static limn_status call_read(limn_context *ctx, const work *w, limn_mpi_mesh **out,
                             double *value)
{
    *value = NAN;
    limn_status st = limn_mpi_mesh_read(ctx, MPI_COMM_WORLD, w->in, LIMN_FORMAT_AUTO, out);
    if (!st && (st = limn_mpi_mesh_repair(ctx, *out, NULL, NULL))) {
        limn_mpi_mesh_destroy(*out);
        *out = NULL;
    }
    return st;
}

/* limn_mpi_mesh_interpolate with a method and a precision; the iterations. */
static limn_status interpolate_with(limn_context *ctx, const work *w, limn_method method,
                                    limn_precision precision, limn_mpi_mesh **out, double *value)
{
    limn_interpolate_options o;
    limn_interpolate_options_default(&o);
    o.scheme = LIMN_SCHEME_LOOP;
    o.method = method;
    o.precision = precision;
    limn_report r;
    memset(&r, 0, sizeof r);
    r.size = sizeof r;
    limn_status st = limn_mpi_mesh_interpolate(ctx, w->mesh, &o, out, &r, NULL, NULL);
    *value = (double)r.iterations;
    return st;
}

static limn_status call_interpolate(limn_context *ctx, const work *w, limn_mpi_mesh **out,
                                    double *value)
{
    return interpolate_with(ctx, w, LIMN_METHOD_AUTO, LIMN_PRECISION_DOUBLE, out, value);
}

static limn_status call_sgs(limn_context *ctx, const work *w, limn_mpi_mesh **out,
                            double *value)
{
    return interpolate_with(ctx, w, LIMN_METHOD_SGS, LIMN_PRECISION_DOUBLE, out, value);
}

static limn_status call_float(limn_context *ctx, const work *w, limn_mpi_mesh **out,
                              double *value)
{
    return interpolate_with(ctx, w, LIMN_METHOD_CHEBYSHEV, LIMN_PRECISION_FLOAT, out, value);
}

static limn_status call_smooth(limn_context *ctx, const work *w, limn_mpi_mesh **out,
                               double *value)
{
    limn_series_options o;
    limn_series_options_default(&o);
    o.scheme = LIMN_SCHEME_LOOP;
    *value = NAN;
    return limn_mpi_mesh_smooth(ctx, w->mesh, &o, 3, out, NULL, NULL, NULL);
}

/* Two bands and the remainder (the first band's positions compared). */
static limn_status call_bands(limn_context *ctx, const work *w, limn_mpi_mesh **out,
                              double *value)
{
    limn_series_options o;
    limn_series_options_default(&o);
    o.scheme = LIMN_SCHEME_LOOP;
    limn_mpi_mesh *b[3] = {NULL, NULL, NULL};
    double energy[3] = {0, 0, 0};
    limn_status st = limn_mpi_mesh_bands(ctx, w->mesh, &o, 2, b, energy, NULL, NULL, NULL);
    *value = energy[0] + energy[1] + energy[2];
    *out = b[0];
    limn_mpi_mesh_destroy(b[1]);
    limn_mpi_mesh_destroy(b[2]);
    return st;
}

static limn_status call_sharpen(limn_context *ctx, const work *w, limn_mpi_mesh **out,
                                double *value)
{
    limn_series_options o;
    limn_series_options_default(&o);
    o.scheme = LIMN_SCHEME_LOOP;
    *value = NAN;
    return limn_mpi_mesh_sharpen(ctx, w->mesh, &o, 1, 2, 2, out, NULL, NULL, NULL);
}

static limn_status call_measure(limn_context *ctx, const work *w, limn_mpi_mesh **out,
                                double *value)
{
    limn_mesh_measures m;
    memset(&m, 0, sizeof m);
    m.size = sizeof m;
    *out = NULL;
    limn_status st = limn_mpi_mesh_measure(ctx, w->mesh, &m);
    *value = st ? NAN : m.volume;
    return st;
}

/* The frames' volumes, summed (the last frame's distance added). */
static limn_status sum_frames(void *user, const limn_mpi_mesh *frame,
                              const limn_morph_frame *measures)
{
    (void)frame;
    *(double *)user += measures->volume + measures->mean_distance_to_target;
    return LIMN_OK;
}

/* From the mesh to its smoothing (made in the call: its allocations are
   swept too). */
static limn_status call_morph(limn_context *ctx, const work *w, limn_mpi_mesh **out,
                              double *value)
{
    limn_series_options so;
    limn_series_options_default(&so);
    so.scheme = LIMN_SCHEME_LOOP;
    limn_morph_options o;
    limn_morph_options_default(&o);
    o.series.scheme = LIMN_SCHEME_LOOP;
    o.frames = 3;
    limn_mpi_mesh *to = NULL;
    *out = NULL;
    *value = 0.0;
    limn_status st = limn_mpi_mesh_smooth(ctx, w->mesh, &so, 2, &to, NULL, NULL, NULL);
    if (!st)
        st = limn_mpi_mesh_morph(ctx, w->mesh, to, &o, sum_frames, value, NULL, NULL, NULL);
    limn_mpi_mesh_destroy(to);
    return st;
}

/* The split files written (refused: none left), then read back (their
   positions compared). */
static limn_status call_split(limn_context *ctx, const work *w, limn_mpi_mesh **out,
                              double *value)
{
    *value = NAN;
    limn_status st = limn_mpi_mesh_write_split(ctx, w->mesh, w->split);
    char mine[340];
    snprintf(mine, sizeof mine, "%s.r%d.ply", w->split, rank);
    struct stat sb;
    CHECK(!st || stat(mine, &sb) != 0, "a refused split write left %s", mine);
    if (!st)
        st = limn_mpi_mesh_read_split(ctx, MPI_COMM_WORLD, w->split, out);
    MPI_Barrier(MPI_COMM_WORLD);
    unlink(mine);
    return st;
}

static limn_status call_texture(limn_context *ctx, const work *w, limn_mpi_mesh **out,
                                double *value)
{
    static const uint8_t colors[] = {200, 40, 40, 40, 200, 40, 40, 40, 200};
    limn_texture_options o;
    limn_texture_options_default(&o);
    o.series.scheme = LIMN_SCHEME_LOOP;
    o.levels = 1;
    o.colors = colors;
    o.color_count = 3;
    *value = NAN;
    return limn_mpi_mesh_texture(ctx, w->mesh, &o, out, NULL, NULL, NULL);
}

static limn_status call_denoise_sure(limn_context *ctx, const work *w, limn_mpi_mesh **out,
                                     double *value)
{
    limn_series_options o;
    limn_series_options_default(&o);
    o.scheme = LIMN_SCHEME_LOOP;
    return limn_mpi_mesh_denoise_sure(ctx, w->mesh, &o, 12, 1, out, value, NULL, NULL, NULL);
}

static limn_status call_features(limn_context *ctx, const work *w, limn_mpi_mesh **out,
                                 double *value)
{
    limn_feature_options o;
    limn_feature_options_default(&o);
    *value = NAN;
    return limn_mpi_mesh_denoise_features(ctx, w->mesh, &o, out, NULL, NULL, NULL);
}

static limn_status call_subdivide(limn_context *ctx, const work *w, limn_mpi_mesh **out,
                                  double *value)
{
    limn_subdivide_options o;
    limn_subdivide_options_default(&o);
    o.scheme = LIMN_SCHEME_LOOP;
    o.levels = 1;
    o.limit = 1;
    *value = NAN;
    return limn_mpi_mesh_subdivide(ctx, w->mesh, &o, out, NULL, NULL, NULL);
}

/* The write: the file whole (its size the value) or, refused, not there. */
static limn_status call_write(limn_context *ctx, const work *w, limn_mpi_mesh **out,
                              double *value)
{
    *out = NULL;
    limn_status st = limn_mpi_mesh_write(ctx, w->mesh, w->out, LIMN_FORMAT_AUTO, NULL, NULL);
    MPI_Barrier(MPI_COMM_WORLD);
    struct stat sb;
    int there = stat(w->out, &sb) == 0;
    *value = there ? (double)sb.st_size : -1.0;
    CHECK(!st || !there, "a refused write left %s", w->out);
    MPI_Barrier(MPI_COMM_WORLD);
    if (rank == 0)
        unlink(w->out);
    return st;
}

/* The reference: the call with nothing failing (its value, the block's
   positions and the victim's allocation count). */
typedef struct reference {
    double value, *pos;
    size_t n;
    long allocations;
} reference;

/* The block's positions of out (NULL: none) as the reference has them. */
static int same_as(const reference *ref, const limn_mpi_mesh *out, double value)
{
    size_t n = out ? 3 * limn_mpi_mesh_vertex_count(out) : 0;
    return memcmp(&value, &ref->value, sizeof value) == 0 && n == ref->n &&
           (!n || memcmp(limn_mpi_mesh_positions(out), ref->pos, n * sizeof *ref->pos) == 0);
}

/* What fails: an allocation, or an OpenCL call (cl_fail.h). */
static int failing_cl;

/* One run of call with the k-th allocation of rank `victim` failing (k <= 0:
   none): the same outcome on every rank, a refusal with the victim's
   message and no mesh, or (a failure the library worked around) the
   reference's bits. 1 when the call succeeded. */
static int run_once(limn_context *ctx, const char *name, call_fn call, const work *w,
                    int victim, long k, reference *ref)
{
    limn_mpi_mesh *f = NULL;
    double value = NAN;
    if (getenv("LIMN_OOM_TRACE"))
        fprintf(stderr, "rank %d: %s, allocation %ld of rank %d failing\n", rank, name, k,
                victim);
    if (failing_cl)
        cl_fail_arm(rank == victim ? k : 0);
    else
        alloc_fail_arm(rank == victim ? k : 0);
    limn_status st = call(ctx, w, &f, &value);
    long seen = failing_cl ? cl_fail_disarm() : alloc_fail_disarm();
    int mine = st == LIMN_OK, all_ok = 0, any_ok = 0;
    MPI_Allreduce(&mine, &all_ok, 1, MPI_INT, MPI_LAND, MPI_COMM_WORLD);
    MPI_Allreduce(&mine, &any_ok, 1, MPI_INT, MPI_LOR, MPI_COMM_WORLD);
    CHECK(all_ok == any_ok, "%s, allocation %ld failing on rank %d: rank %d got %d '%s'", name,
          k, victim, rank, (int)st, limn_context_message(ctx));
    if (!st && k == 0) {
        MPI_Bcast(&seen, 1, MPI_LONG, victim, MPI_COMM_WORLD);
        ref->value = value;
        ref->allocations = seen;
        ref->n = f ? 3 * limn_mpi_mesh_vertex_count(f) : 0;
        ref->pos = malloc((ref->n + 1) * sizeof *ref->pos);
        if (ref->pos && ref->n)
            memcpy(ref->pos, limn_mpi_mesh_positions(f), ref->n * sizeof *ref->pos);
    } else if (!st) {
        CHECK(ref->pos && same_as(ref, f, value),
              "%s, allocation %ld failing on rank %d: a result other than the reference's",
              name, k, victim);
    } else {
        CHECK(f == NULL, "%s, allocation %ld failing on rank %d: a refused call made a mesh",
              name, k, victim);
        /* every rank the same status and message: the victim's */
        char msg[512] = {0}, theirs[512];
        snprintf(msg, sizeof msg, "%s", limn_context_message(ctx));
        memcpy(theirs, msg, sizeof msg);
        MPI_Bcast(theirs, (int)sizeof theirs, MPI_CHAR, victim, MPI_COMM_WORLD);
        int expected = failing_cl ? st == LIMN_ERR_DEVICE || st == LIMN_ERR_MEMORY
                                  : st == LIMN_ERR_MEMORY;
        CHECK(expected && strcmp(msg, theirs) == 0,
              "%s, allocation %ld failing on rank %d: rank %d got %d '%s', rank %d '%s'", name,
              k, victim, rank, (int)st, msg, victim, theirs);
    }
    limn_mpi_mesh_destroy(f);
    return all_ok;
}

/* Every allocation of rank victim's call failing in turn, then none again. */
static void sweep(limn_context *ctx, const char *name, call_fn call, const work *w, int victim)
{
    reference ref = {0};
    int ok = run_once(ctx, name, call, w, victim, 0, &ref);
    CHECK(ok, "%s with nothing failing: %s", name, limn_context_message(ctx));
    long refused = 0;
    for (long k = 1; ok && k <= ref.allocations; k++)
        refused += !run_once(ctx, name, call, w, victim, k, &ref);
    /* and nothing was left in a state that spoils the next call */
    CHECK(!ok || run_once(ctx, name, call, w, victim, -1, &ref),
          "%s: the call after the sweep failed", name);
    if (rank == 0 && ref.allocations)
        printf("  %-21s rank %d's %4ld %s failing in turn: %4ld refused alike on every "
               "rank, %ld worked around\n",
               name, victim, ref.allocations, failing_cl ? "OpenCL calls" : "allocations",
               refused, ref.allocations - refused);
    free(ref.pos);
}

int main(int argc, char **argv)
{
    MPI_Init(&argc, &argv);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    mpi_test_scratch_dir(dir, sizeof dir, "test_mpi_oom");
    limn_context *ctx = limn_context_create();
    char in[320];
    snprintf(in, sizeof in, "%s/in.ply", dir);
    int ok = 1;
    if (rank == 0) {
        limn_mesh *mesh = mpi_test_closed(ctx, 1);
        ok = mesh != NULL;
        if (ok) {
            test_gaussian_noise(mesh, 0.3 * test_mean_edge(mesh), 16);
            ok = limn_mesh_write(ctx, mesh, in, LIMN_FORMAT_AUTO) == LIMN_OK;
        }
        CHECK(ok, "writing %s: %s", in, limn_context_message(ctx));
        limn_mesh_destroy(mesh);
    }
    MPI_Bcast(&ok, 1, MPI_INT, 0, MPI_COMM_WORLD);
    limn_mpi_mesh *m = NULL;
    limn_status st = ok ? limn_mpi_mesh_read(ctx, MPI_COMM_WORLD, in, LIMN_FORMAT_AUTO, &m)
                        : LIMN_ERR_IO;
    if (!st)
        st = limn_mpi_mesh_repair(ctx, m, NULL, NULL);
    CHECK(!ok || st == LIMN_OK, "reading slices: %s", limn_context_message(ctx));
    char out[320];
    snprintf(out, sizeof out, "%s/out.ply", dir);
    char split[320];
    snprintf(split, sizeof split, "%s/split", dir);
    work w = {m, in, out, split};
    static const struct {
        const char *name;
        call_fn call;
    } calls[] = {{"read + repair", call_read},
                 {"interpolate", call_interpolate},
                 {"interpolate sgs", call_sgs},
                 {"interpolate float", call_float},
                 {"measure", call_measure},
                 {"smooth", call_smooth},
                 {"sharpen", call_sharpen},
                 {"bands", call_bands},
                 {"denoise (default)", call_denoise_sure},
                 {"denoise features", call_features},
                 {"subdivide --limit", call_subdivide},
                 {"texture", call_texture},
                 {"morph", call_morph},
                 {"split write + read", call_split},
                 {"write", call_write}};
    /* allocations, then (on 2 ranks: the device layer's paths are the same on
       more, and the sweeps' time counts under the sanitizers) OpenCL calls */
    for (failing_cl = 0; failing_cl < (size == 2 ? 2 : 1); failing_cl++)
        for (size_t c = 0; !st && c < sizeof calls / sizeof *calls; c++) {
            if (argc > 1 && !strstr(calls[c].name, argv[1]))
                continue; /* one call by name, when debugging */
            /* 2 ranks: the last, then the first; more: a middle one (both neighbours) */
            sweep(ctx, calls[c].name, calls[c].call, &w, size == 2 ? 1 : size / 2);
            if (size == 2)
                sweep(ctx, calls[c].name, calls[c].call, &w, 0);
        }
    limn_mpi_mesh_destroy(m);
    if (rank == 0)
        unlink(in);
    limn_context_destroy(ctx);
    return mpi_check_finish("test_mpi_oom", dir, checks, failures);
}
