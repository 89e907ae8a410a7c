/* SPDX-License-Identifier: MIT */
/*
 * The slice reader's entry points (mesh_slice.h): the file opened and
 * mapped, its format told from the extension (and a PLY's header), the part
 * handed to the binary PLY reader (mesh_slice_ply.c) or the text one
 * (mesh_slice_text.c); slices of a mesh in memory.
 */
#ifndef _DEFAULT_SOURCE
#define _DEFAULT_SOURCE /* madvise */
#endif
#ifndef _POSIX_C_SOURCE
#define _POSIX_C_SOURCE 200809L /* fileno, mmap */
#endif
#include "mesh/io/mesh_slice.h"
#include "base/large_alloc.h"
#include "base/context.h"
#include "mesh/io/mesh_slice_formats.h"
#include "mesh/mesh.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

void mesh_slice_free(mesh_slice *s)
{
    if (!s)
        return;
    free(s->positions);
    free(s->face_offsets);
    free(s->face_indices);
    memset(s, 0, sizeof *s);
}

limn_status slice_hand_over(limn_status st, mesh_slice *s, mesh_slice *out)
{
    if (st) {
        mesh_slice_free(s);
        memset(out, 0, sizeof *out);
        return st;
    }
    *out = *s;
    memset(s, 0, sizeof *s);
    return LIMN_OK;
}

void mesh_slice_counts_add(mesh_slice_counts *sum, const mesh_slice_counts *c)
{
    sum->lines += c->lines;
    sum->records += c->records;
    sum->vertices += c->vertices;
    sum->faces += c->faces;
    sum->corners += c->corners;
    sum->irregular += c->irregular;
}

size_t mesh_slice_cut(size_t n, unsigned parts, unsigned p)
{
    /* p * n / parts without overflow: p * (q * parts + r) / parts */
    return n / parts * p + n % parts * p / parts;
}

/* ------------------------------------------------------------------ files */

limn_status slice_file_open(limn_context *ctx, const char *path, slice_file *sf)
{
    struct stat sb;
    memset(sf, 0, sizeof *sf);
    sf->ctx = ctx;
    sf->path = path;
    if (!(sf->f = fopen(path, "rb")) || fstat(fileno(sf->f), &sb) != 0) {
        int e = errno;
        slice_file_close(sf);
        return ctx_fail(ctx, LIMN_ERR_IO, "cannot read %s: %s", path, strerror(e));
    }
    if (!S_ISREG(sb.st_mode) || sb.st_size == 0 || (uint64_t)sb.st_size > SIZE_MAX) {
        slice_file_close(sf);
        return ctx_fail(ctx, S_ISREG(sb.st_mode) ? LIMN_ERR_FORMAT : LIMN_ERR_IO,
                        "%s: %s", path,
                        !S_ISREG(sb.st_mode) ? "not a regular file: slices are read from files"
                        : sb.st_size == 0   ? "the file is empty"
                                            : "the file is too large to map");
    }
    void *map = mmap(NULL, (size_t)sb.st_size, PROT_READ, MAP_PRIVATE, fileno(sf->f), 0);
    if (map == MAP_FAILED) {
        int e = errno;
        slice_file_close(sf);
        return ctx_fail(ctx, LIMN_ERR_IO, "cannot map %s: %s", path, strerror(e));
    }
    sf->map = map;
    sf->size = (size_t)sb.st_size;
    return LIMN_OK;
}

void slice_file_close(slice_file *sf)
{
    if (sf->map)
        munmap((void *)(uintptr_t)sf->map, sf->size);
    if (sf->f)
        fclose(sf->f);
    sf->map = NULL;
    sf->f = NULL;
}

void slice_file_release(const slice_file *sf, uint64_t begin, uint64_t end)
{
    long page = sysconf(_SC_PAGESIZE);
    uint64_t pg = page > 0 ? (uint64_t)page : 4096;
    uint64_t a = (begin + pg - 1) / pg * pg, b = (end < sf->size ? end : sf->size) / pg * pg;
    if (b > a)
        madvise((void *)(uintptr_t)(sf->map + a), (size_t)(b - a), MADV_DONTNEED);
}

/* ------------------------------------------------------------- dispatch */

typedef enum { SRC_BINARY_PLY, SRC_TEXT } src_route;

/* An open input: the file, its PLY header (or none) and how it is read. */
typedef struct slice_src {
    slice_file sf;
    ply *p;
    src_route route;
    slice_text_kind kind;
} slice_src;

static void src_close(slice_src *s)
{
    if (s->p) {
        ply_close(s->p);
        free(s->p);
    }
    slice_file_close(&s->sf);
    s->p = NULL;
}

