/* SPDX-License-Identifier: MIT */
/*
 * The slice reader (host/mesh/io/mesh_slice.h, issue 14.1) against
 * limn_mesh_read on one file:
 *   slice_bench --mixed IN OUT   writes IN as binary PLY (float x y z, `uchar int`
 *                                lists) with every third face given its first
 *                                vertex again: variable lists, for reading only
 *   slice_bench FILE PARTS
 * reads FILE whole in a child process, then phase 1 of every part here and
 * phase 2 of each part in a child of its own; prints each child's time and
 * peak resident memory (wait4's ru_maxrss: the process image, the file pages
 * it touched and what it allocated) and each part's arrays, and checks the
 * parts' concatenation against the whole mesh bit for bit.
 */
#ifndef _DEFAULT_SOURCE
#define _DEFAULT_SOURCE /* wait4 */
#endif
#include "limn.h"
#include "mesh/io/mesh_slice.h"
#include "mesh/mesh.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#define MAX_PARTS 256

/* RssAnon and RssFile now (kB), from /proc/self/status. */
static void rss_now(long *anon, long *file)
{
    char line[256];
    FILE *f = fopen("/proc/self/status", "r");
    *anon = *file = 0;
    while (f && fgets(line, sizeof line, f)) {
        sscanf(line, "RssAnon: %ld", anon);
        sscanf(line, "RssFile: %ld", file);
    }
    if (f)
        fclose(f);
}

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Runs fn(arg) in a child; out[0] gets the seconds it reports, out[1] and
   out[2] its anonymous and file-backed resident kB at the end of the read,
   *kib its peak RSS. */
static int in_child(int (*fn)(void *, double *), void *arg, double out[3], long *kib)
{
    int fd[2];
    if (pipe(fd) != 0)
        return 1;
    pid_t pid = fork();
    if (pid == 0) {
        double s[3] = {0, 0, 0};
        int rc = fn(arg, s);
        if (write(fd[1], s, sizeof s) != (ssize_t)sizeof s)
            rc = 1;
        _exit(rc);
    }
    close(fd[1]);
    int status = 1;
    struct rusage ru;
    if (pid < 0 || read(fd[0], out, 3 * sizeof *out) != (ssize_t)(3 * sizeof *out) ||
        wait4(pid, &status, 0, &ru) != pid)
        status = 1;
    close(fd[0]);
    *kib = ru.ru_maxrss;
    return status != 0;
}

typedef struct job {
    const char *path;
    unsigned part, parts;
    mesh_slice_counts before, total;
} job;

static int whole(void *arg, double *s)
{
    const job *j = arg;
    limn_context *ctx = limn_context_create();
    limn_mesh *m = NULL;
    double t = now();
    limn_status st = limn_mesh_read(ctx, j->path, LIMN_FORMAT_AUTO, &m);
    s[0] = now() - t;
    long anon, file;
    rss_now(&anon, &file);
    s[1] = (double)anon;
    s[2] = (double)file;
    return st != LIMN_OK;
}

static int one_part(void *arg, double *s)
{
    const job *j = arg;
    limn_context *ctx = limn_context_create();
    mesh_slice sl;
    double t = now();
    limn_status st = mesh_slice_read(ctx, j->path, LIMN_FORMAT_AUTO, j->part, j->parts,
                                     &j->before, &j->total, &sl);
    s[0] = now() - t;
    long anon, file;
    rss_now(&anon, &file);
    s[1] = (double)anon;
    s[2] = (double)file;
    if (st)
        fprintf(stderr, "slice_bench: %s\n", limn_context_message(ctx));
    return st != LIMN_OK;
}

/* Every part read here as well, compared with the whole mesh. */
static int compare(limn_context *ctx, const char *path, unsigned parts,
                   const mesh_slice_counts *c)
{
    limn_mesh *m = NULL;
    if (limn_mesh_read(ctx, path, LIMN_FORMAT_AUTO, &m) != LIMN_OK)
        return 1;
    mesh_slice_counts before, total;
    memset(&before, 0, sizeof before);
    memset(&total, 0, sizeof total);
    for (unsigned p = 0; p < parts; p++)
        mesh_slice_counts_add(&total, &c[p]);
    int bad = 0;
    for (unsigned p = 0; p < parts && !bad; p++) {
        mesh_slice s;
        if (mesh_slice_read(ctx, path, LIMN_FORMAT_AUTO, p, parts, &before, &total, &s))
            return 1;
        const uint32_t *off = m->face_offsets + s.face_begin;
        size_t n = s.face_offsets[s.face_count];
        bad = memcmp(s.positions, m->positions + 3 * s.vertex_begin, s.vertex_count * 24) ||
              off[s.face_count] - off[0] != n ||
              memcmp(s.face_indices, m->face_indices + off[0], n * 4);
        printf("part %u: vertices %zu, faces %zu, arrays %.1f MB\n", p, s.vertex_count,
               s.face_count, (double)(s.vertex_count * 24 + (s.face_count + 1 + n) * 4) / 1e6);
        mesh_slice_free(&s);
        mesh_slice_counts_add(&before, &c[p]);
    }
    printf("whole: vertices %zu, faces %zu, arrays %.1f MB; slices %s\n", m->vertex_count,
           m->face_count,
           (double)(m->vertex_count * 24 + (m->face_count + 1 + m->face_offsets[m->face_count]) *
                    4) / 1e6, bad ? "DIFFER" : "equal bit for bit");
    limn_mesh_destroy(m);
    return bad;
}

