/* SPDX-License-Identifier: MIT */
/*
 * The size fields of limn.h's options and report structs (abi.h, limn.h's
 * top comment): checked on entry, options copied in over the defaults,
 * reports copied out within the caller's size.
 */
#include "base/abi.h"

#include "base/context.h"

#include <stdint.h>
#include <stdio.h>
#include <string.h>

/* A size beyond this is no struct of limn's: an uninitialised field. */
#define ABI_MAX_SIZE ((size_t)1 << 16)

/* Bytes up to the end of a field: the first released layout ends at its
   last field (padding after it not required). */
#define ABI_END(type, field) (offsetof(type, field) + sizeof(((type *)0)->field))

#define ABI_FLAT(name, type, init, last, defaults)                                                 \
    const abi_layout name = {#type, init, sizeof(type), ABI_END(type, last), NULL, defaults}

/* The defaults of the options structs (limn.h states each), every byte
   else zero: limn_*_options_default() copies them, and so does abi_enter
   before it reads the caller's bytes over them. */
#define SERIES_DEFAULTS                                                                            \
    {                                                                                              \
        .size = sizeof(limn_series_options), .scheme = LIMN_SCHEME_AUTO, .alpha = 0.0              \
    }
static const limn_series_options series_defaults = SERIES_DEFAULTS;
static const limn_morph_options morph_defaults = {
    .size = sizeof(limn_morph_options), .series = SERIES_DEFAULTS, .frames = 30, .m = 2, .p = 0.8};
static const limn_feature_options feature_defaults = {.size = sizeof(limn_feature_options),
                                                    .outer_steps = 3,
                                                    .normal_steps = 10,
                                                    .vertex_steps = 10,
                                                    .sigma_r = 0.35,
                                                    .sigma_s = 0.0,
                                                    .tangential = 0.1,
                                                    .keep_volume = 0,
                                                    .adaptive = 1,
                                                    .crease_angle = 30.0};
static const limn_texture_options texture_defaults = {.size = sizeof(limn_texture_options),
                                                      .series = SERIES_DEFAULTS,
                                                      .levels = 3,
                                                      .seed = 1,
                                                      .frequency = 4.0,
                                                      .tolerance = 1e-6};
static const limn_interpolate_options interpolate_defaults = {.size =
                                                                  sizeof(limn_interpolate_options),
                                                              .scheme = LIMN_SCHEME_AUTO,
                                                              .tolerance = 1e-6,
                                                              .max_iterations = 1000,
                                                              .reorder = 1,
                                                              .method = LIMN_METHOD_AUTO,
                                                              .precision = LIMN_PRECISION_AUTO};
static const limn_subdivide_options subdivide_defaults = {
    .size = sizeof(limn_subdivide_options), .scheme = LIMN_SCHEME_AUTO, .levels = 1};
static const limn_repair_options repair_defaults = {.size = sizeof(limn_repair_options),
                                                    .repeated_vertices = 1,
                                                    .sub_meshes = 1,
                                                    .keep_topology = 1};
static const limn_write_options write_defaults = {.size = sizeof(limn_write_options),
                                                  .precision = LIMN_OUTPUT_DOUBLE};
static const limn_render_options render_defaults = {.size = sizeof(limn_render_options),
                                                    .width = 400,
                                                    .height = 300,
                                                    .azimuth = 30.0,
                                                    .elevation = 20.0,
                                                    .up_axis = 1,
                                                    .supersample = 2,
                                                    .background = {255, 255, 255},
                                                    .color = {196, 202, 214}};

ABI_FLAT(abi_write_options, limn_write_options, "limn_write_options_default()", precision,
         &write_defaults);
ABI_FLAT(abi_write_report, limn_write_report, "sizeof(limn_write_report)", bbox_diagonal, NULL);
ABI_FLAT(abi_repair_options, limn_repair_options, "limn_repair_options_default()", duplicate_faces,
         &repair_defaults);
ABI_FLAT(abi_repair_report, limn_repair_report, "sizeof(limn_repair_report)", boundary_loops, NULL);
ABI_FLAT(abi_mesh_info, limn_mesh_info, "sizeof(limn_mesh_info)", bbox_diagonal, NULL);
ABI_FLAT(abi_interpolate_options, limn_interpolate_options, "limn_interpolate_options_default()",
         precision, &interpolate_defaults);
ABI_FLAT(abi_report, limn_report, "sizeof(limn_report)", seconds_opencl_kernels, NULL);
ABI_FLAT(abi_subdivide_options, limn_subdivide_options, "limn_subdivide_options_default()",
         max_memory, &subdivide_defaults);
ABI_FLAT(abi_subdivide_report, limn_subdivide_report, "sizeof(limn_subdivide_report)",
         seconds_limit, NULL);
ABI_FLAT(abi_series_options, limn_series_options, "limn_series_options_default()", alpha,
         &series_defaults);
ABI_FLAT(abi_feature_options, limn_feature_options, "limn_feature_options_default()",
         keep_volume, &feature_defaults);
ABI_FLAT(abi_series_report, limn_series_report, "sizeof(limn_series_report)", seconds_compute,
         NULL);
ABI_FLAT(abi_triad_report, limn_triad_report, "sizeof(limn_triad_report)", device, NULL);
ABI_FLAT(abi_mesh_measures, limn_mesh_measures, "sizeof(limn_mesh_measures)", centroid, NULL);
ABI_FLAT(abi_mesh_comparison, limn_mesh_comparison, "sizeof(limn_mesh_comparison)", flipped_faces,
         NULL);
ABI_FLAT(abi_render_options, limn_render_options, "limn_render_options_default()", color,
         &render_defaults);
const abi_layout abi_morph_options = {
    "limn_morph_options",       "limn_morph_options_default()",
    sizeof(limn_morph_options), ABI_END(limn_morph_options, linear),
    &abi_series_options,        &morph_defaults};
const abi_layout abi_texture_options = {
    "limn_texture_options",       "limn_texture_options_default()",
    sizeof(limn_texture_options), ABI_END(limn_texture_options, max_memory),
    &abi_series_options,          &texture_defaults};

/* The embedded struct sits right after the outer size and the outer fields
   right after it, so the caller's layout follows from the inner size. */
_Static_assert(offsetof(limn_morph_options, series) == sizeof(size_t), "series first");
_Static_assert(offsetof(limn_morph_options, frames) == sizeof(size_t) + sizeof(limn_series_options),
               "frames after series");
_Static_assert(offsetof(limn_texture_options, series) == sizeof(size_t), "series first");
_Static_assert(offsetof(limn_texture_options, levels) ==
                   sizeof(size_t) + sizeof(limn_series_options),
               "levels after series");

static size_t size_at(const void *p)
{
    size_t n;
    memcpy(&n, p, sizeof n);
    return n;
}

/* The first non-zero byte of p[from, to), or SIZE_MAX. */
static size_t first_set(const unsigned char *p, size_t from, size_t to)
{
    for (size_t i = from; i < to; i++)
        if (p[i])
            return i;
    return SIZE_MAX;
}

/* The size field of the struct `what` in messages: "options->size", and
   "options->series.size" for an embedded one. */
static const char *size_name(char *buf, size_t cap, const char *what)
{
    snprintf(buf, cap, "%s%ssize", what, strstr(what, "->") ? "." : "->");
    return buf;
}

/* Checks one struct's own size field (not its tail when it embeds one). */
static limn_status check_size(limn_context *ctx, const char *fn, const char *what,
                              const abi_layout *l, size_t n, int options)
{
    char field[112];
    size_name(field, sizeof field, what);
    const char *fix = options ? "initialise it with" : "set it to";
    if (n == 0) {
        if (options)
            return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "%s: %s is 0: initialise %s with %s", fn,
                             field, what, l->init);
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "%s: %s is 0: set it to %s before the call", fn,
                         field, l->init);
    }
    if (n > ABI_MAX_SIZE)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                         "%s: %s is %zu, no size of a %s (this library's is %zu): %s %s", fn, field,
                         n, l->type, l->size, fix, l->init);
    if (options && n < l->min_size)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                         "%s: %s is %zu, smaller than the first released %s (%zu bytes): %s %s", fn,
                         field, n, l->type, l->min_size, fix, l->init);
    size_t min = l->inner ? 2 * sizeof(size_t) : sizeof(size_t);
    if (!options && n < min)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                         "%s: %s is %zu, smaller than its size field%s: set it to %s", fn, field, n,
                         l->inner ? "s" : "", l->init);
    return LIMN_OK;
}