static limn_status src_kind(limn_context *ctx, const char *path, limn_format format,
                            slice_src *s)
{
    const char *base = strrchr(path, '/'), *dot;
    base = base ? base + 1 : path;
    dot = format != LIMN_FORMAT_AUTO ? NULL : strrchr(base, '.');
    dot = dot && dot != base ? dot : "";
    if (format == LIMN_FORMAT_OBJ || strcasecmp(dot, ".obj") == 0)
        s->kind = SLICE_OBJ;
    else if (format == LIMN_FORMAT_OFF || strcasecmp(dot, ".off") == 0)
        s->kind = SLICE_OFF;
    else if (format == LIMN_FORMAT_PLY || format == LIMN_FORMAT_PLY_ASCII ||
             format == LIMN_FORMAT_PLY_BINARY_BE || strcasecmp(dot, ".ply") == 0)
        s->kind = SLICE_PLY;
    else if (format == LIMN_FORMAT_STL || strcasecmp(dot, ".stl") == 0)
        return ctx_fail(ctx, LIMN_ERR_FORMAT,
                        "%s: STL cannot be read in slices: its vertices are welded over the "
                        "whole file (write it as PLY first)", path);
    else
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                        "%s: no mesh file extension the slice reader takes (.ply, .obj, .off)",
                        path);
    return LIMN_OK;
}

static limn_status src_open(limn_context *ctx, const char *path, limn_format format,
                            unsigned part, unsigned parts, slice_src *s)
{
    memset(s, 0, sizeof *s);
    if (parts == 0 || part >= parts)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "%s: part %u of %u parts does not exist", path,
                        part, parts);
    limn_status st = src_kind(ctx, path, format, s);
    if (st || (st = slice_file_open(ctx, path, &s->sf)))
        return st;
    s->route = SRC_TEXT;
    if (s->kind != SLICE_PLY)
        return LIMN_OK;
    if (!(s->p = large_malloc(sizeof *s->p)))
        st = ctx_fail(ctx, LIMN_ERR_MEMORY, "%s: out of memory", path);
    else if (!(st = ply_open(s->p, ctx, path, s->sf.f)) && s->p->nv == 0)
        st = ctx_fail(ctx, LIMN_ERR_FORMAT, "%s: the file defines no vertices", path);
    else if (!st && s->p->format != F_ASCII)
        s->route = SRC_BINARY_PLY;
    if (st)
        src_close(s);
    return st;
}

limn_status mesh_slice_count(limn_context *ctx, const char *path, limn_format format,
                             unsigned part, unsigned parts, mesh_slice_counts *out)
{
    slice_src s;
    memset(out, 0, sizeof *out);
    limn_status st = src_open(ctx, path, format, part, parts, &s);
    if (st)
        return st;
    st = s.route == SRC_BINARY_PLY ? slice_ply_count(&s.sf, s.p, part, parts, out)
                                   : slice_text_count(&s.sf, s.kind, s.p, part, parts, out);
    src_close(&s);
    if (st)
        memset(out, 0, sizeof *out);
    return st;
}

limn_status mesh_slice_read(limn_context *ctx, const char *path, limn_format format,
                            unsigned part, unsigned parts, const mesh_slice_counts *before,
                            const mesh_slice_counts *total, mesh_slice *out)
{
    slice_src s;
    memset(out, 0, sizeof *out);
    limn_status st = src_open(ctx, path, format, part, parts, &s);
    if (st)
        return st;
    if (s.route == SRC_BINARY_PLY)
        st = slice_ply_read(&s.sf, s.p, part, parts, total->irregular == 0, s.p->nv, out);
    else
        st = slice_text_read(&s.sf, s.kind, s.p, part, parts, before, total, out);
    src_close(&s);
    return st;
}

/* ------------------------------------------------------- a mesh in memory */

limn_status mesh_slice_of(limn_context *ctx, const limn_mesh *mesh, unsigned part,
                          unsigned parts, mesh_slice *out)
{
    mesh_slice s;
    memset(&s, 0, sizeof s);
    memset(out, 0, sizeof *out);
    if (parts == 0 || part >= parts)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "part %u of %u parts does not exist", part,
                        parts);
    s.vertex_total = mesh->vertex_count;
    s.face_total = mesh->face_count;
    s.vertex_begin = mesh_slice_cut(s.vertex_total, parts, part);
    s.vertex_count = mesh_slice_cut(s.vertex_total, parts, part + 1) - s.vertex_begin;
    s.face_begin = mesh_slice_cut(s.face_total, parts, part);
    s.face_count = mesh_slice_cut(s.face_total, parts, part + 1) - s.face_begin;
    const uint32_t *off = mesh->face_offsets + s.face_begin;
    size_t corners = off[s.face_count] - off[0];
    s.positions = large_malloc(s.vertex_count * 24 + 1);
    s.face_offsets = large_malloc((s.face_count + 1) * 4);
    s.face_indices = large_malloc(corners * 4 + 1);
    if (!s.positions || !s.face_offsets || !s.face_indices)
        return slice_hand_over(ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for a slice"), &s,
                               out);
    if (s.vertex_count)
        memcpy(s.positions, mesh->positions + 3 * s.vertex_begin, s.vertex_count * 24);
    for (size_t f = 0; f <= s.face_count; f++)
        s.face_offsets[f] = off[f] - off[0];
    if (corners)
        memcpy(s.face_indices, mesh->face_indices + off[0], corners * 4);
    return slice_hand_over(LIMN_OK, &s, out);
}
