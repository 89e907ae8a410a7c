/* SPDX-License-Identifier: MIT */
/* The fuzz harness: see fuzz_common.h. */
#ifndef _GNU_SOURCE
#define _GNU_SOURCE /* memfd_create */
#endif
#include "fuzz_common.h"
#include "limn.h"
#include "mesh/io/formats.h" /* ply_write into memory, for the round trip */
#include "mesh/io/mesh_slice.h" /* the slice reader against the whole one */

#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <unistd.h>

typedef struct target {
    const char *name;
    limn_format format;
    const char *prefix;
} target;

static const target targets[] = {
    {"obj", LIMN_FORMAT_OBJ, NULL},
    {"off", LIMN_FORMAT_OFF, NULL},
    {"stl", LIMN_FORMAT_STL, NULL},
    {"ply", LIMN_FORMAT_PLY, NULL},
    {"ply_le", LIMN_FORMAT_PLY, "ply\nformat binary_little_endian 1.0\n"},
    {"ply_be", LIMN_FORMAT_PLY, "ply\nformat binary_big_endian 1.0\n"},
};

static void broken(const char *what, const char *message)
{
    fprintf(stderr, "limn fuzz: contract broken: %s\n  message: %s\n", what,
            message ? message : "(none)");
    abort();
}

/* A mesh a reader returned: every documented invariant. */
static void check_mesh(const limn_mesh *m, int repaired, const char *msg)
{
    size_t nv = limn_mesh_vertex_count(m), nf = limn_mesh_face_count(m);
    const double *p = limn_mesh_positions(m);
    const uint32_t *off = limn_mesh_face_offsets(m), *idx = limn_mesh_face_indices(m);
    if (!p || !off || !idx)
        broken("a mesh without arrays", msg);
    for (size_t i = 0; i < 3 * nv; i++)
        if (!isfinite(p[i]))
            broken("a non-finite coordinate was accepted", msg);
    if (off[0] != 0)
        broken("face_offsets[0] != 0", msg);
    for (size_t f = 0; f < nf; f++) {
        if (off[f + 1] < off[f] + 3)
            broken("a face with fewer than 3 corners was accepted", msg);
        for (uint32_t c = off[f]; c < off[f + 1]; c++) {
            if (idx[c] >= nv)
                broken("a face index out of range was accepted", msg);
            if (repaired)
                for (uint32_t d = off[f]; d < c; d++)
                    if (idx[d] == idx[c])
                        broken("a repaired face still uses a vertex twice", msg);
        }
    }
}

/* A file in memory (memfd): a regular file to fstat, named /proc/self/fd/N. */
static const char *memfile(int *fd, char *path, size_t size, const void *a, size_t na,
                           const void *b, size_t nb)
{
    if (*fd < 0) {
        *fd = memfd_create("limn_fuzz", 0);
        if (*fd < 0) {
            perror("memfd_create");
            abort();
        }
        snprintf(path, size, "/proc/self/fd/%d", *fd);
    }
    if (ftruncate(*fd, 0) != 0 || (na && pwrite(*fd, a, na, 0) != (ssize_t)na) ||
        (nb && pwrite(*fd, b, nb, (off_t)na) != (ssize_t)nb)) {
        perror("limn fuzz: writing the input");
        abort();
    }
    return path;
}

/* The input through a pipe (/proc/self/fd/N of its read end, the write end
   closed): a file of unknown size, so the readers' other paths (no size
   checks, capped reservations) run too. Returns -1 when it does not fit. */
static int pipefile(char *path, size_t size, const void *a, size_t na, const void *b, size_t nb)
{
    int p[2];
    if (na + nb > 65536 || pipe(p) != 0)
        return -1;
    if ((na && write(p[1], a, na) != (ssize_t)na) || (nb && write(p[1], b, nb) != (ssize_t)nb)) {
        close(p[0]);
        close(p[1]);
        return -1;
    }
    close(p[1]);
    snprintf(path, size, "/proc/self/fd/%d", p[0]);
    return p[0];
}

/* Writes the mesh as binary PLY (doubles: lossless) and reads it back: the
   same vertices, faces and colours, bit for bit. */
