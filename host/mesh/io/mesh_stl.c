/* SPDX-License-Identifier: MIT */
/*
 * STL: ascii (solid / facet normal / outer loop / vertex / endloop / endfacet
 * / endsolid, keywords in any case, several solids in one file) and binary
 * (80-byte header, uint32 triangle count, 50-byte records, little endian).
 *
 * Binary or ascii is told by content, not by the first word: many binary
 * files start their header with "solid". A file is binary when its size is
 * exactly 84 + 50 * count, or when it does not start with "solid", or when
 * its first 84 bytes hold something that is not text; otherwise ascii. The
 * declared count is checked against the file size before anything is
 * allocated.
 *
 * STL has no shared vertices: corners with exactly equal coordinates are
 * welded into one vertex (hash on the coordinates; -0 equals +0), and the
 * counts are reported as a warning. Triangles that weld two corners into one
 * vertex are kept; the repair step (limn_mesh_repair) removes them.
 * Facet normals are ignored (they may be anything, "nan" included).
 */
#include "mesh/io/formats.h"
#include "base/context.h"
#include "mesh/mesh.h"
#include "mesh/io/toolkit.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#define STL_HEADER 84
#define STL_RECORD 50

typedef struct stl {
    mio_reader r;
    limn_context *ctx;
    const char *path;
    mio_arrays a;
    uint32_t *slots;          /* hash table of vertex index + 1; 0 = empty */
    size_t cap;               /* power of two */
    size_t nv;
    uint64_t corners;
    char *tok;                /* ascii: the rest of the current line */
} stl;

/* ------------------------------------------------------------------ welding */

static uint64_t hash_coords(const double c[3])
{
    uint64_t h = 0x9e3779b97f4a7c15ULL;
    for (int k = 0; k < 3; k++) {
        uint64_t u;
        memcpy(&u, &c[k], sizeof u);
        h ^= u + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2);
        h ^= h >> 31;
        h *= 0xbf58476d1ce4e5b9ULL;
    }
    return h ^ (h >> 29);
}

static int weld_grow(stl *s)
{
    size_t cap = s->cap ? s->cap * 2 : 1024;
    if (!growbuf_budget_take(&s->r.budget, (cap - s->cap) * sizeof(uint32_t)))
        return 0;
    uint32_t *slots = calloc(cap, sizeof *slots);
    if (!slots)
        return 0;
    const double *p = (const double *)s->a.pos.data;
    for (size_t v = 0; v < s->nv; v++) {
        size_t i = (size_t)hash_coords(p + 3 * v) & (cap - 1);
        while (slots[i])
            i = (i + 1) & (cap - 1);
        slots[i] = (uint32_t)(v + 1);
    }
    free(s->slots);
    s->slots = slots;
    s->cap = cap;
    return 1;
}

/* The vertex at c (finite), added when new; 0 when out of memory or space. */
static int weld(stl *s, double c[3], uint32_t *index)
{
    for (int k = 0; k < 3; k++)
        if (c[k] == 0.0)
            c[k] = 0.0; /* -0 and +0 are one position */
    if ((s->nv + 1) * 2 > s->cap && !weld_grow(s))
        return 0;
    const double *p = (const double *)s->a.pos.data;
    size_t i = (size_t)hash_coords(c) & (s->cap - 1);
    while (s->slots[i]) {
        const double *q = p + 3 * (s->slots[i] - 1);
        if (q[0] == c[0] && q[1] == c[1] && q[2] == c[2]) {
            *index = s->slots[i] - 1;
            return 1;
        }
        i = (i + 1) & (s->cap - 1);
    }
    if (s->nv >= UINT32_MAX - 1 || !growbuf_push_3d(&s->a.pos, c[0], c[1], c[2]))
        return 0;
    s->slots[i] = (uint32_t)(s->nv + 1);
    *index = (uint32_t)s->nv++;
    return 1;
}

static int add_face(stl *s, const uint32_t *v, size_t n)
{
    if (s->a.indices.len / sizeof(uint32_t) > UINT32_MAX - n ||
        s->a.offsets.len / sizeof(uint32_t) >= UINT32_MAX - 1)
        return 0;
    if (!growbuf_append(&s->a.indices, v, n * sizeof *v) ||
        !growbuf_push_u32(&s->a.offsets, (uint32_t)(s->a.indices.len / sizeof(uint32_t))))
        return 0;
    s->corners += n;
    return 1;
}

