/* SPDX-License-Identifier: MIT */
/*
 * PLY (Stanford): ascii, binary little and big endian. Reads the vertex
 * element (x, y, z of any scalar type, optional uchar red/green/blue, other
 * properties skipped and named in one warning), a `face` element (list vertex_indices / vertex_index)
 * and/or a `tristrips` element (strips separated by -1), and skips every other
 * element. Counts in the header are checked against the file size before
 * anything is allocated. Binary files of the common layout are read by the
 * fast path (mesh_ply_fast.c), ascii ones of one record a line by
 * mesh_ply_text_fast.c; both hand back to this reader whatever they do not
 * handle. The writer is mesh_ply_write.c.
 */
#include "mesh/io/formats.h"
#include "base/context.h"
#include "mesh/mesh.h"
#include "mesh/io/mesh_ply.h"
#include "mesh/io/toolkit.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

const unsigned char ply_type_size[T_COUNT] = {0, 1, 1, 2, 2, 4, 4, 4, 8};
static const char *const type_names[T_COUNT][2] = {
    {"", ""},          {"char", "int8"},   {"uchar", "uint8"},   {"short", "int16"},
    {"ushort", "uint16"}, {"int", "int32"}, {"uint", "uint32"}, {"float", "float32"},
    {"double", "float64"},
};
static const long long type_min[T_COUNT] = {0, -128, 0, -32768, 0, -2147483647LL - 1, 0, 0, 0};
const long long ply_type_max[T_COUNT] = {0, 127, 255, 32767, 65535, 2147483647LL, 4294967295LL,
                                         0, 0};

static const char *const role_names[R_COUNT] = {"", "x", "y", "z", "red", "green", "blue",
                                                 "vertex_indices"};

