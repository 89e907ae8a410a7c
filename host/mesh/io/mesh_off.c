/* SPDX-License-Identifier: MIT */
/*
 * OFF (Geomview and MeshLab): a header word [ST][C][N][4][n]OFF whose
 * prefixes may come in any order (MeshLab writes NCOFF, NSTOFF, ...), nOFF's
 * dimension, the counts "V F [E]" on the header line or the next one, one
 * vertex per line, then one face per line "n i1 ... in" (0-based, extra
 * values such as face colours ignored). '#' starts a comment.
 *
 * A vertex line is "x y z", then normals (N, skipped), a colour (C: 3 or 4
 * values, integers 0-255 or, when none exceeds 1, fractions 0-1) and
 * texture coordinates (ST, skipped). Geomview puts the normal before the
 * colour; MeshLab, whose header word names N before C, the colour first.
 * Vertex colours are kept (RGB; alpha dropped).
 */
#include "mesh/io/formats.h"
#include "base/context.h"
#include "mesh/mesh.h"
#include "mesh/io/text_formats.h"
#include "mesh/io/toolkit.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define OFF_MAX_EXTRA 16 /* values after x y z on a vertex line that are looked at */

typedef struct off_state {
    mio_reader r;
    mio_arrays a;
    int st, c, n, four, ndim;  /* header word prefixes */
    int colour_first;          /* MeshLab order: the colour before the normal */
    long long nv, nf;
    long long crowded_face;    /* first face line holding more than its face, or -1 */
    unsigned long crowded_line;
    long long crowded_declared, crowded_values;
} off_state;

/* The next line with content (comments cut off), or NULL at the end. */
static char *off_line(mio_reader *r)
{
    size_t len;
    char *line;
    while ((line = mio_line(r, &len))) {
        char *hash = memchr(line, '#', len);
        if (hash)
            *hash = '\0';
        char *s = mio_skip_space(line);
        if (*s)
            return s;
    }
    return NULL;
}

/* What is left of this line, or the next line with content. */
static char *off_more(mio_reader *r, char *s)
{
    s = mio_skip_space(s);
    return *s ? s : off_line(r);
}

/* Reads the header word's prefixes (each at most once, any order). Returns
   NULL when fine, else what is wrong. */
static const char *off_header_word(off_state *o, const char *w, size_t n)
{
    if (n < 3 || memcmp(w + n - 3, "OFF", 3) != 0)
        return "not an OFF file (the first word is not OFF)";
    for (size_t i = 0, end = n - 3; i < end;) {
        int *flag = NULL;
        size_t len = 1;
        if (w[i] == 'S' && i + 1 < end && w[i + 1] == 'T')
            flag = &o->st, len = 2;
        else if (w[i] == 'C')
            flag = &o->c;
        else if (w[i] == 'N')
            flag = &o->n;
        else if (w[i] == '4')
            flag = &o->four;
        else if (w[i] == 'n')
            flag = &o->ndim;
        if (!flag || *flag)
            return "unknown OFF variant (supported: OFF with the prefixes ST, C, N and n, "
                   "e.g. COFF, NOFF, CNOFF, NCOFF, STOFF, STCNOFF)";
        *flag = 1;
        /* MeshLab names N before C and writes the colour first; Geomview the reverse */
        if (flag == &o->c)
            o->colour_first = o->n;
        i += len;
    }
    if (o->four)
        return "4OFF and nOFF (not 3-D) files are not supported (4OFF: 4 coordinates per "
               "vertex)";
    return NULL;
}

