/* SPDX-License-Identifier: MIT */
/*
 * Refinement over ranks against the single process, under mpirun with 2, 3
 * and 5 ranks: limn_mpi_mesh_subdivide + limn_mpi_mesh_write give the bytes
 * of limn_subdivide + limn_mesh_write for Loop and Catmull-Clark (alpha 0
 * and 0.5), 1 and 2 levels, with and without the limit, and 0 levels with
 * the limit, on meshes with boundaries, several components, a non-manifold
 * fin, isolated vertices, n-gons (a hexagonal prism, a pyramid) and the
 * shared meshes when present; on even blocks (limn_mpi_mesh_read) and on
 * uneven ones (limn_mpi_mesh_create: vertex blocks growing with the rank,
 * face blocks shrinking). A failure on one rank (its device does not open)
 * and a Loop refusal (a quad in the last rank's block) reach every rank
 * with one message, the single process's for the refusal, and no surface.
 * Per-rank memory (internal probe mpi_mesh_subdivide): no array a rank
 * builds reaches a level's global vertex count.
 * Texture over ranks: limn_mpi_mesh_texture + limn_mpi_mesh_write give the
 * bytes of limn_texture + limn_mesh_write (Loop, Catmull-Clark with alpha
 * 0.5, 0 to 4 levels: three carried fields per extra refinement and one
 * more, seeds, frequencies, colours) on the same meshes, even and uneven
 * blocks; a singular level fails as in one process (its message, every
 * rank); a Loop refusal, NULL options and a device failing on the last rank
 * reach every rank with one message and no surface.
 */
#include "mpi_check.h"
#include "mpi_meshes.h"
#include "shell.h"
#include "support.h"

#include "limn_mpi.h"
#include "mesh/mesh.h"
#include "mpi/mpi_refine.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

MPI_CHECK_STATE;
static char dir[256];
static double last_share; /* mpi_refine_stats.share of the last distributed run here */

/* limn_subdivide on rank 0 of the file in, written to ref; 1 on success. */
static int single(limn_context *ctx, const char *in, const limn_subdivide_options *o,
                  const char *ref)
{
    limn_mesh *m = NULL, *s = NULL;
    limn_subdivide_report r = {.size = sizeof r};
    int ok = limn_mesh_read(ctx, in, LIMN_FORMAT_AUTO, &m) == LIMN_OK &&
             limn_mesh_repair(ctx, m, NULL, NULL) == LIMN_OK &&
             limn_subdivide(ctx, m, o, &s, &r) == LIMN_OK &&
             limn_mesh_write(ctx, s, ref, LIMN_FORMAT_AUTO) == LIMN_OK;
    CHECK(ok, "single process on %s: %s", in, limn_context_message(ctx));
    limn_mesh_destroy(m);
    limn_mesh_destroy(s);
    return ok;
}

/* This rank's share of the whole mesh m in uneven blocks: vertices in
   shares growing with the rank, faces in shares shrinking with it. */
static limn_status uneven(limn_context *ctx, const limn_mesh *m, limn_mpi_mesh **out)
{
    size_t w = (size_t)size * ((size_t)size + 1) / 2, before = (size_t)rank * ((size_t)rank + 1) / 2;
    size_t vb = m->vertex_count * before / w, ve = m->vertex_count * (before + (size_t)rank + 1) / w;
    size_t rb = (size_t)(size - 1 - rank), rbefore = w - (rb + 1) * (rb + 2) / 2;
    size_t fb = m->face_count * rbefore / w, fe = m->face_count * (rbefore + rb + 1) / w;
    uint32_t *off = malloc((fe - fb + 1) * sizeof *off);
    if (!off)
        return LIMN_ERR_MEMORY;
    for (size_t f = fb; f <= fe; f++)
        off[f - fb] = m->face_offsets[f] - m->face_offsets[fb];
    limn_status st = limn_mpi_mesh_create(ctx, MPI_COMM_WORLD, ve - vb, m->positions + 3 * vb,
                                          fe - fb, off, m->face_indices + m->face_offsets[fb], out);
    free(off);
    return st;
}

/* Every rank: the distributed mesh (read in slices, or uneven blocks of the
   whole file), repaired, refined and written to out. */
