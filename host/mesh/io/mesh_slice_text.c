/* SPDX-License-Identifier: MIT */
/*
 * OBJ, OFF and ASCII PLY in slices (mesh_slice.h). Part p's byte range of
 * the body is cut as the text fast path cuts its ranges (text_fast.c): even
 * splits moved to the next line start. Phase 1 counts the range's lines and
 * content lines (OBJ: its vertex and face lines and corners). Phase 2 parses
 * the range with the fast path's line parsers (mesh_obj_fast.c,
 * mesh_off_fast.c, mesh_ply_text_fast.c), which give the general readers'
 * values bit for bit, numbering from the counts of the parts before: a
 * positional format's record number says whether a line is a vertex or a
 * face, an OBJ face's negative numbers count back from the vertices before
 * its line. Line numbers in messages are the file's.
 */
#include "base/c_locale.h"
#include "base/context.h"
#include "base/large_alloc.h"
#include "mesh/io/mesh_slice_formats.h"
#include "mesh/io/text_fast.h"
#include "mesh/io/text_formats.h"

#include <stdlib.h>
#include <string.h>

/* What is known of the file before its body. */
typedef struct text_fmt {
    const slice_file *sf;
    slice_text_kind kind;
    size_t body;               /* the body's first byte */
    uint64_t header_lines;     /* '\n' before it */
    uint64_t nv, nf;           /* positional: the header's counts */
    uint64_t vfirst, ffirst;   /* positional: record numbers of the first vertex, face */
    tf_text *t;                /* positional: the line parser */
    ply_text pt;
} text_fmt;

static limn_status positional(text_fmt *x, const ply *p)
{
    const slice_file *sf = x->sf;
    if (x->kind == SLICE_OFF) {
        long long nv, nf;
        uint64_t body;
        limn_status st = off_read_header(sf->ctx, sf->path, sf->f, &body, &nv, &nf);
        if (st)
            return st;
        x->body = (size_t)body;
        x->nv = (uint64_t)nv;
        x->nf = (uint64_t)nf;
        x->ffirst = x->nv;
        return off_fast_setup(x->t, nv, nf) ? LIMN_OK
               : ctx_fail(sf->ctx, LIMN_ERR_FORMAT, "%s: the file defines no vertices", sf->path);
    }
    x->body = (size_t)mio_offset(&p->r);
    x->nv = p->nv;
    if (x->nv == 0)
        return ctx_fail(sf->ctx, LIMN_ERR_FORMAT, "%s: the file defines no vertices", sf->path);
    if (!ply_text_setup(p, &x->pt, x->t))
        return ctx_fail(sf->ctx, LIMN_ERR_FORMAT,
                        "%s: this ASCII PLY cannot be read in slices: the slice reader takes a "
                        "vertex element of scalars and a face element of one index list among "
                        "scalars, one record a line, and no other element with records",
                        sf->path);
    int faces_first = x->pt.order[0]->kind == E_FACE;
    x->nf = faces_first ? x->pt.order[0]->count
            : x->pt.order[1] != x->pt.order[0] ? x->pt.order[1]->count : 0;
    x->vfirst = faces_first ? x->pt.first : 0;
    x->ffirst = faces_first ? 0 : x->pt.first;
    x->t->colors = 0; /* slices keep positions only */
    return LIMN_OK;
}

static limn_status fmt_open(const slice_file *sf, slice_text_kind kind, const ply *p,
                            text_fmt *x)
{
    memset(x, 0, sizeof *x);
    x->sf = sf;
    x->kind = kind;
    limn_status st = LIMN_OK;
    if (kind == SLICE_OBJ) {
        x->body = sf->size >= 3 && memcmp(sf->map, "\xEF\xBB\xBF", 3) == 0 ? 3 : 0;
    } else if (!(x->t = calloc(1, sizeof *x->t))) {
        return ctx_fail(sf->ctx, LIMN_ERR_MEMORY, "%s: out of memory", sf->path);
    } else {
        x->t->ctx = sf->ctx;
        st = positional(x, p);
    }
    for (size_t i = 0; i < x->body && !st; i++)
        x->header_lines += sf->map[i] == '\n';
    return st;
}

