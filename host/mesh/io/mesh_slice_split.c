/* SPDX-License-Identifier: MIT */
/*
 * Split input (mesh_slice.h): one binary PLY a part, NAME.r<p>.ply, whose
 * faces hold global vertex indices and whose header comment
 *   comment limn-slice part p parts P vertex_begin B vertex_total N face_begin F face_total M
 * places the part in the whole. The writer writes one part (atomically; or
 * stages it, complete and synced, for the caller to commit with the others);
 * the reader reads one part with the binary PLY slice reader
 * (mesh_slice_ply.c, indices checked against N) and checks its header
 * against its predecessor's, so that parts that all succeed agree.
 */
#include "base/atomic_file.h"
#include "base/context.h"
#include "mesh/io/mesh_slice_formats.h"

#include <inttypes.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

int mesh_slice_split_name(const char *name, unsigned part, char *buf, size_t size)
{
    size_t n = strlen(name);
    if (n >= 4 && strcasecmp(name + n - 4, ".ply") == 0)
        n -= 4;
    int w = snprintf(buf, size, "%.*s.r%u.ply", (int)n, name, part);
    return w > 0 && (size_t)w < size;
}

/* ------------------------------------------------------------------ write */

static void put_le(unsigned char *b, uint64_t v, unsigned n)
{
    for (unsigned i = 0; i < n; i++, v >>= 8)
        b[i] = (unsigned char)v;
}

static int write_records(FILE *f, const mesh_slice *s, int wide)
{
    unsigned char b[24];
    for (size_t i = 0; i < 3 * s->vertex_count; i++) {
        uint64_t u;
        memcpy(&u, &s->positions[i], 8);
        put_le(b, u, 8);
        if (fwrite(b, 1, 8, f) != 8)
            return 0;
    }
    for (size_t k = 0; k < s->face_count; k++) {
        uint32_t a = s->face_offsets[k], n = s->face_offsets[k + 1] - a;
        put_le(b, n, wide ? 4 : 1);
        if (fwrite(b, 1, wide ? 4 : 1, f) != (wide ? 4u : 1u))
            return 0;
        for (uint32_t j = 0; j < n; j++) {
            put_le(b, s->face_indices[a + j], 4);
            if (fwrite(b, 1, 4, f) != 4)
                return 0;
        }
    }
    return 1;
}

limn_status mesh_slice_stage_split(limn_context *ctx, const char *name, unsigned part,
                                   unsigned parts, const mesh_slice *s, atomic_file *af)
{
    char path[4096];
    memset(af, 0, sizeof *af);
    if (!mesh_slice_split_name(name, part, path, sizeof path))
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "%s: the name is too long", name);
    int wide = 0;
    for (size_t k = 0; k < s->face_count; k++)
        wide |= s->face_offsets[k + 1] - s->face_offsets[k] > 255;
    limn_status st = atomic_file_open(ctx, path, af);
    if (st)
        return st;
    int ok = fprintf(af->f,
                     "ply\nformat binary_little_endian 1.0\ncomment limn-slice part %u parts %u "
                     "vertex_begin %zu vertex_total %zu face_begin %zu face_total %zu\n"
                     "element vertex %zu\nproperty double x\nproperty double y\n"
                     "property double z\nelement face %zu\nproperty list %s uint "
                     "vertex_indices\nend_header\n",
                     part, parts, s->vertex_begin, s->vertex_total, s->face_begin,
                     s->face_total, s->vertex_count, s->face_count,
                     wide ? "uint" : "uchar") > 0 &&
             write_records(af->f, s, wide);
    if (!ok) {
        st = ctx_fail(ctx, LIMN_ERR_IO, "cannot write %s", path);
        atomic_file_abort(af);
        return st;
    }
    return atomic_file_finish(ctx, af);
}

limn_status mesh_slice_write_split(limn_context *ctx, const char *name, unsigned part,
                                   unsigned parts, const mesh_slice *s)
{
    atomic_file af;
    limn_status st = mesh_slice_stage_split(ctx, name, part, parts, s, &af);
    return st ? st : atomic_file_commit(ctx, &af);
}

/* ------------------------------------------------------------------- read */

/* A part's header: its place in the whole and its own counts. */
typedef struct split_head {
    unsigned part, parts;
    unsigned long long vb, vt, fb, ft, nv, nf;
} split_head;

