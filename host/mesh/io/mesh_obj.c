/* SPDX-License-Identifier: MIT */
/*
 * Wavefront OBJ: `v x y z [w | r g b]` and `f` records (forms a, a/b, a//c,
 * a/b/c; negative indices count back from the last vertex defined). Every
 * other record is skipped. Written with "%.17g" so positions round-trip.
 */
#include "mesh/io/formats.h"
#include "base/context.h"
#include "mesh/mesh.h"
#include "mesh/io/text_formats.h"
#include "mesh/io/toolkit.h"

#include <string.h>

/* Records that carry nothing limn uses. */
static const char *const obj_skipped[] = {
    "vt", "vn", "vp", "o", "g", "s", "usemtl", "mtllib", "l", "p", "t",
    "cstype", "deg", "bmat", "step", "curv", "curv2", "surf", "parm", "trim",
    "hole", "scrv", "sp", "end", "con", "mg", "lod", "maplib", "usemap",
    "bevel", "c_interp", "d_interp", "shadow_obj", "trace_obj", "ctech",
    "stech", "call", "csh",
};

int obj_skipped_record(const char *word, size_t n)
{
    for (size_t i = 0; i < sizeof obj_skipped / sizeof obj_skipped[0]; i++)
        if (strlen(obj_skipped[i]) == n && memcmp(obj_skipped[i], word, n) == 0)
            return 1;
    return 0;
}

typedef struct obj_state {
    mio_reader r;
    mio_arrays a;
    size_t vertices;             /* defined so far */
    long long max_ref;           /* largest positive index used */
    unsigned long max_ref_line;  /* where it was first used */
} obj_state;

static limn_status obj_vertex(obj_state *o, char *s)
{
    mio_reader *r = &o->r;
    double c[3];
    char tok[64];
    for (int k = 0; k < 3; k++) {
        s = mio_skip_space(s);
        if (!*s)
            return ctx_fail(r->ctx, LIMN_ERR_FORMAT,
                             "%s:%lu: vertex %zu has %d coordinates (3 needed)", r->path,
                             r->line, o->vertices + 1, k);
        int rc = mio_parse_double(&s, &c[k]);
        if (rc != 1)
            return ctx_fail(r->ctx, LIMN_ERR_FORMAT, "%s:%lu: vertex %zu: coordinate %s is %s",
                             r->path, r->line, o->vertices + 1, mio_token(s, tok),
                             rc == 2 ? "not finite" : "not a number");
    }
    if (o->vertices >= UINT32_MAX - 1)
        return ctx_fail(r->ctx, LIMN_ERR_FORMAT, "%s:%lu: too many vertices (limit %u)",
                         r->path, r->line, (unsigned)(UINT32_MAX - 1));
    if (!growbuf_push_3d(&o->a.pos, c[0], c[1], c[2]))
        return ctx_fail(r->ctx, LIMN_ERR_MEMORY, "%s:%lu: out of memory for %zu vertices",
                         r->path, r->line, o->vertices + 1);
    o->vertices++;
    return LIMN_OK;
}

/* Checks the texture/normal part of a face token ("/b", "//c", "/b/c"). */
static int obj_skip_refs(char **s)
{
    long long unused;
    for (int part = 0; part < 2 && **s == '/'; part++) {
        (*s)++;
        if (**s == '/' || !**s || mio_space(**s))
            continue;
        if (!mio_parse_ll(s, &unused, part == 0 ? '/' : 0))
            return 0;
    }
    return !**s || mio_space(**s);
}