static int hash_comments(const text_fmt *x) { return x->kind != SLICE_PLY; }

/* The next line start at or after `at` (the body's start stays). */
static size_t line_start(const text_fmt *x, size_t at)
{
    if (at <= x->body)
        return x->body;
    const char *map = (const char *)x->sf->map;
    const char *nl = memchr(map + at - 1, '\n', x->sf->size - at + 1);
    return nl ? (size_t)(nl - map) + 1 : x->sf->size;
}

static void text_range(const text_fmt *x, unsigned part, unsigned parts, size_t *a, size_t *b)
{
    size_t n = x->sf->size - x->body;
    *a = line_start(x, x->body + mesh_slice_cut(n, parts, part));
    *b = part + 1 < parts ? line_start(x, x->body + mesh_slice_cut(n, parts, part + 1))
                          : x->sf->size;
}

/* An OBJ record's word at s: 'v' or 'f' alone, else 0. */
static char obj_word(const char *s, const char *e)
{
    return (s[0] == 'v' || s[0] == 'f') && (s + 1 == e || tf_space(s[1])) ? s[0] : 0;
}

static uint64_t tokens(const char *s, const char *e)
{
    uint64_t n = 0;
    for (s = tf_skip(s, e); s < e; s = tf_skip(tf_token_end(s, e), e))
        n++;
    return n;
}

limn_status slice_text_count(const slice_file *sf, slice_text_kind kind, const ply *p,
                             unsigned part, unsigned parts, mesh_slice_counts *out)
{
    text_fmt x;
    size_t a, b;
    limn_status st = fmt_open(sf, kind, p, &x);
    memset(out, 0, sizeof *out);
    if (!st) {
        text_range(&x, part, parts, &a, &b);
        const char *q = (const char *)sf->map + a, *stop = (const char *)sf->map + b;
        while (q < stop) {
            const char *nl = memchr(q, '\n', (size_t)(stop - q)), *le = nl ? nl : stop;
            const char *s = tf_skip(q, le);
            out->lines += nl != NULL;
            q = nl ? nl + 1 : stop;
            if (s == le || (hash_comments(&x) && *s == '#'))
                continue;
            out->records++;
            char w = kind == SLICE_OBJ ? obj_word(s, le) : 0;
            out->vertices += w == 'v';
            out->faces += w == 'f';
            out->corners += w == 'f' ? tokens(s + 1, le) : 0;
        }
    }
    free(x.t);
    return st;
}

/* ------------------------------------------------------------------ read */

/* The parse of one range. */
typedef struct text_run {
    const text_fmt *x;
    const mesh_slice_counts *before, *total;
    tf_chunk c;
    uint64_t line, record;     /* of the line being read (line from 1) */
    size_t unknown;            /* OBJ records limn does not know */
} text_run;

static limn_status line_fail(const text_run *r, const char *what)
{
    return ctx_fail(r->x->sf->ctx, LIMN_ERR_FORMAT, "%s:%llu: %s", r->x->sf->path,
                    (unsigned long long)r->line, what);
}

/* Lines the fast line parsers would read otherwise than the general reader. */
static limn_status plain(const text_run *r, const char *s, const char *e)
{
    size_t n = (size_t)(e - s);
    const char *cr = memchr(s, '\r', n);
    if (n > MIO_MAX_LINE)
        return line_fail(r, "a line longer than 64 MiB");
    if (memchr(s, '\0', n))
        return line_fail(r, "a NUL byte: binary data in a text file");
    if (cr && cr != e - 1)
        return line_fail(r, "a carriage return inside a line (old Mac line ends are not read "
                            "in slices)");
    const char *end = cr ? cr : e;
    /* the last line too: the general reader reads a final "v\" as "v" (joined to nothing) */
    if (r->x->kind == SLICE_OBJ && end > s && end[-1] == '\\')
        return line_fail(r, "a '\\' line continuation (not read in slices)");
    return LIMN_OK;
}

