/* SPDX-License-Identifier: MIT */
/*
 * Mesh files: the public read/write entry points, format detection, the
 * atomic write (temporary file + fsync + rename) and the buffered reader and
 * number parsing shared by the formats.
 */
#ifndef _POSIX_C_SOURCE
#define _POSIX_C_SOURCE 200809L /* mkstemp, fdopen, fileno, fchmod, fsync */
#endif
#include "mesh_io.h"
#include "base/atomic_file.h"
#include "base/c_locale.h"
#include "mesh/check.h"
#include "base/context.h"
#include "mesh/mesh.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#define MIO_BUFFER (1u << 16)

/* ------------------------------------------------------------ buffered reader */

int mio_init(mio_reader *r, limn_context *ctx, const char *path, FILE *f)
{
    memset(r, 0, sizeof *r);
    r->ctx = ctx;
    r->path = path;
    r->f = f;
    r->next_line = 1;
    r->cap = MIO_BUFFER;
    r->budget.limit = context_max_memory(ctx);
    if (!growbuf_budget_take(&r->budget, r->cap)) {
        limn_fail(ctx, LIMN_ERR_MEMORY,
                  "%s: the memory limit of %zu bytes does not hold the %zu-byte read buffer: "
                  "raise --max-memory (limn_context_set_max_memory)", path, r->budget.limit,
                  r->cap);
        return 0;
    }
    if (!(r->buf = malloc(r->cap))) {
        limn_fail(ctx, LIMN_ERR_MEMORY, "%s: out of memory for a read buffer", path);
        return 0;
    }
    struct stat st;
    if (fstat(fileno(f), &st) == 0 && S_ISREG(st.st_mode) && st.st_size > 0) {
        long pos = ftell(f);
        r->buf_offset = pos > 0 ? (uint64_t)pos : 0;
        r->file_size = (uint64_t)st.st_size;
    }
    return 1;
}

void mio_free(mio_reader *r)
{
    free(r->buf);
    r->buf = NULL;
}

uint64_t mio_remaining(const mio_reader *r)
{
    if (!r->file_size)
        return UINT64_MAX;
    uint64_t off = mio_offset(r);
    return off < r->file_size ? r->file_size - off : 0;
}

/* Grows the buffer to cap bytes, within the budget; 0 (r->error) when not. */
static int mio_grow(mio_reader *r, size_t cap)
{
    if (!growbuf_budget_take(&r->budget, cap - r->cap)) {
        r->error = ENOMEM;
        return 0;
    }
    char *p = realloc(r->buf, cap);
    if (!p) {
        growbuf_budget_give(&r->budget, cap - r->cap);
        r->error = ENOMEM;
        return 0;
    }
    r->buf = p;
    r->cap = cap;
    return 1;
}

/* Reads more data, moving the unread part to the front and growing the buffer
   when it is full. Returns the number of bytes added (0 at EOF or error). */
static size_t mio_fill(mio_reader *r)
{
    if (r->eof || r->error)
        return 0;
    if (r->start > 0) {
        memmove(r->buf, r->buf + r->start, r->end - r->start);
        r->buf_offset += r->start;
        r->end -= r->start;
        r->start = 0;
    }
    if (r->end + 1 >= r->cap) {
        if (r->cap > SIZE_MAX / 2) {
            r->error = ENOMEM;
            return 0;
        }
        if (!mio_grow(r, r->cap * 2))
            return 0;
    }
    size_t n = fread(r->buf + r->end, 1, r->cap - 1 - r->end, r->f);
    if (n == 0) {
        if (ferror(r->f))
            r->error = errno ? errno : MIO_ERR_UNKNOWN;
        else
            r->eof = 1;
    }
    r->end += n;
    if (n && r->file_size)
        limn_progress(r->ctx, "read", (double)(r->buf_offset + r->end) / (double)r->file_size);
    return n;
}

/* Finds the end of the line at base among bytes [from, avail): *e gets the
   end of its content and *next where the following line starts. A lone '\r'
   (old Mac files) ends a line and "\r\n" is one end, so a '\r' that is the
   last byte read so far waits for the next byte unless the file ends. Returns
   0 when no end is seen yet; *seen then tells how far the bytes are done. */
static int mio_line_end(const char *base, size_t from, size_t avail, int eof, size_t *e,
                        size_t *next, size_t *seen)
{
    const char *nl = memchr(base + from, '\n', avail - from);
    size_t lim = nl ? (size_t)(nl - base) : avail;
    const char *cr = memchr(base + from, '\r', lim - from);
    if (cr) {
        size_t i = (size_t)(cr - base);
        if (i + 1 < avail || eof) {
            *e = i;
            *next = i + 1 < avail && base[i + 1] == '\n' ? i + 2 : i + 1;
            return 1;
        }
        *seen = i;
        return 0;
    }
    if (nl) {
        *e = lim;
        *next = lim + 1;
        return 1;
    }
    *seen = avail;
    return 0;
}