/* ------------------------------------------------------------------- binary */

static float le_float(const unsigned char *b)
{
    uint32_t u = (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 |
                 (uint32_t)b[3] << 24;
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

static limn_status stl_binary(stl *s)
{
    mio_reader *r = &s->r;
    const unsigned char *h = mio_bytes(r, STL_HEADER);
    if (!h)
        return r->error ? mio_read_failed(r)
                        : ctx_fail(s->ctx, LIMN_ERR_FORMAT,
                                    "%s: binary STL: the file ends inside the 84-byte header",
                                    s->path);
    uint32_t count = (uint32_t)h[80] | (uint32_t)h[81] << 8 | (uint32_t)h[82] << 16 |
                     (uint32_t)h[83] << 24;
    uint64_t need = STL_HEADER + (uint64_t)STL_RECORD * count, size = r->file_size;
    if (size && size < need)
        return ctx_fail(s->ctx, LIMN_ERR_FORMAT,
                         "%s: binary STL: the header declares %lu triangles (%llu bytes) but the "
                         "file has %llu bytes (truncated?)",
                         s->path, (unsigned long)count, (unsigned long long)need,
                         (unsigned long long)size);
    if (count == 0)
        return ctx_fail(s->ctx, LIMN_ERR_FORMAT, "%s: binary STL: the header declares no triangles",
                         s->path);
    if (count > (UINT32_MAX - 2) / 3)
        return ctx_fail(s->ctx, LIMN_ERR_FORMAT, "%s: binary STL: too many triangles (%lu)",
                         s->path, (unsigned long)count);
    if (size > need)
        ctx_warn(s->ctx, "%s: %llu bytes after the last of %lu triangles ignored", s->path,
                  (unsigned long long)(size - need), (unsigned long)count);
    size_t reserve = size || count <= 65536 ? count : 65536;
    if (!growbuf_reserve(&s->a.offsets, (reserve + 1) * sizeof(uint32_t)) ||
        !growbuf_reserve(&s->a.indices, reserve * 3 * sizeof(uint32_t)) ||
        !growbuf_reserve(&s->a.pos, reserve / 2 * 3 * sizeof(double)))
        return ctx_fail(s->ctx, LIMN_ERR_MEMORY, "%s: out of memory for %lu triangles", s->path,
                         (unsigned long)count);
    for (uint32_t t = 0; t < count; t++) {
        uint64_t at = mio_offset(r);
        const unsigned char *b = mio_bytes(r, STL_RECORD);
        if (!b)
            return r->error ? mio_read_failed(r)
                            : ctx_fail(s->ctx, LIMN_ERR_FORMAT,
                                        "%s: byte %llu: triangle %lu: the file ends early "
                                        "(truncated)",
                                        s->path, (unsigned long long)at, (unsigned long)t);
        uint32_t v[3];
        for (int k = 0; k < 3; k++) {
            double c[3];
            for (int j = 0; j < 3; j++)
                c[j] = le_float(b + 12 + 12 * k + 4 * j);
            if (!isfinite(c[0]) || !isfinite(c[1]) || !isfinite(c[2]))
                return ctx_fail(s->ctx, LIMN_ERR_FORMAT,
                                 "%s: byte %llu: triangle %lu: vertex %d has a non-finite "
                                 "coordinate",
                                 s->path, (unsigned long long)(at + 12 + 12 * (unsigned)k),
                                 (unsigned long)t, k);
            if (!weld(s, c, &v[k]))
                return ctx_fail(s->ctx, LIMN_ERR_MEMORY, "%s: out of memory at triangle %lu",
                                 s->path, (unsigned long)t);
        }
        if (!add_face(s, v, 3))
            return ctx_fail(s->ctx, LIMN_ERR_MEMORY, "%s: out of memory at triangle %lu",
                             s->path, (unsigned long)t);
    }
    return LIMN_OK;
}

/* -------------------------------------------------------------------- ascii */

/* The next whitespace-separated token (NUL-terminated in place), or NULL at
   the end of the file or on a read error. */
static char *next_token(stl *s)
{
    for (;;) {
        if (s->tok) {
            char *t = mio_skip_space(s->tok);
            if (*t) {
                char *e = t;
                while (*e && !mio_space(*e))
                    e++;
                if (*e)
                    *e++ = '\0';
                s->tok = e;
                return t;
            }
        }
        size_t len;
        if (!(s->tok = mio_line(&s->r, &len)))
            return NULL;
    }
}

static int is_word(const char *t, const char *word) { return t && strcasecmp(t, word) == 0; }

/* Message for a missing token: a read error, the end of the file, or another word. */
static limn_status unexpected(stl *s, const char *t, const char *wanted, unsigned long facet)
{
    char tok[64], where[64] = "";
    if (s->r.error)
        return mio_read_failed(&s->r);
    if (facet)
        snprintf(where, sizeof where, "facet %lu: ", facet - 1);
    if (!t)
        return ctx_fail(s->ctx, LIMN_ERR_FORMAT, "%s:%lu: %sthe file ends %s(truncated)",
                         s->path, s->r.line, where,
                         facet ? "inside the facet " : "without 'endsolid' ");
    return ctx_fail(s->ctx, LIMN_ERR_FORMAT, "%s:%lu: %sexpected %s, found %s", s->path,
                     s->r.line, where, wanted, mio_token(t, tok));
}

/* The coordinates after 'vertex' in facet f - 1, welded and added to loop. */
static limn_status stl_vertex(stl *s, unsigned long f, growbuf *loop)
{
    double c[3];
    for (int k = 0; k < 3; k++) {
        char tok[64];
        char *p = next_token(s);
        if (!p)
            return unexpected(s, p, "a coordinate", f);
        int rc = mio_parse_double(&p, &c[k]);
        if (rc != 1)
            return ctx_fail(s->ctx, LIMN_ERR_FORMAT, "%s:%lu: facet %lu: coordinate %s is %s",
                            s->path, s->r.line, f - 1, mio_token(p, tok),
                            rc == 2 ? "not finite" : "not a number");
    }
    uint32_t v;
    if (!weld(s, c, &v) || !growbuf_push_u32(loop, v))
        return ctx_fail(s->ctx, LIMN_ERR_MEMORY, "%s:%lu: out of memory", s->path, s->r.line);
    return LIMN_OK;
}

/* Facet f - 1 after its 'facet' word, through 'endfacet', added as a face
   (loop: room for its vertices). */
static limn_status stl_facet(stl *s, unsigned long f, growbuf *loop)
{
    char *t = next_token(s);
    if (is_word(t, "normal")) {
        for (int k = 0; k < 3 && t; k++)
            t = next_token(s);
        if (t)
            t = next_token(s);
    }
    if (!is_word(t, "outer") || !is_word(t = next_token(s), "loop"))
        return unexpected(s, t, "'outer loop'", f);
    loop->len = 0;
    while (is_word(t = next_token(s), "vertex")) {
        limn_status st = stl_vertex(s, f, loop);
        if (st)
            return st;
    }
    if (!is_word(t, "endloop"))
        return unexpected(s, t, "'vertex' or 'endloop'", f);
    size_t n = loop->len / sizeof(uint32_t);
    if (n < 3)
        return ctx_fail(s->ctx, LIMN_ERR_FORMAT,
                        "%s:%lu: facet %lu has %zu vertices (at least 3 needed)", s->path,
                        s->r.line, f - 1, n);
    if (!is_word(t = next_token(s), "endfacet"))
        return unexpected(s, t, "'endfacet'", f);
    if (!add_face(s, (const uint32_t *)loop->data, n))
        return ctx_fail(s->ctx, LIMN_ERR_MEMORY, "%s:%lu: out of memory or too many facets",
                        s->path, s->r.line);
    return LIMN_OK;
}

static limn_status stl_ascii(stl *s)
{
    char *t = next_token(s);
    if (!is_word(t, "solid"))
        return unexpected(s, t, "'solid'", 0);
    s->tok = NULL; /* the name: rest of the line */
    unsigned long facets = 0;
    growbuf loop = {0};
    limn_status st = LIMN_OK;
    for (;;) {
        t = next_token(s);
        if (is_word(t, "endsolid")) {
            s->tok = NULL;
            if (!(t = next_token(s)))
                break;
            if (!is_word(t, "solid")) {
                st = unexpected(s, t, "'solid' or the end of the file after 'endsolid'", 0);
                break;
            }
            s->tok = NULL;
            continue;
        }
        if (!is_word(t, "facet")) {
            st = unexpected(s, t, "'facet' or 'endsolid'", 0);
            break;
        }
        if ((st = stl_facet(s, ++facets, &loop))) /* facet number + 1, for messages */
            break;
    }
    growbuf_free(&loop);
    if (!st && s->r.error)
        st = mio_read_failed(&s->r);
    if (!st && facets == 0)
        st = ctx_fail(s->ctx, LIMN_ERR_FORMAT, "%s: the STL file has no facets", s->path);
    return st;
}

/* ------------------------------------------------------------------- detect */

static int starts_with_solid(const unsigned char *b, size_t n)
{
    size_t i = 0;
    while (i < n && (b[i] == ' ' || b[i] == '\t' || b[i] == '\r' || b[i] == '\n'))
        i++;
    return n - i >= 5 && strncasecmp((const char *)b + i, "solid", 5) == 0 &&
           (n - i == 5 || b[i + 5] == ' ' || b[i + 5] == '\t' || b[i + 5] == '\r' ||
            b[i + 5] == '\n');
}

static int all_text(const unsigned char *b, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if ((b[i] < 32 && b[i] != '\n' && b[i] != '\r' && b[i] != '\t' && b[i] != '\f' &&
             b[i] != '\v') ||
            b[i] == 127)
            return 0;
    return 1;
}

/* Tells a binary STL (*binary = 1) from an ascii one by its first bytes. */
static limn_status stl_detect(stl *s, int *binary)
{
    size_t avail;
    const unsigned char *head = mio_peek(&s->r, STL_HEADER, &avail);
    /* an ascii file may start with a UTF-8 byte order mark; a binary header too,
       which the size rule below still tells */
    size_t bom = avail >= 3 && head[0] == 0xEF && head[1] == 0xBB && head[2] == 0xBF ? 3 : 0;
    int solid = starts_with_solid(head + bom, avail - bom);
    *binary = 0;
    if (s->r.error)
        return mio_read_failed(&s->r);
    if (avail < STL_HEADER) {
        if (!solid)
            return ctx_fail(s->ctx, LIMN_ERR_FORMAT,
                            "%s: not an STL file: %zu bytes, too short for a binary STL (84-byte "
                            "header), and it does not start with 'solid'",
                            s->path, avail);
        return LIMN_OK;
    }
    uint32_t count = (uint32_t)head[80] | (uint32_t)head[81] << 8 | (uint32_t)head[82] << 16 |
                     (uint32_t)head[83] << 24;
    int exact = s->r.file_size == STL_HEADER + (uint64_t)STL_RECORD * count;
    *binary = exact || !solid || !all_text(head, STL_HEADER);
    return LIMN_OK;
}

static limn_status stl_parse(void *state, int *binary)
{
    stl *s = state;
    limn_status st = stl_detect(s, binary);
    if (st)
        return st;
    if (!growbuf_push_u32(&s->a.offsets, 0))
        return ctx_fail(s->ctx, LIMN_ERR_MEMORY, "%s: out of memory", s->path);
    if (!*binary)
        mio_skip_bom(&s->r);
    st = *binary ? stl_binary(s) : stl_ascii(s);
    if (st)
        return st;
    size_t faces = s->a.offsets.len / sizeof(uint32_t) - 1;
    ctx_warn(s->ctx,
              "%s: %zu %s, %llu corners welded into %zu vertices (exactly equal coordinates)",
              s->path, faces, *binary ? "triangles" : "facets", (unsigned long long)s->corners,
              s->nv);
    return LIMN_OK;
}

limn_status stl_read(limn_context *ctx, const char *path, FILE *f, limn_mesh **out)
{
    stl *s = calloc(1, sizeof *s);
    if (!s)
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "%s: out of memory", path);
    s->ctx = ctx;
    s->path = path;
    limn_status st = mio_read(&s->r, &s->a, ctx, path, f, stl_parse, s, out);
    free(s->slots);
    free(s);
    return st;
}