static limn_status ply_err(ply *p, limn_status st, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;
static limn_status ply_err(ply *p, limn_status st, const char *fmt, ...)
{
    char msg[1024], where[160] = "";
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    if (p->elem)
        snprintf(where, sizeof where, "%s %llu: ", p->elem->name, (unsigned long long)p->index);
    if (p->format == F_ASCII || p->in_header)
        return ctx_fail(p->ctx, st, "%s:%lu: %s%s", p->path, p->r.line, where, msg);
    return ctx_fail(p->ctx, st, "%s: byte %llu: %s%s", p->path, (unsigned long long)p->at,
                     where, msg);
}

static limn_status ply_truncated(ply *p)
{
    if (p->r.error)
        return mio_read_failed(&p->r);
    return ply_err(p, LIMN_ERR_FORMAT, "the file ends early (truncated)");
}

/* ------------------------------------------------------------------ values */

static uint64_t load(const unsigned char *b, unsigned n, int big)
{
    uint64_t v = 0;
    if (big)
        for (unsigned i = 0; i < n; i++)
            v = v << 8 | b[i];
    else
        for (unsigned i = n; i-- > 0;)
            v = v << 8 | b[i];
    return v;
}

long long ply_bin_int(const unsigned char *b, int t, int big)
{
    uint64_t v = load(b, ply_type_size[t], big);
    switch (t) {
    case T_I8: return v >= 0x80 ? (long long)v - 0x100 : (long long)v;
    case T_I16: return v >= 0x8000 ? (long long)v - 0x10000 : (long long)v;
    case T_I32: return v >= 0x80000000u ? (long long)v - 0x100000000LL : (long long)v;
    default: return (long long)v;
    }
}

double ply_bin_double(const unsigned char *b, int t, int big)
{
    if (t == T_F32) {
        uint32_t u = (uint32_t)load(b, 4, big);
        float f;
        memcpy(&f, &u, 4);
        return f;
    }
    if (t == T_F64) {
        uint64_t u = load(b, 8, big);
        double d;
        memcpy(&d, &u, 8);
        return d;
    }
    return (double)ply_bin_int(b, t, big);
}

/* ascii: the next token (NULL at the end of the file) */
static char *ply_token(ply *p)
{
    for (;;) {
        if (p->tok) {
            p->tok = mio_skip_space(p->tok);
            if (*p->tok)
                return p->tok;
        }
        size_t len;
        if (!(p->tok = mio_line(&p->r, &len)))
            return NULL;
    }
}

/* The next scalar of type t: its bytes in *b (binary; p->at is where) or
   its token in *s (ascii), the other one NULL; or the truncation message. */
static limn_status ply_next(ply *p, int t, const unsigned char **b, char **s)
{
    *b = NULL;
    *s = NULL;
    if (p->format != F_ASCII) {
        p->at = mio_offset(&p->r);
        *b = mio_bytes(&p->r, ply_type_size[t]);
        return *b ? LIMN_OK : ply_truncated(p);
    }
    *s = ply_token(p);
    return *s ? LIMN_OK : ply_truncated(p);
}

static limn_status ply_int(ply *p, int t, long long *v)
{
    char tok[64], *s;
    const unsigned char *b;
    limn_status st = ply_next(p, t, &b, &s);
    if (st)
        return st;
    if (b) {
        *v = ply_bin_int(b, t, p->format == F_BE);
        return LIMN_OK;
    }
    if (!mio_parse_ll(&p->tok, v, 0))
        return ply_err(p, LIMN_ERR_FORMAT, "%s is not an integer", mio_token(s, tok));
    if (*v < type_min[t] || *v > ply_type_max[t])
        return ply_err(p, LIMN_ERR_FORMAT, "%lld is out of range for type %s", *v,
                       type_names[t][0]);
    return LIMN_OK;
}

static limn_status ply_double(ply *p, int t, double *v)
{
    char tok[64], *s;
    const unsigned char *b;
    limn_status st = ply_next(p, t, &b, &s);
    if (st)
        return st;
    if (b) {
        *v = ply_bin_double(b, t, p->format == F_BE);
        if (!isfinite(*v))
            return ply_err(p, LIMN_ERR_FORMAT, "a coordinate is not finite");
        return LIMN_OK;
    }
    int rc = mio_parse_double(&p->tok, v);
    if (rc != 1)
        return ply_err(p, LIMN_ERR_FORMAT, "coordinate %s is %s", mio_token(s, tok),
                       rc == 2 ? "not finite" : "not a number");
    return LIMN_OK;
}

/* Skips n scalars of type t. */
static limn_status ply_skip(ply *p, int t, uint64_t n)
{
    if (p->format != F_ASCII) {
        p->at = mio_offset(&p->r);
        return n <= UINT64_MAX / 8 && mio_skip(&p->r, n * ply_type_size[t]) ? LIMN_OK
                                                                        : ply_truncated(p);
    }
    for (uint64_t i = 0; i < n; i++) {
        char *s = ply_token(p);
        if (!s)
            return ply_truncated(p);
        while (*s && !mio_space(*s))
            s++;
        p->tok = s;
    }
    return LIMN_OK;
}

/* Reads a list count and checks it against what is left of the file. */
static limn_status ply_list_count(ply *p, const ply_prop *pr, long long *n)
{
    limn_status st = ply_int(p, pr->count_type, n);
    if (st)
        return st;
    if (*n < 0)
        return ply_err(p, LIMN_ERR_FORMAT, "list count %lld is negative", *n);
    uint64_t left = mio_remaining(&p->r);
    uint64_t least = p->format == F_ASCII ? 2 : ply_type_size[pr->type];
    if (p->format == F_ASCII && left != UINT64_MAX)
        left += strlen(p->tok) + 1;
    if (left != UINT64_MAX && (uint64_t)*n > left / least)
        return ply_err(p, LIMN_ERR_FORMAT,
                       "list count %lld is larger than the rest of the file (%llu bytes) allows",
                       *n, (unsigned long long)left);
    return LIMN_OK;
}

/* ------------------------------------------------------------------ header */

static int type_from_name(const char *s)
{
    for (int t = 1; t < T_COUNT; t++)
        if (strcmp(s, type_names[t][0]) == 0 || strcmp(s, type_names[t][1]) == 0)
            return t;
    return T_NONE;
}

/* Remembers a vertex property that is read past, to name it in a warning. */
static void ply_note_dropped(ply *p, const char *name)
{
    size_t len = strlen(p->dropped), room = sizeof p->dropped - len;
    if (p->ndropped++ == 0)
        snprintf(p->dropped, sizeof p->dropped, "'%.40s'", name);
    else if (room > 50)
        snprintf(p->dropped + len, room, ", '%.40s'", name);
    else if (room > 5 && !strstr(p->dropped, "..."))
        snprintf(p->dropped + len, room, ", ...");
}

static limn_status ply_property(ply *p, char **w, int nw)
{
    ply_elem *e = &p->elems[p->nelems - 1];
    ply_prop pr = {T_NONE, T_NONE, R_OTHER};
    const char *name;
    int list = nw >= 2 && strcmp(w[1], "list") == 0;
    if (list ? nw != 5 : nw != 3)
        return ply_err(p, LIMN_ERR_FORMAT, "expected 'property TYPE NAME' or "
                                           "'property list COUNT_TYPE ITEM_TYPE NAME'");
    const char *tn = list ? w[3] : w[1];
    if (!(pr.type = (unsigned char)type_from_name(tn)) ||
        (list && !(pr.count_type = (unsigned char)type_from_name(w[2]))))
        return ply_err(p, LIMN_ERR_FORMAT, "unknown property type '%.40s'",
                       pr.type ? w[2] : tn);
    if (list && !IS_INT(pr.count_type))
        return ply_err(p, LIMN_ERR_FORMAT, "list count type '%s' is not an integer type",
                       w[2]);
    name = list ? w[4] : w[2];
    if (e->kind == E_VERTEX) {
        for (int r = R_X; r <= R_BLUE; r++)
            if (strcmp(name, role_names[r]) == 0)
                pr.role = (unsigned char)r;
        if (pr.role == R_OTHER)
            ply_note_dropped(p, name);
        if (pr.role >= R_X && pr.role <= R_Z && list)
            return ply_err(p, LIMN_ERR_FORMAT, "vertex property '%s' is a list", name);
        if (pr.role >= R_RED && (list || pr.type != T_U8)) {
            ctx_warn(p->ctx, "%s:%lu: vertex colour '%s' is not uchar; colours ignored",
                      p->path, p->r.line, name);
            pr.role = R_OTHER;
        }
    } else if ((e->kind == E_FACE || e->kind == E_TRISTRIPS) &&
               (strcmp(name, "vertex_indices") == 0 || strcmp(name, "vertex_index") == 0)) {
        if (!list || !IS_INT(pr.type))
            return ply_err(p, LIMN_ERR_FORMAT, "'%s' must be a list of an integer type", name);
        pr.role = R_INDICES;
    }
    if (pr.role && e->roles[pr.role])
        return ply_err(p, LIMN_ERR_FORMAT, "the '%s' element has two '%s' properties", e->name,
                       name);
    if (e->nprops >= PLY_MAX_PROPERTIES)
        return ply_err(p, LIMN_ERR_FORMAT, "too many properties (limit %d)", PLY_MAX_PROPERTIES);
    ply_prop *grown = realloc(e->props, (e->nprops + 1) * sizeof *grown);
    if (!grown)
        return ply_err(p, LIMN_ERR_MEMORY, "out of memory");
    e->props = grown;
    e->props[e->nprops++] = pr;
    e->roles[pr.role]++;
    e->has_list |= list;
    e->min_size += p->format == F_ASCII ? 2 : ply_type_size[list ? pr.count_type : pr.type];
    return LIMN_OK;
}

/* Splits a header line into at most 6 words (NUL-terminated in place). */
static int ply_words(char *s, char *w[6])
{
    int nw = 0;
    while (nw < 6) {
        s = mio_skip_space(s);
        if (!*s)
            break;
        w[nw++] = s;
        while (*s && !mio_space(*s))
            s++;
        if (*s)
            *s++ = '\0';
    }
    return nw;
}

static limn_status ply_format(ply *p, char **w, int nw)
{
    static const char *const formats[] = {"ascii", "binary_little_endian", "binary_big_endian"};
    int fmt = F_NONE;
    for (int i = 0; i < 3 && nw >= 2; i++)
        if (strcmp(w[1], formats[i]) == 0)
            fmt = F_ASCII + i;
    if (p->format != F_NONE)
        return ply_err(p, LIMN_ERR_FORMAT, "a second format line");
    if (nw != 3 || fmt == F_NONE)
        return ply_err(p, LIMN_ERR_FORMAT,
                       "bad format line (expected 'format ascii|binary_little_endian|"
                       "binary_big_endian 1.0')");
    if (strcmp(w[2], "1.0") != 0)
        return ply_err(p, LIMN_ERR_FORMAT, "unsupported PLY version '%.20s' (expected 1.0)",
                       w[2]);
    p->format = fmt;
    return LIMN_OK;
}

static limn_status ply_element(ply *p, char **w, int nw)
{
    char *end = w[0];
    errno = 0;
    unsigned long long count =
        nw == 3 && w[2][0] >= '0' && w[2][0] <= '9' ? strtoull(w[2], &end, 10) : 0;
    if (nw != 3 || w[2][0] < '0' || w[2][0] > '9' || *end || errno == ERANGE)
        return ply_err(p, LIMN_ERR_FORMAT,
                       "expected 'element NAME COUNT' with a non-negative count");
    if (p->nelems >= PLY_MAX_ELEMENTS)
        return ply_err(p, LIMN_ERR_FORMAT, "too many elements (limit %d)", PLY_MAX_ELEMENTS);
    ply_elem *e = &p->elems[p->nelems];
    e->kind = strcmp(w[1], "vertex") == 0      ? E_VERTEX
              : strcmp(w[1], "face") == 0      ? E_FACE
              : strcmp(w[1], "tristrips") == 0 ? E_TRISTRIPS
                                               : E_OTHER;
    for (size_t i = 0; i < p->nelems; i++)
        if (e->kind != E_OTHER && p->elems[i].kind == e->kind)
            return ply_err(p, LIMN_ERR_FORMAT, "a second '%s' element", w[1]);
    snprintf(e->name, sizeof e->name, "%s", w[1]);
    e->count = count;
    p->nelems++;
    return LIMN_OK;
}

/* One header line after the first, split into words; *end set at end_header. */
static limn_status ply_header_line(ply *p, char **w, int nw, int *end)
{
    if (nw == 0 || strcmp(w[0], "comment") == 0 || strcmp(w[0], "obj_info") == 0)
        return LIMN_OK;
    if (strcmp(w[0], "end_header") == 0) {
        *end = 1;
        return LIMN_OK;
    }
    if (strcmp(w[0], "format") == 0)
        return ply_format(p, w, nw);
    if (strcmp(w[0], "element") == 0)
        return ply_element(p, w, nw);
    if (strcmp(w[0], "property") == 0) {
        if (p->nelems == 0)
            return ply_err(p, LIMN_ERR_FORMAT, "a property before any element");
        if (p->format == F_NONE)
            return ply_err(p, LIMN_ERR_FORMAT, "a property before the format line");
        return ply_property(p, w, nw);
    }
    char tok[64];
    return ply_err(p, LIMN_ERR_FORMAT, "unknown header line starting with %s",
                   mio_token(w[0], tok));
}

static limn_status ply_header(ply *p)
{
    mio_reader *r = &p->r;
    size_t len;
    char *line;
    const unsigned char *magic = mio_bytes(r, 3);
    if (!magic || memcmp(magic, "ply", 3) != 0 || !(line = mio_line(r, &len)) ||
        *mio_skip_space(line))
        return r->error ? mio_read_failed(r)
                        : ctx_fail(p->ctx, LIMN_ERR_FORMAT,
                                    "%s:1: not a PLY file (the first line is not 'ply')", p->path);
    for (int end = 0; !end;) {
        if (!(line = mio_line(r, &len)))
            return r->error ? mio_read_failed(r)
                            : ply_err(p, LIMN_ERR_FORMAT, "the header has no end_header line");
        const char *c = mio_skip_space(line);
        if (strncmp(c, "comment limn-slice ", 19) == 0)
            snprintf(p->slice_comment, sizeof p->slice_comment, "%s", c + 19);
        char *w[6];
        int nw = ply_words(line, w);
        limn_status st = ply_header_line(p, w, nw, &end);
        if (st)
            return st;
    }
    if (p->format == F_NONE)
        return ply_err(p, LIMN_ERR_FORMAT, "the header has no format line");
    if (p->ndropped)
        ctx_warn(p->ctx, "%s: %zu vertex %s dropped (limn keeps x, y, z and red, green, "
                          "blue): %s", p->path, p->ndropped,
                  p->ndropped == 1 ? "property" : "properties", p->dropped);
    return LIMN_OK;
}

/* Checks the header's elements against each other and the file size. */
static limn_status ply_check(ply *p)
{
    const ply_elem *v = NULL;
    for (size_t i = 0; i < p->nelems; i++) {
        const ply_elem *e = &p->elems[i];
        if (e->kind == E_VERTEX)
            v = e;
        if ((e->kind == E_FACE || e->kind == E_TRISTRIPS) && !e->roles[R_INDICES])
            return ctx_fail(p->ctx, LIMN_ERR_FORMAT,
                             "%s: the '%s' element has no 'vertex_indices' list", p->path,
                             e->name);
    }
    if (!v)
        return ctx_fail(p->ctx, LIMN_ERR_FORMAT, "%s: the header has no 'vertex' element",
                         p->path);
    for (int r = R_X; r <= R_Z; r++)
        if (!v->roles[r])
            return ctx_fail(p->ctx, LIMN_ERR_FORMAT,
                             "%s: the 'vertex' element has no '%s' property", p->path,
                             role_names[r]);
    p->colors = v->roles[R_RED] && v->roles[R_GREEN] && v->roles[R_BLUE];
    if (v->count >= UINT32_MAX)
        return ctx_fail(p->ctx, LIMN_ERR_FORMAT, "%s: too many vertices (%llu)", p->path,
                         (unsigned long long)v->count);
    p->nv = v->count;
    uint64_t left = mio_remaining(&p->r), need = 0;
    if (left == UINT64_MAX)
        return LIMN_OK;
    for (size_t i = 0; i < p->nelems; i++) {
        const ply_elem *e = &p->elems[i];
        if (e->min_size && (e->count > (UINT64_MAX - need) / e->min_size ||
                            need + e->count * e->min_size > left))
            return ctx_fail(p->ctx, LIMN_ERR_FORMAT,
                             "%s: the header declares %llu '%s' records (at least %llu bytes "
                             "each) but only %llu bytes follow the header", p->path,
                             (unsigned long long)e->count, e->name,
                             (unsigned long long)e->min_size, (unsigned long long)left);
        need += e->count * e->min_size;
    }
    return LIMN_OK;
}

/* ------------------------------------------------------------------ records */

static limn_status ply_vertex(ply *p, const ply_elem *e)
{
    double xyz[3] = {0, 0, 0};
    unsigned char rgb[3] = {0, 0, 0};
    limn_status st = LIMN_OK;
    for (size_t k = 0; k < e->nprops && !st; k++) {
        const ply_prop *pr = &e->props[k];
        long long n;
        if (pr->count_type) {
            if (!(st = ply_list_count(p, pr, &n)))
                st = ply_skip(p, pr->type, (uint64_t)n);
        } else if (pr->role >= R_X && pr->role <= R_Z) {
            st = ply_double(p, pr->type, &xyz[pr->role - R_X]);
        } else if (pr->role >= R_RED && pr->role <= R_BLUE) {
            if (!(st = ply_int(p, T_U8, &n)))
                rgb[pr->role - R_RED] = (unsigned char)n;
        } else {
            st = ply_skip(p, pr->type, 1);
        }
    }
    if (st)
        return st;
    if (!growbuf_push_3d(&p->a.pos, xyz[0], xyz[1], xyz[2]) ||
        (p->colors && !growbuf_append(&p->a.col, rgb, 3)))
        return ply_err(p, LIMN_ERR_MEMORY, "out of memory");
    return LIMN_OK;
}

static limn_status ply_index(ply *p, const ply_prop *pr, long long *v)
{
    limn_status st = ply_int(p, pr->type, v);
    if (st)
        return st;
    if (*v < -1 || *v >= (long long)p->nv || (*v == -1 && p->elem->kind != E_TRISTRIPS))
        return ply_err(p, LIMN_ERR_FORMAT,
                       "references vertex %lld but only %llu vertices are defined", *v,
                       (unsigned long long)p->nv);
    return LIMN_OK;
}

static limn_status ply_add_face(ply *p, const uint32_t *v, size_t n)
{
    if (p->a.indices.len / sizeof(uint32_t) > UINT32_MAX - n ||
        p->a.offsets.len / sizeof(uint32_t) >= UINT32_MAX - 1)
        return ply_err(p, LIMN_ERR_FORMAT, "too many faces");
    if (!growbuf_append(&p->a.indices, v, n * sizeof *v) ||
        !growbuf_push_u32(&p->a.offsets, (uint32_t)(p->a.indices.len / sizeof(uint32_t))))
        return ply_err(p, LIMN_ERR_MEMORY, "out of memory");
    return LIMN_OK;
}

static limn_status ply_face(ply *p, const ply_elem *e)
{
    limn_status st = LIMN_OK;
    for (size_t k = 0; k < e->nprops && !st; k++) {
        const ply_prop *pr = &e->props[k];
        long long n, v;
        if (!pr->count_type) {
            st = ply_skip(p, pr->type, 1);
            continue;
        }
        if ((st = ply_list_count(p, pr, &n)))
            return st;
        if (pr->role != R_INDICES) {
            st = ply_skip(p, pr->type, (uint64_t)n);
        } else if (e->kind == E_FACE) {
            if (n < 3)
                return ply_err(p, LIMN_ERR_FORMAT, "face has %lld vertices (at least 3 needed)",
                               n);
            if (p->a.indices.len / sizeof(uint32_t) > UINT32_MAX - (uint64_t)n ||
                p->a.offsets.len / sizeof(uint32_t) >= UINT32_MAX - 1)
                return ply_err(p, LIMN_ERR_FORMAT, "too many faces");
            for (long long i = 0; i < n; i++) {
                if ((st = ply_index(p, pr, &v)))
                    return st;
                if (!growbuf_push_u32(&p->a.indices, (uint32_t)v))
                    return ply_err(p, LIMN_ERR_MEMORY, "out of memory");
            }
            if (!growbuf_push_u32(&p->a.offsets, (uint32_t)(p->a.indices.len / sizeof(uint32_t))))
                return ply_err(p, LIMN_ERR_MEMORY, "out of memory");
        } else {
            /* tristrips: -1 ends a strip; odd triangles are flipped to keep the
               orientation; triangles that repeat a vertex are dropped */
            uint32_t s[2] = {0, 0};
            long long len = 0;
            for (long long i = 0; i < n; i++) {
                if ((st = ply_index(p, pr, &v)))
                    return st;
                if (v < 0) {
                    len = 0;
                    continue;
                }
                uint32_t c = (uint32_t)v;
                if (len >= 2 && s[0] != s[1] && s[0] != c && s[1] != c) {
                    uint32_t t[3] = {s[0], s[1], c};
                    if (len & 1) {
                        t[0] = s[1];
                        t[1] = s[0];
                    }
                    if ((st = ply_add_face(p, t, 3)))
                        return st;
                }
                s[0] = s[1];
                s[1] = c;
                len++;
            }
        }
    }
    return st;
}

/* Reads the elements after the header, in their order. */
static limn_status ply_body(ply *p)
{
    limn_status st = LIMN_OK;
    for (size_t i = 0; i < p->nelems && !st; i++) {
        const ply_elem *e = &p->elems[i];
        p->elem = e;
        if (e->nprops == 0)
            continue;
        if (e->kind == E_OTHER && !e->has_list && p->format != F_ASCII) {
            p->index = 0;
            p->at = mio_offset(&p->r);
            if (e->count > UINT64_MAX / e->min_size ||
                !mio_skip(&p->r, e->count * e->min_size))
                st = ply_truncated(p);
            continue;
        }
        for (p->index = 0; p->index < e->count && !st; p->index++) {
            if (e->kind == E_VERTEX)
                st = ply_vertex(p, e);
            else if (e->kind == E_OTHER)
                for (size_t k = 0; k < e->nprops && !st; k++) {
                    long long n = 1;
                    const ply_prop *pr = &e->props[k];
                    if (!pr->count_type || !(st = ply_list_count(p, pr, &n)))
                        st = ply_skip(p, pr->type, (uint64_t)n);
                }
            else
                st = ply_face(p, e);
        }
    }
    p->elem = NULL;
    return st;
}

/* Room for the declared vertices (unless that cannot be checked against the
   file size and is large) and the first face offset. */
static limn_status ply_reserve(ply *p)
{
    uint64_t left = mio_remaining(&p->r);
    size_t reserve = left == UINT64_MAX && p->nv > 65536 ? 65536 : (size_t)p->nv;
    if (!growbuf_reserve(&p->a.pos, reserve * 3 * sizeof(double)) ||
        (p->colors && !growbuf_reserve(&p->a.col, reserve * 3)) ||
        !growbuf_push_u32(&p->a.offsets, 0))
        return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "%s: out of memory for %llu vertices", p->path,
                        (unsigned long long)p->nv);
    return LIMN_OK;
}

