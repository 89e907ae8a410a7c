/* SPDX-License-Identifier: MIT */
/*
 * The text readers' fast path (text_fast.h). Two passes over the ranges:
 * the first checks every line is plain text the general reader would take
 * the same way (no NUL, '\r' only before '\n', at most TF_MAX_LINE bytes so
 * the general reader's buffer would not grow, no OBJ '\' continuation) and
 * counts content lines, which tells each range of a positional format (OFF,
 * PLY) which record it starts at; the second parses the lines. Then the
 * ranges' buffers are copied into exact arrays in file order.
 */
#ifndef _POSIX_C_SOURCE
#define _POSIX_C_SOURCE 200809L /* fileno, mmap */
#endif
#include "mesh/io/text_fast.h"
#include "base/c_locale.h"
#include "base/context.h"
#include "mesh/io/text_number.h"

#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>

/* Far below the general reader's 64 KiB buffer: a longer line would make it
   grow the buffer, which its memory budget counts. */
#define TF_MAX_LINE 32768
#define TF_PROGRESS_BYTES ((size_t)1 << 20)

int tf_enabled(void)
{
    const char *general = getenv("LIMN_TEST_TEXT_GENERAL");
    return !(general && *general && strcmp(general, "0") != 0);
}

/* ----------------------------------------------------------- line helpers */

int tf_double(const char **s, const char *e, double *out)
{
    const char *p = tf_skip(*s, e), *te = tn_double(p, e, out);
    if (te && (te == e || tf_space(*te))) {
        *s = te;
        return 1;
    }
    char buf[128], *q = buf; /* strtod needs a terminated copy: the map is not */
    te = tf_token_end(p, e);
    if (p == te || (size_t)(te - p) >= sizeof buf)
        return 0;
    memcpy(buf, p, (size_t)(te - p));
    buf[te - p] = '\0';
    if (mio_parse_double(&q, out) != 1)
        return 0;
    *s = te;
    return 1;
}

int tf_int(const char **s, const char *e, long long *out, char stop)
{
    const char *p = tf_skip(*s, e);
    int neg = 0, digits = 0;
    long long v = 0;
    if (p < e && (*p == '+' || *p == '-'))
        neg = *p++ == '-';
    for (; p < e && *p >= '0' && *p <= '9'; p++) {
        if (++digits > 18)
            return 0;
        v = v * 10 + (*p - '0');
    }
    if (!digits || (p < e && !tf_space(*p) && !(stop && *p == stop)))
        return 0;
    *out = neg ? -v : v;
    *s = p;
    return 1;
}

int tf_push_vertex(tf_chunk *c, const double xyz[3])
{
    return growbuf_append(&c->pos, xyz, 3 * sizeof(double));
}

int tf_push_index(tf_chunk *c, uint32_t v) { return growbuf_push_u32(&c->idx, v); }

int tf_end_face(tf_chunk *c)
{
    return c->idx.len / 4 < UINT32_MAX && growbuf_push_u32(&c->off, (uint32_t)(c->idx.len / 4));
}

/* ------------------------------------------------------------------ passes */

/* Whether the line [s, e) is one the general reader reads as this path does. */
static int plain_line(const tf_text *t, const char *s, const char *e, int terminated)
{
    size_t n = (size_t)(e - s);
    const char *cr;
    if (n > TF_MAX_LINE || memchr(s, '\0', n) || ((cr = memchr(s, '\r', n)) && cr != e - 1))
        return 0;
    if (t->obj) {
        if (e > s && e[-1] == '\r')
            e--;
        if (!terminated || (e > s && e[-1] == '\\'))
            return 0;
    }
    return 1;
}

static int is_content(const tf_text *t, const char *s, const char *e)
{
    s = tf_skip(s, e);
    return s < e && !(t->hash_comments && *s == '#');
}

/* Pass 1 over range i: plain lines, counted. */
static int scan_range(void *arg, size_t i, size_t end)
{
    tf_text *t = arg;
    (void)end;
    tf_chunk *c = &t->chunk[i];
    const char *p = t->map + t->cut[i], *stop = t->map + t->cut[i + 1];
    while (p < stop) {
        const char *nl = memchr(p, '\n', (size_t)(stop - p)), *le = nl ? nl : stop;
        if (!plain_line(t, p, le, nl != NULL))
            return 1;
        c->records += is_content(t, p, le);
        c->lines += nl != NULL;
        p = nl ? nl + 1 : stop;
    }
    return 0;
}