static limn_status record_fail(const text_run *r, int face, uint64_t index)
{
    char what[256];
    if (r->c.budget.exceeded)
        return ctx_fail(r->x->sf->ctx, LIMN_ERR_MEMORY, "%s:%llu: the memory limit of %zu "
                        "bytes does not hold this slice", r->x->sf->path,
                        (unsigned long long)r->line, r->c.budget.limit);
    uint64_t nv = r->x->kind == SLICE_OBJ ? r->total->vertices : r->x->nv;
    if (face)
        snprintf(what, sizeof what, "face %llu cannot be read: a malformed face, fewer than 3 "
                 "vertices or a vertex out of range (%llu vertices)", (unsigned long long)index,
                 (unsigned long long)nv);
    else
        snprintf(what, sizeof what, "vertex %llu cannot be read: 3 finite coordinates expected",
                 (unsigned long long)index);
    return line_fail(r, what);
}

static limn_status obj_record(text_run *r, const char *s, const char *e)
{
    tf_chunk *c = &r->c;
    char w = obj_word(s, e);
    uint64_t vertices = r->before->vertices + c->pos.len / 24;
    uint64_t faces = r->before->faces + c->off.len / 4;
    if (!w) {
        if (!obj_skipped_record(s, (size_t)(tf_token_end(s, e) - s)) && r->unknown++ == 0) {
            char tok[64], word[41];
            size_t n = (size_t)(tf_token_end(s, e) - s);
            snprintf(word, sizeof word, "%.*s", (int)(n < 40 ? n : 40), s);
            ctx_warn(r->x->sf->ctx, "%s:%llu: unknown OBJ record %s ignored", r->x->sf->path,
                     (unsigned long long)r->line, mio_token(word, tok));
        }
        return LIMN_OK;
    }
    if (!obj_fast_record(c, s, e, (long long)r->before->vertices))
        return record_fail(r, w == 'f', w == 'f' ? faces : vertices);
    if (w == 'f' && c->max_ref > r->total->vertices) {
        char what[160];
        snprintf(what, sizeof what, "face references vertex %llu but only %llu vertices are "
                 "defined", (unsigned long long)c->max_ref,
                 (unsigned long long)r->total->vertices);
        return line_fail(r, what);
    }
    return LIMN_OK;
}

static limn_status content(text_run *r, const char *s, const char *e)
{
    const text_fmt *x = r->x;
    if (x->kind == SLICE_OBJ)
        return obj_record(r, s, e);
    int face = r->record >= x->ffirst && r->record < x->ffirst + x->nf;
    if (!x->t->line(x->t, &r->c, s, e, r->record))
        return record_fail(r, face, r->record - (face ? x->ffirst : x->vfirst));
    return LIMN_OK;
}

/* The range's lines parsed into r->c (positional: up to the last record). */
static limn_status parse(text_run *r, size_t a, size_t b)
{
    const text_fmt *x = r->x;
    const char *q = (const char *)x->sf->map + a, *stop = (const char *)x->sf->map + b;
    uint64_t records = x->nv + x->nf;
    limn_status st = LIMN_OK;
    while (q < stop && !st) {
        const char *nl = memchr(q, '\n', (size_t)(stop - q)), *le = nl ? nl : stop;
        const char *s = tf_skip(q, le);
        int line = s < le && !(hash_comments(x) && *s == '#');
        /* after the last record: lines up to the first with content checked
           (the whole reader reads that far to warn of it), the rest ignored */
        int after = x->kind != SLICE_OBJ && r->record >= records;
        if (!(st = plain(r, q, le)) && line && after)
            break;
        if (!st && line) {
            st = content(r, s, le);
            r->record++;
        }
        r->line += nl != NULL;
        q = nl ? nl + 1 : stop;
    }
    if (!st && r->c.budget.exceeded)
        st = ctx_fail(x->sf->ctx, LIMN_ERR_MEMORY, "%s: the memory limit of %zu bytes does not "
                      "hold this slice", x->sf->path, r->c.budget.limit);
    return st;
}