/* The header: word, nOFF's dimension, counts; checks them against the size. */
static limn_status off_header(off_state *o)
{
    mio_reader *r = &o->r;
    char tok[64];
    char *s = off_line(r);
    if (!s)
        return r->error ? mio_read_failed(r)
                        : ctx_fail(r->ctx, LIMN_ERR_FORMAT, "%s: no OFF header", r->path);
    size_t n = 0;
    while (s[n] && !mio_space(s[n]))
        n++;
    const char *bad = off_header_word(o, s, n);
    if (bad)
        return ctx_fail(r->ctx, LIMN_ERR_FORMAT, "%s:%lu: %s (found %s)", r->path, r->line, bad,
                         mio_token(s, tok));
    s = mio_skip_space(s + n);
    if (strncmp(s, "BINARY", 6) == 0)
        return ctx_fail(r->ctx, LIMN_ERR_FORMAT, "%s:%lu: binary OFF files are not supported",
                         r->path, r->line);
    long long dim = 3, ne = 0;
    if (o->ndim) {
        char *d = s = off_more(r, s);
        if (!s || !mio_parse_ll(&s, &dim, 0))
            return r->error ? mio_read_failed(r)
                            : ctx_fail(r->ctx, LIMN_ERR_FORMAT,
                                        "%s:%lu: nOFF: expected the dimension, found %s",
                                        r->path, r->line, d ? mio_token(d, tok) : "the end");
        if (dim != 3)
            return ctx_fail(r->ctx, LIMN_ERR_FORMAT,
                             "%s:%lu: nOFF of dimension %lld: only 3-D vertices are supported",
                             r->path, r->line, dim);
    }
    if (!(s = off_more(r, s)))
        return r->error ? mio_read_failed(r)
                        : ctx_fail(r->ctx, LIMN_ERR_FORMAT,
                                    "%s:%lu: the file ends before the vertex and face counts",
                                    r->path, r->line);
    char *c1 = s;
    if (!mio_parse_ll(&s, &o->nv, 0) || (s = mio_skip_space(s), !mio_parse_ll(&s, &o->nf, 0)) ||
        (s = mio_skip_space(s), *s && !mio_parse_ll(&s, &ne, 0)))
        return ctx_fail(r->ctx, LIMN_ERR_FORMAT,
                         "%s:%lu: expected the counts 'vertices faces [edges]', found %s",
                         r->path, r->line, mio_token(c1, tok));
    if (o->nv < 0 || o->nf < 0 || o->nv >= (long long)UINT32_MAX ||
        o->nf >= (long long)UINT32_MAX - 1)
        return ctx_fail(r->ctx, LIMN_ERR_FORMAT,
                         "%s:%lu: invalid counts: %lld vertices, %lld faces", r->path, r->line,
                         o->nv, o->nf);
    /* every vertex line takes >= 6 bytes ("0 0 0\n"), every face >= 8 */
    uint64_t need = (uint64_t)o->nv * 6 + (uint64_t)o->nf * 8, left = mio_remaining(r);
    if (need > left)
        return ctx_fail(r->ctx, LIMN_ERR_FORMAT,
                         "%s:%lu: the header declares %lld vertices and %lld faces (at least "
                         "%llu bytes) but only %llu bytes follow", r->path, r->line, o->nv,
                         o->nf, (unsigned long long)need, (unsigned long long)left);
    return LIMN_OK;
}

/* Reads up to OFF_MAX_EXTRA numbers after x y z; stops at anything else. */
static int off_extras(char *s, double *v)
{
    int n = 0;
    for (s = mio_skip_space(s); *s && n < OFF_MAX_EXTRA; s = mio_skip_space(s))
        if (mio_parse_double(&s, &v[n]) == 1)
            n++;
        else
            break;
    return n;
}

/* The vertex colour among the extra values, into rgb; 0 when there is none
   that can be read (a colour map index, values missing). */
static int off_colour(const off_state *o, const double *x, int nx, unsigned char rgb[3])
{
    int nc = nx - (o->n ? 3 : 0) - (o->st ? 2 : 0);
    if (nc != 3 && nc != 4)
        return 0;
    const double *c = x + (o->colour_first || !o->n ? 0 : 3);
    int bytes = 0; /* 0-255 when any value exceeds 1, else fractions */
    for (int k = 0; k < nc; k++)
        bytes |= c[k] > 1.0;
    for (int k = 0; k < 3; k++) {
        double v = bytes ? c[k] : c[k] * 255.0;
        rgb[k] = (unsigned char)(v <= 0 ? 0 : v >= 255 ? 255 : floor(v + 0.5));
    }
    return 1;
}

