/* SPDX-License-Identifier: MIT */
/*
 * Memory running out anywhere in limn is a clear refusal, never a crash or
 * a half-made result, and loses nothing (README "Bad input gets a clear
 * error"). limn's allocations are wrapped at link time (alloc_fail.h): for
 * each public call below, one run with nothing failing counts its
 * allocations, then one run for every k up to that count has the k-th
 * fail. Each run must return LIMN_ERR_MEMORY with a message and no result,
 * or, where limn works around the failure (a fallback path), the bits of
 * the run with nothing failing; a write refused must leave the file it
 * would have replaced as it was and no temporary beside it; and a last run
 * must work as the first. Under the sanitizers (scripts/sanitize.sh) every
 * refusal is also checked for leaks and bad accesses. Calls: reading PLY,
 * OBJ and OFF, repair, info, measure, interpolate (default, cg, sgs,
 * float), subdivide with the limit, smooth, the paper's denoise, the
 * default one, the feature-preserving one, sharpen, bands, morph, texture,
 * the writes (PLY, OBJ) and an output set of two files; then reading,
 * info and interpolate on a mesh large enough for two host threads, and
 * the same with no host thread able to start (pthread_create failing: each
 * range runs on the caller), the same bits. The sweep is run twice: with
 * allocations failing, then with limn's OpenCL calls failing (cl_fail.h:
 * LIMN_ERR_DEVICE, or LIMN_ERR_MEMORY, with a message expected).
 * `test_oom NAME` sweeps only the calls whose name contains NAME.
 */
#include "alloc_fail.h"
#include "cl_fail.h"
#include "noise.h"
#include "support.h"

#include "limn.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static int checks, failures;

#define CHECK(cond, ...)                                                                       \
    do {                                                                                       \
        checks++;                                                                              \
        if (!(cond)) {                                                                         \
            failures++;                                                                        \
            fprintf(stderr, "FAIL (%s:%d): ", __FILE__, __LINE__);                             \
            fprintf(stderr, __VA_ARGS__);                                                      \
            fprintf(stderr, "\n");                                                             \
        }                                                                                      \
    } while (0)

/* What a call works on: a noisy closed triangle mesh (repaired), its files
   in three formats, the scratch directory and a file that a write replaces. */
typedef struct work {
    const limn_mesh *mesh;
    char dir[256], ply[320], obj[320], off[320], target[320], second[320];
    double *bands; /* room for limn_bands' three vectors (made before any sweep) */
} work;

/* A call: its status, *out the mesh it makes (NULL: none), *value a number
   it reports (NaN: none). */
typedef limn_status (*call_fn)(limn_context *ctx, const work *w, limn_mesh **out,
                               double *value);

static limn_status read_as(limn_context *ctx, const char *path, limn_mesh **out, double *value)
{
    *value = NAN;
    return limn_mesh_read(ctx, path, LIMN_FORMAT_AUTO, out);
}

static limn_status call_read_ply(limn_context *ctx, const work *w, limn_mesh **out, double *v)
{
    return read_as(ctx, w->ply, out, v);
}

static limn_status call_read_obj(limn_context *ctx, const work *w, limn_mesh **out, double *v)
{
    return read_as(ctx, w->obj, out, v);
}

static limn_status call_read_off(limn_context *ctx, const work *w, limn_mesh **out, double *v)
{
    return read_as(ctx, w->off, out, v);
}

/* A copy repaired (its vertex count the value). */
static limn_status call_repair(limn_context *ctx, const work *w, limn_mesh **out, double *value)
{
    limn_repair_report r;
    memset(&r, 0, sizeof r);
    r.size = sizeof r;
    limn_status st = limn_mesh_copy(ctx, w->mesh, out);
    if (!st && (st = limn_mesh_repair(ctx, *out, NULL, &r))) {
        limn_mesh_destroy(*out);
        *out = NULL;
    }
    *value = st ? NAN : (double)limn_mesh_vertex_count(*out);
    return st;
}

static limn_status call_info(limn_context *ctx, const work *w, limn_mesh **out, double *value)
{
    limn_mesh_info info;
    memset(&info, 0, sizeof info);
    info.size = sizeof info;
    *out = NULL;
    limn_mesh *copy = NULL; /* without the topology the repair left on w->mesh */
    limn_status st = limn_mesh_copy(ctx, w->mesh, &copy);
    if (!st)
        st = limn_mesh_info_compute(ctx, copy, &info);
    limn_mesh_destroy(copy);
    *value = st ? NAN : (double)info.edges * 1e6 + (double)info.components;
    return st;
}

