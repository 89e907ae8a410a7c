/* SPDX-License-Identifier: MIT */
/*
 * limn_mpi_output_set_add_mesh under mpirun (2 and 3 ranks): the parallel
 * write staged in rank 0's output set instead of appearing. A mesh and a
 * report staged over old files leave the old bytes until rank 0 commits,
 * then both are there, the mesh the same bytes as limn_mpi_mesh_write's; a
 * set destroyed without a commit leaves the old files as they were and
 * nothing beside them; rank 0's set NULL is refused on every rank with one
 * message and nothing written; a set of 40 outputs (grown) takes the mesh
 * and commits all 41; a character device (/dev/null) target is staged and
 * written through at the commit.
 *
 * Not cmocka: a failed assertion on one rank would leave the others in a
 * collective; checks count failures and the ranks agree at the end.
 */
#include "mpi_check.h"
#include "mpi_meshes.h"
#include "shell.h"
#include "support.h"

#include "limn_mpi.h"

#include <stdio.h>
#include <string.h>

MPI_CHECK_STATE;
static char dir[256];

static const char old_mesh[] = "an old mesh\n", old_report[] = "an old report\n";

/* Rank 0: the two targets hold their old bytes again. */
static void put_old(const char *mesh, const char *report)
{
    if (rank == 0)
        CHECK(test_write_text(mesh, old_mesh) == 0 && test_write_text(report, old_report) == 0,
              "cannot write the old files");
    MPI_Barrier(MPI_COMM_WORLD);
}

/* Rank 0: does path hold exactly text? */
static int holds(const char *path, const char *text)
{
    char buf[64] = "";
    FILE *f = fopen(path, "rb");
    size_t n = f ? fread(buf, 1, sizeof buf - 1, f) : 0;
    if (f)
        fclose(f);
    return f && n == strlen(text) && memcmp(buf, text, n) == 0;
}

/* Staged mesh and report over old files: old until the commit, new after;
   without a commit: old, nothing beside. */
static void stage_and_commit(limn_context *ctx, const limn_mpi_mesh *m, const char *ref)
{
    char mesh[320], report[320];
    snprintf(mesh, sizeof mesh, "%s/out.ply", dir);
    snprintf(report, sizeof report, "%s/report.json", dir);
    for (int commit = 0; commit < 2; commit++) {
        put_old(mesh, report);
        limn_output_set *set = NULL;
        limn_status st = limn_output_set_create(ctx, &set);
        CHECK(st == LIMN_OK, "limn_output_set_create: %s", limn_context_message(ctx));
        limn_write_report wr = {.size = sizeof wr};
        st = limn_mpi_output_set_add_mesh(ctx, set, m, mesh, LIMN_FORMAT_AUTO, NULL, &wr);
        CHECK(st == LIMN_OK, "staging the mesh: %s", limn_context_message(ctx));
        if (rank == 0 && !st) {
            st = limn_output_set_add_bytes(ctx, set, report, "{}\n", 3);
            CHECK(st == LIMN_OK && limn_output_set_count(set) == 2,
                  "staging the report: %s (%d staged)", limn_context_message(ctx),
                  limn_output_set_count(set));
            CHECK(holds(mesh, old_mesh) && holds(report, old_report) &&
                      test_dir_entries(dir) == 3 + 2,
                  "before the commit: the old files changed, or %d entries (ref, the two "
                  "old files, two staged)", test_dir_entries(dir));
            if (commit) {
                st = limn_output_set_commit(ctx, set);
                CHECK(st == LIMN_OK && test_same_bytes(mesh, ref) && holds(report, "{}\n"),
                      "after the commit: %s, the mesh %s", limn_context_message(ctx),
                      test_same_bytes(mesh, ref) ? "as limn_mpi_mesh_write's" : "other bytes");
            }
        } else if (rank != 0) {
            CHECK(limn_output_set_count(set) == 0, "rank %d's set holds %d outputs", rank,
                  limn_output_set_count(set));
        }
        limn_output_set_destroy(set);
        if (rank == 0 && !commit)
            CHECK(holds(mesh, old_mesh) && holds(report, old_report) &&
                      test_dir_entries(dir) == 3,
                  "no commit: the old files changed, or %d entries", test_dir_entries(dir));
        MPI_Barrier(MPI_COMM_WORLD);
    }
}

/* Rank 0's set NULL: refused everywhere alike, nothing written. Then a set
   already holding 40 outputs (past its first growth) takes the mesh too, and
   all 41 appear at the commit. */