static limn_status off_vertices(off_state *o)
{
    mio_reader *r = &o->r;
    char tok[64];
    for (long long v = 0; v < o->nv; v++) {
        char *s = off_line(r);
        if (!s)
            return r->error ? mio_read_failed(r)
                            : ctx_fail(r->ctx, LIMN_ERR_FORMAT,
                                        "%s:%lu: the file ends after %lld of %lld vertices",
                                        r->path, r->line, v, o->nv);
        double c[3];
        for (int k = 0; k < 3; k++) {
            s = mio_skip_space(s);
            if (!*s)
                return ctx_fail(r->ctx, LIMN_ERR_FORMAT,
                                 "%s:%lu: vertex %lld has %d coordinates (3 needed)", r->path,
                                 r->line, v, k);
            int rc = mio_parse_double(&s, &c[k]);
            if (rc != 1)
                return ctx_fail(r->ctx, LIMN_ERR_FORMAT,
                                 "%s:%lu: vertex %lld: coordinate %s is %s", r->path, r->line, v,
                                 mio_token(s, tok), rc == 2 ? "not finite" : "not a number");
        }
        if (!growbuf_push_3d(&o->a.pos, c[0], c[1], c[2]))
            return ctx_fail(r->ctx, LIMN_ERR_MEMORY, "%s:%lu: out of memory", r->path, r->line);
        if (!o->c)
            continue;
        double x[OFF_MAX_EXTRA];
        unsigned char rgb[3];
        if (!off_colour(o, x, off_extras(s, x), rgb)) {
            ctx_warn(r->ctx, "%s:%lu: vertex %lld has no RGB colour that can be read: the "
                              "colours of the file are ignored", r->path, r->line, v);
            o->c = 0;
            growbuf_free(&o->a.col);
        } else if (!growbuf_append(&o->a.col, rgb, 3)) {
            return ctx_fail(r->ctx, LIMN_ERR_MEMORY, "%s:%lu: out of memory", r->path, r->line);
        }
    }
    return LIMN_OK;
}

/* After a face's indices: values that could be another face ("3 0 1 2 3 0 2
   3") are remembered, to explain a file that then ends faces early. */
static void off_face_rest(off_state *o, char *s, long long fc, long long k)
{
    long long first, values = 0, x;
    char *t = mio_skip_space(s);
    if (o->crowded_face >= 0 || !mio_parse_ll(&t, &first, 0) || first < 3)
        return;
    for (t = mio_skip_space(s); *t && mio_parse_ll(&t, &x, 0); t = mio_skip_space(t))
        values++;
    if (*t || values < first + 1)
        return; /* not all integers, or too few for a face: colours */
    o->crowded_face = fc;
    o->crowded_line = o->r.line;
    o->crowded_declared = k;
    o->crowded_values = k + values;
}

static limn_status off_face(off_state *o, char *s, long long fc)
{
    mio_reader *r = &o->r;
    char tok[64];
    long long k, idx;
    char *t = s;
    if (!mio_parse_ll(&s, &k, 0))
        return ctx_fail(r->ctx, LIMN_ERR_FORMAT,
                         "%s:%lu: face %lld: vertex count %s is not an integer", r->path, r->line,
                         fc, mio_token(t, tok));
    if (k < 3)
        return ctx_fail(r->ctx, LIMN_ERR_FORMAT,
                         "%s:%lu: face %lld has %lld vertices (at least 3 needed)", r->path,
                         r->line, fc, k);
    for (long long i = 0; i < k; i++) {
        s = mio_skip_space(s);
        t = s;
        if (!*s)
            return ctx_fail(r->ctx, LIMN_ERR_FORMAT,
                             "%s:%lu: face %lld declares %lld vertices but lists %lld", r->path,
                             r->line, fc, k, i);
        if (!mio_parse_ll(&s, &idx, 0))
            return ctx_fail(r->ctx, LIMN_ERR_FORMAT,
                             "%s:%lu: face %lld: vertex index %s is not an integer", r->path,
                             r->line, fc, mio_token(t, tok));
        if (idx < 0 || idx >= o->nv)
            return ctx_fail(r->ctx, LIMN_ERR_FORMAT,
                             "%s:%lu: face %lld references vertex %lld but only %lld vertices "
                             "are defined", r->path, r->line, fc, idx, o->nv);
        if (o->a.indices.len / sizeof(uint32_t) >= UINT32_MAX)
            return ctx_fail(r->ctx, LIMN_ERR_FORMAT, "%s:%lu: too many face indices", r->path,
                             r->line);
        if (!growbuf_push_u32(&o->a.indices, (uint32_t)idx))
            return ctx_fail(r->ctx, LIMN_ERR_MEMORY, "%s:%lu: out of memory", r->path, r->line);
    }
    off_face_rest(o, s, fc, k);
    if (!growbuf_push_u32(&o->a.offsets, (uint32_t)(o->a.indices.len / sizeof(uint32_t))))
        return ctx_fail(r->ctx, LIMN_ERR_MEMORY, "%s:%lu: out of memory", r->path, r->line);
    return LIMN_OK;
}

