/* SPDX-License-Identifier: MIT */
/*
 * Mesh files: the public read/write entry points, format detection and the
 * atomic write (temporary file + fsync + rename); each format's reader and
 * writer is in its own file (formats.h), their shared toolkit in toolkit.c.
 */
#ifndef _POSIX_C_SOURCE
#define _POSIX_C_SOURCE 200809L /* mkstemp, fdopen, fileno, fchmod, fsync */
#endif

#include "mesh/io/dispatch.h"
#include "base/abi.h"
#include "base/atomic_file.h"
#include "base/c_locale.h"
#include "base/context.h"
#include "mesh/check.h"
#include "mesh/io/formats.h"
#include "mesh/mesh.h"

#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

/* ----------------------------------------------------------------- formats */

int limn_format_from_name(const char *name, limn_format *out)
{
    static const struct { const char *name; limn_format format; } names[] = {
        {"obj", LIMN_FORMAT_OBJ},          {"ply", LIMN_FORMAT_PLY},
        {"ply-le", LIMN_FORMAT_PLY},       {"ply-ascii", LIMN_FORMAT_PLY_ASCII},
        {"ply-be", LIMN_FORMAT_PLY_BINARY_BE}, {"off", LIMN_FORMAT_OFF},
        {"stl", LIMN_FORMAT_STL},
    };
    if (!name)
        return 0;
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++)
        if (strcasecmp(name, names[i].name) == 0) {
            if (out)
                *out = names[i].format;
            return 1;
        }
    return 0;
}

static limn_status format_from_path(limn_context *ctx, const char *path, limn_format *out)
{
    const char *base = strrchr(path, '/');
    base = base ? base + 1 : path;
    const char *dot = strrchr(base, '.');
    if (dot && dot != base) {
        if (strcasecmp(dot, ".obj") == 0) {
            *out = LIMN_FORMAT_OBJ;
            return LIMN_OK;
        }
        if (strcasecmp(dot, ".ply") == 0) {
            *out = LIMN_FORMAT_PLY;
            return LIMN_OK;
        }
        if (strcasecmp(dot, ".off") == 0) {
            *out = LIMN_FORMAT_OFF;
            return LIMN_OK;
        }
        if (strcasecmp(dot, ".stl") == 0) {
            *out = LIMN_FORMAT_STL;
            return LIMN_OK;
        }
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                         "%s: unknown mesh file extension '%.20s' (accepted: .obj, .ply, .off, "
                         ".stl)",
                         path, dot);
    }
    return ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                     "%s: no file extension to tell the mesh format (accepted: .obj, .ply, .off, "
                     ".stl)",
                     path);
}

/* A pipe or device has no size to check counts against and may never end:
   read only when its format is named. */
static limn_status not_regular(limn_context *ctx, const char *path, mode_t mode)
{
    return ctx_fail(ctx, LIMN_ERR_IO,
                     "%s: not a regular file (a %s: its size is unknown): name its format "
                     "(--input-format) to read it as a stream", path,
                     S_ISFIFO(mode)   ? "pipe"
                     : S_ISCHR(mode)  ? "character device"
                     : S_ISSOCK(mode) ? "socket"
                                      : "special file");
}

/* Reads an open file in the format; refuses what cannot be a mesh file. */
static limn_status read_open(limn_context *ctx, const char *path, limn_format format,
                             int format_given, FILE *f, limn_mesh **out)
{
    struct stat sb;
    if (fstat(fileno(f), &sb) != 0)
        return ctx_fail(ctx, LIMN_ERR_IO, "cannot read %s: %s", path, strerror(errno));
    if (S_ISDIR(sb.st_mode))
        return ctx_fail(ctx, LIMN_ERR_IO, "cannot read %s: it is a directory", path);
    if (S_ISREG(sb.st_mode) && sb.st_size == 0)
        return ctx_fail(ctx, LIMN_ERR_FORMAT, "%s: the file is empty", path);
    if (!S_ISREG(sb.st_mode) && !format_given)
        return not_regular(ctx, path, sb.st_mode);
    if (format == LIMN_FORMAT_OBJ)
        return obj_read(ctx, path, f, out);
    if (format == LIMN_FORMAT_OFF)
        return off_read(ctx, path, f, out);
    if (format == LIMN_FORMAT_STL)
        return stl_read(ctx, path, f, out);
    return ply_read(ctx, path, f, out);
}