static limn_status distributed(limn_context *ctx, const char *in, int blocks,
                               const limn_subdivide_options *o, const char *out)
{
    limn_mpi_mesh *m = NULL, *s = NULL;
    limn_status st;
    if (blocks) {
        limn_mesh *whole = NULL;
        st = limn_mesh_read(ctx, in, LIMN_FORMAT_AUTO, &whole);
        if (!st)
            st = uneven(ctx, whole, &m);
        limn_mesh_destroy(whole);
    } else {
        st = limn_mpi_mesh_read(ctx, MPI_COMM_WORLD, in, LIMN_FORMAT_AUTO, &m);
    }
    if (!st)
        st = limn_mpi_mesh_repair(ctx, m, NULL, NULL);
    limn_subdivide_report r = {.size = sizeof r};
    mpi_refine_stats rs = {0};
    if (!st)
        st = mpi_mesh_subdivide(ctx, m, o, &s, &r, NULL, NULL, &rs);
    if (!st)
        last_share = rs.share;
    if (!st)
        st = limn_mpi_mesh_write(ctx, s, out, LIMN_FORMAT_AUTO, NULL, NULL);
    limn_mpi_mesh_destroy(m);
    limn_mpi_mesh_destroy(s);
    return st;
}

/* One mesh and option set: both routes on the same file. */
static void refine_case(limn_context *ctx, const char *name, const limn_mesh *mesh,
                        limn_scheme scheme, double alpha, int levels, int limit, int blocks)
{
    char in[320], ref[320], out[320];
    snprintf(in, sizeof in, "%s/in.ply", dir);
    snprintf(ref, sizeof ref, "%s/ref.ply", dir);
    snprintf(out, sizeof out, "%s/out.ply", dir);
    limn_subdivide_options o;
    limn_subdivide_options_default(&o);
    o.scheme = scheme;
    o.alpha = alpha;
    o.levels = levels;
    o.limit = limit;
    int ok = 1;
    if (rank == 0) {
        ok = limn_mesh_write(ctx, mesh, in, LIMN_FORMAT_AUTO) == LIMN_OK;
        CHECK(ok, "%s: writing %s: %s", name, in, limn_context_message(ctx));
        ok = ok && single(ctx, in, &o, ref);
    }
    MPI_Bcast(&ok, 1, MPI_INT, 0, MPI_COMM_WORLD);
    if (!ok)
        return;
    limn_status st = distributed(ctx, in, blocks, &o, out);
    CHECK(st == LIMN_OK, "%s: distributed: %s", name, limn_context_message(ctx));
    if (rank == 0 && !st)
        CHECK(test_same_bytes(ref, out),
              "%s (%d ranks, %s, alpha %g, %d levels%s%s): differs from one process's", name,
              size, limn_scheme_name(scheme), alpha, levels, limit ? ", limit" : "",
              blocks ? ", uneven blocks" : "");
    MPI_Barrier(MPI_COMM_WORLD);
    if (rank == 0) {
        unlink(in);
        unlink(ref);
        unlink(out);
    }
}

/* An n x n grid of quads (n + 1 squared vertices), or of triangles. */
static limn_mesh *grid(limn_context *ctx, int n, int triangles)
{
    size_t nv = (size_t)(n + 1) * (size_t)(n + 1), nq = (size_t)n * (size_t)n;
    double *pos = malloc(3 * nv * sizeof *pos);
    uint32_t *idx = malloc(6 * nq * sizeof *idx), *off = malloc((2 * nq + 1) * sizeof *off);
    limn_mesh *m = NULL;
    if (pos && idx && off) {
        for (int y = 0, k = 0; y <= n; y++)
            for (int x = 0; x <= n; x++, k++) {
                pos[3 * k] = x;
                pos[3 * k + 1] = y;
                pos[3 * k + 2] = 0.1 * ((x * 7 + y * 3) % 5);
            }
        size_t f = 0, c = 0;
        off[0] = 0;
        for (int y = 0; y < n; y++)
            for (int x = 0; x < n; x++) {
                uint32_t a = (uint32_t)(y * (n + 1) + x), b = a + 1, d = a + (uint32_t)n + 1,
                         e = d + 1;
                uint32_t q[6] = {a, b, e, a, e, d};
                int faces = triangles ? 2 : 1, corners = triangles ? 3 : 4;
                if (!triangles)
                    q[2] = e, q[3] = d;
                for (int i = 0; i < faces * corners; i++)
                    idx[c++] = q[i];
                for (int i = 0; i < faces; i++, f++)
                    off[f + 1] = off[f] + (uint32_t)corners;
            }
        limn_mesh_create(ctx, nv, pos, f, off, idx, &m);
    }
    free(pos);
    free(idx);
    free(off);
    return m;
}