static void round_trip(const limn_mesh *m)
{
    static int fd = -1;
    static char path[64];
    char *buf = NULL;
    size_t len = 0;
    limn_context *ctx = limn_context_create();
    FILE *f = open_memstream(&buf, &len);
    if (!ctx || !f) {
        if (f)
            fclose(f);
        free(buf);
        limn_context_destroy(ctx);
        return;
    }
    limn_status st = ply_write(ctx, m, "round-trip.ply", f, LIMN_FORMAT_PLY, 0);
    if (fclose(f) != 0 && !st)
        st = LIMN_ERR_MEMORY;
    limn_mesh *back = NULL;
    if (!st) {
        memfile(&fd, path, sizeof path, buf, len, NULL, 0);
        st = limn_mesh_read(ctx, path, LIMN_FORMAT_PLY, &back);
    }
    free(buf);
    if (st == LIMN_ERR_MEMORY) {
        limn_context_destroy(ctx);
        return;
    }
    if (st)
        broken("a written mesh does not read back", limn_context_message(ctx));
    size_t nv = limn_mesh_vertex_count(m), nf = limn_mesh_face_count(m);
    const uint32_t *off = limn_mesh_face_offsets(m);
    if (limn_mesh_vertex_count(back) != nv || limn_mesh_face_count(back) != nf ||
        memcmp(limn_mesh_positions(back), limn_mesh_positions(m), 3 * nv * sizeof(double)) ||
        memcmp(limn_mesh_face_offsets(back), off, (nf + 1) * sizeof *off) ||
        memcmp(limn_mesh_face_indices(back), limn_mesh_face_indices(m),
               off[nf] * sizeof(uint32_t)) ||
        !limn_mesh_colors(back) != !limn_mesh_colors(m) ||
        (limn_mesh_colors(m) && memcmp(limn_mesh_colors(back), limn_mesh_colors(m), 3 * nv)))
        broken("a mesh written as PLY reads back different", NULL);
    limn_mesh_destroy(back);
    limn_context_destroy(ctx);
}

/* The text readers' fast path (text_fast.c) against the general reader
   (LIMN_TEST_TEXT_GENERAL=1) on the same file: the same status, message,
   warnings and mesh, bit for bit. */
static void same_as_general(const char *input, limn_format format, limn_status st,
                            const limn_mesh *m, limn_context *fast)
{
    limn_context *ctx = limn_context_create();
    if (!ctx)
        return;
    setenv("LIMN_TEST_TEXT_GENERAL", "1", 1);
    limn_mesh *g = NULL;
    limn_status gst = limn_mesh_read(ctx, input, format, &g);
    unsetenv("LIMN_TEST_TEXT_GENERAL");
    const char *fw = limn_context_warnings(fast), *gw = limn_context_warnings(ctx);
    if (gst != st || strcmp(limn_context_message(ctx), limn_context_message(fast)) != 0 ||
        strcmp(fw ? fw : "", gw ? gw : "") != 0)
        broken("the text fast path and the general reader disagree",
               limn_context_message(ctx));
    if (m && g) {
        size_t nv = limn_mesh_vertex_count(m), nf = limn_mesh_face_count(m);
        if (limn_mesh_vertex_count(g) != nv || limn_mesh_face_count(g) != nf ||
            memcmp(limn_mesh_positions(g), limn_mesh_positions(m), 3 * nv * sizeof(double)) ||
            memcmp(limn_mesh_face_offsets(g), limn_mesh_face_offsets(m),
                   (nf + 1) * sizeof(uint32_t)) ||
            memcmp(limn_mesh_face_indices(g), limn_mesh_face_indices(m),
                   limn_mesh_index_count(m) * sizeof(uint32_t)) ||
            !limn_mesh_colors(g) != !limn_mesh_colors(m) ||
            (limn_mesh_colors(m) && memcmp(limn_mesh_colors(g), limn_mesh_colors(m), 3 * nv)))
            broken("the text fast path reads a different mesh than the general reader", NULL);
    }
    limn_mesh_destroy(g);
    limn_context_destroy(ctx);
}

/* The slice reader (mesh_slice.h) in 3 parts against limn_mesh_read's
   status st and mesh m: it may refuse more (with a message naming the file)
   but never accept a file refused for anything but memory, and what it
   reads is m bit for bit. */
static int slices_match(const limn_mesh *m, const mesh_slice *s, unsigned parts)
{
    size_t v = 0, f = 0;
    const uint32_t *off = limn_mesh_face_offsets(m);
    for (unsigned p = 0; p < parts; p++) {
        const mesh_slice *q = &s[p];
        size_t n = q->face_offsets[q->face_count];
        if (q->vertex_begin != v || q->face_begin != f ||
            q->vertex_total != limn_mesh_vertex_count(m) ||
            q->face_total != limn_mesh_face_count(m) || f + q->face_count > q->face_total ||
            v + q->vertex_count > q->vertex_total ||
            (q->vertex_count && memcmp(q->positions, limn_mesh_positions(m) + 3 * v,
                                       q->vertex_count * 24) != 0) ||
            off[f + q->face_count] - off[f] != n ||
            (n && memcmp(q->face_indices, limn_mesh_face_indices(m) + off[f], n * 4) != 0))
            return 0;
        v += q->vertex_count;
        f += q->face_count;
    }
    return v == limn_mesh_vertex_count(m) && f == limn_mesh_face_count(m);
}