/* A line that cannot be text: NUL bytes (binary data, /dev/zero) or no end
   in sight. Records where and returns NULL for mio_line. */
static char *mio_not_text(mio_reader *r, int error, unsigned long lines)
{
    r->error = error;
    r->error_line = r->next_line + lines;
    return NULL;
}

char *mio_line(mio_reader *r, size_t *len)
{
    size_t scan = 0; /* relative to r->start: bytes already searched */
    unsigned long lines = 0;
    for (;;) {
        char *base = r->buf + r->start;
        size_t avail = r->end - r->start;
        size_t e, next, seen = 0;
        if (!mio_line_end(base, scan, avail, r->eof, &e, &next, &seen)) {
            if (r->error)
                return NULL;
            if (memchr(base + scan, '\0', seen - scan))
                return mio_not_text(r, MIO_ERR_NUL, lines);
            scan = seen;
            if (!r->eof) {
                if (avail >= MIO_MAX_LINE)
                    return mio_not_text(r, MIO_ERR_LONG_LINE, lines);
                mio_fill(r);
                continue;
            }
            if (avail == 0)
                return NULL;
            next = e = avail;
            r->unterminated = 1;
        }
        if (e > scan && memchr(base + scan, '\0', e - scan))
            return mio_not_text(r, MIO_ERR_NUL, lines);
        lines++;
        if (r->continuation && e > 0 && base[e - 1] == '\\' && next > e) {
            memset(base + e - 1, ' ', next - (e - 1));
            scan = next;
            continue;
        }
        if (e > 0 && base[e - 1] == '\\' && r->continuation)
            e--; /* a continuation at the very end of the file */
        base[e] = '\0';
        *len = e;
        r->start += next;
        r->line = r->next_line;
        r->next_line += lines;
        return base;
    }
}

const unsigned char *mio_peek(mio_reader *r, size_t n, size_t *avail)
{
    while (r->end - r->start < n && mio_fill(r))
        ;
    *avail = r->end - r->start < n ? r->end - r->start : n;
    return (const unsigned char *)r->buf + r->start;
}

const unsigned char *mio_bytes(mio_reader *r, size_t n)
{
    while (r->end - r->start < n) {
        if (r->error || r->eof)
            return NULL;
        if (n >= r->cap - 1 && r->start == 0) {
            /* grow to hold n bytes at once (callers bound n by the file size) */
            size_t cap = r->cap;
            while (cap - 1 <= n) {
                if (cap > SIZE_MAX / 2) {
                    r->error = ENOMEM;
                    return NULL;
                }
                cap *= 2;
            }
            if (!mio_grow(r, cap))
                return NULL;
        }
        mio_fill(r);
    }
    const unsigned char *p = (const unsigned char *)r->buf + r->start;
    r->start += n;
    return p;
}

int mio_skip(mio_reader *r, uint64_t n)
{
    while (n) {
        size_t avail = r->end - r->start;
        if (avail == 0) {
            if (!mio_fill(r))
                return 0;
            continue;
        }
        size_t take = avail < n ? avail : (size_t)n;
        r->start += take;
        n -= take;
    }
    return 1;
}

void mio_skip_bom(mio_reader *r)
{
    size_t avail;
    if (mio_offset(r) != 0)
        return;
    const unsigned char *b = mio_peek(r, 3, &avail);
    if (avail == 3 && b[0] == 0xEF && b[1] == 0xBB && b[2] == 0xBF)
        r->start += 3;
}

/* The limit in MiB for messages. */
static double mib(size_t bytes) { return (double)bytes / (1024.0 * 1024.0); }

limn_status mio_read_failed(mio_reader *r)
{
    if (r->error == MIO_ERR_NUL)
        return limn_fail(r->ctx, LIMN_ERR_FORMAT,
                         "%s:%lu: a NUL byte: binary data in a text file (wrong format or "
                         "--input-format?)", r->path, r->error_line);
    if (r->error == MIO_ERR_LONG_LINE)
        return limn_fail(r->ctx, LIMN_ERR_FORMAT,
                         "%s:%lu: a line longer than %.0f MiB: not a text mesh file (wrong "
                         "format or --input-format?)", r->path, r->error_line, mib(MIO_MAX_LINE));
    if (r->error == ENOMEM && r->budget.exceeded)
        return mio_finish(r, LIMN_ERR_MEMORY, 0);
    if (r->error == ENOMEM)
        return limn_fail(r->ctx, LIMN_ERR_MEMORY, "%s: out of memory while reading", r->path);
    return limn_fail(r->ctx, LIMN_ERR_IO, "%s: read error: %s", r->path,
                     r->error > 0 ? strerror(r->error) : "unknown error");
}

