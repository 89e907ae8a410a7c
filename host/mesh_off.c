/*
 * OFF (Geomview): a header word OFF (with the C/N/ST prefixes, whose extra
 * per-vertex values are ignored), the counts "V F [E]" on the header line or
 * the next one, one vertex per line, then one face per line "n i1 ... in"
 * (0-based, extra values such as colours ignored). '#' starts a comment.
 */
#include "mesh_io.h"
#include "context.h"
#include "mesh.h"

#include <string.h>

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

/* Checks the header word. Returns NULL when fine, else what is wrong. */
static const char *off_header_word(const char *w, size_t n)
{
    if (n < 3 || memcmp(w + n - 3, "OFF", 3) != 0)
        return "not an OFF file (the first word is not OFF)";
    size_t i = 0, end = n - 3;
    if (i + 2 <= end && memcmp(w + i, "ST", 2) == 0)
        i += 2;
    if (i < end && w[i] == 'C')
        i++;
    if (i < end && w[i] == 'N')
        i++;
    if (i < end && (w[i] == '4' || w[i] == 'n'))
        return "4OFF and nOFF (not 3-D) files are not supported";
    if (i != end)
        return "unknown OFF variant (supported: OFF, COFF, NOFF, CNOFF, STOFF and similar)";
    return NULL;
}