static limn_status call_measure(limn_context *ctx, const work *w, limn_mesh **out,
                                double *value)
{
    limn_mesh_measures m;
    memset(&m, 0, sizeof m);
    m.size = sizeof m;
    *out = NULL;
    limn_mesh *copy = NULL;
    limn_status st = limn_mesh_copy(ctx, w->mesh, &copy);
    if (!st)
        st = limn_mesh_measure(ctx, copy, &m);
    limn_mesh_destroy(copy);
    *value = st ? NAN : m.volume;
    return st;
}

/* limn_interpolate with a method and a precision; the iterations. */
static limn_status interpolate_with(limn_context *ctx, const work *w, limn_method method,
                                    limn_precision precision, limn_mesh **out, double *value)
{
    limn_interpolate_options o;
    limn_interpolate_options_default(&o);
    o.method = method;
    o.precision = precision;
    limn_report r;
    memset(&r, 0, sizeof r);
    r.size = sizeof r;
    limn_status st = limn_interpolate(ctx, w->mesh, &o, out, &r);
    *value = (double)r.iterations;
    return st;
}

static limn_status call_interpolate(limn_context *ctx, const work *w, limn_mesh **out,
                                    double *v)
{
    return interpolate_with(ctx, w, LIMN_METHOD_AUTO, LIMN_PRECISION_DOUBLE, out, v);
}

static limn_status call_cg(limn_context *ctx, const work *w, limn_mesh **out, double *v)
{
    return interpolate_with(ctx, w, LIMN_METHOD_CG, LIMN_PRECISION_DOUBLE, out, v);
}

static limn_status call_sgs(limn_context *ctx, const work *w, limn_mesh **out, double *v)
{
    return interpolate_with(ctx, w, LIMN_METHOD_SGS, LIMN_PRECISION_DOUBLE, out, v);
}

static limn_status call_float(limn_context *ctx, const work *w, limn_mesh **out, double *v)
{
    return interpolate_with(ctx, w, LIMN_METHOD_CHEBYSHEV, LIMN_PRECISION_FLOAT, out, v);
}

static limn_status call_subdivide(limn_context *ctx, const work *w, limn_mesh **out,
                                  double *value)
{
    limn_subdivide_options o;
    limn_subdivide_options_default(&o);
    o.levels = 2;
    o.limit = 1;
    *value = NAN;
    return limn_subdivide(ctx, w->mesh, &o, out, NULL);
}

static void series_defaults(limn_series_options *o)
{
    limn_series_options_default(o);
}

static limn_status call_smooth(limn_context *ctx, const work *w, limn_mesh **out, double *v)
{
    limn_series_options o;
    series_defaults(&o);
    *v = NAN;
    return limn_smooth(ctx, w->mesh, &o, 3, out, NULL);
}

static limn_status call_denoise(limn_context *ctx, const work *w, limn_mesh **out, double *v)
{
    limn_series_options o;
    series_defaults(&o);
    *v = NAN;
    return limn_denoise(ctx, w->mesh, &o, 2, 3, 1, out, NULL);
}

static limn_status call_denoise_sure(limn_context *ctx, const work *w, limn_mesh **out,
                                     double *v)
{
    limn_series_options o;
    series_defaults(&o);
    return limn_denoise_sure(ctx, w->mesh, &o, 12, 1, out, v, NULL);
}

static limn_status call_features(limn_context *ctx, const work *w, limn_mesh **out, double *v)
{
    limn_feature_options o;
    limn_feature_options_default(&o);
    *v = NAN;
    return limn_denoise_features(ctx, w->mesh, &o, out, NULL);
}

static limn_status call_sharpen(limn_context *ctx, const work *w, limn_mesh **out, double *v)
{
    limn_series_options o;
    series_defaults(&o);
    *v = NAN;
    return limn_sharpen(ctx, w->mesh, &o, 1, 2, 2, out, NULL);
}

/* Two bands and the remainder into the caller's array: their sum the value. */
static limn_status call_bands(limn_context *ctx, const work *w, limn_mesh **out, double *value)
{
    limn_series_options o;
    series_defaults(&o);
    size_t n = 3 * limn_mesh_vertex_count(w->mesh);
    double energy[3] = {0, 0, 0}, sum = 0.0;
    *out = NULL;
    limn_status st = limn_bands(ctx, w->mesh, &o, 2, w->bands, energy, NULL);
    for (size_t k = 0; !st && k < 3 * n; k++)
        sum += w->bands[k];
    *value = st ? NAN : sum + energy[0] + energy[1] + energy[2];
    return st;
}

