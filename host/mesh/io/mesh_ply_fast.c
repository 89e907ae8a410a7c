/* SPDX-License-Identifier: MIT */
/*
 * The binary PLY fast path (mesh_ply.h): the layout scanners write (vertex
 * records of fixed-size scalars, one face list of any integer types, other
 * elements without lists) converted straight from the mapped file, over
 * ranges of records in parallel (base/parallel.h). Face records are found from
 * their counts: when every count is the first one's, record i lies at
 * i * stride (checked in parallel); else one serial pass over the counts
 * gives the face offsets, and the offsets give the records. Values are
 * converted as the general reader converts them (ply_bin_*), so the mesh is
 * the same bit for bit. Whatever the general reader would refuse or warn
 * about in the data (a short file, a bad index or count, a coordinate that
 * is not finite, too many faces, the memory limit) makes this path give up
 * with nothing changed, and the general reader reads the body and says it.
 */
#ifndef _POSIX_C_SOURCE
#define _POSIX_C_SOURCE 200809L /* fileno, mmap */
#endif
#include "mesh/io/mesh_ply.h"
#include "base/context.h"
#include "base/parallel.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>

typedef struct fast {
    ply *p;
    const unsigned char *map; /* the whole file */
    size_t size;
    uint64_t at;              /* file offset of the element being read */
    mio_arrays a;
    int big;
} fast;

/* A vertex element's layout and where its values go. */
typedef struct fast_vertices {
    const unsigned char *base;
    size_t stride;
    size_t off[6];            /* x y z, red green blue */
    unsigned char type[3];
    int colors;
    int big;
    double *pos;
    uint8_t *col;
} fast_vertices;

/* A face element's layout: a record is lead bytes (scalars and the count),
   the indices, then the scalars after the list. */
typedef struct fast_faces {
    const unsigned char *base;
    size_t before, lead, fixed; /* bytes before the count, before the indices, not indices */
    unsigned char ctype, itype;
    size_t isize;
    int big;
    uint32_t k;               /* the count of every face, or 0 */
    uint32_t nv;
    uint32_t *off, *idx;
} fast_faces;

/* The values in line for the common types (mesh_ply.h), as the slice reader reads them. */
static double coord_at(const fast_vertices *v, const unsigned char *rec, int c)
{
    return ply_bin_double_inline(rec + v->off[c], v->type[c], v->big);
}

static int vertex_range(void *arg, size_t begin, size_t end)
{
    const fast_vertices *v = arg;
    double *pos = v->pos; /* locals: the stores could alias *v */
    uint8_t *col = v->colors ? v->col : NULL;
    const unsigned char *rec = v->base + begin * v->stride;
    size_t stride = v->stride;
    int bad = 0;
    for (size_t i = begin; i < end; i++, rec += stride) {
        for (int c = 0; c < 3; c++) {
            double x = coord_at(v, rec, c);
            pos[3 * i + c] = x;
            bad |= !isfinite(x);
        }
        if (col)
            for (int c = 0; c < 3; c++)
                col[3 * i + c] = rec[v->off[3 + c]];
    }
    return bad;
}

int ply_vertex_records(const ply_elem *e, ply_vertex_layout *v)
{
    size_t at = 0;
    memset(v, 0, sizeof *v);
    for (size_t k = 0; k < e->nprops; k++) {
        const ply_prop *pr = &e->props[k];
        if (pr->count_type)
            return 0;
        if (pr->role >= R_X && pr->role <= R_BLUE)
            v->off[pr->role - R_X] = at;
        if (pr->role >= R_X && pr->role <= R_Z)
            v->type[pr->role - R_X] = pr->type;
        at += ply_type_size[pr->type];
    }
    v->stride = at;
    return 1;
}

/* The vertex records' layout: 0 when a property is a list. */
static int vertex_layout(const fast *f, const ply_elem *e, fast_vertices *v)
{
    ply_vertex_layout l;
    memset(v, 0, sizeof *v);
    if (!ply_vertex_records(e, &l))
        return 0;
    v->stride = l.stride;
    memcpy(v->off, l.off, sizeof v->off);
    memcpy(v->type, l.type, sizeof v->type);
    v->big = f->big;
    v->colors = f->p->colors;
    return 1;
}

static int fast_vertex(fast *f, const ply_elem *e)
{
    fast_vertices v;
    uint64_t nv = e->count;
    if (!vertex_layout(f, e, &v) || nv == 0 || nv > (f->size - f->at) / v.stride ||
        nv > SIZE_MAX / 24 || !mio_array_exact(&f->a.pos, (size_t)nv * 24) ||
        (v.colors && !mio_array_exact(&f->a.col, (size_t)nv * 3)))
        return 0;
    v.base = f->map + f->at;
    v.pos = (double *)(void *)f->a.pos.data;
    v.col = f->a.col.data;
    if (parallel_run((size_t)nv, parallel_threads(f->p->ctx, nv * v.stride), vertex_range, &v))
        return 0;
    f->at += nv * v.stride;
    return 1;
}

