/* SPDX-License-Identifier: MIT */
/*
 * limn_mpi_mesh_morph against limn_morph, under mpirun with 2, 3 and 5
 * ranks: FROM is a PLY file and TO an OBJ (so their blocks differ), every
 * frame written in parallel (limn_mpi_mesh_write) is the single process's
 * bytes and its measures (volume, area, flipped faces, distance to TO) its
 * bits; the series (Loop, Catmull-Clark alpha 0.5) and the linear blend;
 * meshes with boundaries, several components, a non-manifold fin, isolated
 * vertices, n-gons, and closed ones (a volume). Errors reach every rank with
 * one message: TO with other faces (limn_morph's message), a frame callback
 * failing on the last rank only.
 */
#include "mpi_check.h"
#include "mpi_meshes.h"
#include "shell.h"
#include "support.h"

#include "limn_mpi.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

MPI_CHECK_STATE;
static char dir[256];

#define FRAMES 4

typedef struct frames {
    limn_context *ctx;
    limn_mesh *frame;            /* single process: the frame to write */
    const char *tag;             /* file names: dir/TAG_k.ply */
    limn_morph_frame seen[FRAMES];
    int fail_at, fail_rank;      /* the callback fails at this frame on this rank */
} frames;

static void frame_path(const frames *f, int k, char *out, size_t cap)
{
    snprintf(out, cap, "%s/%s_%d.ply", dir, f->tag, k);
}

static limn_status single_frame(void *user, const limn_morph_frame *fr)
{
    frames *f = user;
    char path[320];
    frame_path(f, fr->index, path, sizeof path);
    memcpy(limn_mesh_positions_mutable(f->frame), fr->positions,
           3 * limn_mesh_vertex_count(f->frame) * sizeof(double));
    f->seen[fr->index] = *fr;
    f->seen[fr->index].positions = NULL;
    return limn_mesh_write(f->ctx, f->frame, path, LIMN_FORMAT_AUTO);
}

static limn_status many_frame(void *user, const limn_mpi_mesh *frame, const limn_morph_frame *fr)
{
    frames *f = user;
    char path[320];
    frame_path(f, fr->index, path, sizeof path);
    f->seen[fr->index] = *fr;
    f->seen[fr->index].positions = NULL;
    limn_status st = limn_mpi_mesh_write(f->ctx, frame, path, LIMN_FORMAT_AUTO, NULL, NULL);
    /* after the collective write: one rank's own failure */
    return !st && fr->index == f->fail_at && rank == f->fail_rank ? LIMN_ERR_IO : st;
}