/* The frames' volumes, summed. */
static limn_status sum_volumes(void *user, const limn_morph_frame *frame)
{
    *(double *)user += frame->volume;
    return LIMN_OK;
}

static limn_status call_morph(limn_context *ctx, const work *w, limn_mesh **out, double *value)
{
    limn_morph_options o;
    limn_morph_options_default(&o);
    o.frames = 4;
    limn_mesh *to = NULL;
    limn_status st = limn_mesh_copy(ctx, w->mesh, &to);
    if (!st) {
        test_perturb(to, 0.05, 3);
        *value = 0.0;
        st = limn_morph(ctx, w->mesh, to, &o, sum_volumes, value, NULL);
    }
    limn_mesh_destroy(to);
    *out = NULL;
    return st;
}

static limn_status call_texture(limn_context *ctx, const work *w, limn_mesh **out, double *v)
{
    static const uint8_t colors[] = {200, 40, 40, 40, 200, 40, 40, 40, 200};
    limn_texture_options o;
    limn_texture_options_default(&o);
    o.levels = 1;
    o.colors = colors;
    o.color_count = 3;
    *v = NAN;
    return limn_texture(ctx, w->mesh, &o, out, NULL);
}

/* The file's bytes (NULL when it cannot be read). */
static char *slurp_file(const char *path, long *len)
{
    FILE *f = fopen(path, "rb");
    char *b = NULL;
    *len = -1;
    if (f && fseek(f, 0, SEEK_END) == 0 && (*len = ftell(f)) >= 0 && fseek(f, 0, SEEK_SET) == 0 &&
        (b = malloc((size_t)*len + 1)) && fread(b, 1, (size_t)*len, f) != (size_t)*len) {
        free(b);
        b = NULL;
    }
    if (f)
        fclose(f);
    return b;
}

/* A write over an existing file: refused, the old bytes stay and nothing is
   left beside them; written, its size is the value. */
static limn_status write_over(limn_context *ctx, const work *w, const char *ext,
                              limn_mesh **out, double *value)
{
    char path[340];
    snprintf(path, sizeof path, "%s.%s", w->target, ext);
    static const char old[] = "the file a refused write must leave as it was\n";
    *out = NULL;
    *value = NAN;
    int before = test_dir_entries(w->dir);
    if (test_write_text(path, old) != 0)
        return LIMN_ERR_IO;
    limn_status st = limn_mesh_write(ctx, w->mesh, path, LIMN_FORMAT_AUTO);
    long len = 0;
    char *now = slurp_file(path, &len);
    if (st)
        CHECK(now && len == (long)strlen(old) && memcmp(now, old, (size_t)len) == 0 &&
                  test_dir_entries(w->dir) == before + 1,
              "a refused write of %s changed it or left a file beside it", path);
    else
        *value = (double)len;
    free(now);
    unlink(path);
    return st;
}

static limn_status call_write_ply(limn_context *ctx, const work *w, limn_mesh **out, double *v)
{
    return write_over(ctx, w, "ply", out, v);
}

static limn_status call_write_obj(limn_context *ctx, const work *w, limn_mesh **out, double *v)
{
    return write_over(ctx, w, "obj", out, v);
}

/* Two outputs staged and committed together: refused, neither is there. */
static limn_status call_output_set(limn_context *ctx, const work *w, limn_mesh **out,
                                   double *value)
{
    *out = NULL;
    *value = NAN;
    int before = test_dir_entries(w->dir);
    limn_output_set *set = NULL;
    limn_status st = limn_output_set_create(ctx, &set);
    if (!st)
        st = limn_output_set_add_mesh(ctx, set, w->mesh, w->target, LIMN_FORMAT_PLY);
    if (!st)
        st = limn_output_set_add_mesh(ctx, set, w->mesh, w->second, LIMN_FORMAT_OFF);
    if (!st)
        st = limn_output_set_commit(ctx, set);
    limn_output_set_destroy(set);
    int there = test_dir_entries(w->dir) - before;
    CHECK(st ? there == 0 : there == 2, "an output set %s left %d new files",
          st ? "refused" : "committed", there);
    if (!st)
        *value = (double)there;
    unlink(w->target);
    unlink(w->second);
    return st;
}

/* The reference: the call with nothing failing. */
typedef struct reference {
    double value, *pos;
    size_t n;
    long allocations;
} reference;