static void put_le(FILE *f, uint32_t v, int n)
{
    for (int i = 0; i < n; i++)
        fputc((int)(v >> (8 * i) & 0xff), f);
}

static int mixed(const char *in, const char *out)
{
    limn_context *ctx = limn_context_create();
    limn_mesh *m = NULL;
    FILE *f = NULL;
    if (limn_mesh_read(ctx, in, LIMN_FORMAT_AUTO, &m) != LIMN_OK || !(f = fopen(out, "wb")))
        return fprintf(stderr, "slice_bench: %s\n", limn_context_message(ctx)), 1;
    fprintf(f, "ply\nformat binary_little_endian 1.0\nelement vertex %zu\nproperty float x\n"
               "property float y\nproperty float z\nelement face %zu\n"
               "property list uchar int vertex_indices\nend_header\n", m->vertex_count,
            m->face_count);
    for (size_t i = 0; i < 3 * m->vertex_count; i++) {
        float x = (float)m->positions[i];
        uint32_t u;
        memcpy(&u, &x, 4);
        put_le(f, u, 4);
    }
    for (size_t k = 0; k < m->face_count; k++) {
        uint32_t a = m->face_offsets[k], n = m->face_offsets[k + 1] - a;
        put_le(f, n + (k % 3 == 0), 1);
        for (uint32_t c = 0; c < n; c++)
            put_le(f, m->face_indices[a + c], 4);
        if (k % 3 == 0)
            put_le(f, m->face_indices[a], 4);
    }
    int bad = fclose(f) != 0;
    limn_mesh_destroy(m);
    limn_context_destroy(ctx);
    return bad;
}

int main(int argc, char **argv)
{
    if (argc == 4 && strcmp(argv[1], "--mixed") == 0)
        return mixed(argv[2], argv[3]);
    if (argc != 3 || atoi(argv[2]) < 1 || atoi(argv[2]) > MAX_PARTS) {
        fprintf(stderr, "usage: slice_bench FILE PARTS (1-%d)\n", MAX_PARTS);
        return 2;
    }
    job j = {.path = argv[1], .parts = (unsigned)atoi(argv[2])};
    static mesh_slice_counts c[MAX_PARTS];
    limn_context *ctx = limn_context_create();
    double s[3], count = 0;
    long kib;
    if (in_child(whole, &j, s, &kib))
        return fprintf(stderr, "slice_bench: %s cannot be read\n", j.path), 1;
    printf("limn_mesh_read: %.3f s, peak RSS %.1f MB (after the read: anonymous %.1f MB, "
           "file %.1f MB)\n", s[0], (double)kib / 1024, s[1] / 1024, s[2] / 1024);
    for (unsigned p = 0; p < j.parts; p++) {
        double t = now();
        if (mesh_slice_count(ctx, j.path, LIMN_FORMAT_AUTO, p, j.parts, &c[p]))
            return fprintf(stderr, "slice_bench: %s\n", limn_context_message(ctx)), 1;
        double d = now() - t;
        count = d > count ? d : count;
        mesh_slice_counts_add(&j.total, &c[p]);
    }
    double worst = 0;
    long worst_kib = 0;
    for (j.part = 0; j.part < j.parts; j.part++) {
        if (in_child(one_part, &j, s, &kib))
            return 1;
        printf("part %u: phase 2 %.3f s, peak RSS %.1f MB (after the read: anonymous %.1f MB, "
               "file %.1f MB)\n", j.part, s[0], (double)kib / 1024, s[1] / 1024, s[2] / 1024);
        worst = s[0] > worst ? s[0] : worst;
        worst_kib = kib > worst_kib ? kib : worst_kib;
        mesh_slice_counts_add(&j.before, &c[j.part]);
    }
    printf("%u parts: phase 1 at most %.3f s, phase 2 at most %.3f s, peak RSS at most %.1f MB"
           "%s\n", j.parts, count, worst, (double)worst_kib / 1024,
           j.total.irregular ? " (binary PLY with variable face lists: counts streamed)" : "");
    int rc = compare(ctx, j.path, j.parts, c);
    limn_context_destroy(ctx);
    return rc;
}