/* The caller's bytes [0, have) read into the library's [0, lib), skipping
   the leading size field: extra caller bytes must be zero. `at` is where
   the piece starts in the caller's struct (for messages). */
static limn_status piece_in(limn_context *ctx, const char *fn, const char *what,
                            const abi_layout *l, size_t n, const unsigned char *src, size_t have,
                            unsigned char *dst, size_t lib, size_t skip, size_t at)
{
    if (have > lib) {
        size_t set = first_set(src, lib, have);
        char field[112];
        if (set != SIZE_MAX)
            return ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                             "%s: %s is %zu but this liblimn %s knows %zu bytes of %s and "
                             "byte %zu of the caller's is set: an option this library does not "
                             "have (built against a newer limn.h than the library loaded?)",
                             fn, size_name(field, sizeof field, what), n, limn_version(), l->size,
                             l->type, at + set);
    }
    size_t copy = have < lib ? have : lib;
    if (copy > skip)
        memcpy(dst + skip, src + skip, copy - skip);
    return LIMN_OK;
}

limn_status abi_options_in(limn_context *ctx, const char *fn, const char *what, const abi_layout *l,
                           const void *src_v, void *dst_v)
{
    if (!src_v)
        return LIMN_OK;
    const unsigned char *src = src_v;
    unsigned char *dst = dst_v;
    size_t n = size_at(src);
    limn_status st = check_size(ctx, fn, what, l, n, 1);
    if (st || !l->inner)
        return st ? st : piece_in(ctx, fn, what, l, n, src, n, dst, l->size, sizeof(size_t), 0);
    /* [size][inner: inner.size bytes][tail] */
    const abi_layout *in = l->inner;
    char inner_what[96];
    snprintf(inner_what, sizeof inner_what, "%s->series", what);
    const unsigned char *isrc = src + sizeof(size_t);
    size_t ni = size_at(isrc);
    st = check_size(ctx, fn, inner_what, in, ni, 1);
    size_t tail_at = sizeof(size_t) + ni;
    size_t lib_tail_at = sizeof(size_t) + in->size;
    size_t min_tail = l->min_size - (sizeof(size_t) + in->min_size);
    if (!st && (n < tail_at || n - tail_at < min_tail))
        st = ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                       "%s: %s->size is %zu, smaller than the first released %s (%zu bytes "
                       "with %s.size %zu): initialise it with %s",
                       fn, what, n, l->type, tail_at + min_tail, inner_what, ni, l->init);
    if (!st)
        st = piece_in(ctx, fn, inner_what, in, ni, isrc, ni, dst + sizeof(size_t), in->size,
                      sizeof(size_t), sizeof(size_t));
    if (!st)
        st = piece_in(ctx, fn, what, l, n, src + tail_at, n - tail_at, dst + lib_tail_at,
                      l->size - lib_tail_at, 0, tail_at);
    return st;
}

