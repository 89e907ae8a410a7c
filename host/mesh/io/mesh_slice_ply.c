/* SPDX-License-Identifier: MIT */
/*
 * Binary PLY in slices (mesh_slice.h): part p's vertex and face blocks read
 * straight from the mapped file. The layout is the one the fast path takes
 * (mesh_ply_fast.c): fixed-size vertex records, one face list (the indices)
 * among scalars, other elements without lists. Vertex record i lies at a
 * fixed stride. Face record i does too when every count is the first one's:
 * phase 1 checks that for the part's own block (irregular = 0), so when the
 * sum over all parts is 0 every record is where the stride says. Otherwise
 * each part streams the count bytes of the faces before its block to find
 * where it starts (O(F) time, O(1) memory), then counts its own corners,
 * allocates them exactly and reads them. Values are converted as the
 * general reader converts them (ply_bin_*), so the slices are its mesh.
 */
#include "base/context.h"
#include "base/large_alloc.h"
#include "mesh/io/mesh_slice_formats.h"

#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

typedef struct ply_layout {
    const slice_file *sf;
    int big;
    uint64_t nv, nf;
    ply_vertex_layout v;
    ply_face_layout f;
    uint64_t fstart;   /* file offset of the face block */
    uint64_t vstart;   /* of the vertex block; when vafter, counted from the face block's end */
    int vafter;
} ply_layout;

static limn_status at_fail(const ply_layout *l, limn_status st, uint64_t at, const char *elem,
                           uint64_t index, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 6, 7)))
#endif
    ;