/* The header, then the data, then what is left after it. */
static limn_status ply_parse(ply *p)
{
    p->in_header = 1;
    limn_status st = ply_header(p);
    p->in_header = 0;
    if (st || (st = ply_check(p)) ||
        (!ply_fast_body(p) && !ply_text_fast_body(p) &&
         ((st = ply_reserve(p)) || (st = ply_body(p)))))
        return st;
    int has_faces = 0;
    for (size_t i = 0; i < p->nelems; i++)
        has_faces |= p->elems[i].kind == E_FACE || p->elems[i].kind == E_TRISTRIPS;
    uint64_t left = mio_remaining(&p->r);
    if (p->format == F_ASCII ? ply_token(p) != NULL : left > 0 && left != UINT64_MAX)
        ctx_warn(p->ctx, "%s: data after the last element ignored", p->path);
    if (!has_faces)
        ctx_warn(p->ctx, "%s: the file has no faces", p->path);
    if (p->nv == 0)
        return ctx_fail(p->ctx, LIMN_ERR_FORMAT, "%s: the file defines no vertices", p->path);
    return LIMN_OK;
}

static limn_status ply_run(void *state, int *binary)
{
    ply *p = state;
    mio_skip_bom(&p->r);
    limn_status st = ply_parse(p);
    *binary = p->format != F_ASCII && !p->in_header;
    return st;
}

limn_status ply_open(ply *p, limn_context *ctx, const char *path, FILE *f)
{
    memset(p, 0, sizeof *p);
    p->ctx = ctx;
    p->path = path;
    if (!mio_init(&p->r, ctx, path, f))
        return LIMN_ERR_MEMORY;
    mio_skip_bom(&p->r);
    p->in_header = 1;
    limn_status st = ply_header(p);
    p->in_header = 0;
    return st ? st : ply_check(p);
}

void ply_close(ply *p)
{
    for (size_t i = 0; i < p->nelems; i++)
        free(p->elems[i].props);
    p->nelems = 0;
    mio_free(&p->r);
}

limn_status ply_read(limn_context *ctx, const char *path, FILE *f, limn_mesh **out)
{
    ply *p = calloc(1, sizeof *p);
    if (!p)
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "%s: out of memory", path);
    p->ctx = ctx;
    p->path = path;
    limn_status st = mio_read(&p->r, &p->a, ctx, path, f, ply_run, p, out);
    for (size_t i = 0; i < p->nelems; i++)
        free(p->elems[i].props);
    free(p);
    return st;
}