/* Pass 2 over range i: its content lines parsed (positional formats: up to
   the last record). Range 0 runs on the calling thread and reports. */
static int parse_range(void *arg, size_t i, size_t end)
{
    tf_text *t = arg;
    (void)end;
    tf_chunk *c = &t->chunk[i];
    const char *base = t->map + t->cut[i], *p = base, *stop = t->map + t->cut[i + 1];
    uint64_t record = t->first[i];
    size_t told = 0, span = (size_t)(stop - base);
    c->lines = 0;
    if (!t->obj && record >= t->records)
        return 0;
    c_locale_scope loc; /* the fallback strtod, on threads of their own */
    if (!c_locale_enter(&loc))
        return 1;
    int bad = 0;
    while (p < stop && !bad) {
        const char *nl = memchr(p, '\n', (size_t)(stop - p)), *le = nl ? nl : stop;
        const char *s = tf_skip(p, le);
        c->lines += nl != NULL;
        p = nl ? nl + 1 : stop;
        if (s == le || (t->hash_comments && *s == '#'))
            continue;
        bad = !t->line(t, c, s, le, record++);
        if (!t->obj && record == t->records) {
            c->stop = (size_t)(p - t->map);
            break;
        }
        if (i == 0 && (size_t)(p - base) - told >= TF_PROGRESS_BYTES) {
            told = (size_t)(p - base);
            ctx_progress(t->ctx, "read", 0.1 + 0.8 * (double)told / (double)span);
        }
    }
    c_locale_leave(&loc);
    return bad;
}

/* Range ends: even splits moved to the next line start. */
static void cut_ranges(tf_text *t)
{
    size_t n = t->size - t->begin;
    t->cut[0] = t->begin;
    for (unsigned i = 1; i < t->parts; i++) {
        size_t at = t->begin + parallel_cut(n, t->parts, i);
        if (at < t->cut[i - 1])
            at = t->cut[i - 1];
        const char *nl = at > t->begin ? memchr(t->map + at - 1, '\n', t->size - at + 1) : NULL;
        t->cut[i] = at == t->begin ? at : nl ? (size_t)(nl - t->map) + 1 : t->size;
    }
    t->cut[t->parts] = t->size;
}

/* --------------------------------------------------------------- assembly */

typedef struct tf_place {
    tf_text *t;
    mio_arrays *a;
    size_t v[PARALLEL_MAX + 1], f[PARALLEL_MAX + 1], x[PARALLEL_MAX + 1]; /* starts */
} tf_place;

static int copy_range(void *arg, size_t i, size_t end)
{
    tf_place *pl = arg;
    (void)end;
    const tf_chunk *c = &pl->t->chunk[i];
    mio_arrays *a = pl->a;
    if (c->pos.len)
        memcpy(a->pos.data + pl->v[i] * 24, c->pos.data, c->pos.len);
    if (c->col.len)
        memcpy(a->col.data + pl->v[i] * 3, c->col.data, c->col.len);
    if (c->idx.len)
        memcpy(a->indices.data + pl->x[i] * 4, c->idx.data, c->idx.len);
    uint32_t *off = (uint32_t *)(void *)a->offsets.data + pl->f[i] + 1;
    const uint32_t *local = (const uint32_t *)(const void *)c->off.data;
    for (size_t k = 0; k < c->off.len / 4; k++)
        off[k] = (uint32_t)pl->x[i] + local[k];
    return 0;
}

/* The totals, checked as the general reader checks them, and whether its
   growing arrays (at most twice their contents, 256 bytes at least) would
   stay within the memory limit. */
static int totals(const tf_text *t, tf_place *pl, const growbuf_budget *b, int colors)
{
    uint64_t max_ref = 0;
    for (unsigned i = 0; i < t->parts; i++) {
        const tf_chunk *c = &t->chunk[i];
        pl->v[i + 1] = pl->v[i] + c->pos.len / 24;
        pl->f[i + 1] = pl->f[i] + c->off.len / 4;
        pl->x[i + 1] = pl->x[i] + c->idx.len / 4;
        max_ref = c->max_ref > max_ref ? c->max_ref : max_ref;
        if (colors && c->col.len != c->pos.len / 8)
            return 0;
    }
    uint64_t nv = pl->v[t->parts], nf = pl->f[t->parts], ni = pl->x[t->parts];
    if (nv == 0 || nv >= UINT32_MAX - 1 || nf >= UINT32_MAX - 1 || ni >= UINT32_MAX ||
        max_ref > nv || (!t->obj && nv != t->nv))
        return 0;
    uint64_t exact = nv * 24 + (colors ? nv * 3 : 0) + (nf + 1) * 4 + ni * 4;
    return b->used <= b->limit && 2 * exact + 1024 <= b->limit - b->used;
}