/* read_open, then the checks every mesh file must pass; *out is NULL on failure. */
static limn_status read_checked(limn_context *ctx, const char *path, limn_format format,
                                int format_given, FILE *f, limn_mesh **out)
{
    limn_status st = read_open(ctx, path, format, format_given, f, out);
    if (st == LIMN_OK && (*out)->vertex_count == 0) {
        limn_mesh_destroy(*out);
        *out = NULL;
        st = ctx_fail(ctx, LIMN_ERR_FORMAT, "%s: the file defines no vertices", path);
    }
    if (st != LIMN_OK && *out) {
        limn_mesh_destroy(*out);
        *out = NULL;
    }
    return st;
}

static limn_status mesh_read(limn_context *ctx, const char *path, limn_format format,
                             limn_mesh **out)
{
    int given = format != LIMN_FORMAT_AUTO;
    limn_status st;
    struct stat sb; /* before opening: a FIFO's open would wait for a writer */
    if (!given && stat(path, &sb) == 0 && !S_ISREG(sb.st_mode) && !S_ISDIR(sb.st_mode))
        return not_regular(ctx, path, sb.st_mode);
    if (!given && (st = format_from_path(ctx, path, &format)))
        return st;
    if (format < LIMN_FORMAT_OBJ || format > LIMN_FORMAT_STL)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "limn_mesh_read: unknown format %d",
                         (int)format);
    FILE *f = fopen(path, "rb");
    if (!f)
        return ctx_fail(ctx, LIMN_ERR_IO, "cannot open %s: %s", path, strerror(errno));
    st = read_checked(ctx, path, format, given, f, out);
    fclose(f);
    return st;
}

limn_status limn_mesh_read(limn_context *ctx, const char *path, limn_format format,
                           limn_mesh **out)
{
    ctx_clear(ctx);
    if (!out)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "limn_mesh_read: out is NULL");
    *out = NULL;
    if (!path || !*path)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "limn_mesh_read: no file name");
    c_locale_scope loc;
    if (!c_locale_enter(&loc))
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "%s: out of memory for the C locale", path);
    limn_status st = mesh_read(ctx, path, format, out);
    c_locale_leave(&loc);
    return st;
}

limn_status limn_mesh_read_stream(limn_context *ctx, FILE *stream, const char *name,
                                  limn_format format, limn_mesh **out)
{
    ctx_clear(ctx);
    if (!out)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "limn_mesh_read_stream: out is NULL");
    *out = NULL;
    if (!name || !*name)
        name = "(stream)";
    if (!stream)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "limn_mesh_read_stream: %s: stream is NULL",
                         name);
    if (format == LIMN_FORMAT_AUTO)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                         "%s: a stream has no file extension to tell the mesh format: name "
                         "the format (obj, ply, off, stl)",
                         name);
    if (format < LIMN_FORMAT_OBJ || format > LIMN_FORMAT_STL)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "limn_mesh_read_stream: unknown format %d",
                         (int)format);
    c_locale_scope loc;
    if (!c_locale_enter(&loc))
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "%s: out of memory for the C locale", name);
    limn_status st = read_checked(ctx, name, format, 1, stream, out);
    c_locale_leave(&loc);
    return st;
}

/* ------------------------------------------------------------------ write */

/* The write options against the format, before any file exists. */
static limn_status check_write_options(limn_context *ctx, const limn_write_options *o,
                                       limn_format format)
{
    if (o->precision != LIMN_OUTPUT_DOUBLE && o->precision != LIMN_OUTPUT_FLOAT)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                        "limn_mesh_write: options->precision %d is neither LIMN_OUTPUT_DOUBLE "
                        "nor LIMN_OUTPUT_FLOAT",
                        (int)o->precision);
    if (o->precision == LIMN_OUTPUT_FLOAT && format != LIMN_FORMAT_PLY &&
        format != LIMN_FORMAT_PLY_ASCII && format != LIMN_FORMAT_PLY_BINARY_BE)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                        "limn_mesh_write: float precision is written to PLY only, not %s; "
                        "nothing was written",
                        format == LIMN_FORMAT_OBJ   ? "OBJ"
                        : format == LIMN_FORMAT_OFF ? "OFF"
                                                    : "STL (always float32)");
    return LIMN_OK;
}