/* The frames of both routes on FROM (ply) and TO (obj). */
static void morph_case(limn_context *ctx, const char *name, const limn_mesh *from,
                       const limn_mesh *to, limn_scheme scheme, double alpha, int linear)
{
    char pf[320], pt[320];
    snprintf(pf, sizeof pf, "%s/from.ply", dir);
    snprintf(pt, sizeof pt, "%s/to.obj", dir);
    limn_morph_options o;
    limn_morph_options_default(&o);
    o.frames = FRAMES;
    o.series.scheme = scheme;
    o.series.alpha = alpha;
    o.linear = linear;
    frames one = {.ctx = ctx, .tag = "ref", .fail_at = -1}, many = one;
    many.tag = "out";
    int ok = 1;
    if (rank == 0) {
        limn_mesh *a = NULL, *b = NULL;
        limn_series_report r = {.size = sizeof r};
        ok = limn_mesh_write(ctx, from, pf, LIMN_FORMAT_AUTO) == LIMN_OK &&
             limn_mesh_write(ctx, to, pt, LIMN_FORMAT_AUTO) == LIMN_OK &&
             limn_mesh_read(ctx, pf, LIMN_FORMAT_AUTO, &a) == LIMN_OK &&
             limn_mesh_read(ctx, pt, LIMN_FORMAT_AUTO, &b) == LIMN_OK &&
             limn_mesh_repair(ctx, a, NULL, NULL) == LIMN_OK &&
             limn_mesh_repair(ctx, b, NULL, NULL) == LIMN_OK &&
             limn_mesh_copy(ctx, a, &one.frame) == LIMN_OK &&
             limn_morph(ctx, a, b, &o, single_frame, &one, &r) == LIMN_OK;
        CHECK(ok, "%s: single process: %s", name, limn_context_message(ctx));
        limn_mesh_destroy(a);
        limn_mesh_destroy(b);
        limn_mesh_destroy(one.frame);
    }
    MPI_Bcast(&ok, 1, MPI_INT, 0, MPI_COMM_WORLD);
    MPI_Bcast(one.seen, (int)sizeof one.seen, MPI_BYTE, 0, MPI_COMM_WORLD);
    limn_mpi_mesh *a = NULL, *b = NULL;
    limn_series_report r = {.size = sizeof r};
    limn_status st = ok ? limn_mpi_mesh_read(ctx, MPI_COMM_WORLD, pf, LIMN_FORMAT_AUTO, &a)
                        : LIMN_ERR_ARGUMENT;
    if (!st)
        st = limn_mpi_mesh_read(ctx, MPI_COMM_WORLD, pt, LIMN_FORMAT_AUTO, &b);
    if (!st)
        st = limn_mpi_mesh_repair(ctx, a, NULL, NULL);
    if (!st)
        st = limn_mpi_mesh_repair(ctx, b, NULL, NULL);
    if (!st)
        st = limn_mpi_mesh_morph(ctx, a, b, &o, many_frame, &many, &r, NULL, NULL);
    CHECK(!ok || st == LIMN_OK, "%s: limn_mpi_mesh_morph: %s", name, limn_context_message(ctx));
    for (int k = 0; ok && !st && k < FRAMES; k++) {
        char x[320], y[320];
        frame_path(&one, k, x, sizeof x);
        frame_path(&many, k, y, sizeof y);
        if (rank == 0)
            CHECK(test_same_bytes(x, y), "%s (%d ranks): frame %d differs from one process's", name,
                  size, k);
        const limn_morph_frame *u = &one.seen[k], *v = &many.seen[k];
        CHECK(u->index == v->index && memcmp(&u->volume, &v->volume, sizeof u->volume) == 0 &&
                  memcmp(&u->area, &v->area, sizeof u->area) == 0 &&
                  u->flipped_faces == v->flipped_faces &&
                  memcmp(&u->mean_distance_to_target, &v->mean_distance_to_target,
                         sizeof u->mean_distance_to_target) == 0,
              "%s (%d ranks): frame %d's measures: volume %.17g area %.17g flipped %zu distance "
              "%.17g, one process %.17g %.17g %zu %.17g",
              name, size, k, many.seen[k].volume, many.seen[k].area, many.seen[k].flipped_faces,
              many.seen[k].mean_distance_to_target, one.seen[k].volume, one.seen[k].area,
              one.seen[k].flipped_faces, one.seen[k].mean_distance_to_target);
    }
    limn_mpi_mesh_destroy(a);
    limn_mpi_mesh_destroy(b);
    MPI_Barrier(MPI_COMM_WORLD);
    if (rank == 0) {
        for (int k = 0; k < FRAMES; k++) {
            char x[320];
            frame_path(&one, k, x, sizeof x);
            unlink(x);
            frame_path(&many, k, x, sizeof x);
            unlink(x);
        }
        unlink(pf);
        unlink(pt);
    }
}

/* TO with one face's corners turned: limn_morph's message on every rank;
   a callback failing on the last rank at frame 1 stops every rank. */