static int same_as(limn_context *ctx, const reference *ref, const limn_mesh *out, double value)
{
    size_t n = out ? 3 * limn_mesh_vertex_count(out) : 0;
    double *pos = n ? malloc(n * sizeof *pos) : NULL;
    int same = (memcmp(&value, &ref->value, sizeof value) == 0 || (isnan(value) && isnan(ref->value))) &&
               n == ref->n &&
               (!n || (pos && !limn_mesh_copy_positions(ctx, out, pos, n / 3) &&
                       memcmp(pos, ref->pos, n * sizeof *pos) == 0));
    free(pos);
    return same;
}

/* What fails: an allocation, or an OpenCL call (cl_fail.h). */
static int failing_cl;

/* One run with the k-th allocation (or OpenCL call) failing (k <= 0:
   none); 1 when it worked. */
static int run_once(limn_context *ctx, const char *name, call_fn call, const work *w, long k,
                    reference *ref)
{
    limn_mesh *f = NULL;
    double value = NAN;
    if (failing_cl)
        cl_fail_arm(k);
    else
        alloc_fail_arm(k);
    limn_status st = call(ctx, w, &f, &value);
    long seen = failing_cl ? cl_fail_disarm() : alloc_fail_disarm();
    if (!st && k == 0) {
        ref->value = value;
        ref->allocations = seen;
        ref->n = f ? 3 * limn_mesh_vertex_count(f) : 0;
        ref->pos = malloc((ref->n + 1) * sizeof *ref->pos);
        if (ref->pos && ref->n)
            limn_mesh_copy_positions(ctx, f, ref->pos, ref->n / 3);
    } else if (!st) {
        CHECK(ref->pos && same_as(ctx, ref, f, value),
              "%s, allocation %ld failing: a result other than the reference's", name, k);
    } else {
        const char *msg = limn_context_message(ctx);
        CHECK(f == NULL, "%s, allocation %ld failing: a refused call made a mesh", name, k);
        int expected = failing_cl ? st == LIMN_ERR_DEVICE || st == LIMN_ERR_MEMORY
                                  : st == LIMN_ERR_MEMORY;
        CHECK(expected && msg && *msg,
              "%s, %s %ld failing: status %d '%s' (LIMN_ERR_%s and a message expected)", name,
              failing_cl ? "OpenCL call" : "allocation", k, (int)st, msg ? msg : "(null)",
              failing_cl ? "DEVICE or _MEMORY" : "MEMORY");
    }
    limn_mesh_destroy(f);
    return st == LIMN_OK;
}

static void sweep(limn_context *ctx, const char *name, call_fn call, const work *w)
{
    reference ref = {0};
    int ok = run_once(ctx, name, call, w, 0, &ref);
    CHECK(ok, "%s with nothing failing: %s", name, limn_context_message(ctx));
    long refused = 0;
    for (long k = 1; ok && k <= ref.allocations; k++)
        refused += !run_once(ctx, name, call, w, k, &ref);
    CHECK(!ok || run_once(ctx, name, call, w, -1, &ref), "%s: the call after the sweep failed",
          name);
    if (ref.allocations)
        printf("  %-20s %5ld %s failing in turn: %4ld refused, %ld worked around\n", name,
               ref.allocations, failing_cl ? "OpenCL calls" : "allocations", refused,
               ref.allocations - refused);
    free(ref.pos);
}

/* call with every host thread failing to start (parallel_run then runs
   each range on the calling thread): the bits of a run where they start. */
static void no_threads(limn_context *ctx, const char *name, call_fn call, const work *w)
{
    reference ref = {0};
    int ok = run_once(ctx, name, call, w, 0, &ref);
    alloc_fail_threads(1);
    CHECK(ok && run_once(ctx, name, call, w, -1, &ref), "%s without threads: %s", name,
          limn_context_message(ctx));
    alloc_fail_threads(0);
    printf("  %-20s no host thread starting: the same bits\n", name);
    free(ref.pos);
}