limn_status mio_finish(mio_reader *r, limn_status st, int binary)
{
    if (st != LIMN_ERR_MEMORY || !r->budget.exceeded)
        return st;
    char where[64];
    if (binary)
        snprintf(where, sizeof where, ": byte %llu", (unsigned long long)mio_offset(r));
    else
        snprintf(where, sizeof where, ":%lu", r->line ? r->line : 1);
    return limn_fail(r->ctx, LIMN_ERR_MEMORY,
                     "%s%s: reading stopped at the memory limit of %.1f MiB (%.1f MiB held): "
                     "the file needs more; raise --max-memory (limn_context_set_max_memory) "
                     "if it is really this large", r->path, where, mib(r->budget.limit),
                     mib(r->budget.used));
}

/* ----------------------------------------------------------------- numbers */

int mio_parse_double(char **s, double *out)
{
    char *p = *s, *end;
    if (!*p || mio_space(*p))
        return 0;
    double v = strtod(p, &end);
    if (end == p || (*end && !mio_space(*end)))
        return 0;
    if (!isfinite(v))
        return 2;
    *out = v;
    *s = end;
    return 1;
}

int mio_parse_ll(char **s, long long *out, char stop)
{
    char *p = *s, *end;
    if (!((*p >= '0' && *p <= '9') || *p == '-' || *p == '+'))
        return 0;
    errno = 0;
    long long v = strtoll(p, &end, 10);
    if (end == p || errno == ERANGE)
        return 0;
    if (*end && !mio_space(*end) && !(stop && *end == stop))
        return 0;
    *out = v;
    *s = end;
    return 1;
}

const char *mio_token(const char *s, char buf[64])
{
    size_t n = 0;
    buf[n++] = '\'';
    while (*s && !mio_space(*s) && n < 41) {
        unsigned char c = (unsigned char)*s++;
        buf[n++] = (c >= 32 && c < 127) ? (char)c : '?';
    }
    if (*s && !mio_space(*s)) {
        memcpy(buf + n, "...", 3);
        n += 3;
    }
    buf[n++] = '\'';
    buf[n] = '\0';
    return buf;
}

/* -------------------------------------------------------------- mesh build */

limn_status mio_make_mesh(limn_context *ctx, growbuf *pos, growbuf *offsets, growbuf *indices,
                          growbuf *colors, limn_mesh **out)
{
    size_t nv = pos->len / (3 * sizeof(double));
    size_t nf = offsets->len / sizeof(uint32_t) - 1;
    limn_mesh *m;
    limn_status st = mesh_alloc(ctx, 0, 0, 0, &m);
    if (st)
        return st;
    free(m->positions);
    free(m->face_offsets);
    free(m->face_indices);
    m->positions = growbuf_take(pos);
    m->face_offsets = growbuf_take(offsets);
    m->face_indices = growbuf_take(indices);
    m->colors = colors->len ? growbuf_take(colors) : NULL;
    m->vertex_count = nv;
    m->face_count = nf;
    if (!m->positions || !m->face_offsets || !m->face_indices) {
        limn_mesh_destroy(m);
        return limn_fail(ctx, LIMN_ERR_MEMORY, "out of memory for a mesh");
    }
    *out = m;
    return LIMN_OK;
}

limn_status mio_write_failed(limn_context *ctx, const char *path)
{
    int e = errno;
    return limn_fail(ctx, LIMN_ERR_IO, "cannot write %s: %s", path,
                     e ? strerror(e) : "write error");
}

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
        return limn_fail(ctx, LIMN_ERR_ARGUMENT,
                         "%s: unknown mesh file extension '%.20s' (accepted: .obj, .ply, .off, "
                         ".stl)",
                         path, dot);
    }
    return limn_fail(ctx, LIMN_ERR_ARGUMENT,
                     "%s: no file extension to tell the mesh format (accepted: .obj, .ply, .off, "
                     ".stl)",
                     path);
}

/* A pipe or device has no size to check counts against and may never end:
   read only when its format is named. */