/* The format's writer into the open staged file. */
static limn_status write_format(limn_context *ctx, const limn_mesh *mesh, const char *path,
                                limn_format format, int single, FILE *f)
{
    if (format == LIMN_FORMAT_OBJ)
        return obj_write(ctx, mesh, path, f);
    if (format == LIMN_FORMAT_OFF)
        return off_write(ctx, mesh, path, f);
    if (format == LIMN_FORMAT_STL)
        return stl_write(ctx, mesh, path, f);
    return ply_write(ctx, mesh, path, f, format, single);
}

limn_status mesh_write_format(limn_context *ctx, const char *path,
                              const limn_write_options *options, limn_format *format)
{
    limn_status st;
    if (*format == LIMN_FORMAT_AUTO && (st = format_from_path(ctx, path, format)))
        return st;
    if (*format < LIMN_FORMAT_OBJ || *format > LIMN_FORMAT_STL)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "limn_mesh_write: unknown format %d",
                         (int)*format);
    return check_write_options(ctx, options, *format);
}

limn_status mesh_write_staged(limn_context *ctx, const limn_mesh *mesh, const char *path,
                              limn_format format, const limn_write_options *options,
                              limn_write_report *report, atomic_file *af)
{
    memset(af, 0, sizeof *af);
    if (!mesh || !path || !*path)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "limn_mesh_write: %s is NULL or empty",
                         !mesh ? "mesh" : "path");
    limn_status st = mesh_write_format(ctx, path, options, &format);
    if (st)
        return st;
    st = check_mesh_writable(ctx, mesh, format); /* before any file exists */
    if (st)
        return st;
    st = atomic_file_open(ctx, path, af);
    if (st)
        return st;
    int single = options->precision == LIMN_OUTPUT_FLOAT;
    c_locale_scope loc; /* the headers' printf with a '.', whatever the host's locale */
    if (!c_locale_enter(&loc))
        st = ctx_fail(ctx, LIMN_ERR_MEMORY, "%s: out of memory for the C locale", path);
    else
        st = write_format(ctx, mesh, path, format, single, af->f);
    c_locale_leave(&loc);
    if (st) {
        atomic_file_abort(af);
        return st;
    }
    double lo[3], hi[3];
    report->bbox_diagonal = mesh_bbox_diagonal(mesh, lo, hi);
    if (single)
        ply_float_error(mesh, &report->max_error, &report->mean_error);
    return atomic_file_finish(ctx, af);
}

void limn_write_options_default(limn_write_options *options)
{
    abi_default(&abi_write_options, options);
}

limn_status limn_mesh_write(limn_context *ctx, const limn_mesh *mesh, const char *path,
                            limn_format format)
{
    return limn_mesh_write_with(ctx, mesh, path, format, NULL, NULL);
}

limn_status limn_mesh_write_with(limn_context *ctx, const limn_mesh *mesh, const char *path,
                                 limn_format format, const limn_write_options *options,
                                 limn_write_report *report)
{
    abi_call c;
    limn_status st = abi_enter(&c, ctx, "limn_mesh_write_with", &abi_write_options, options,
                               &abi_write_report, report, NULL);
    if (st)
        return st;
    atomic_file af;
    st = mesh_write_staged(ctx, mesh, path, format, c.options, c.report, &af);
    return abi_leave(&c, st ? st : atomic_file_commit(ctx, &af));
}

int limn_format_from_path(const char *path, limn_format *out)
{
    limn_format f = LIMN_FORMAT_AUTO;
    if (!path || format_from_path(NULL, path, &f) != LIMN_OK)
        return 0;
    if (out)
        *out = f;
    return 1;
}