int main(int argc, char **argv)
{
    work w;
    memset(&w, 0, sizeof w);
    snprintf(w.dir, sizeof w.dir, "%s/limn_test_oom_XXXXXX",
             getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp");
    if (!mkdtemp(w.dir)) {
        perror("mkdtemp");
        return 1;
    }
    snprintf(w.ply, sizeof w.ply, "%s/in.ply", w.dir);
    snprintf(w.obj, sizeof w.obj, "%s/in.obj", w.dir);
    snprintf(w.off, sizeof w.off, "%s/in.off", w.dir);
    snprintf(w.target, sizeof w.target, "%s/out.ply", w.dir);
    snprintf(w.second, sizeof w.second, "%s/second.off", w.dir);
    limn_context *ctx = limn_context_create();
    limn_mesh *mesh = test_mesh_icosahedron(ctx), *fine = NULL;
    limn_subdivide_options so;
    limn_subdivide_options_default(&so);
    so.levels = 2;
    int ok = mesh && !limn_subdivide(ctx, mesh, &so, &fine, NULL);
    if (ok) {
        test_gaussian_noise(fine, 0.3 * test_mean_edge(fine), 7);
        ok = !limn_mesh_repair(ctx, fine, NULL, NULL) &&
             !limn_mesh_write(ctx, fine, w.ply, LIMN_FORMAT_AUTO) &&
             !limn_mesh_write(ctx, fine, w.obj, LIMN_FORMAT_AUTO) &&
             !limn_mesh_write(ctx, fine, w.off, LIMN_FORMAT_AUTO);
    }
    CHECK(ok, "making the inputs: %s", limn_context_message(ctx));
    w.mesh = fine;
    w.bands = ok ? malloc(9 * limn_mesh_vertex_count(fine) * sizeof *w.bands) : NULL;
    ok = ok && w.bands;
    static const struct {
        const char *name;
        call_fn call;
    } calls[] = {{"read PLY", call_read_ply},     {"read OBJ", call_read_obj},
                 {"read OFF", call_read_off},     {"repair", call_repair},
                 {"info", call_info},             {"measure", call_measure},
                 {"interpolate", call_interpolate}, {"interpolate cg", call_cg},
                 {"interpolate sgs", call_sgs},   {"interpolate float", call_float},
                 {"subdivide --limit", call_subdivide}, {"smooth", call_smooth},
                 {"denoise paper", call_denoise}, {"denoise default", call_denoise_sure},
                 {"denoise features", call_features}, {"sharpen", call_sharpen},
                 {"bands", call_bands},           {"morph", call_morph},
                 {"texture", call_texture},       {"write PLY", call_write_ply},
                 {"write OBJ", call_write_obj},   {"output set", call_output_set}};
    for (failing_cl = 0; failing_cl < 2; failing_cl++)
        for (size_t c = 0; ok && c < sizeof calls / sizeof *calls; c++)
            if (argc < 2 || strstr(calls[c].name, argv[1]))
                sweep(ctx, calls[c].name, calls[c].call, &w);
    failing_cl = 0;
    /* a mesh large enough for the host threads (parallel_threads: 4 MiB of
       work a thread), two of them: an allocation failing inside a range */
    limn_mesh *large = NULL;
    so.levels = 5;
    ok = ok && !limn_context_set_host_threads(ctx, 2) &&
         !limn_subdivide(ctx, fine, &so, &large, NULL) &&
         !limn_mesh_write(ctx, large, w.ply, LIMN_FORMAT_AUTO) &&
         !limn_mesh_write(ctx, large, w.obj, LIMN_FORMAT_AUTO);
    CHECK(ok, "making the large inputs: %s", limn_context_message(ctx));
    static const struct {
        const char *name;
        call_fn call;
    } threaded[] = {{"read PLY, large", call_read_ply}, {"read OBJ, large", call_read_obj},
                    {"info, large", call_info}, {"interpolate, large", call_interpolate}};
    w.mesh = large;
    for (failing_cl = 0; failing_cl < 2; failing_cl++)
        for (size_t c = 0; ok && c < sizeof threaded / sizeof *threaded; c++)
            if (argc < 2 || strstr(threaded[c].name, argv[1]))
                sweep(ctx, threaded[c].name, threaded[c].call, &w);
    failing_cl = 0;
    /* no host thread starts: every range runs on the caller, the same bits */
    for (size_t c = 0; ok && c < sizeof threaded / sizeof *threaded; c++)
        if (argc < 2 || strstr(threaded[c].name, argv[1]))
            no_threads(ctx, threaded[c].name, threaded[c].call, &w);
    limn_mesh_destroy(large);
    free(w.bands);
    limn_mesh_destroy(mesh);
    limn_mesh_destroy(fine);
    limn_context_destroy(ctx);
    unlink(w.ply);
    unlink(w.obj);
    unlink(w.off);
    rmdir(w.dir);
    printf("test_oom: %d checks, %d failures\n", checks, failures);
    return failures != 0;
}