static limn_status not_regular(limn_context *ctx, const char *path, mode_t mode)
{
    return limn_fail(ctx, LIMN_ERR_IO,
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
        return limn_fail(ctx, LIMN_ERR_IO, "cannot read %s: %s", path, strerror(errno));
    if (S_ISDIR(sb.st_mode))
        return limn_fail(ctx, LIMN_ERR_IO, "cannot read %s: it is a directory", path);
    if (S_ISREG(sb.st_mode) && sb.st_size == 0)
        return limn_fail(ctx, LIMN_ERR_FORMAT, "%s: the file is empty", path);
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
        st = limn_fail(ctx, LIMN_ERR_FORMAT, "%s: the file defines no vertices", path);
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
        return limn_fail(ctx, LIMN_ERR_ARGUMENT, "limn_mesh_read: unknown format %d",
                         (int)format);
    FILE *f = fopen(path, "rb");
    if (!f)
        return limn_fail(ctx, LIMN_ERR_IO, "cannot open %s: %s", path, strerror(errno));
    st = read_checked(ctx, path, format, given, f, out);
    fclose(f);
    return st;
}

limn_status limn_mesh_read(limn_context *ctx, const char *path, limn_format format,
                           limn_mesh **out)
{
    limn_clear(ctx);
    if (!out)
        return limn_fail(ctx, LIMN_ERR_ARGUMENT, "limn_mesh_read: out is NULL");
    *out = NULL;
    if (!path || !*path)
        return limn_fail(ctx, LIMN_ERR_ARGUMENT, "limn_mesh_read: no file name");
    c_locale_scope loc;
    if (!c_locale_enter(&loc))
        return limn_fail(ctx, LIMN_ERR_MEMORY, "%s: out of memory for the C locale", path);
    limn_status st = mesh_read(ctx, path, format, out);
    c_locale_leave(&loc);
    return st;
}

limn_status limn_mesh_read_stream(limn_context *ctx, FILE *stream, const char *name,
                                  limn_format format, limn_mesh **out)
{
    limn_clear(ctx);
    if (!out)
        return limn_fail(ctx, LIMN_ERR_ARGUMENT, "limn_mesh_read_stream: out is NULL");
    *out = NULL;
    if (!name || !*name)
        name = "(stream)";
    if (!stream)
        return limn_fail(ctx, LIMN_ERR_ARGUMENT, "limn_mesh_read_stream: %s: stream is NULL",
                         name);
    if (format == LIMN_FORMAT_AUTO)
        return limn_fail(ctx, LIMN_ERR_ARGUMENT,
                         "%s: a stream has no file extension to tell the mesh format: name "
                         "the format (obj, ply, off, stl)",
                         name);
    if (format < LIMN_FORMAT_OBJ || format > LIMN_FORMAT_STL)
        return limn_fail(ctx, LIMN_ERR_ARGUMENT, "limn_mesh_read_stream: unknown format %d",
                         (int)format);
    c_locale_scope loc;
    if (!c_locale_enter(&loc))
        return limn_fail(ctx, LIMN_ERR_MEMORY, "%s: out of memory for the C locale", name);
    limn_status st = read_checked(ctx, name, format, 1, stream, out);
    c_locale_leave(&loc);
    return st;
}

/* ------------------------------------------------------------------ write */

limn_status mesh_write_staged(limn_context *ctx, const limn_mesh *mesh, const char *path,
                              limn_format format, atomic_file *af)
{
    memset(af, 0, sizeof *af);
    if (!mesh || !path || !*path)
        return limn_fail(ctx, LIMN_ERR_ARGUMENT, "limn_mesh_write: %s is NULL or empty",
                         !mesh ? "mesh" : "path");
    limn_status st;
    if (format == LIMN_FORMAT_AUTO && (st = format_from_path(ctx, path, &format)))
        return st;
    if (format < LIMN_FORMAT_OBJ || format > LIMN_FORMAT_STL)
        return limn_fail(ctx, LIMN_ERR_ARGUMENT, "limn_mesh_write: unknown format %d",
                         (int)format);
    st = check_mesh_writable(ctx, mesh, format); /* before any file exists */
    if (st)
        return st;
    st = atomic_file_open(ctx, path, af);
    if (st)
        return st;
    c_locale_scope loc; /* "%.17g" with a '.', whatever the host's locale */
    if (!c_locale_enter(&loc))
        st = limn_fail(ctx, LIMN_ERR_MEMORY, "%s: out of memory for the C locale", path);
    else if (format == LIMN_FORMAT_OBJ)
        st = obj_write(ctx, mesh, path, af->f);
    else if (format == LIMN_FORMAT_OFF)
        st = off_write(ctx, mesh, path, af->f);
    else if (format == LIMN_FORMAT_STL)
        st = stl_write(ctx, mesh, path, af->f);
    else
        st = ply_write(ctx, mesh, path, af->f, format);
    c_locale_leave(&loc);
    if (st) {
        atomic_file_abort(af);
        return st;
    }
    return atomic_file_finish(ctx, af);
}

limn_status limn_mesh_write(limn_context *ctx, const limn_mesh *mesh, const char *path,
                            limn_format format)
{
    limn_clear(ctx);
    atomic_file af;
    limn_status st = mesh_write_staged(ctx, mesh, path, format, &af);
    return st ? st : atomic_file_commit(ctx, &af);
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