static long long index_at(const fast_faces *ff, const unsigned char *b)
{
    return ply_bin_int_inline(b, ff->itype, ff->big);
}

static int face_range(void *arg, size_t begin, size_t end)
{
    const fast_faces *ff = arg;
    const uint32_t *off = ff->off;
    uint32_t *idx = ff->idx; /* locals: the stores could alias *ff */
    const unsigned char *base = ff->base + ff->lead;
    size_t fixed = ff->fixed, isize = ff->isize;
    long long nv = ff->nv;
    int bad = 0;
    for (size_t i = begin; i < end; i++) {
        uint32_t a = off[i], n = off[i + 1] - a;
        const unsigned char *s = base + i * fixed + (size_t)a * isize;
        for (uint32_t j = 0; j < n; j++, s += isize) {
            long long v = index_at(ff, s);
            bad |= v < 0 || v >= nv;
            idx[a + j] = (uint32_t)v;
        }
    }
    return bad;
}

static long long count_at(const fast_faces *ff, const unsigned char *b)
{
    return ply_bin_int_inline(b, ff->ctype, ff->big);
}

/* Whether every count in the range is ff->k (records at a fixed stride);
   also writes those faces' offsets. */
static int uniform_range(void *arg, size_t begin, size_t end)
{
    const fast_faces *ff = arg;
    size_t stride = ff->fixed + ff->k * ff->isize;
    const unsigned char *c = ff->base + begin * stride + ff->before;
    int bad = 0;
    for (size_t i = begin; i < end; i++, c += stride) {
        bad |= count_at(ff, c) != ff->k;
        ff->off[i + 1] = (uint32_t)((i + 1) * ff->k);
    }
    return bad;
}

int ply_face_records(const ply_elem *e, ply_face_layout *f)
{
    size_t at = 0, lists = 0;
    memset(f, 0, sizeof *f);
    for (size_t k = 0; k < e->nprops; k++) {
        const ply_prop *pr = &e->props[k];
        if (!pr->count_type) {
            at += ply_type_size[pr->type];
            continue;
        }
        if (pr->role != R_INDICES || lists++)
            return 0;
        f->before = at;
        f->ctype = pr->count_type;
        f->itype = pr->type;
        at += ply_type_size[pr->count_type];
        f->lead = at;
    }
    f->fixed = at;
    f->isize = ply_type_size[f->itype];
    return lists == 1;
}

/* The face records' layout: 0 unless the one list is the indices. */
static int face_layout(const fast *f, const ply_elem *e, fast_faces *ff)
{
    ply_face_layout l;
    memset(ff, 0, sizeof *ff);
    if (!ply_face_records(e, &l))
        return 0;
    ff->before = l.before;
    ff->lead = l.lead;
    ff->fixed = l.fixed;
    ff->ctype = l.ctype;
    ff->itype = l.itype;
    ff->isize = l.isize;
    ff->big = f->big;
    ff->nv = (uint32_t)f->p->nv;
    ff->base = f->map + f->at;
    return 1;
}

/* One pass over the counts of faces of any size: their offsets, and in
   *bytes the records' length. */
static int serial_counts(const fast *f, uint64_t nf, fast_faces *ff, uint64_t *bytes)
{
    uint64_t left = f->size - f->at, at = 0, total = 0;
    for (uint64_t i = 0; i < nf; i++) {
        if (left - at < ff->fixed)
            return 0;
        long long n = count_at(ff, ff->base + at + ff->before);
        if (n < 3 || (uint64_t)n > UINT32_MAX - 1 - total ||
            (uint64_t)n > (left - at - ff->fixed) / ff->isize)
            return 0;
        at += ff->fixed + (uint64_t)n * ff->isize;
        total += (uint64_t)n;
        ff->off[i + 1] = (uint32_t)total;
    }
    *bytes = at;
    return 1;
}

/* The face offsets: at a fixed stride when every count is the first one's
   (checked in parallel), else from one pass over the counts. */
static int face_counts(const fast *f, uint64_t nf, fast_faces *ff, uint64_t *bytes)
{
    uint64_t left = f->size - f->at;
    long long k = nf && left >= ff->lead ? count_at(ff, ff->base + ff->before) : 0;
    uint64_t stride = ff->fixed + (uint64_t)(k > 0 ? k : 0) * ff->isize;
    if (k >= 3 && (uint64_t)k <= (UINT32_MAX - 1) / nf && nf <= left / stride) {
        ff->k = (uint32_t)k;
        if (!parallel_run((size_t)nf, parallel_threads(f->p->ctx, nf * ff->lead), uniform_range,
                        ff)) {
            *bytes = nf * stride;
            return 1;
        }
    }
    return serial_counts(f, nf, ff, bytes);
}

