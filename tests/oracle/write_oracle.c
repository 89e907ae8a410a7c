/* SPDX-License-Identifier: MIT */
/* The writers before the block writers (write_oracle.h). */
#include "write_oracle.h"

#include <string.h>

static int put(FILE *f, uint64_t v, unsigned size, int big)
{
    for (unsigned i = 0; i < size; i++)
        if (fputc((int)(unsigned char)(v >> (8 * (big ? size - 1 - i : i))), f) == EOF)
            return 1;
    return 0;
}

static int text_vertices(const limn_mesh *m, const char *lead, const uint8_t *c, int single,
                         FILE *f)
{
    const double *p = limn_mesh_positions(m);
    for (size_t v = 0; v < limn_mesh_vertex_count(m); v++, p += 3) {
        double x = p[0], y = p[1], z = p[2];
        if (single) {
            x = (float)x;
            y = (float)y;
            z = (float)z;
        }
        if (fprintf(f, "%s%.17g %.17g %.17g", lead, x, y, z) < 0 ||
            (c && fprintf(f, " %u %u %u", c[3 * v], c[3 * v + 1], c[3 * v + 2]) < 0) ||
            fputc('\n', f) == EOF)
            return 1;
    }
    return 0;
}

static int text_faces(const limn_mesh *m, const char *lead, unsigned base, FILE *f)
{
    const uint32_t *off = limn_mesh_face_offsets(m), *idx = limn_mesh_face_indices(m);
    for (size_t fc = 0; fc < limn_mesh_face_count(m); fc++) {
        uint32_t a = off[fc], b = off[fc + 1];
        if (lead ? fputs(lead, f) == EOF : fprintf(f, "%lu", (unsigned long)(b - a)) < 0)
            return 1;
        for (uint32_t i = a; i < b; i++)
            if (fprintf(f, " %lu", (unsigned long)idx[i] + base) < 0)
                return 1;
        if (fputc('\n', f) == EOF)
            return 1;
    }
    return 0;
}

static int ply_binary(const limn_mesh *m, int big, int single, unsigned count_size, FILE *f)
{
    const double *p = limn_mesh_positions(m);
    const uint8_t *c = limn_mesh_colors(m);
    for (size_t v = 0; v < 3 * limn_mesh_vertex_count(m); v++) {
        if (single) {
            float x = (float)p[v];
            uint32_t u;
            memcpy(&u, &x, 4);
            if (put(f, u, 4, big))
                return 1;
        } else {
            uint64_t u;
            memcpy(&u, &p[v], 8);
            if (put(f, u, 8, big))
                return 1;
        }
        if (c && v % 3 == 2 && (put(f, c[v - 2], 1, 0) || put(f, c[v - 1], 1, 0) ||
                                put(f, c[v], 1, 0)))
            return 1;
    }
    const uint32_t *off = limn_mesh_face_offsets(m), *idx = limn_mesh_face_indices(m);
    for (size_t fc = 0; fc < limn_mesh_face_count(m); fc++) {
        if (put(f, off[fc + 1] - off[fc], count_size, big))
            return 1;
        for (uint32_t i = off[fc]; i < off[fc + 1]; i++)
            if (put(f, idx[i], 4, big))
                return 1;
    }
    return 0;
}

static int ply(const limn_mesh *m, limn_format format, int single, FILE *f)
{
    const uint32_t *off = limn_mesh_face_offsets(m);
    uint32_t max_face = 0;
    for (size_t fc = 0; fc < limn_mesh_face_count(m); fc++)
        if (off[fc + 1] - off[fc] > max_face)
            max_face = off[fc + 1] - off[fc];
    const char *name = format == LIMN_FORMAT_PLY_ASCII       ? "ascii"
                       : format == LIMN_FORMAT_PLY_BINARY_BE ? "binary_big_endian"
                                                             : "binary_little_endian";
    const char *t = single ? "float" : "double";
    if (fprintf(f, "ply\nformat %s 1.0\ncomment written by limn\nelement vertex %zu\n"
                   "property %s x\nproperty %s y\nproperty %s z\n",
                name, limn_mesh_vertex_count(m), t, t, t) < 0 ||
        (limn_mesh_colors(m) &&
         fputs("property uchar red\nproperty uchar green\nproperty uchar blue\n", f) == EOF) ||
        fprintf(f, "element face %zu\nproperty list %s %s vertex_indices\nend_header\n",
                limn_mesh_face_count(m), max_face > 255 ? "uint" : "uchar",
                limn_mesh_vertex_count(m) > 2147483647u ? "uint" : "int") < 0)
        return 1;
    if (format == LIMN_FORMAT_PLY_ASCII)
        return text_vertices(m, "", limn_mesh_colors(m), single, f) || text_faces(m, NULL, 0, f);
    return ply_binary(m, format == LIMN_FORMAT_PLY_BINARY_BE, single, max_face > 255 ? 4 : 1, f);
}

int write_oracle(const limn_mesh *m, limn_format format, int single, FILE *f)
{
    size_t nv = limn_mesh_vertex_count(m), nf = limn_mesh_face_count(m);
    if (format == LIMN_FORMAT_OBJ)
        return fprintf(f, "# limn: %zu vertices, %zu faces\n", nv, nf) < 0 ||
               text_vertices(m, "v ", NULL, 0, f) || text_faces(m, "f", 1, f);
    if (format == LIMN_FORMAT_OFF)
        return fprintf(f, "OFF\n%zu %zu 0\n", nv, nf) < 0 || text_vertices(m, "", NULL, 0, f) ||
               text_faces(m, NULL, 0, f);
    return ply(m, format, single, f);
}