static int place(tf_text *t, mio_reader *r, mio_arrays *a, int colors)
{
    tf_place pl;
    memset(&pl, 0, sizeof pl);
    pl.t = t;
    pl.a = a;
    if (!totals(t, &pl, &r->budget, colors))
        return 0;
    size_t nv = pl.v[t->parts], nf = pl.f[t->parts], ni = pl.x[t->parts];
    mio_arrays_init(a, r);
    if (!mio_array_exact(&a->pos, nv * 24) || (colors && !mio_array_exact(&a->col, nv * 3)) ||
        !mio_array_exact(&a->offsets, (nf + 1) * 4) || !mio_array_exact(&a->indices, ni * 4)) {
        mio_arrays_free(a);
        return 0;
    }
    memset(a->offsets.data, 0, 4);
    parallel_run(t->parts, t->parts, copy_range, &pl);
    return 1;
}

/* ------------------------------------------------------------------ driver */

/* The passes over the mapped file; 1 when every line was read. */
static int passes(tf_text *t)
{
    if (parallel_run(t->parts, t->parts, scan_range, t))
        return 0;
    if (t->obj && (t->size == t->begin || t->map[t->size - 1] != '\n'))
        return 0; /* the general reader warns of the unterminated line */
    for (unsigned i = 0; i < t->parts; i++)
        t->first[i + 1] = t->first[i] + t->chunk[i].records;
    if (!t->obj && (t->records == 0 || t->first[t->parts] < t->records))
        return 0;
    ctx_progress(t->ctx, "read", 0.1);
    return !parallel_run(t->parts, t->parts, parse_range, t);
}

/* Where the reader goes on: after the last record (positional) or the end;
   0 when the file cannot seek there. */
static int move_reader(const tf_text *t, mio_reader *r)
{
    size_t stop = t->size;
    uint64_t lines = 0;
    for (unsigned i = 0; i < t->parts; i++) {
        lines += t->chunk[i].lines;
        if (!t->obj && t->chunk[i].stop) {
            stop = t->chunk[i].stop;
            break;
        }
    }
    if (!mio_jump(r, stop))
        return 0;
    r->next_line += lines;
    r->line = r->next_line - 1;
    return 1;
}

static void free_chunks(tf_text *t)
{
    for (unsigned i = 0; i < t->parts; i++) {
        tf_chunk *c = &t->chunk[i];
        growbuf_free(&c->pos);
        growbuf_free(&c->col);
        growbuf_free(&c->off);
        growbuf_free(&c->idx);
    }
}

int tf_read(tf_text *t, mio_reader *r, mio_arrays *a)
{
    if (!tf_enabled() || !r->file_size || r->file_size > SIZE_MAX ||
        mio_offset(r) >= r->file_size)
        return 0;
    t->ctx = r->ctx;
    t->size = (size_t)r->file_size;
    t->begin = (size_t)mio_offset(r);
    void *map = mmap(NULL, t->size, PROT_READ, MAP_PRIVATE, fileno(r->f), 0);
    if (map == MAP_FAILED)
        return 0;
    t->map = map;
    t->parts = parallel_threads(r->ctx, t->size - t->begin);
    cut_ranges(t);
    const growbuf_budget *b = &r->budget;
    size_t share = b->used < b->limit ? (b->limit - b->used) / 2 / t->parts : 0;
    for (unsigned i = 0; i < t->parts; i++) {
        tf_chunk *c = &t->chunk[i];
        memset(c, 0, sizeof *c);
        c->budget.limit = share;
        c->pos.budget = c->col.budget = c->off.budget = c->idx.budget = &c->budget;
    }
    int exceeded = r->budget.exceeded;
    int ok = passes(t) && place(t, r, a, t->colors);
    if (ok && !move_reader(t, r)) {
        mio_arrays_free(a);
        ok = 0;
    }
    r->budget.exceeded = exceeded;
    free_chunks(t);
    munmap(map, t->size);
    if (ok)
        ctx_progress(t->ctx, "read", 1.0);
    return ok;
}