static limn_status totals(const text_fmt *x, const mesh_slice_counts *total)
{
    const slice_file *sf = x->sf;
    if (x->kind == SLICE_OBJ)
        return total->vertices ? LIMN_OK
               : ctx_fail(sf->ctx, LIMN_ERR_FORMAT, "%s: the file defines no vertices",
                          sf->path);
    if (total->records < x->nv + x->nf)
        return ctx_fail(sf->ctx, LIMN_ERR_FORMAT,
                        "%s:%llu: the file ends after %llu of the %llu vertex and %llu face "
                        "records its header declares (truncated)", sf->path,
                        (unsigned long long)(x->header_lines + total->lines),
                        (unsigned long long)total->records, (unsigned long long)x->nv,
                        (unsigned long long)x->nf);
    return LIMN_OK;
}

static uint64_t clamp_sub(uint64_t a, uint64_t b, uint64_t most)
{
    uint64_t d = a > b ? a - b : 0;
    return d < most ? d : most;
}

/* The slice from the parsed range. */
static limn_status make(text_run *r, mesh_slice *s)
{
    const text_fmt *x = r->x;
    tf_chunk *c = &r->c;
    int obj = x->kind == SLICE_OBJ;
    s->vertex_total = obj ? r->total->vertices : x->nv;
    s->face_total = obj ? r->total->faces : x->nf;
    s->vertex_begin = obj ? r->before->vertices : clamp_sub(r->before->records, x->vfirst, x->nv);
    s->face_begin = obj ? r->before->faces : clamp_sub(r->before->records, x->ffirst, x->nf);
    s->vertex_count = c->pos.len / 24;
    s->face_count = c->off.len / 4;
    s->positions = growbuf_take(&c->pos);
    s->face_indices = growbuf_take(&c->idx);
    s->face_offsets = large_malloc(c->off.len + 4);
    if (!s->positions || !s->face_indices || !s->face_offsets)
        return ctx_fail(x->sf->ctx, LIMN_ERR_MEMORY, "%s: out of memory for a slice",
                        x->sf->path);
    s->face_offsets[0] = 0;
    if (c->off.len)
        memcpy(s->face_offsets + 1, c->off.data, c->off.len);
    return LIMN_OK;
}

static void chunk_free(tf_chunk *c)
{
    growbuf_free(&c->pos);
    growbuf_free(&c->col);
    growbuf_free(&c->off);
    growbuf_free(&c->idx);
}

limn_status slice_text_read(const slice_file *sf, slice_text_kind kind, const ply *p,
                            unsigned part, unsigned parts, const mesh_slice_counts *before,
                            const mesh_slice_counts *total, mesh_slice *out)
{
    text_fmt x;
    mesh_slice s;
    memset(&s, 0, sizeof s);
    limn_status st = fmt_open(sf, kind, p, &x);
    if (!st && !(st = totals(&x, total))) {
        text_run *r = calloc(1, sizeof *r);
        size_t a, b;
        c_locale_scope loc; /* the parsers' strtod fallback */
        if (!r || !c_locale_enter(&loc)) {
            free(r);
            free(x.t);
            return slice_hand_over(ctx_fail(sf->ctx, LIMN_ERR_MEMORY, "%s: out of memory",
                                            sf->path), &s, out);
        }
        r->x = &x;
        r->before = before;
        r->total = total;
        r->line = x.header_lines + before->lines + 1;
        r->record = before->records;
        r->c.budget.limit = context_max_memory(sf->ctx);
        r->c.pos.budget = r->c.col.budget = r->c.off.budget = r->c.idx.budget = &r->c.budget;
        text_range(&x, part, parts, &a, &b);
        st = parse(r, a, b);
        c_locale_leave(&loc);
        if (!st)
            st = make(r, &s);
        chunk_free(&r->c);
        free(r);
    }
    free(x.t);
    return slice_hand_over(st, &s, out);
}