static limn_status head_parse(limn_context *ctx, const char *path, const ply *p, split_head *h)
{
    memset(h, 0, sizeof *h);
    int n = sscanf(p->slice_comment,
                   "part %u parts %u vertex_begin %llu vertex_total %llu face_begin %llu "
                   "face_total %llu", &h->part, &h->parts, &h->vb, &h->vt, &h->fb, &h->ft);
    if (n != 6)
        return ctx_fail(ctx, LIMN_ERR_FORMAT,
                        "%s: not a part of a split input (no header line 'comment limn-slice "
                        "part P parts N vertex_begin B vertex_total N face_begin F face_total "
                        "M')", path);
    h->nv = p->nv;
    for (size_t i = 0; i < p->nelems; i++)
        if (p->elems[i].kind == E_FACE)
            h->nf = p->elems[i].count;
    if (p->format == F_ASCII || h->vb + h->nv > h->vt || h->fb + h->nf > h->ft ||
        h->vb > h->vt || h->fb > h->ft)
        return ctx_fail(ctx, LIMN_ERR_FORMAT,
                        "%s: a split part must be binary and hold vertices [%llu, %llu) of %llu "
                        "and faces [%llu, %llu) of %llu within the totals", path, h->vb,
                        h->vb + h->nv, h->vt, h->fb, h->fb + h->nf, h->ft);
    return LIMN_OK;
}

/* Opens part `part`'s file (sf, p for the caller, who closes them). */
static limn_status head_open(limn_context *ctx, const char *name, unsigned part, char *path,
                             slice_file *sf, ply *p, split_head *h)
{
    memset(p, 0, sizeof *p);
    memset(sf, 0, sizeof *sf);
    if (!mesh_slice_split_name(name, part, path, 4096))
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "%s: the name is too long", name);
    limn_status st = slice_file_open(ctx, path, sf);
    if (!st && !(st = ply_open(p, ctx, path, sf->f)))
        st = head_parse(ctx, path, p, h);
    return st;
}

static void head_close(slice_file *sf, ply *p)
{
    ply_close(p);
    slice_file_close(sf);
}

static limn_status disagree(limn_context *ctx, const char *path, const char *what)
{
    return ctx_fail(ctx, LIMN_ERR_FORMAT, "%s: the split input's parts disagree: %s", path,
                    what);
}

/* The part's header against the reader's part and its predecessor's. */
static limn_status agree(limn_context *ctx, const char *name, const char *path,
                         const split_head *h, unsigned part, unsigned parts)
{
    if (h->part != part || h->parts != parts) {
        char what[160];
        snprintf(what, sizeof what, "it says part %u of %u, read as part %u of %u", h->part,
                 h->parts, part, parts);
        return disagree(ctx, path, what);
    }
    if (part == 0 && (h->vb || h->fb))
        return disagree(ctx, path, "the first part does not start at vertex 0 and face 0");
    if (part + 1 == parts && (h->vb + h->nv != h->vt || h->fb + h->nf != h->ft))
        return disagree(ctx, path, "the last part does not end at the totals");
    char other[4096];
    struct stat sb;
    if (part + 1 == parts && mesh_slice_split_name(name, parts, other, sizeof other) &&
        stat(other, &sb) == 0)
        return disagree(ctx, other, "the file exists beyond the last part");
    if (part == 0)
        return LIMN_OK;
    slice_file sf;
    ply *p = malloc(sizeof *p);
    split_head q;
    if (!p)
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "%s: out of memory", path);
    limn_status st = head_open(ctx, name, part - 1, other, &sf, p, &q);
    if (!st && (q.vb + q.nv != h->vb || q.fb + q.nf != h->fb || q.vt != h->vt ||
                q.ft != h->ft || q.parts != parts))
        st = disagree(ctx, path, "it does not start where the part before it ends, or "
                                 "their totals differ");
    head_close(&sf, p);
    free(p);
    return st;
}

limn_status mesh_slice_read_split(limn_context *ctx, const char *name, unsigned part,
                                  unsigned parts, mesh_slice *out)
{
    char path[4096];
    slice_file sf;
    split_head h;
    mesh_slice_counts c;
    memset(out, 0, sizeof *out);
    if (parts == 0 || part >= parts)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "%s: part %u of %u parts does not exist", name,
                        part, parts);
    ply *p = malloc(sizeof *p);
    if (!p)
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "%s: out of memory", name);
    limn_status st = head_open(ctx, name, part, path, &sf, p, &h);
    if (!st)
        st = agree(ctx, name, path, &h, part, parts);
    if (!st && !(st = slice_ply_count(&sf, p, 0, 1, &c)))
        st = slice_ply_read(&sf, p, 0, 1, c.irregular == 0, h.vt, out);
    head_close(&sf, p);
    free(p);
    if (!st) {
        out->vertex_total = (size_t)h.vt;
        out->face_total = (size_t)h.ft;
        out->vertex_begin = (size_t)h.vb;
        out->face_begin = (size_t)h.fb;
    }
    return st;
}
