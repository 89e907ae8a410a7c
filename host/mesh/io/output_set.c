/* SPDX-License-Identifier: MIT */
/* The public face of atomic outputs (limn.h "outputs"): the preflight check
   and a set of staged outputs committed together, over atomic_file. */
#include "base/abi.h"
#include "base/atomic_file.h"
#include "base/context.h"
#include "mesh/io/dispatch.h"
#include "mesh/io/output_set.h"
#include "base/output_path.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* int counts; a bands run of 10,001 files or a morph of 10^6 frames fits */
#define OUTPUT_SET_MAX (1 << 24)

struct limn_output_set {
    atomic_file *staged; /* grown by doubling */
    int n, cap;
};

int limn_output_is_stdout(const char *path) { return output_is_stdout(path); }

/* Do two paths name the same existing file? Standard input or output never. */
static int same_file(const char *a, const char *b)
{
    struct stat sa, sb;
    if (!strcmp(a, "-") || !strcmp(b, "-") || output_is_stdout(a) || stat(a, &sa) != 0 ||
        stat(b, &sb) != 0)
        return 0;
    return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

limn_status limn_output_check(limn_context *ctx, const char *path, const char *input)
{
    ctx_clear(ctx);
    if (!path || !*path)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "limn_output_check: path is NULL or empty");
    if (input && same_file(input, path))
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                         "output '%s' is the input file; refusing to overwrite it", path);
    return atomic_file_check(ctx, path);
}

limn_status limn_output_set_create(limn_context *ctx, limn_output_set **out)
{
    ctx_clear(ctx);
    if (!out)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "limn_output_set_create: out is NULL");
    *out = calloc(1, sizeof **out);
    if (!*out)
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for an output set");
    return LIMN_OK;
}

limn_status output_set_room(limn_context *ctx, const char *fn, limn_output_set *set,
                            const char *path)
{
    if (!set)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "%s: set is NULL", fn);
    if (!path || !*path)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "%s: path is NULL or empty", fn);
    if (set->n >= OUTPUT_SET_MAX)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "%s: a set holds at most %d outputs", fn,
                         OUTPUT_SET_MAX);
    if (set->n < set->cap)
        return LIMN_OK;
    int cap = set->cap ? 2 * set->cap : 16;
    atomic_file *grown = realloc(set->staged, (size_t)cap * sizeof *grown);
    if (!grown)
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for an output set of %d outputs",
                         set->n + 1);
    memset(grown + set->cap, 0, (size_t)(cap - set->cap) * sizeof *grown);
    set->staged = grown;
    set->cap = cap;
    return LIMN_OK;
}

limn_status limn_output_set_add_mesh(limn_context *ctx, limn_output_set *set,
                                     const limn_mesh *mesh, const char *path,
                                     limn_format format)
{
    return limn_output_set_add_mesh_with(ctx, set, mesh, path, format, NULL, NULL);
}

limn_status limn_output_set_add_mesh_with(limn_context *ctx, limn_output_set *set,
                                          const limn_mesh *mesh, const char *path,
                                          limn_format format, const limn_write_options *options,
                                          limn_write_report *report)
{
    const char *fn = "limn_output_set_add_mesh";
    abi_call c;
    limn_status st = abi_enter(&c, ctx, fn, &abi_write_options, options, &abi_write_report,
                               report, NULL);
    if (!st)
        st = output_set_room(ctx, fn, set, path);
    if (!st)
        st = mesh_write_staged(ctx, mesh, path, format, c.options, c.report, &set->staged[set->n]);
    if (!st)
        set->n++;
    return abi_leave(&c, st);
}

limn_status limn_output_set_add_bytes(limn_context *ctx, limn_output_set *set,
                                      const char *path, const void *data, size_t size)
{
    ctx_clear(ctx);
    limn_status st = output_set_room(ctx, "limn_output_set_add_bytes", set, path);
    if (st)
        return st;
    if (!data && size)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "limn_output_set_add_bytes: data is NULL");
    atomic_file *af = &set->staged[set->n];
    st = atomic_file_open(ctx, path, af);
    if (st)
        return st;
    errno = 0;
    if (size && fwrite(data, 1, size, af->f) != size) {
        int e = errno;
        atomic_file_abort(af);
        return ctx_fail(ctx, LIMN_ERR_IO, "cannot write %s: %s", path,
                         e ? strerror(e) : "write error");
    }
    st = atomic_file_finish(ctx, af);
    if (!st)
        set->n++;
    return st;
}

void output_set_adopt(limn_output_set *set, atomic_file *af)
{
    set->staged[set->n++] = *af;
    memset(af, 0, sizeof *af);
}

int limn_output_set_count(const limn_output_set *set) { return set ? set->n : 0; }

limn_status limn_output_set_commit(limn_context *ctx, limn_output_set *set)
{
    ctx_clear(ctx);
    if (!set)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "limn_output_set_commit: set is NULL");
    limn_status st = set->n ? atomic_file_commit_all(ctx, set->staged, set->n) : LIMN_OK;
    set->n = 0;
    return st;
}

void limn_output_set_destroy(limn_output_set *set)
{
    if (!set)
        return;
    for (int i = 0; i < set->n; i++)
        atomic_file_abort(&set->staged[i]);
    free(set->staged);
    free(set);
}
