/* SPDX-License-Identifier: MIT */
/*
 * OBJ's fast path (text_formats.h): `v x y z ...` (what follows z ignored,
 * as the general reader ignores it), `f` with positive vertex numbers in the
 * forms a, a/b, a//c, a/b/c, comments and the records the general reader
 * skips in silence. Negative (relative) numbers, unknown records and every
 * error give way to the general reader (mesh_obj.c).
 */
#include "mesh/io/text_formats.h"
#include "mesh/io/text_fast.h"

#include <stdlib.h>
#include <string.h>

static int obj_fast_vertex(tf_chunk *c, const char *s, const char *e)
{
    double xyz[3];
    for (int k = 0; k < 3; k++)
        if (!tf_double(&s, e, &xyz[k]))
            return 0;
    return tf_push_vertex(c, xyz);
}

/* The texture and normal parts of a face token, as obj_skip_refs checks them. */
static int obj_fast_refs(const char **s, const char *te)
{
    long long unused;
    for (int part = 0; part < 2 && *s < te && **s == '/'; part++) {
        (*s)++;
        if (*s == te || **s == '/')
            continue;
        if (!tf_int(s, te, &unused, part == 0 ? '/' : 0))
            return 0;
    }
    return *s == te;
}

/* A negative (relative) number counts back from the vertices defined before
   the line: `before` of them before c's range, none known when before < 0. */
static int obj_fast_face(tf_chunk *c, const char *s, const char *e, long long before)
{
    size_t n = 0;
    long long defined = before < 0 ? -1 : before + (long long)(c->pos.len / 24);
    for (;;) {
        s = tf_skip(s, e);
        if (s == e)
            break;
        long long v;
        if (!tf_int(&s, e, &v, '/') ||
            (s < e && *s == '/' && !obj_fast_refs(&s, tf_token_end(s, e))))
            return 0;
        if (v < 0 && defined >= 0 && -v <= defined) {
            if (!tf_push_index(c, (uint32_t)(defined + v)))
                return 0;
            n++;
            continue;
        }
        if (v <= 0 || v >= (long long)UINT32_MAX || !tf_push_index(c, (uint32_t)(v - 1)))
            return 0;
        if ((uint64_t)v > c->max_ref)
            c->max_ref = (uint64_t)v;
        n++;
    }
    return n >= 3 && tf_end_face(c);
}

static int obj_fast_line(const tf_text *t, tf_chunk *c, const char *s, const char *e,
                         uint64_t record)
{
    (void)t;
    (void)record;
    return obj_fast_record(c, s, e, -1);
}

int obj_fast_record(tf_chunk *c, const char *s, const char *e, long long before)
{
    if ((s[0] == 'v' || s[0] == 'f') && (s + 1 == e || tf_space(s[1])))
        return s[0] == 'v' ? obj_fast_vertex(c, s + 1, e) : obj_fast_face(c, s + 1, e, before);
    return obj_skipped_record(s, (size_t)(tf_token_end(s, e) - s));
}

int obj_fast_read(mio_reader *r, mio_arrays *a, size_t *vertices)
{
    tf_text *t = calloc(1, sizeof *t);
    if (!t)
        return 0;
    t->line = obj_fast_line;
    t->obj = 1;
    t->hash_comments = 1;
    int ok = tf_read(t, r, a);
    if (ok)
        *vertices = a->pos.len / 24;
    free(t);
    return ok;
}