static limn_status obj_face(obj_state *o, char *s)
{
    mio_reader *r = &o->r;
    size_t n = 0;
    char tok[64];
    for (;;) {
        s = mio_skip_space(s);
        if (!*s)
            break;
        char *start = s;
        long long v;
        if (!mio_parse_ll(&s, &v, '/') || !obj_skip_refs(&s))
            return ctx_fail(r->ctx, LIMN_ERR_FORMAT,
                             "%s:%lu: face: %s is not a vertex reference (a, a/b, a//c or a/b/c)",
                             r->path, r->line, mio_token(start, tok));
        uint32_t index;
        if (v > 0) {
            if (v >= (long long)UINT32_MAX)
                return ctx_fail(r->ctx, LIMN_ERR_FORMAT,
                                 "%s:%lu: face references vertex %lld but only %zu vertices "
                                 "are defined", r->path, r->line, v, o->vertices);
            if ((unsigned long long)v > o->vertices && v > o->max_ref) {
                o->max_ref = v;
                o->max_ref_line = r->line;
            }
            index = (uint32_t)(v - 1);
        } else if (v < 0) {
            if ((unsigned long long)(-(v + 1)) >= o->vertices)
                return ctx_fail(r->ctx, LIMN_ERR_FORMAT,
                                 "%s:%lu: face references vertex %lld but only %zu vertices "
                                 "are defined before it", r->path, r->line, v, o->vertices);
            index = (uint32_t)((long long)o->vertices + v);
        } else {
            return ctx_fail(r->ctx, LIMN_ERR_FORMAT,
                             "%s:%lu: face references vertex 0 (OBJ indices start at 1)",
                             r->path, r->line);
        }
        if (o->a.indices.len / sizeof(uint32_t) >= UINT32_MAX)
            return ctx_fail(r->ctx, LIMN_ERR_FORMAT, "%s:%lu: too many face indices",
                             r->path, r->line);
        if (!growbuf_push_u32(&o->a.indices, index))
            return ctx_fail(r->ctx, LIMN_ERR_MEMORY, "%s:%lu: out of memory for faces",
                             r->path, r->line);
        n++;
    }
    if (n < 3)
        return ctx_fail(r->ctx, LIMN_ERR_FORMAT,
                         "%s:%lu: face has %zu vertices (at least 3 needed)", r->path, r->line, n);
    if (o->a.offsets.len / sizeof(uint32_t) >= UINT32_MAX - 1)
        return ctx_fail(r->ctx, LIMN_ERR_FORMAT, "%s:%lu: too many faces", r->path, r->line);
    if (!growbuf_push_u32(&o->a.offsets, (uint32_t)(o->a.indices.len / sizeof(uint32_t))))
        return ctx_fail(r->ctx, LIMN_ERR_MEMORY, "%s:%lu: out of memory for faces", r->path,
                         r->line);
    return LIMN_OK;
}

static limn_status obj_parse(void *state, int *binary)
{
    obj_state *o = state;
    mio_reader *r = &o->r;
    limn_context *ctx = r->ctx;
    const char *path = r->path;
    (void)binary; /* OBJ is text only */
    r->continuation = 1;
    mio_skip_bom(r);
    if (obj_fast_read(r, &o->a, &o->vertices))
        return LIMN_OK; /* mesh_obj_fast.c: the same mesh, faster */
    limn_status st = LIMN_OK;
    size_t unknown = 0;
    if (!growbuf_push_u32(&o->a.offsets, 0))
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "%s: out of memory", path);
    size_t len;
    char *line;
    while ((line = mio_line(r, &len))) {
        char *s = mio_skip_space(line);
        if (s[0] == 'v' && (mio_space(s[1]) || !s[1]))
            st = obj_vertex(o, s + 1);
        else if (s[0] == 'f' && (mio_space(s[1]) || !s[1]))
            st = obj_face(o, s + 1);
        else if (s[0] && s[0] != '#') {
            size_t n = 0;
            while (s[n] && !mio_space(s[n]))
                n++;
            if (!obj_skipped_record(s, n) && unknown++ == 0) {
                char tok[64];
                ctx_warn(ctx, "%s:%lu: unknown OBJ record %s ignored", path, r->line,
                          mio_token(s, tok));
            }
        }
        if (st)
            return st;
    }
    if (r->error)
        return mio_read_failed(r);
    if (unknown > 1)
        ctx_warn(ctx, "%s: %zu unknown OBJ records ignored in all", path, unknown);
    if (r->unterminated)
        ctx_warn(ctx, "%s:%lu: the last line does not end with a new line: the file may be "
                       "truncated (OBJ has no counts to check)",
                  path, r->line);
    if (o->max_ref > 0 && (unsigned long long)o->max_ref > o->vertices)
        return ctx_fail(ctx, LIMN_ERR_FORMAT,
                        "%s:%lu: face references vertex %lld but only %zu vertices are defined",
                        path, o->max_ref_line, o->max_ref, o->vertices);
    if (o->vertices == 0)
        return ctx_fail(ctx, LIMN_ERR_FORMAT, "%s: the file defines no vertices", path);
    return LIMN_OK;
}

limn_status obj_read(limn_context *ctx, const char *path, FILE *f, limn_mesh **out)
{
    obj_state o;
    memset(&o, 0, sizeof o);
    return mio_read(&o.r, &o.a, ctx, path, f, obj_parse, &o, out);
}
