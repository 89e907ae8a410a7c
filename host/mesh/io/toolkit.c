/* SPDX-License-Identifier: MIT */
/*
 * The reader toolkit of the mesh file formats (toolkit.h): the buffered
 * reader, number parsing and the mesh built from reader buffers. The public
 * entry points and format detection are in dispatch.c.
 */
#ifndef _POSIX_C_SOURCE
#define _POSIX_C_SOURCE 200809L /* fileno */
#endif

#include "mesh/io/toolkit.h"
#include "base/context.h"
#include "base/large_alloc.h"
#include "mesh/mesh.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

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
        ctx_fail(ctx, LIMN_ERR_MEMORY,
                  "%s: the memory limit of %zu bytes does not hold the %zu-byte read buffer: "
                  "raise --max-memory (limn_context_set_max_memory)", path, r->budget.limit,
                  r->cap);
        return 0;
    }
    if (!(r->buf = malloc(r->cap))) {
        ctx_fail(ctx, LIMN_ERR_MEMORY, "%s: out of memory for a read buffer", path);
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
        ctx_progress(r->ctx, "read", (double)(r->buf_offset + r->end) / (double)r->file_size);
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

int mio_jump(mio_reader *r, uint64_t offset)
{
    if (offset > (uint64_t)INT64_MAX || fseeko(r->f, (off_t)offset, SEEK_SET) != 0)
        return 0;
    r->buf_offset = offset;
    r->start = r->end = 0;
    r->eof = 0;
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
        return ctx_fail(r->ctx, LIMN_ERR_FORMAT,
                         "%s:%lu: a NUL byte: binary data in a text file (wrong format or "
                         "--input-format?)", r->path, r->error_line);
    if (r->error == MIO_ERR_LONG_LINE)
        return ctx_fail(r->ctx, LIMN_ERR_FORMAT,
                         "%s:%lu: a line longer than %.0f MiB: not a text mesh file (wrong "
                         "format or --input-format?)", r->path, r->error_line, mib(MIO_MAX_LINE));
    if (r->error == ENOMEM && r->budget.exceeded)
        return mio_finish(r, LIMN_ERR_MEMORY, 0);
    if (r->error == ENOMEM)
        return ctx_fail(r->ctx, LIMN_ERR_MEMORY, "%s: out of memory while reading", r->path);
    return ctx_fail(r->ctx, LIMN_ERR_IO, "%s: read error: %s", r->path,
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
    return ctx_fail(r->ctx, LIMN_ERR_MEMORY,
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

void mio_arrays_init(mio_arrays *a, mio_reader *r)
{
    a->pos.budget = a->col.budget = a->offsets.budget = a->indices.budget = &r->budget;
}

void mio_arrays_free(mio_arrays *a)
{
    growbuf_free(&a->pos);
    growbuf_free(&a->col);
    growbuf_free(&a->offsets);
    growbuf_free(&a->indices);
}

int mio_array_exact(growbuf *g, size_t n)
{
    if (!growbuf_budget_take(g->budget, n))
        return 0;
    if (!(g->data = large_malloc(n))) {
        growbuf_budget_give(g->budget, n);
        return 0;
    }
    g->len = g->cap = n;
    return 1;
}

limn_status mio_make_mesh(limn_context *ctx, mio_arrays *a, limn_mesh **out)
{
    size_t nv = a->pos.len / (3 * sizeof(double));
    size_t nf = a->offsets.len / sizeof(uint32_t) - 1;
    limn_mesh *m;
    limn_status st = mesh_alloc(ctx, 0, 0, 0, &m);
    if (st)
        return st;
    free(m->positions);
    m->positions = growbuf_take(&a->pos);
    mesh_faces_replace(m, nf, growbuf_take(&a->offsets), growbuf_take(&a->indices));
    m->colors = a->col.len ? growbuf_take(&a->col) : NULL;
    m->vertex_count = nv;
    if (!m->positions || !m->face_offsets || !m->face_indices) {
        limn_mesh_destroy(m);
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for a mesh");
    }
    *out = m;
    return LIMN_OK;
}

limn_status mio_read(mio_reader *r, mio_arrays *a, limn_context *ctx, const char *path, FILE *f,
                     mio_parse_fn parse, void *state, limn_mesh **out)
{
    if (!mio_init(r, ctx, path, f))
        return LIMN_ERR_MEMORY;
    mio_arrays_init(a, r);
    int binary = 0;
    limn_status st = parse(state, &binary);
    if (!st)
        st = mio_make_mesh(ctx, a, out);
    st = mio_finish(r, st, binary);
    mio_arrays_free(a);
    mio_free(r);
    return st;
}

limn_status mio_write_failed(limn_context *ctx, const char *path)
{
    int e = errno;
    return ctx_fail(ctx, LIMN_ERR_IO, "cannot write %s: %s", path,
                     e ? strerror(e) : "write error");
}