static void refusal_and_many(limn_context *ctx, const limn_mpi_mesh *m, const char *ref)
{
    char mesh[320], report[320];
    snprintf(mesh, sizeof mesh, "%s/out.ply", dir);
    snprintf(report, sizeof report, "%s/report.json", dir);
    put_old(mesh, report);
    limn_output_set *set = NULL;
    limn_output_set_create(ctx, &set);
    /* the other ranks pass a set: rank 0's NULL alone must be refused */
    limn_status st = limn_mpi_output_set_add_mesh(ctx, rank == 0 ? NULL : set, m, mesh,
                                                  LIMN_FORMAT_AUTO, NULL, NULL);
    CHECK(st == LIMN_ERR_ARGUMENT && strstr(limn_context_message(ctx), "set is NULL"),
          "rank 0's set NULL: status %d '%s'", (int)st, limn_context_message(ctx));
    if (rank == 0)
        CHECK(holds(mesh, old_mesh) && test_dir_entries(dir) == 3,
              "after the refusal: the old mesh changed, or %d entries", test_dir_entries(dir));
    char name[320];
    int filled = 1;
    for (int i = 0; rank == 0 && i < 40 && filled; i++) {
        snprintf(name, sizeof name, "%s/filler%d.txt", dir, i);
        filled = limn_output_set_add_bytes(ctx, set, name, "x", 1) == LIMN_OK;
    }
    CHECK(filled, "40 outputs in a set: %s", limn_context_message(ctx));
    st = limn_mpi_output_set_add_mesh(ctx, set, m, mesh, LIMN_FORMAT_AUTO, NULL, NULL);
    CHECK(st == LIMN_OK, "the mesh after 40 outputs: %s", limn_context_message(ctx));
    if (rank == 0 && !st) {
        st = limn_output_set_commit(ctx, set);
        snprintf(name, sizeof name, "%s/filler39.txt", dir);
        CHECK(st == LIMN_OK && holds(name, "x") && test_same_bytes(mesh, ref) &&
                  test_dir_entries(dir) == 3 + 40,
              "41 outputs committed: %s, %d entries", limn_context_message(ctx),
              test_dir_entries(dir));
        for (int i = 0; i < 40; i++) {
            snprintf(name, sizeof name, "%s/filler%d.txt", dir, i);
            remove(name);
        }
    }
    limn_output_set_destroy(set);
    MPI_Barrier(MPI_COMM_WORLD);
}

/* A target no rename can replace: its bytes written through at the commit. */
static void device_target(limn_context *ctx, const limn_mpi_mesh *m)
{
    limn_output_set *set = NULL;
    limn_output_set_create(ctx, &set);
    limn_status st = limn_mpi_output_set_add_mesh(ctx, set, m, "/dev/null", LIMN_FORMAT_PLY,
                                                  NULL, NULL);
    CHECK(st == LIMN_OK, "staging /dev/null: %s", limn_context_message(ctx));
    if (rank == 0 && !st) {
        st = limn_output_set_commit(ctx, set);
        CHECK(st == LIMN_OK, "committing /dev/null: %s", limn_context_message(ctx));
    }
    limn_output_set_destroy(set);
}

int main(int argc, char **argv)
{
    MPI_Init(&argc, &argv);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    mpi_test_scratch_dir(dir, sizeof dir, "test_mpi_output_set");
    if (rank == 0)
        printf("test_mpi_output_set: %d ranks\n", size);
    limn_context *ctx = limn_context_create();
    limn_mesh *whole = mpi_test_composite(ctx, 0);
    char in[320], ref[320];
    snprintf(in, sizeof in, "%s/in.ply", dir);
    snprintf(ref, sizeof ref, "%s/ref.ply", dir);
    int ok = rank != 0 || limn_mesh_write(ctx, whole, in, LIMN_FORMAT_AUTO) == LIMN_OK;
    MPI_Allreduce(MPI_IN_PLACE, &ok, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    limn_mpi_mesh *m = NULL;
    limn_status st = ok ? limn_mpi_mesh_read(ctx, MPI_COMM_WORLD, in, LIMN_FORMAT_AUTO, &m)
                        : LIMN_ERR_IO;
    if (!st)
        st = limn_mpi_mesh_write(ctx, m, ref, LIMN_FORMAT_AUTO, NULL, NULL);
    CHECK(st == LIMN_OK, "the mesh and its reference write: %s", limn_context_message(ctx));
    if (!st) {
        if (rank == 0)
            remove(in); /* the directory holds ref.ply and the outputs under test */
        MPI_Barrier(MPI_COMM_WORLD);
        stage_and_commit(ctx, m, ref);
        refusal_and_many(ctx, m, ref);
        device_target(ctx, m);
    }
    limn_mpi_mesh_destroy(m);
    limn_mesh_destroy(whole);
    limn_context_destroy(ctx);
    return mpi_check_finish("test_mpi_output_set", dir, checks, failures);
}