limn_status abi_report_begin(limn_context *ctx, const char *fn, const char *what,
                             const abi_layout *l, const void *dst, void *local)
{
    /* the library's own copy is of its own layout (so it can be passed on) */
    memset(local, 0, l->size);
    memcpy(local, &l->size, sizeof(size_t));
    if (l->inner)
        memcpy((unsigned char *)local + sizeof(size_t), &l->inner->size, sizeof(size_t));
    if (!dst)
        return LIMN_OK;
    size_t n = size_at(dst);
    limn_status st = check_size(ctx, fn, what, l, n, 0);
    if (st || !l->inner)
        return st;
    size_t ni = size_at((const unsigned char *)dst + sizeof(size_t));
    char inner_what[96];
    snprintf(inner_what, sizeof inner_what, "%s->stats", what);
    st = check_size(ctx, fn, inner_what, l->inner, ni, 0);
    if (!st && n - sizeof(size_t) < ni)
        st = ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                       "%s: %s->size is %zu, which cannot hold %s of %zu bytes: set both to "
                       "their sizeof",
                       fn, what, n, inner_what, ni);
    return st;
}

/* Writes the library's [skip, lib) into the caller's [skip, have), zeroing
   what the library does not have. */
static void piece_out(unsigned char *dst, size_t have, const unsigned char *src, size_t lib,
                      size_t skip)
{
    size_t copy = have < lib ? have : lib;
    if (copy > skip)
        memcpy(dst + skip, src + skip, copy - skip);
    if (have > lib)
        memset(dst + (lib > skip ? lib : skip), 0, have - (lib > skip ? lib : skip));
}