static void same_as_slices(const char *input, limn_format format, limn_status st,
                           const limn_mesh *m)
{
    enum { P = 3 };
    mesh_slice s[P];
    mesh_slice_counts c[P], before, total;
    limn_context *ctx = limn_context_create();
    if (!ctx)
        return;
    memset(s, 0, sizeof s);
    memset(&before, 0, sizeof before);
    memset(&total, 0, sizeof total);
    limn_status ss = LIMN_OK;
    for (unsigned p = 0; p < P && !ss; p++)
        if (!(ss = mesh_slice_count(ctx, input, format, p, P, &c[p])))
            mesh_slice_counts_add(&total, &c[p]);
    for (unsigned p = 0; p < P && !ss; p++)
        if (!(ss = mesh_slice_read(ctx, input, format, p, P, &before, &total, &s[p])))
            mesh_slice_counts_add(&before, &c[p]);
    if (ss && !strstr(limn_context_message(ctx), input))
        broken("a failed slice read without a message naming the file",
               limn_context_message(ctx));
    if (!ss && st && st != LIMN_ERR_MEMORY)
        broken("the slice reader accepted a file limn_mesh_read refuses", NULL);
    if (!ss && m && !slices_match(m, s, P))
        broken("the slices differ from limn_mesh_read's mesh", NULL);
    for (unsigned p = 0; p < P; p++)
        mesh_slice_free(&s[p]);
    limn_context_destroy(ctx);
}

int limn_fuzz_run(const char *name, const uint8_t *data, size_t size)
{
    static int fd = -1;
    static char path[64];
    const target *t = NULL;
    for (size_t i = 0; i < sizeof targets / sizeof targets[0]; i++)
        if (strcmp(name, targets[i].name) == 0)
            t = &targets[i];
    if (!t)
        return -1;
    size_t plen = t->prefix ? strlen(t->prefix) : 0;
    /* one input in four through a pipe (size unknown), the others from a regular file */
    char pipe_path[64];
    int pfd = (size >> 1) % 4 == 1 ? pipefile(pipe_path, sizeof pipe_path, t->prefix, plen, data,
                                                size)
                                   : -1;
    const char *input = pfd >= 0 ? pipe_path
                                 : memfile(&fd, path, sizeof path, t->prefix, plen, data, size);

    limn_context *ctx = limn_context_create();
    if (!ctx) {
        if (pfd >= 0)
            close(pfd);
        return 0;
    }
    limn_mesh *m = NULL;
    limn_status st = limn_mesh_read(ctx, input, t->format, &m);
    if (pfd >= 0)
        close(pfd);
    else if (t->format == LIMN_FORMAT_OBJ || t->format == LIMN_FORMAT_OFF ||
             (t->format == LIMN_FORMAT_PLY && !t->prefix))
        same_as_general(input, t->format, st, m, ctx);
    if (pfd < 0)
        same_as_slices(input, t->format, st, m);
    const char *msg = limn_context_message(ctx);
    if (st != LIMN_OK) {
        if (m)
            broken("a failed read returned a mesh", msg);
        if (!msg[0] || !strstr(msg, input))
            broken("a failed read without a message naming the file", msg);
        limn_context_destroy(ctx);
        return 0;
    }
    if (!m || limn_mesh_vertex_count(m) == 0)
        broken("a successful read without vertices", msg);
    check_mesh(m, 0, msg);

    limn_repair_options o;
    limn_repair_options_default(&o);
    o.duplicate_faces = size & 1; /* both policies, deterministically per input */
    limn_repair_report r = {.size = sizeof r};
    st = limn_mesh_repair(ctx, m, &o, &r);
    if (st == LIMN_OK) {
        check_mesh(m, 1, limn_context_message(ctx));
        if (r.faces_after != limn_mesh_face_count(m))
            broken("the repair report's face count is wrong", NULL);
        limn_mesh_info info = {.size = sizeof info};
        st = limn_mesh_info_compute(ctx, m, &info);
        if (st != LIMN_OK && st != LIMN_ERR_MEMORY)
            broken("topology failed on a repaired mesh", limn_context_message(ctx));
        if (st == LIMN_OK && (info.vertices != limn_mesh_vertex_count(m) ||
                              info.referenced_vertices > info.vertices))
            broken("inconsistent mesh info", NULL);
        round_trip(m);
    } else if (st != LIMN_ERR_MEMORY) {
        broken("the repair failed", limn_context_message(ctx));
    }
    limn_mesh_destroy(m);
    limn_context_destroy(ctx);
    return 0;
}