/* Per-rank memory: on a 48 x 48 grid no array any rank builds reaches a
   level's global vertex count, and the largest is about a rank's share. */
static void memory_case(limn_context *ctx, int triangles)
{
    limn_mesh *m = grid(ctx, 48, triangles);
    CHECK(m != NULL, "grid: %s", limn_context_message(ctx));
    refine_case(ctx, triangles ? "grid tri" : "grid quad", m,
                triangles ? LIMN_SCHEME_LOOP : LIMN_SCHEME_CATMARK, 0.0, 2, 1, 0);
    double worst = 0.0;
    MPI_Allreduce(&last_share, &worst, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
    /* a rank's share of a level plus its ring of ghost faces (a strip of the grid) */
    double bound = size == 1 ? 1.0 : 1.0 / size + 0.15;
    CHECK(worst <= bound && (size == 1 || worst < 1.0),
          "grid %s, %d ranks: a rank's largest vertex array is %.3f of its level's vertices "
          "(bound %.3f)",
          triangles ? "tri" : "quad", size, worst, bound);
    if (rank == 0)
        printf("grid %s, %d ranks: largest per-rank vertex array %.3f of the level's vertices\n",
               triangles ? "tri" : "quad", size, worst);
    limn_mesh_destroy(m);
}

/* Every scheme and option on one mesh (Loop only on triangles). */
static void all_options(limn_context *ctx, const char *name, const limn_mesh *m, int triangles)
{
    static const int levels[][2] = {{1, 0}, {1, 1}, {2, 0}, {2, 1}, {0, 1}};
    for (size_t k = 0; k < sizeof levels / sizeof *levels; k++) {
        if (triangles)
            refine_case(ctx, name, m, LIMN_SCHEME_LOOP, 0.0, levels[k][0], levels[k][1], 0);
        refine_case(ctx, name, m, LIMN_SCHEME_CATMARK, 0.0, levels[k][0], levels[k][1], 0);
    }
    refine_case(ctx, name, m, LIMN_SCHEME_CATMARK, 0.5, 2, 1, 0);
    refine_case(ctx, name, m, LIMN_SCHEME_CATMARK, 0.5, 0, 1, 0);
    refine_case(ctx, name, m, triangles ? LIMN_SCHEME_LOOP : LIMN_SCHEME_CATMARK, 0.0, 2, 1, 1);
}

/* The texture options of the cases: three colours, seed and frequency as given. */
static limn_texture_options texture_options(limn_scheme scheme, double alpha, int levels,
                                            uint64_t seed, double frequency)
{
    static const uint8_t rgb[9] = {200, 30, 10, 20, 220, 40, 10, 50, 240};
    limn_texture_options o;
    limn_texture_options_default(&o);
    o.series.scheme = scheme;
    o.series.alpha = alpha;
    o.levels = levels;
    o.seed = seed;
    o.frequency = frequency;
    o.colors = rgb;
    o.color_count = 3;
    return o;
}

/* limn_texture of in on rank 0 (written to ref on success); its status and
   message in *msg. */
static limn_status texture_single(limn_context *ctx, const char *in,
                                  const limn_texture_options *o, const char *ref, char *msg,
                                  size_t cap)
{
    limn_mesh *m = NULL, *s = NULL;
    limn_series_report r = {.size = sizeof r};
    limn_status st = limn_mesh_read(ctx, in, LIMN_FORMAT_AUTO, &m);
    if (!st)
        st = limn_mesh_repair(ctx, m, NULL, NULL);
    if (!st)
        st = limn_texture(ctx, m, o, &s, &r);
    if (!st)
        st = limn_mesh_write(ctx, s, ref, LIMN_FORMAT_AUTO);
    snprintf(msg, cap, "%s", st ? limn_context_message(ctx) : "");
    limn_mesh_destroy(m);
    limn_mesh_destroy(s);
    return st;
}

/* Every rank: the distributed mesh as `distributed` reads it, textured and written. */
static limn_status texture_distributed(limn_context *ctx, const char *in, int blocks,
                                       const limn_texture_options *o, const char *out)
{
    limn_mpi_mesh *m = NULL, *s = NULL;
    limn_status st;
    if (blocks) {
        limn_mesh *whole = NULL;
        st = limn_mesh_read(ctx, in, LIMN_FORMAT_AUTO, &whole);
        if (!st)
            st = uneven(ctx, whole, &m);
        limn_mesh_destroy(whole);
    } else {
        st = limn_mpi_mesh_read(ctx, MPI_COMM_WORLD, in, LIMN_FORMAT_AUTO, &m);
    }
    if (!st)
        st = limn_mpi_mesh_repair(ctx, m, NULL, NULL);
    limn_series_report r = {.size = sizeof r};
    if (!st)
        st = limn_mpi_mesh_texture(ctx, m, o, &s, &r, NULL, NULL);
    if (!st)
        st = limn_mpi_mesh_write(ctx, s, out, LIMN_FORMAT_AUTO, NULL, NULL);
    limn_mpi_mesh_destroy(m);
    limn_mpi_mesh_destroy(s);
    return st;
}

static int agreed(limn_context *ctx, limn_status st, char *msg, size_t cap);

/* One texture case: the same bytes, or the same failure on every rank. */
static void texture_case(limn_context *ctx, const char *name, const limn_mesh *mesh,
                         const limn_texture_options *o, int blocks, int must_succeed)
{
    char in[320], ref[320], out[320], want[512] = "", msg[512];
    snprintf(in, sizeof in, "%s/tin.ply", dir);
    snprintf(ref, sizeof ref, "%s/tref.ply", dir);
    snprintf(out, sizeof out, "%s/tout.ply", dir);
    int sst = 0;
    if (rank == 0) {
        CHECK(limn_mesh_write(ctx, mesh, in, LIMN_FORMAT_AUTO) == LIMN_OK, "%s: writing %s",
              name, in);
        sst = (int)texture_single(ctx, in, o, ref, want, sizeof want);
    }
    MPI_Bcast(&sst, 1, MPI_INT, 0, MPI_COMM_WORLD);
    MPI_Bcast(want, sizeof want, MPI_CHAR, 0, MPI_COMM_WORLD);
    CHECK(!must_succeed || !sst, "%s texture, one process: %s", name, want);
    limn_status st = texture_distributed(ctx, in, blocks, o, out);
    int same = agreed(ctx, st, msg, sizeof msg);
    CHECK((int)st == sst && same && strcmp(msg, sst ? want : msg) == 0,
          "%s texture (%d ranks, %s, alpha %g, %d levels): status %d, one process %d ('%s' "
          "against '%s')", name, size, limn_scheme_name(o->series.scheme), o->series.alpha,
          o->levels, (int)st, sst, msg, want);
    if (rank == 0 && !st && !sst && o->levels == 4)
        printf("%s texture, %d ranks, %s, 4 levels: same bytes\n", name, size,
               limn_scheme_name(o->series.scheme));
    if (rank == 0 && !st && !sst)
        CHECK(test_same_bytes(ref, out),
              "%s texture (%d ranks, %s, alpha %g, %d levels%s): differs from one process's",
              name, size, limn_scheme_name(o->series.scheme), o->series.alpha, o->levels,
              blocks ? ", uneven blocks" : "");
    if (rank == 0 && sst)
        CHECK(!test_file_exists(out), "%s: %s written after a failure", name, out);
    MPI_Barrier(MPI_COMM_WORLD);
    if (rank == 0) {
        unlink(in);
        unlink(ref);
        unlink(out);
    }
}

/* The texture's levels and options on one mesh (Loop only on triangles). */
static void texture_options_case(limn_context *ctx, const char *name, const limn_mesh *m,
                                 int triangles)
{
    limn_scheme own = triangles ? LIMN_SCHEME_LOOP : LIMN_SCHEME_CATMARK;
    for (int levels = 0; levels <= 4; levels++) {
        limn_texture_options o = texture_options(own, 0.5, levels, 1, 4.0);
        texture_case(ctx, name, m, &o, 0, 1);
    }
    limn_texture_options o = texture_options(LIMN_SCHEME_CATMARK, 0.5, 2, 12345, 1.5);
    texture_case(ctx, name, m, &o, 1, 1);
    o = texture_options(LIMN_SCHEME_CATMARK, 0.0, 1, 3, 4.0); /* may be singular: either way */
    texture_case(ctx, name, m, &o, 0, 0);
}

/* A Loop refusal (a quad), NULL options and a device failing on the last
   rank: one message on every rank, no surface. */
static void texture_failures(limn_context *ctx, const limn_mesh *quads)
{
    char in[320], msg[512];
    snprintf(in, sizeof in, "%s/tfail.ply", dir);
    if (rank == 0)
        CHECK(limn_mesh_write(ctx, quads, in, LIMN_FORMAT_AUTO) == LIMN_OK, "writing %s", in);
    MPI_Barrier(MPI_COMM_WORLD);
    limn_mpi_mesh *m = NULL, *s = NULL;
    limn_status st = limn_mpi_mesh_read(ctx, MPI_COMM_WORLD, in, LIMN_FORMAT_AUTO, &m);
    CHECK(st == LIMN_OK, "reading %s: %s", in, limn_context_message(ctx));
    limn_texture_options o = texture_options(LIMN_SCHEME_LOOP, 0.0, 1, 1, 4.0);
    st = limn_mpi_mesh_texture(ctx, m, &o, &s, NULL, NULL, NULL);
    int same = agreed(ctx, st, msg, sizeof msg);
    CHECK(st == LIMN_ERR_TOPOLOGY && !s && same, "Loop on quads: status %d, '%s' (agreed %d)",
          (int)st, msg, same);
    st = limn_mpi_mesh_texture(ctx, m, NULL, &s, NULL, NULL, NULL);
    same = agreed(ctx, st, msg, sizeof msg);
    CHECK(st == LIMN_ERR_ARGUMENT && !s && same && strstr(msg, "colours"),
          "NULL options: status %d, '%s' (agreed %d)", (int)st, msg, same);
    limn_texture_options tight = texture_options(LIMN_SCHEME_CATMARK, 0.5, 1, 1, 4.0);
    tight.max_memory = 1 << 20; /* below any run: a rank's share of the estimate */
    st = limn_mpi_mesh_texture(ctx, m, &tight, &s, NULL, NULL, NULL);
    same = agreed(ctx, st, msg, sizeof msg);
    CHECK(st == LIMN_ERR_MEMORY && !s && same && strstr(msg, "GiB a rank"),
          "max_memory 1 MiB: status %d, '%s' (agreed %d)", (int)st, msg, same);
    limn_context *bad = limn_context_create();
    if (rank == size - 1)
        limn_context_set_device(bad, "opencl:99.99");
    o.series.scheme = LIMN_SCHEME_CATMARK;
    o.series.alpha = 0.5;
    st = limn_mpi_mesh_texture(bad, m, &o, &s, NULL, NULL, NULL);
    same = agreed(bad, st, msg, sizeof msg);
    CHECK(st != LIMN_OK && !s && same && msg[0],
          "texture, device on rank %d: status %d, '%s' (agreed %d)", size - 1, (int)st, msg,
          same);
    if (!st)
        limn_mpi_mesh_destroy(s);
    limn_context_destroy(bad);
    limn_mpi_mesh_destroy(m);
    MPI_Barrier(MPI_COMM_WORLD);
    if (rank == 0)
        unlink(in);
}

/* The same status and message on every rank, the message rank 0's. */
static int agreed(limn_context *ctx, limn_status st, char *msg, size_t cap)
{
    snprintf(msg, cap, "%s", limn_context_message(ctx));
    char root[512];
    snprintf(root, sizeof root, "%s", msg);
    MPI_Bcast(root, sizeof root, MPI_CHAR, 0, MPI_COMM_WORLD);
    int s = (int)st, lo = s, hi = s;
    MPI_Allreduce(&s, &lo, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    MPI_Allreduce(&s, &hi, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    return lo == hi && strcmp(root, msg) == 0;
}

/* A device that does not open on the last rank only, and Loop asked of a
   mesh whose last face (the last rank's block) is a quad: every rank fails
   with one message (the refusal's the single process's) and no surface. */
static void failures_case(limn_context *ctx, const limn_mesh *tri)
{
    char in[320], out[320], msg[512];
    snprintf(in, sizeof in, "%s/fail.obj", dir);
    snprintf(out, sizeof out, "%s/fail_out.ply", dir);
    if (rank == 0) {
        CHECK(limn_mesh_write(ctx, tri, in, LIMN_FORMAT_AUTO) == LIMN_OK, "writing %s", in);
        FILE *f = fopen(in, "a");
        if (f) {
            fprintf(f, "v 9 9 9\nv 10 9 9\nv 10 10 9\nv 9 10 9\nf -4 -3 -2 -1\n");
            fclose(f);
        }
    }
    MPI_Barrier(MPI_COMM_WORLD);
    limn_mpi_mesh *m = NULL, *s = NULL;
    limn_status st = limn_mpi_mesh_read(ctx, MPI_COMM_WORLD, in, LIMN_FORMAT_AUTO, &m);
    if (!st)
        st = limn_mpi_mesh_repair(ctx, m, NULL, NULL);
    CHECK(st == LIMN_OK, "reading %s: %s", in, limn_context_message(ctx));
    limn_subdivide_options o;
    limn_subdivide_options_default(&o);
    o.levels = 2;
    o.scheme = LIMN_SCHEME_LOOP;
    st = limn_mpi_mesh_subdivide(ctx, m, &o, &s, NULL, NULL, NULL);
    char want[512] = "";
    if (rank == 0) {
        limn_mesh *w = NULL, *ws = NULL;
        limn_mesh_read(ctx, in, LIMN_FORMAT_AUTO, &w);
        limn_mesh_repair(ctx, w, NULL, NULL);
        limn_status sst = limn_subdivide(ctx, w, &o, &ws, NULL);
        CHECK(sst != LIMN_OK, "the single process refined a quad with Loop");
        snprintf(want, sizeof want, "%s", limn_context_message(ctx));
        limn_mesh_destroy(w);
        limn_mesh_destroy(ws);
    }
    MPI_Bcast(want, sizeof want, MPI_CHAR, 0, MPI_COMM_WORLD);
    int same = agreed(ctx, st, msg, sizeof msg);
    CHECK(st == LIMN_ERR_TOPOLOGY && s == NULL && same && strcmp(msg, want) == 0,
          "Loop on a quad: status %d, surface %p, message '%s', one process '%s'", (int)st,
          (void *)s, msg, want);
    /* a device that does not open on the last rank (another context, the same mesh) */
    limn_context *bad = limn_context_create();
    if (rank == size - 1)
        limn_context_set_device(bad, "opencl:99.99");
    o.scheme = LIMN_SCHEME_CATMARK;
    st = limn_mpi_mesh_subdivide(bad, m, &o, &s, NULL, NULL, NULL);
    same = agreed(bad, st, msg, sizeof msg);
    CHECK(st != LIMN_OK && s == NULL && same && msg[0],
          "device on rank %d: status %d, surface %p, message '%s' (agreed %d)", size - 1,
          (int)st, (void *)s, msg, same);
    if (!st)
        limn_mpi_mesh_destroy(s);
    s = NULL;
    limn_context_destroy(bad);
    /* the memory budget: a rank's share of the single process's estimate,
       at least the share of limn_subdivide_estimate's (the edges from the
       corners and boundary edges: above it where an edge is non-manifold);
       just below it, every rank refuses with one message and no surface */
    limn_subdivide_report r1 = {.size = sizeof r1};
    o.levels = 3;
    st = limn_mpi_mesh_subdivide(ctx, m, &o, &s, &r1, NULL, NULL);
    CHECK(st == LIMN_OK && r1.estimated_bytes > 0, "3 levels: status %d (%s), estimate %zu",
          (int)st, limn_context_message(ctx), r1.estimated_bytes);
    limn_mpi_mesh_destroy(s);
    s = NULL;
    if (rank == 0) {
        limn_mesh *w = NULL;
        size_t nv = 0, nf = 0, whole = 0, runtime = (size_t)192 << 20;
        limn_mesh_read(ctx, in, LIMN_FORMAT_AUTO, &w);
        limn_mesh_repair(ctx, w, NULL, NULL);
        CHECK(limn_subdivide_estimate(ctx, w, &o, &nv, &nf, &whole) == LIMN_OK,
              "limn_subdivide_estimate: %s", limn_context_message(ctx));
        double share = 1.0 / size + 0.2 < 1.0 ? 1.0 / size + 0.2 : 1.0;
        size_t least = (size_t)((double)(whole - runtime) * share) + runtime;
        CHECK(r1.estimated_bytes + 1 >= least,
              "%d ranks: a rank's estimate %zu below the share of one process's %zu (%zu)", size,
              r1.estimated_bytes, whole, least);
        limn_mesh_destroy(w);
    }
    o.max_memory = r1.estimated_bytes - 1;
    st = limn_mpi_mesh_subdivide(ctx, m, &o, &s, NULL, NULL, NULL);
    same = agreed(ctx, st, msg, sizeof msg);
    CHECK(st == LIMN_ERR_MEMORY && s == NULL && same && strstr(msg, "GiB a rank"),
          "max_memory below a rank's estimate: status %d, surface %p, message '%s' (agreed %d)",
          (int)st, (void *)s, msg, same);
    o.max_memory = 0;
    CHECK(!test_file_exists(out), "%s was written", out);
    limn_mpi_mesh_destroy(m);
    MPI_Barrier(MPI_COMM_WORLD);
    if (rank == 0)
        unlink(in);
}

/* A shared mesh (mpi_check_shared): its own scheme, then Catmull-Clark
   with the limit, and Loop when it is all triangles. */
static void shared_case(limn_context *ctx, size_t k, const char *path, limn_mesh *m)
{
    (void)k;
    int tri = rank == 0 && m->face_offsets[m->face_count] == 3 * m->face_count;
    MPI_Bcast(&tri, 1, MPI_INT, 0, MPI_COMM_WORLD);
    refine_case(ctx, path, m, LIMN_SCHEME_AUTO, 0.0, 2, 0, 0);
    refine_case(ctx, path, m, LIMN_SCHEME_CATMARK, 0.0, 1, 1, 0);
    if (tri)
        refine_case(ctx, path, m, LIMN_SCHEME_LOOP, 0.0, 1, 1, 0);
}

int main(int argc, char **argv)
{
    MPI_Init(&argc, &argv);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    mpi_test_scratch_dir(dir, sizeof dir, "test_mpi_refine");
    limn_context *ctx = limn_context_create();
    limn_mesh *otri = mpi_test_composite(ctx, 1), *oquad = mpi_test_composite(ctx, 0);
    limn_mesh *ctri = mpi_test_closed(ctx, 1), *cquad = mpi_test_closed(ctx, 0);
    all_options(ctx, "composite tri", otri, 1);
    all_options(ctx, "composite quad", oquad, 0);
    all_options(ctx, "closed tri", ctri, 1);
    all_options(ctx, "closed quad", cquad, 0);
    failures_case(ctx, otri);
    memory_case(ctx, 0);
    memory_case(ctx, 1);
    texture_options_case(ctx, "composite tri", otri, 1);
    texture_options_case(ctx, "composite quad", oquad, 0);
    texture_options_case(ctx, "closed tri", ctri, 1);
    texture_options_case(ctx, "closed quad", cquad, 0);
    texture_failures(ctx, oquad);
    static const char *const real[] = {"small/suzanne.obj", "medium/bob_quad.obj",
                                       "medium/fertility.off"};
    mpi_check_shared(ctx, real, sizeof real / sizeof *real, shared_case);
    limn_mesh_destroy(otri);
    limn_mesh_destroy(oquad);
    limn_mesh_destroy(ctri);
    limn_mesh_destroy(cquad);
    limn_context_destroy(ctx);
    return mpi_check_finish("test_mpi_refine", dir, checks, failures);
}