void abi_default(const abi_layout *l, void *o)
{
    if (o) /* no context to report a NULL to */
        memcpy(o, l->defaults, l->size);
}

limn_status abi_begin(limn_context *ctx, const char *fn, const char *what, const void *p)
{
    if (!ctx)
        return LIMN_ERR_ARGUMENT;
    ctx_clear(ctx);
    if (what && !p)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "%s: %s is NULL", fn, what);
    return LIMN_OK;
}

limn_status abi_enter(abi_call *c, limn_context *ctx, const char *fn,
                      const abi_layout *options_layout, const void *options,
                      const abi_layout *report_layout, void *report, limn_mesh **out)
{
    _Static_assert(sizeof c->o >= sizeof(limn_texture_options), "room for the options");
    if (abi_begin(ctx, fn, NULL, NULL))
        return LIMN_ERR_ARGUMENT;
    if (out)
        *out = NULL;
    *c = (abi_call){.fn = fn,
                    .options_layout = options_layout,
                    .report_layout = report_layout,
                    .caller_report = report};
    abi_default(options_layout, &c->o);
    /* the report is set up even after a refusal of the options: MPI's
       entry agrees over both before it returns */
    limn_status st = abi_options_in(ctx, fn, "options", options_layout, options, &c->o);
    limn_status rs = abi_report_begin(ctx, fn, "report", report_layout, st ? NULL : report, &c->r);
    c->options = &c->o;
    c->report = &c->r;
    return st ? st : rs;
}

limn_status abi_enter_result(abi_call *c, limn_context *ctx, const char *fn, const char *what,
                             const abi_layout *layout, void *result)
{
    if (abi_begin(ctx, fn, NULL, NULL))
        return LIMN_ERR_ARGUMENT;
    *c = (abi_call){.fn = fn, .report_layout = layout, .caller_report = result};
    c->report = result ? &c->r : NULL;
    return abi_report_begin(ctx, fn, what, layout, result, &c->r);
}

limn_status abi_leave(const abi_call *c, limn_status st)
{
    abi_report_end(c->report_layout, c->caller_report, &c->r);
    return st;
}

void abi_report_end(const abi_layout *l, void *dst_v, const void *local_v)
{
    if (!dst_v)
        return;
    unsigned char *dst = dst_v;
    const unsigned char *src = local_v;
    size_t n = size_at(dst);
    if (!l->inner) {
        piece_out(dst, n, src, l->size, sizeof(size_t));
        return;
    }
    size_t ni = size_at(dst + sizeof(size_t));
    piece_out(dst + sizeof(size_t), ni, src + sizeof(size_t), l->inner->size, sizeof(size_t));
    size_t tail_at = sizeof(size_t) + ni, lib_tail_at = sizeof(size_t) + l->inner->size;
    piece_out(dst + tail_at, n - tail_at, src + lib_tail_at, l->size - lib_tail_at, 0);
}

int abi_report_holds(const abi_layout *l, const void *p_v, size_t end)
{
    const unsigned char *p = p_v;
    size_t n = size_at(p);
    if (!l->inner)
        return n >= end;
    if (n < 2 * sizeof(size_t))
        return 0;
    size_t tail_at = sizeof(size_t) + size_at(p + sizeof(size_t));
    size_t lib_tail_at = sizeof(size_t) + l->inner->size;
    if (n < tail_at)
        return 0;
    return end <= lib_tail_at || n - tail_at >= end - lib_tail_at;
}
