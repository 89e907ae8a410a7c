/* SPDX-License-Identifier: MIT */
/*
 * ASCII PLY's fast path (mesh_ply.h, text_fast.h) for the body after the
 * header the general reader (mesh_ply.c) has read and checked: a vertex
 * element of scalars and a face element of one index list and scalars (in
 * either order), one record a line, values as the general reader converts
 * them (x, y, z of any type as doubles, uchar colours 0-255, other scalars
 * stepped over as tokens, counts and indices in their types' ranges). Other
 * elements with records, tristrips, records across lines and every error
 * give way to the general reader, which also checks what follows.
 */
#include "mesh/io/mesh_ply.h"
#include "mesh/io/text_fast.h"

#include <stdlib.h>

/* Steps over one token. */
static int skip_token(const char **s, const char *e)
{
    const char *p = tf_skip(*s, e);
    if (p == e)
        return 0;
    *s = tf_token_end(p, e);
    return 1;
}

static int text_vertex(const tf_text *t, tf_chunk *c, const ply_elem *el, const char *s,
                       const char *e)
{
    double xyz[3] = {0, 0, 0};
    unsigned char rgb[3] = {0, 0, 0};
    for (size_t k = 0; k < el->nprops; k++) {
        const ply_prop *pr = &el->props[k];
        long long v;
        if (pr->role >= R_X && pr->role <= R_Z) {
            if (!tf_double(&s, e, &xyz[pr->role - R_X]))
                return 0;
        } else if (pr->role >= R_RED && pr->role <= R_BLUE) {
            if (!tf_int(&s, e, &v, 0) || v < 0 || v > 255)
                return 0;
            rgb[pr->role - R_RED] = (unsigned char)v;
        } else if (!skip_token(&s, e)) {
            return 0;
        }
    }
    return tf_skip(s, e) == e && tf_push_vertex(c, xyz) &&
           (!t->colors || growbuf_append(&c->col, rgb, 3));
}

static int text_face(const tf_text *t, tf_chunk *c, const ply_elem *el, const char *s,
                     const char *e)
{
    for (size_t k = 0; k < el->nprops; k++) {
        const ply_prop *pr = &el->props[k];
        long long n, v;
        if (!pr->count_type) {
            if (!skip_token(&s, e))
                return 0;
            continue;
        }
        if (!tf_int(&s, e, &n, 0) || n < 3 || n > ply_type_max[pr->count_type])
            return 0;
        for (long long i = 0; i < n; i++)
            if (!tf_int(&s, e, &v, 0) || v < 0 || v >= (long long)t->nv ||
                v > ply_type_max[pr->type] || !tf_push_index(c, (uint32_t)v))
                return 0;
        if (!tf_end_face(c))
            return 0;
    }
    return tf_skip(s, e) == e;
}

static int text_line(const tf_text *t, tf_chunk *c, const char *s, const char *e,
                     uint64_t record)
{
    const ply_text *pt = t->format;
    const ply_elem *el = pt->order[record >= pt->first];
    return el->kind == E_VERTEX ? text_vertex(t, c, el, s, e) : text_face(t, c, el, s, e);
}

/* The elements with records: a vertex one without lists and at most a face
   one with the index list as its only list. */
static int text_layout(const ply *p, ply_text *pt)
{
    size_t n = 0;
    for (size_t i = 0; i < p->nelems; i++) {
        const ply_elem *e = &p->elems[i];
        size_t lists = 0;
        if (e->nprops == 0 || e->count == 0)
            continue;
        if (e->kind != E_VERTEX && e->kind != E_FACE)
            return 0;
        for (size_t k = 0; k < e->nprops; k++)
            if (e->props[k].count_type &&
                (lists++ || e->kind != E_FACE || e->props[k].role != R_INDICES))
                return 0;
        pt->order[n++] = e;
    }
    if (n == 0)
        return 0;
    pt->first = pt->order[0]->count;
    if (n == 1)
        pt->order[1] = pt->order[0];
    return 1;
}

int ply_text_setup(const ply *p, ply_text *pt, tf_text *t)
{
    if (p->format != F_ASCII || p->nv == 0 || !text_layout(p, pt))
        return 0;
    t->line = text_line;
    t->format = pt;
    t->nv = (uint32_t)p->nv;
    t->colors = p->colors;
    t->records = pt->first + (pt->order[1] != pt->order[0] ? pt->order[1]->count : 0);
    return 1;
}

int ply_text_fast_body(ply *p)
{
    ply_text pt;
    tf_text *t = calloc(1, sizeof *t);
    if (!t)
        return 0;
    if (!ply_text_setup(p, &pt, t)) {
        free(t);
        return 0;
    }
    int ok = tf_read(t, &p->r, &p->a);
    free(t);
    if (ok)
        p->tok = NULL;
    return ok;
}