static void morph_errors(limn_context *ctx, const limn_mesh *from, const limn_mesh *to)
{
    char pf[320], pt[320], want[1024] = "";
    snprintf(pf, sizeof pf, "%s/efrom.ply", dir);
    snprintf(pt, sizeof pt, "%s/eto.obj", dir);
    limn_morph_options o;
    limn_morph_options_default(&o);
    o.frames = FRAMES;
    frames f = {.ctx = ctx, .tag = "err", .fail_at = -1};
    if (rank == 0) {
        limn_mesh *a = NULL, *b = NULL;
        limn_series_report r = {.size = sizeof r};
        limn_mesh_write(ctx, from, pf, LIMN_FORMAT_AUTO);
        limn_mesh_write(ctx, to, pt, LIMN_FORMAT_AUTO);
        limn_mesh_read(ctx, pf, LIMN_FORMAT_AUTO, &a);
        limn_mesh_read(ctx, pt, LIMN_FORMAT_AUTO, &b);
        CHECK(limn_morph(ctx, a, b, &o, single_frame, &f, &r) == LIMN_ERR_TOPOLOGY,
              "the single process accepts other faces");
        snprintf(want, sizeof want, "%s", limn_context_message(ctx));
        limn_mesh_destroy(a);
        limn_mesh_destroy(b);
    }
    MPI_Bcast(want, sizeof want, MPI_CHAR, 0, MPI_COMM_WORLD);
    limn_mpi_mesh *a = NULL, *b = NULL;
    limn_status st = limn_mpi_mesh_read(ctx, MPI_COMM_WORLD, pf, LIMN_FORMAT_AUTO, &a);
    if (!st)
        st = limn_mpi_mesh_read(ctx, MPI_COMM_WORLD, pt, LIMN_FORMAT_AUTO, &b);
    CHECK(st == LIMN_OK, "reading: %s", limn_context_message(ctx));
    limn_status got = limn_mpi_mesh_morph(ctx, a, b, &o, many_frame, &f, NULL, NULL, NULL);
    CHECK(got == LIMN_ERR_TOPOLOGY && strcmp(limn_context_message(ctx), want) == 0,
          "other faces: %d '%s', one process '%s'", (int)got, limn_context_message(ctx), want);
    f.fail_at = 1;
    f.fail_rank = size - 1;
    got = limn_mpi_mesh_morph(ctx, a, a, &o, many_frame, &f, NULL, NULL, NULL);
    CHECK(got == LIMN_ERR_IO, "a callback failing on rank %d: status %d on rank %d", size - 1,
          (int)got, rank);
    limn_mpi_mesh_destroy(a);
    limn_mpi_mesh_destroy(b);
    MPI_Barrier(MPI_COMM_WORLD);
    if (rank == 0) {
        char x[320];
        for (int k = 0; k < 2; k++) {
            frame_path(&f, k, x, sizeof x);
            unlink(x);
        }
        unlink(pf);
        unlink(pt);
    }
}

/* A copy of m with every vertex moved (the same faces). */
static limn_mesh *moved(limn_context *ctx, const limn_mesh *m, unsigned seed)
{
    limn_mesh *t = NULL;
    limn_mesh_copy(ctx, m, &t);
    test_perturb(t, 0.3, seed);
    return t;
}

int main(int argc, char **argv)
{
    MPI_Init(&argc, &argv);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    mpi_test_scratch_dir(dir, sizeof dir, "test_mpi_morph");
    limn_context *ctx = limn_context_create();
    limn_mesh *tri = mpi_test_composite(ctx, 1), *quad = mpi_test_composite(ctx, 0);
    limn_mesh *closed = mpi_test_closed(ctx, 0);
    limn_mesh *tri2 = moved(ctx, tri, 3), *quad2 = moved(ctx, quad, 4);
    limn_mesh *closed2 = moved(ctx, closed, 5);
    morph_case(ctx, "composite tri", tri, tri2, LIMN_SCHEME_LOOP, 0.0, 0);
    morph_case(ctx, "composite quad", quad, quad2, LIMN_SCHEME_CATMARK, 0.5, 0);
    morph_case(ctx, "closed quad", closed, closed2, LIMN_SCHEME_AUTO, 0.0, 0);
    morph_case(ctx, "closed quad linear", closed, closed2, LIMN_SCHEME_AUTO, 0.0, 1);
    morph_case(ctx, "composite tri linear", tri, tri2, LIMN_SCHEME_AUTO, 0.0, 1);
    limn_mesh *bad = mpi_test_turned(ctx, quad2, limn_mesh_face_count(quad2) / 2);
    morph_errors(ctx, quad, bad);
    limn_mesh_destroy(bad);
    limn_mesh_destroy(tri);
    limn_mesh_destroy(quad);
    limn_mesh_destroy(closed);
    limn_mesh_destroy(tri2);
    limn_mesh_destroy(quad2);
    limn_mesh_destroy(closed2);
    limn_context_destroy(ctx);
    return mpi_check_finish("test_mpi_morph", dir, checks, failures);
}