limn_status off_read(limn_context *ctx, const char *path, FILE *f, limn_mesh **out)
{
    mio_reader r;
    if (!mio_init(&r, ctx, path, f))
        return LIMN_ERR_MEMORY;
    growbuf pos = {0}, offsets = {0}, indices = {0};
    limn_status st = LIMN_OK;
    char tok[64];
    char *s = off_line(&r);
    if (!s) {
        st = r.error ? mio_read_failed(&r)
                     : limn_fail(ctx, LIMN_ERR_FORMAT, "%s: no OFF header", path);
        goto done;
    }
    size_t n = 0;
    while (s[n] && !mio_space(s[n]))
        n++;
    const char *bad = off_header_word(s, n);
    if (bad) {
        st = limn_fail(ctx, LIMN_ERR_FORMAT, "%s:%lu: %s (found %s)", path, r.line, bad,
                       mio_token(s, tok));
        goto done;
    }
    s = mio_skip_space(s + n);
    if (strncmp(s, "BINARY", 6) == 0) {
        st = limn_fail(ctx, LIMN_ERR_FORMAT, "%s:%lu: binary OFF files are not supported",
                       path, r.line);
        goto done;
    }
    if (!*s && !(s = off_line(&r))) {
        st = r.error ? mio_read_failed(&r)
                     : limn_fail(ctx, LIMN_ERR_FORMAT,
                                 "%s:%lu: the file ends before the vertex and face counts", path,
                                 r.line);
        goto done;
    }
    long long nv, nf, ne = 0;
    s = mio_skip_space(s);
    char *c1 = s;
    if (!mio_parse_ll(&s, &nv, 0) || (s = mio_skip_space(s), !mio_parse_ll(&s, &nf, 0)) ||
        (s = mio_skip_space(s), *s && !mio_parse_ll(&s, &ne, 0))) {
        st = limn_fail(ctx, LIMN_ERR_FORMAT,
                       "%s:%lu: expected the counts 'vertices faces [edges]', found %s", path,
                       r.line, mio_token(c1, tok));
        goto done;
    }
    if (nv < 0 || nf < 0 || nv >= (long long)UINT32_MAX || nf >= (long long)UINT32_MAX - 1) {
        st = limn_fail(ctx, LIMN_ERR_FORMAT, "%s:%lu: invalid counts: %lld vertices, %lld faces",
                       path, r.line, nv, nf);
        goto done;
    }
    /* every vertex line takes >= 6 bytes ("0 0 0\n"), every face >= 8 */
    uint64_t need = (uint64_t)nv * 6 + (uint64_t)nf * 8, left = mio_remaining(&r);
    if (need > left) {
        st = limn_fail(ctx, LIMN_ERR_FORMAT,
                       "%s:%lu: the header declares %lld vertices and %lld faces (at least %llu "
                       "bytes) but only %llu bytes follow", path, r.line, nv, nf,
                       (unsigned long long)need, (unsigned long long)left);
        goto done;
    }
    size_t rv = left == UINT64_MAX && nv > 65536 ? 65536 : (size_t)nv;
    size_t rf = left == UINT64_MAX && nf > 65536 ? 65536 : (size_t)nf;
    if (!growbuf_reserve(&pos, rv * 3 * sizeof(double)) ||
        !growbuf_reserve(&offsets, (rf + 1) * sizeof(uint32_t)) ||
        !growbuf_reserve(&indices, rf * 3 * sizeof(uint32_t)) || !growbuf_push_u32(&offsets, 0))
        goto nomem;

    for (long long v = 0; v < nv; v++) {
        if (!(s = off_line(&r))) {
            st = r.error ? mio_read_failed(&r)
                         : limn_fail(ctx, LIMN_ERR_FORMAT,
                                     "%s:%lu: the file ends after %lld of %lld vertices", path,
                                     r.line, v, nv);
            goto done;
        }
        double c[3];
        for (int k = 0; k < 3; k++) {
            s = mio_skip_space(s);
            if (!*s) {
                st = limn_fail(ctx, LIMN_ERR_FORMAT,
                               "%s:%lu: vertex %lld has %d coordinates (3 needed)", path, r.line,
                               v, k);
                goto done;
            }
            int rc = mio_parse_double(&s, &c[k]);
            if (rc != 1) {
                st = limn_fail(ctx, LIMN_ERR_FORMAT, "%s:%lu: vertex %lld: coordinate %s is %s",
                               path, r.line, v, mio_token(s, tok),
                               rc == 2 ? "not finite" : "not a number");
                goto done;
            }
        }
        if (!growbuf_push_3d(&pos, c[0], c[1], c[2]))
            goto nomem;
    }
    for (long long fc = 0; fc < nf; fc++) {
        if (!(s = off_line(&r))) {
            st = r.error ? mio_read_failed(&r)
                         : limn_fail(ctx, LIMN_ERR_FORMAT,
                                     "%s:%lu: the file ends after %lld of %lld faces", path,
                                     r.line, fc, nf);
            goto done;
        }
        long long k, idx;
        char *t = s;
        if (!mio_parse_ll(&s, &k, 0)) {
            st = limn_fail(ctx, LIMN_ERR_FORMAT,
                           "%s:%lu: face %lld: vertex count %s is not an integer", path, r.line,
                           fc, mio_token(t, tok));
            goto done;
        }
        if (k < 3) {
            st = limn_fail(ctx, LIMN_ERR_FORMAT,
                           "%s:%lu: face %lld has %lld vertices (at least 3 needed)", path,
                           r.line, fc, k);
            goto done;
        }
        for (long long i = 0; i < k; i++) {
            s = mio_skip_space(s);
            t = s;
            if (!*s) {
                st = limn_fail(ctx, LIMN_ERR_FORMAT,
                               "%s:%lu: face %lld declares %lld vertices but lists %lld", path,
                               r.line, fc, k, i);
                goto done;
            }
            if (!mio_parse_ll(&s, &idx, 0)) {
                st = limn_fail(ctx, LIMN_ERR_FORMAT,
                               "%s:%lu: face %lld: vertex index %s is not an integer", path,
                               r.line, fc, mio_token(t, tok));
                goto done;
            }
            if (idx < 0 || idx >= nv) {
                st = limn_fail(ctx, LIMN_ERR_FORMAT,
                               "%s:%lu: face %lld references vertex %lld but only %lld "
                               "vertices are defined", path, r.line, fc, idx, nv);
                goto done;
            }
            if (indices.len / sizeof(uint32_t) >= UINT32_MAX) {
                st = limn_fail(ctx, LIMN_ERR_FORMAT, "%s:%lu: too many face indices", path,
                               r.line);
                goto done;
            }
            if (!growbuf_push_u32(&indices, (uint32_t)idx))
                goto nomem;
        }
        if (!growbuf_push_u32(&offsets, (uint32_t)(indices.len / sizeof(uint32_t))))
            goto nomem;
    }
    if (off_line(&r))
        limn_warn(ctx, "%s:%lu: data after the last face ignored", path, r.line);
    if (r.error) {
        st = mio_read_failed(&r);
        goto done;
    }
    if (nv == 0) {
        st = limn_fail(ctx, LIMN_ERR_FORMAT, "%s: the file defines no vertices", path);
        goto done;
    }
    growbuf nocolors = {0};
    st = mio_make_mesh(ctx, &pos, &offsets, &indices, &nocolors, out);
    goto done;
nomem:
    st = limn_fail(ctx, LIMN_ERR_MEMORY, "%s:%lu: out of memory", path, r.line);
done:
    growbuf_free(&pos);
    growbuf_free(&offsets);
    growbuf_free(&indices);
    mio_free(&r);
    return st;
}

limn_status off_write(limn_context *ctx, const limn_mesh *m, const char *path, FILE *f)
{
    if (fprintf(f, "OFF\n%zu %zu 0\n", m->vertex_count, m->face_count) < 0)
        return mio_write_failed(ctx, path);
    const double *p = m->positions;
    for (size_t v = 0; v < m->vertex_count; v++, p += 3)
        if (fprintf(f, "%.17g %.17g %.17g\n", p[0], p[1], p[2]) < 0)
            return mio_write_failed(ctx, path);
    for (size_t fc = 0; fc < m->face_count; fc++) {
        uint32_t a = m->face_offsets[fc], b = m->face_offsets[fc + 1];
        if (fprintf(f, "%lu", (unsigned long)(b - a)) < 0)
            return mio_write_failed(ctx, path);
        for (uint32_t i = a; i < b; i++)
            if (fprintf(f, " %lu", (unsigned long)m->face_indices[i]) < 0)
                return mio_write_failed(ctx, path);
        if (fputc('\n', f) == EOF)
            return mio_write_failed(ctx, path);
    }
    return LIMN_OK;
}
