/* SPDX-License-Identifier: MIT */
/*
 * The ABI rule of limn.h's options and report structs (limn.h's top
 * comment): each begins with `size_t size`, the caller's sizeof of it. On
 * entry the library copies the caller's options into a library-side struct
 * holding the defaults, min(caller size, library size) bytes, and later
 * copies its own full report out into the caller's, never past the caller's
 * size. A struct embedding another one (morph's and texture's `series`,
 * the MPI result's `stats`) embeds it right after its own size field, so the
 * caller's layout is [size][inner, inner.size bytes][the rest]: each part is
 * read or written by its own size.
 */
#ifndef LIMN_ABI_H
#define LIMN_ABI_H

#include "limn.h"

#include <stddef.h>

/* A caller struct of this library: its name, the defaults function that
   sets its size, the library's sizeof and the first released size (options
   smaller than that are refused; reports need only the size field). */
typedef struct abi_layout {
    const char *type;
    const char *init; /* "limn_interpolate_options_default()" */
    size_t size;
    size_t min_size;
    const struct abi_layout *inner; /* a struct embedded right after `size`, or NULL */
    const void *defaults;           /* options: what limn_*_default() gives; reports: NULL */
} abi_layout;

/*
 * Reads the caller's options `src` (NULL: nothing, LIMN_OK) into `dst`,
 * which holds the defaults already (layout->size bytes): checks the size
 * fields and copies the bytes the caller has. fn and what name the call and
 * the argument in messages ("limn_interpolate", "options"). On a refusal
 * dst keeps its defaults and ctx has the message.
 */
limn_status abi_options_in(limn_context *ctx, const char *fn, const char *what,
                           const abi_layout *layout, const void *src, void *dst);

/*
 * Checks the caller's report `dst` (NULL: LIMN_OK) before the call: its size
 * is set and not below sizeof(size_t) (and so for an embedded struct); then
 * zeroes the library-side `local` (layout->size bytes) and sets its size
 * fields to the library's.
 */
limn_status abi_report_begin(limn_context *ctx, const char *fn, const char *what,
                             const abi_layout *layout, const void *dst, void *local);

/* limn_*_options_default(): o (NULL: nothing) gets the layout's defaults. */
void abi_default(const abi_layout *layout, void *o);

/* The start of a public call: LIMN_ERR_ARGUMENT, no message, without a
   context (nowhere to put one); else ctx cleared and, where `what` is
   given, the pointer p required ("fn: what is NULL"). */
limn_status abi_begin(limn_context *ctx, const char *fn, const char *what, const void *p);

/*
 * A public call taking options and a report, around its *_sized function:
 *     abi_call c;
 *     limn_status st = abi_enter(&c, ctx, "limn_x", &abi_x_options, options, &abi_x_report,
 *                                report, out);
 *     return st ? st : abi_leave(&c, x_sized(ctx, ..., c.options, ..., c.report));
 * The library-side copies live in c (a union of the structs of limn.h).
 */
typedef struct abi_call {
    const char *fn;
    const abi_layout *options_layout, *report_layout;
    void *caller_report;
    /* set by abi_enter: the library-side copies, never NULL (what the
       *_sized function takes): the defaults where the caller passed no
       options, a report nobody reads where it passed none */
    const void *options;
    void *report;
    union {
        limn_series_options series;
        limn_morph_options morph;
        limn_feature_options feature;
        limn_texture_options texture;
        limn_interpolate_options interpolate;
        limn_subdivide_options subdivide;
        limn_repair_options repair;
        limn_write_options write;
    } o;
    union {
        limn_series_report series;
        limn_report interpolate;
        limn_subdivide_report subdivide;
        limn_repair_report repair;
        limn_mesh_info info;
        limn_mesh_measures measures;
        limn_mesh_comparison comparison;
        limn_triad_report triad;
        limn_write_report write;
    } r;
} abi_call;

/* abi_begin (no pointer required), *out = NULL (out may be NULL), the
   options set to the defaults and the caller's read over them, the report
   checked; the first refusal is returned. */
limn_status abi_enter(abi_call *c, limn_context *ctx, const char *fn,
                      const abi_layout *options_layout, const void *options,
                      const abi_layout *report_layout, void *report, limn_mesh **out);
/* The entry of a call whose one struct is a result it fills (info,
   measure, compare): the context checked and cleared, the caller's result
   (named `what`) checked; c->report is the library-side copy, NULL when the
   caller passed none (the *_sized function then refuses with its message). */
limn_status abi_enter_result(abi_call *c, limn_context *ctx, const char *fn, const char *what,
                             const abi_layout *layout, void *result);
/* After an entered call: the report copied out; returns st. */
limn_status abi_leave(const abi_call *c, limn_status st);

/* Copies the library-side report into the caller's (NULL: nothing): the
   bytes its size holds, zeroing those beyond the library's layout; the
   caller's size fields stay as they are. */
void abi_report_end(const abi_layout *layout, void *dst, const void *local);

/* Whether the caller's struct `p` (of this layout) holds the bytes up to
   `end` of the library's layout (offsetof + sizeof of a field after the
   embedded struct, or within a flat one). */
int abi_report_holds(const abi_layout *layout, const void *p, size_t end);

extern const abi_layout abi_repair_options, abi_repair_report, abi_mesh_info,
    abi_interpolate_options, abi_report, abi_subdivide_options, abi_subdivide_report,
    abi_series_options, abi_feature_options, abi_series_report, abi_morph_options, abi_mesh_measures,
    abi_mesh_comparison, abi_texture_options, abi_render_options, abi_write_options,
    abi_write_report, abi_triad_report;

#endif