static limn_status at_fail(const ply_layout *l, limn_status st, uint64_t at, const char *elem,
                           uint64_t index, const char *fmt, ...)
{
    char msg[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    return ctx_fail(l->sf->ctx, st, "%s: byte %llu: %s %llu: %s", l->sf->path,
                    (unsigned long long)at, elem, (unsigned long long)index, msg);
}

static limn_status refuse(const ply_layout *l, const char *why, const char *name)
{
    return ctx_fail(l->sf->ctx, LIMN_ERR_FORMAT,
                    "%s: this PLY cannot be read in slices: %s%s (the slice reader takes "
                    "fixed-size vertex records and one face list among scalars)",
                    l->sf->path, why, name);
}

/* ------------------------------------------------------------------ layout */

/* The blocks' places from the header (file offsets: ply_check has checked
   the fixed sizes against the file's). */
static limn_status layout(const slice_file *sf, const ply *p, ply_layout *l)
{
    memset(l, 0, sizeof *l);
    l->sf = sf;
    l->big = p->format == F_BE;
    l->nv = p->nv;
    uint64_t at = mio_offset(&p->r);
    int after = 0;
    for (size_t i = 0; i < p->nelems; i++) {
        const ply_elem *e = &p->elems[i];
        if (e->kind == E_TRISTRIPS && e->count)
            return refuse(l, "it has triangle strips", "");
        if (e->kind == E_VERTEX) {
            if (!ply_vertex_records(e, &l->v))
                return refuse(l, "a list in the vertex element", "");
            l->vstart = at;
            l->vafter = after;
            at += e->count * l->v.stride;
        } else if (e->kind == E_FACE) {
            if (!ply_face_records(e, &l->f))
                return refuse(l, "a list beside the vertex indices in the element ", e->name);
            l->fstart = at;
            l->nf = e->count;
            after = 1;
            at = 0;
        } else if (e->has_list && e->count) {
            return refuse(l, "a list in the element ", e->name);
        } else {
            at += e->count * e->min_size;
        }
    }
    if (l->nf > UINT32_MAX - 2)
        return ctx_fail(sf->ctx, LIMN_ERR_FORMAT, "%s: too many faces (%llu)", sf->path,
                        (unsigned long long)l->nf);
    return LIMN_OK;
}

static long long count_at(const ply_layout *l, uint64_t at)
{
    return ply_bin_int_inline(l->sf->map + at + l->f.before, l->f.ctype, l->big);
}

/* The fixed count k of the first face, when its records could all lie at a
   stride (0 otherwise). */
static uint32_t first_count(const ply_layout *l)
{
    uint64_t size = l->sf->size;
    if (l->nf == 0 || l->fstart > size || size - l->fstart < l->f.fixed)
        return 0;
    long long k = count_at(l, l->fstart);
    if (k < 3 || (uint64_t)k > (UINT32_MAX - 1) / l->nf)
        return 0;
    uint64_t stride = l->f.fixed + (uint64_t)k * l->f.isize;
    return l->nf <= (size - l->fstart) / stride ? (uint32_t)k : 0;
}

/* Whether faces [fb, fe) all have count k at the stride k gives. */
static int regular_block(const ply_layout *l, uint32_t k, uint64_t fb, uint64_t fe)
{
    uint64_t stride = l->f.fixed + (uint64_t)k * l->f.isize;
    for (uint64_t i = fb; i < fe; i++)
        if (count_at(l, l->fstart + i * stride) != k)
            return 0;
    return 1;
}

limn_status slice_ply_count(const slice_file *sf, const ply *p, unsigned part, unsigned parts,
                            mesh_slice_counts *out)
{
    ply_layout l;
    limn_status st = layout(sf, p, &l);
    if (st)
        return st;
    uint64_t vb = mesh_slice_cut(l.nv, parts, part), ve = mesh_slice_cut(l.nv, parts, part + 1);
    uint64_t fb = mesh_slice_cut(l.nf, parts, part), fe = mesh_slice_cut(l.nf, parts, part + 1);
    memset(out, 0, sizeof *out);
    out->vertices = ve - vb;
    out->faces = fe - fb;
    uint32_t k = first_count(&l);
    if (fe > fb && (!k || !regular_block(&l, k, fb, fe)))
        out->irregular = 1;
    else
        out->corners = (fe - fb) * k;
    return LIMN_OK;
}

/* ------------------------------------------------------------------- read */

#define RELEASE_BYTES ((uint64_t)16 << 20)

/* Steps over n face records from *at (face number first): each count
   checked as the general reader checks it; *corners gets their sum (NULL:
   the records are not the part's, their pages are released as it goes). */
static limn_status scan(const ply_layout *l, uint64_t *at, uint64_t first, uint64_t n,
                        uint64_t *corners)
{
    uint64_t size = l->sf->size, sum = 0, a = *at, told = a;
    for (uint64_t i = 0; i < n; i++) {
        if (!corners && a - told >= RELEASE_BYTES) {
            slice_file_release(l->sf, told, a);
            told = a;
        }
        if (a > size || size - a < l->f.fixed)
            return at_fail(l, LIMN_ERR_FORMAT, a, "face", first + i,
                           "the file ends early (truncated)");
        long long c = count_at(l, a);
        if (c < 0 || (uint64_t)c > (size - a - l->f.fixed) / l->f.isize)
            return at_fail(l, LIMN_ERR_FORMAT, a + l->f.before, "face", first + i,
                           "list count %lld is larger than the rest of the file (%llu bytes) "
                           "allows", c, (unsigned long long)(size - a - l->f.lead));
        if (c < 3)
            return at_fail(l, LIMN_ERR_FORMAT, a + l->f.before, "face", first + i,
                           "face has %lld vertices (at least 3 needed)", c);
        if ((uint64_t)c > UINT32_MAX - 1 - sum)
            return at_fail(l, LIMN_ERR_FORMAT, a, "face", first + i, "too many face indices");
        sum += (uint64_t)c;
        a += l->f.fixed + (uint64_t)c * l->f.isize;
    }
    *at = a;
    if (corners)
        *corners = sum;
    return LIMN_OK;
}

static limn_status read_vertices(const ply_layout *l, uint64_t vstart, mesh_slice *s)
{
    const unsigned char *rec = l->sf->map + vstart + s->vertex_begin * l->v.stride;
    for (size_t i = 0; i < s->vertex_count; i++, rec += l->v.stride)
        for (int c = 0; c < 3; c++) {
            double x = ply_bin_double_inline(rec + l->v.off[c], l->v.type[c], l->big);
            if (!isfinite(x))
                return at_fail(l, LIMN_ERR_FORMAT, (uint64_t)(rec + l->v.off[c] - l->sf->map),
                               "vertex", s->vertex_begin + i, "a coordinate is not finite");
            s->positions[3 * i + c] = x;
        }
    return LIMN_OK;
}

/* The part's face records from at, whose counts scan has checked. */
static limn_status read_faces(const ply_layout *l, uint64_t at, uint64_t limit, mesh_slice *s)
{
    uint32_t n = 0;
    s->face_offsets[0] = 0;
    for (size_t f = 0; f < s->face_count; f++) {
        uint32_t c = (uint32_t)count_at(l, at);
        const unsigned char *b = l->sf->map + at + l->f.lead;
        for (uint32_t j = 0; j < c; j++, b += l->f.isize) {
            long long v = ply_bin_int_inline(b, l->f.itype, l->big);
            if (v < 0 || (uint64_t)v >= limit)
                return at_fail(l, LIMN_ERR_FORMAT, (uint64_t)(b - l->sf->map), "face",
                               s->face_begin + f,
                               "references vertex %lld but only %llu vertices are defined", v,
                               (unsigned long long)limit);
            s->face_indices[n + j] = (uint32_t)v;
        }
        n += c;
        s->face_offsets[f + 1] = n;
        at += l->f.fixed + (uint64_t)c * l->f.isize;
    }
    return LIMN_OK;
}

/* Where the part's faces start (*fat) and its corner count; where the
   vertex block starts (*vat), checked against the file size. */
static limn_status places(const ply_layout *l, int regular, const mesh_slice *s, uint64_t *fat,
                          uint64_t *corners, uint64_t *vat)
{
    uint32_t k = regular ? first_count(l) : 0;
    uint64_t stride = l->f.fixed + (uint64_t)k * l->f.isize, end;
    limn_status st = LIMN_OK;
    *fat = l->fstart;
    if (k) {
        *fat += s->face_begin * stride;
        end = *fat;
        st = scan(l, &end, s->face_begin, s->face_count, corners);
    } else if (!(st = scan(l, fat, 0, s->face_begin, NULL))) {
        end = *fat;
        st = scan(l, &end, s->face_begin, s->face_count, corners);
    }
    if (!st && l->vafter) { /* the vertex block after the faces: their whole length */
        if (k)
            end = l->fstart + l->nf * stride;
        else
            st = scan(l, &end, s->face_begin + s->face_count,
                      l->nf - s->face_begin - s->face_count, NULL);
    }
    *vat = l->vafter ? end + l->vstart : l->vstart;
    if (!st && (*vat > l->sf->size || (l->sf->size - *vat) / l->v.stride < l->nv))
        return ctx_fail(l->sf->ctx, LIMN_ERR_FORMAT,
                        "%s: byte %llu: the vertex element does not fit in the file "
                        "(truncated)", l->sf->path, (unsigned long long)*vat);
    return st;
}

limn_status slice_ply_read(const slice_file *sf, const ply *p, unsigned part, unsigned parts,
                           int regular, uint64_t index_limit, mesh_slice *out)
{
    ply_layout l;
    mesh_slice s;
    memset(&s, 0, sizeof s);
    limn_status st = layout(sf, p, &l);
    if (st)
        return slice_hand_over(st, &s, out);
    s.vertex_total = l.nv;
    s.face_total = l.nf;
    s.vertex_begin = mesh_slice_cut(l.nv, parts, part);
    s.vertex_count = mesh_slice_cut(l.nv, parts, part + 1) - s.vertex_begin;
    s.face_begin = mesh_slice_cut(l.nf, parts, part);
    s.face_count = mesh_slice_cut(l.nf, parts, part + 1) - s.face_begin;
    uint64_t fat, corners = 0, vat;
    if ((st = places(&l, regular, &s, &fat, &corners, &vat)))
        return slice_hand_over(st, &s, out);
    uint64_t need = (uint64_t)s.vertex_count * 24 + (s.face_count + 1) * 4 + corners * 4;
    if (need > context_max_memory(sf->ctx))
        return slice_hand_over(ctx_fail(sf->ctx, LIMN_ERR_MEMORY,
                                        "%s: the memory limit of %zu bytes does not hold this "
                                        "slice (%llu bytes)", sf->path,
                                        context_max_memory(sf->ctx), (unsigned long long)need),
                               &s, out);
    s.positions = large_malloc(s.vertex_count * 24 + 1);
    s.face_offsets = large_malloc((s.face_count + 1) * 4);
    s.face_indices = large_malloc(corners * 4 + 1);
    if (!s.positions || !s.face_offsets || !s.face_indices)
        st = ctx_fail(sf->ctx, LIMN_ERR_MEMORY, "%s: out of memory for a slice of %zu vertices "
                      "and %zu faces", sf->path, s.vertex_count, s.face_count);
    if (!st && !(st = read_vertices(&l, vat, &s)))
        st = read_faces(&l, fat, index_limit, &s);
    return slice_hand_over(st, &s, out);
}