/* The file ended after fc faces: says so, naming a line that held two. */
static limn_status off_faces_end(off_state *o, long long fc)
{
    mio_reader *r = &o->r;
    if (r->error)
        return mio_read_failed(r);
    if (o->crowded_face >= 0)
        return ctx_fail(r->ctx, LIMN_ERR_FORMAT,
                         "%s:%lu: face %lld has %lld indices declared but the line holds %lld "
                         "values (two faces on one line?); the file ends after %lld of %lld "
                         "faces", r->path, o->crowded_line, o->crowded_face, o->crowded_declared,
                         o->crowded_values, fc, o->nf);
    return ctx_fail(r->ctx, LIMN_ERR_FORMAT, "%s:%lu: the file ends after %lld of %lld faces",
                     r->path, r->line, fc, o->nf);
}

/* The vertex and face records, line by line. */
static limn_status off_records(off_state *o)
{
    mio_reader *r = &o->r;
    size_t rv = mio_remaining(r) == UINT64_MAX && o->nv > 65536 ? 65536 : (size_t)o->nv;
    size_t rf = mio_remaining(r) == UINT64_MAX && o->nf > 65536 ? 65536 : (size_t)o->nf;
    if (!growbuf_reserve(&o->a.pos, rv * 3 * sizeof(double)) ||
        !growbuf_reserve(&o->a.offsets, (rf + 1) * sizeof(uint32_t)) ||
        !growbuf_reserve(&o->a.indices, rf * 3 * sizeof(uint32_t)) ||
        !growbuf_push_u32(&o->a.offsets, 0))
        return ctx_fail(r->ctx, LIMN_ERR_MEMORY, "%s:%lu: out of memory", r->path, r->line);
    limn_status st = off_vertices(o);
    for (long long fc = 0; fc < o->nf && !st; fc++) {
        char *s = off_line(r);
        st = s ? off_face(o, s, fc) : off_faces_end(o, fc);
    }
    return st;
}

static limn_status off_body(off_state *o)
{
    mio_reader *r = &o->r;
    /* mesh_off_fast.c: the same mesh, faster, for files without colours */
    limn_status st = !o->c && off_fast_body(r, &o->a, o->nv, o->nf) ? LIMN_OK : off_records(o);
    if (st)
        return st;
    if (off_line(r))
        ctx_warn(r->ctx, "%s:%lu: data after the last face ignored", r->path, r->line);
    if (r->error)
        return mio_read_failed(r);
    if (o->nv == 0)
        return ctx_fail(r->ctx, LIMN_ERR_FORMAT, "%s: the file defines no vertices", r->path);
    return LIMN_OK;
}

static limn_status off_parse(void *state, int *binary)
{
    off_state *o = state;
    (void)binary; /* OFF is read as text only */
    mio_skip_bom(&o->r);
    limn_status st = off_header(o);
    return st ? st : off_body(o);
}

limn_status off_read_header(limn_context *ctx, const char *path, FILE *f, uint64_t *body,
                            long long *nv, long long *nf)
{
    off_state *o = calloc(1, sizeof *o);
    if (!o)
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "%s: out of memory", path);
    limn_status st = LIMN_ERR_MEMORY;
    if (mio_init(&o->r, ctx, path, f)) {
        mio_skip_bom(&o->r);
        st = off_header(o);
        *body = mio_offset(&o->r);
        *nv = o->nv;
        *nf = o->nf;
    }
    mio_free(&o->r);
    free(o);
    return st;
}

limn_status off_read(limn_context *ctx, const char *path, FILE *f, limn_mesh **out)
{
    off_state *o = calloc(1, sizeof *o);
    if (!o)
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "%s: out of memory", path);
    o->crowded_face = -1;
    limn_status st = mio_read(&o->r, &o->a, ctx, path, f, off_parse, o, out);
    free(o);
    return st;
}