static int fast_face(fast *f, const ply_elem *e)
{
    fast_faces ff;
    uint64_t nf = e->count, bytes = 0;
    if (!face_layout(f, e, &ff) || nf > UINT32_MAX - 3 ||
        !mio_array_exact(&f->a.offsets, (size_t)(nf + 1) * 4))
        return 0;
    ff.off = (uint32_t *)(void *)f->a.offsets.data;
    ff.off[0] = 0;
    if (!face_counts(f, nf, &ff, &bytes) ||
        !mio_array_exact(&f->a.indices, (size_t)ff.off[nf] * 4))
        return 0;
    ff.idx = (uint32_t *)(void *)f->a.indices.data;
    if (parallel_run((size_t)nf, parallel_threads(f->p->ctx, bytes), face_range, &ff))
        return 0;
    f->at += bytes;
    return 1;
}

/* The elements in their order; the others (no lists) are stepped over. */
static int fast_elements(fast *f)
{
    const ply *p = f->p;
    for (size_t i = 0; i < p->nelems; i++) {
        const ply_elem *e = &p->elems[i];
        if (e->nprops == 0)
            continue;
        if (e->kind == E_VERTEX ? !fast_vertex(f, e)
            : e->kind == E_FACE ? !fast_face(f, e)
                                : e->count > (f->size - f->at) / e->min_size)
            return 0;
        if (e->kind == E_OTHER)
            f->at += e->count * e->min_size;
        ctx_progress(p->ctx, "read", (double)f->at / (double)f->size);
    }
    if (!f->a.offsets.len) { /* no face element: no faces, the first offset all the same */
        if (!mio_array_exact(&f->a.offsets, 4))
            return 0;
        memset(f->a.offsets.data, 0, 4);
    }
    return 1;
}

/* What the general reader's growing arrays hold at the end: 256 bytes
   doubled until n fit (growbuf_reserve's rule); 0 for an array never
   pushed to. */
static uint64_t grown(uint64_t n)
{
    uint64_t cap = 256;
    while (cap < n)
        cap *= 2;
    return n ? cap : 0;
}

/* Whether the general reader would stay within the memory limit: it books
   its arrays' capacities, which are larger than this path's exact sizes, so
   a file it refuses must be refused the same way. used: booked before. */
static int general_fits(const fast *f, size_t used)
{
    const growbuf_budget *b = &f->p->r.budget;
    uint64_t nv = f->p->nv, nf = f->a.offsets.len ? f->a.offsets.len / 4 - 1 : 0;
    uint64_t need = grown(nv * 24) + (f->p->colors ? grown(nv * 3) : 0) +
                    grown((nf + 1) * 4) + grown(f->a.indices.len);
    return used <= b->limit && need <= b->limit - used;
}

/* The file and header are for this path: binary, of known size, no
   tristrips, no lists in other elements (the vertex and face layouts are
   checked as they are read). */
static int fast_eligible(const ply *p)
{
    const char *general = getenv("LIMN_TEST_PLY_GENERAL");
    if ((general && *general && strcmp(general, "0") != 0) || p->format == F_ASCII ||
        !p->r.file_size || p->r.file_size > SIZE_MAX || p->nv == 0 ||
        mio_offset(&p->r) > p->r.file_size)
        return 0;
    for (size_t i = 0; i < p->nelems; i++) {
        const ply_elem *e = &p->elems[i];
        if (e->kind == E_TRISTRIPS || (e->kind == E_OTHER && e->has_list))
            return 0;
    }
    return 1;
}

int ply_fast_body(ply *p)
{
    if (!fast_eligible(p))
        return 0;
    fast f;
    memset(&f, 0, sizeof f);
    f.p = p;
    f.size = (size_t)p->r.file_size;
    f.at = mio_offset(&p->r);
    f.big = p->format == F_BE;
    void *map = mmap(NULL, f.size, PROT_READ, MAP_PRIVATE, fileno(p->r.f), 0);
    if (map == MAP_FAILED)
        return 0;
    f.map = map;
    mio_arrays_init(&f.a, &p->r);
    int exceeded = p->r.budget.exceeded;
    size_t used = p->r.budget.used;
    int ok = fast_elements(&f) && general_fits(&f, used) && mio_jump(&p->r, f.at);
    munmap(map, f.size);
    if (!ok) {
        mio_arrays_free(&f.a);
        p->r.budget.exceeded = exceeded;
        return 0;
    }
    p->a = f.a;
    return 1;
}
