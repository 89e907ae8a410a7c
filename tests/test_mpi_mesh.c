/* SPDX-License-Identifier: MIT */
/*
 * The distributed pipeline against the single process, under mpirun with
 * 2, 3 and 5 ranks: every rank reads its slice of a file
 * (limn_mpi_mesh_read), repairs it (limn_mpi_mesh_repair), the operator is
 * built with no rank holding the whole mesh (limn_mpi_mesh_interpolate: the
 * curve partition, local rows; from the sub-mesh the repair left, and again
 * from its own partition) and the control mesh is written in
 * parallel (limn_mpi_mesh_write). Rank 0 runs limn_mesh_read, repair,
 * limn_interpolate and limn_mesh_write on the same file: the two outputs
 * must be the same bytes (paper and Chebyshev: the single process's bits),
 * for every input format, on generated meshes with several components,
 * boundaries, a non-manifold fin, isolated vertices, n-gons and faces that
 * need the repair, and on shared real meshes when present. Also: the split
 * input round trip, limn_mpi_mesh_create with uneven blocks, and errors
 * (a bad face on one rank's slice, a missing file) that reach every rank
 * with one message and write nothing.
 *
 * Not cmocka: a failed assertion on one rank would leave the others in a
 * collective; checks count failures and the ranks agree at the end.
 */
#include "mpi_meshes.h"
#include "shell.h"
#include "mpi_check.h"
#include "support.h"

#include "limn_mpi.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

MPI_CHECK_STATE;
static char dir[256];

/* The single process on rank 0: read, repair, interpolate, write. */
static int single(limn_context *ctx, const char *in, const limn_interpolate_options *o,
                  const char *out)
{
    limn_mesh *m = NULL, *p = NULL;
    limn_report r = {.size = sizeof r};
    int ok = limn_mesh_read(ctx, in, LIMN_FORMAT_AUTO, &m) == LIMN_OK &&
             limn_mesh_repair(ctx, m, NULL, NULL) == LIMN_OK &&
             limn_interpolate(ctx, m, o, &p, &r) == LIMN_OK &&
             limn_mesh_write(ctx, p, out, LIMN_FORMAT_AUTO) == LIMN_OK;
    CHECK(ok, "single process on %s: %s", in, limn_context_message(ctx));
    limn_mesh_destroy(m);
    limn_mesh_destroy(p);
    return ok;
}

/* Every rank: the distributed pipeline on in, writing out. With again, a
   second interpolation of the same mesh is written there: the first built
   its rows from the sub-mesh the repair left (no partition of its own), the
   second, that sub-mesh taken, partitions and exchanges the faces itself. */
static limn_status distributed(limn_context *ctx, const char *in,
                               const limn_interpolate_options *o, const char *out,
                               const char *again, limn_report *r)
{
    limn_mpi_mesh *m = NULL, *p = NULL;
    limn_mpi_result res[2] = {{.size = sizeof res[0], .stats.size = sizeof res[0].stats},
                              {.size = sizeof res[1], .stats.size = sizeof res[1].stats}};
    limn_status st = limn_mpi_mesh_read(ctx, MPI_COMM_WORLD, in, LIMN_FORMAT_AUTO, &m);
    if (!st)
        st = limn_mpi_mesh_repair(ctx, m, NULL, NULL);
    if (!st)
        st = limn_mpi_mesh_interpolate(ctx, m, o, &p, r, NULL, &res[0]);
    if (!st)
        st = limn_mpi_mesh_write(ctx, p, out, LIMN_FORMAT_AUTO, NULL, NULL);
    limn_mpi_mesh_destroy(p);
    p = NULL;
    if (!st && again) {
        limn_report r2 = {.size = sizeof r2};
        st = limn_mpi_mesh_interpolate(ctx, m, o, &p, &r2, NULL, &res[1]);
        if (!st)
            st = limn_mpi_mesh_write(ctx, p, again, LIMN_FORMAT_AUTO, NULL, NULL);
        CHECK(st ||
                  (res[0].stats.seconds_partition == 0.0 && res[1].stats.seconds_partition > 0.0),
              "%s: partition seconds %g then %g: the repair's sub-mesh was not used once", in,
              res[0].stats.seconds_partition, res[1].stats.seconds_partition);
    }
    limn_mpi_result_free(&res[0]);
    limn_mpi_result_free(&res[1]);
    limn_mpi_mesh_destroy(m);
    limn_mpi_mesh_destroy(p);
    return st;
}

/* One mesh in one input format and method: both routes, the same bytes. */
static void pipeline_case(limn_context *ctx, const char *name, const limn_mesh *mesh,
                          const char *ext, limn_scheme scheme, double alpha, limn_method method)
{
    char in[320], ref[320], out[320], again[320];
    snprintf(in, sizeof in, "%s/in.%s", dir, ext);
    snprintf(ref, sizeof ref, "%s/ref.ply", dir);
    snprintf(out, sizeof out, "%s/out.ply", dir);
    snprintf(again, sizeof again, "%s/again.ply", dir);
    limn_interpolate_options o;
    limn_interpolate_options_default(&o);
    o.scheme = scheme;
    o.alpha = alpha;
    o.method = method;
    o.tolerance = 1e-9;
    int ok = 1;
    if (rank == 0) {
        ok = limn_mesh_write(ctx, mesh, in, LIMN_FORMAT_AUTO) == LIMN_OK;
        CHECK(ok, "%s: writing %s: %s", name, in, limn_context_message(ctx));
        ok = ok && single(ctx, in, &o, ref);
    }
    MPI_Bcast(&ok, 1, MPI_INT, 0, MPI_COMM_WORLD);
    if (!ok)
        return;
    limn_report r = {.size = sizeof r};
    limn_status st = distributed(ctx, in, &o, out, again, &r);
    CHECK(st == LIMN_OK, "%s (%s, %s): %s", name, ext, limn_method_name(method),
          limn_context_message(ctx));
    if (rank == 0 && st == LIMN_OK) {
        CHECK(test_same_bytes(ref, out), "%s (%s, %s, %d ranks): output differs from one process's",
              name, ext, limn_method_name(method), size);
        CHECK(test_same_bytes(ref, again),
              "%s (%s, %s, %d ranks): the second interpolation (its own partition) differs",
              name, ext, limn_method_name(method), size);
    }
    MPI_Barrier(MPI_COMM_WORLD);
    if (rank == 0) {
        unlink(in);
        unlink(ref);
        unlink(out);
        unlink(again);
    }
}

/* An OBJ that needs the repair: a quad grid (n-gons: a pentagon replaces two
   quads' corner) plus a face with a repeated corner and one that visits a
   vertex twice, spread through the file so they land on different ranks. */
static void write_repair_obj(const char *path)
{
    FILE *f = fopen(path, "w");
    if (!f)
        return;
    const int nx = 24, ny = 18;
    for (int j = 0; j <= ny; j++)
        for (int i = 0; i <= nx; i++)
            fprintf(f, "v %d %d %.17g\n", i, j, 0.05 * ((i * 7 + j * 3) % 5));
    for (int j = 0; j < ny; j++)
        for (int i = 0; i < nx; i++) {
            int a = j * (nx + 1) + i + 1;
            if (i == 3 && j == 2)
                fprintf(f, "f %d %d %d %d %d\n", a, a + 1, a + 1, a + nx + 2, a + nx + 1);
            else if (i == 10 && j == 9) /* a b c a d: split into (a b c) and a degenerate */
                fprintf(f, "f %d %d %d %d %d %d\n", a, a + 1, a + nx + 2, a, a + nx + 2,
                        a + nx + 1);
            else
                fprintf(f, "f %d %d %d %d\n", a, a + 1, a + nx + 2, a + nx + 1);
        }
    fclose(f);
}

static void repair_case(limn_context *ctx)
{
    char in[320], ref[320], out[320];
    snprintf(in, sizeof in, "%s/repair.obj", dir);
    snprintf(ref, sizeof ref, "%s/repair_ref.ply", dir);
    snprintf(out, sizeof out, "%s/repair_out.ply", dir);
    limn_interpolate_options o;
    limn_interpolate_options_default(&o);
    int ok = 1;
    if (rank == 0) {
        write_repair_obj(in);
        ok = single(ctx, in, &o, ref);
    }
    MPI_Bcast(&ok, 1, MPI_INT, 0, MPI_COMM_WORLD);
    limn_mpi_mesh *m = NULL, *p = NULL;
    limn_repair_report rr = {.size = sizeof rr};
    limn_report r = {.size = sizeof r};
    limn_status st = limn_mpi_mesh_read(ctx, MPI_COMM_WORLD, in, LIMN_FORMAT_AUTO, &m);
    if (!st)
        st = limn_mpi_mesh_repair(ctx, m, NULL, &rr);
    CHECK(st == LIMN_OK && rr.repeat_faces == 2 && rr.faces_after == rr.faces_before + 1,
          "repair: %s; %zu repeat faces, %zu -> %zu faces", limn_context_message(ctx),
          rr.repeat_faces, rr.faces_before, rr.faces_after);
    if (!st)
        st = limn_mpi_mesh_interpolate(ctx, m, &o, &p, &r, NULL, NULL);
    if (!st)
        st = limn_mpi_mesh_write(ctx, p, out, LIMN_FORMAT_AUTO, NULL, NULL);
    CHECK(st == LIMN_OK, "repair pipeline: %s", limn_context_message(ctx));
    if (rank == 0 && ok && !st)
        CHECK(test_same_bytes(ref, out), "repaired mesh: output differs from one process's");
    limn_mpi_mesh_destroy(m);
    limn_mpi_mesh_destroy(p);
    MPI_Barrier(MPI_COMM_WORLD);
    if (rank == 0) {
        unlink(in);
        unlink(ref);
        unlink(out);
    }
}

/* The split input: written by every rank, read back, the same blocks; and a
   mesh made from the ranks' own uneven arrays gives the single process's bytes. */
static void split_and_create(limn_context *ctx, const limn_mesh *mesh)
{
    char in[320], name[320], ref[320], out[320];
    snprintf(in, sizeof in, "%s/split_in.ply", dir);
    snprintf(name, sizeof name, "%s/parts", dir);
    snprintf(ref, sizeof ref, "%s/split_ref.ply", dir);
    snprintf(out, sizeof out, "%s/split_out.ply", dir);
    limn_interpolate_options o;
    limn_interpolate_options_default(&o);
    int ok = 1;
    if (rank == 0)
        ok = limn_mesh_write(ctx, mesh, in, LIMN_FORMAT_AUTO) == LIMN_OK &&
             single(ctx, in, &o, ref);
    MPI_Bcast(&ok, 1, MPI_INT, 0, MPI_COMM_WORLD);
    limn_mpi_mesh *a = NULL, *b = NULL, *c = NULL, *p = NULL;
    limn_status st = limn_mpi_mesh_read(ctx, MPI_COMM_WORLD, in, LIMN_FORMAT_AUTO, &a);
    if (!st)
        st = limn_mpi_mesh_write_split(ctx, a, name);
    if (!st)
        st = limn_mpi_mesh_read_split(ctx, MPI_COMM_WORLD, name, &b);
    CHECK(st == LIMN_OK, "split round trip: %s", limn_context_message(ctx));
    if (!st) {
        size_t nv = limn_mpi_mesh_vertex_count(a), nf = limn_mpi_mesh_face_count(a);
        const uint32_t *oa = limn_mpi_mesh_face_offsets(a), *ob = limn_mpi_mesh_face_offsets(b);
        CHECK(nv == limn_mpi_mesh_vertex_count(b) && nf == limn_mpi_mesh_face_count(b) &&
                  limn_mpi_mesh_vertex_begin(a) == limn_mpi_mesh_vertex_begin(b) &&
                  memcmp(limn_mpi_mesh_positions(a), limn_mpi_mesh_positions(b),
                         3 * nv * sizeof(double)) == 0 &&
                  memcmp(oa, ob, (nf + 1) * sizeof *oa) == 0 &&
                  memcmp(limn_mpi_mesh_face_indices(a), limn_mpi_mesh_face_indices(b),
                         oa[nf] * sizeof(uint32_t)) == 0,
              "split round trip: rank %d's blocks differ", rank);
    }
    /* uneven blocks of the caller's own: rank r takes a share growing with r */
    size_t n = limn_mesh_vertex_count(mesh), nf = limn_mesh_face_count(mesh);
    size_t weight = (size_t)size * ((size_t)size + 1) / 2, sum = (size_t)rank * (rank + 1) / 2;
    size_t v0 = n * sum / weight, v1 = n * (sum + (size_t)rank + 1) / weight;
    size_t f0 = nf * (size_t)rank / (size_t)size, f1 = nf * ((size_t)rank + 1) / (size_t)size;
    const uint32_t *off = limn_mesh_face_offsets(mesh);
    uint32_t *loff = malloc((f1 - f0 + 1) * sizeof *loff);
    for (size_t f = f0; f <= f1; f++)
        loff[f - f0] = off[f] - off[f0];
    st = limn_mpi_mesh_create(ctx, MPI_COMM_WORLD, v1 - v0, limn_mesh_positions(mesh) + 3 * v0,
                              f1 - f0, loff, limn_mesh_face_indices(mesh) + off[f0], &c);
    free(loff);
    limn_report r = {.size = sizeof r};
    if (!st)
        st = limn_mpi_mesh_repair(ctx, c, NULL, NULL);
    if (!st)
        st = limn_mpi_mesh_interpolate(ctx, c, &o, &p, &r, NULL, NULL);
    if (!st)
        st = limn_mpi_mesh_write(ctx, p, out, LIMN_FORMAT_AUTO, NULL, NULL);
    CHECK(st == LIMN_OK, "created mesh: %s", limn_context_message(ctx));
    if (rank == 0 && ok && !st)
        CHECK(test_same_bytes(ref, out), "uneven blocks: output differs from one process's");
    limn_mpi_mesh_destroy(a);
    limn_mpi_mesh_destroy(b);
    limn_mpi_mesh_destroy(c);
    limn_mpi_mesh_destroy(p);
    MPI_Barrier(MPI_COMM_WORLD);
    if (rank == 0) {
        unlink(in);
        unlink(ref);
        unlink(out);
        for (int k = 0; k < size; k++) {
            char part[340];
            snprintf(part, sizeof part, "%s.r%d.ply", name, k);
            unlink(part);
        }
    }
}

/* limn_mpi_mesh_create with a face index past every rank's vertices on the
   last rank's last face: every rank fails with that face's message. */
static void created_index_error(limn_context *ctx)
{
    const double pos[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
    uint32_t b = 4 * (uint32_t)rank, total = 4 * (uint32_t)size;
    uint32_t off[3] = {0, 3, 6};
    uint32_t idx[6] = {b, b + 1, b + 2, b + 1, b + 3, rank == size - 1 ? total + 5 : b + 2};
    limn_mpi_mesh *m = NULL;
    limn_status st = limn_mpi_mesh_create(ctx, MPI_COMM_WORLD, 4, pos, 2, off, idx, &m);
    char want[160];
    snprintf(want, sizeof want, "face %u uses vertex %u but the mesh has %u vertices",
             2 * (unsigned)size - 1, (unsigned)total + 5, (unsigned)total);
    CHECK(st == LIMN_ERR_ARGUMENT && m == NULL && strstr(limn_context_message(ctx), want),
          "created mesh, bad index: status %d, '%s' (want '%s')", (int)st,
          limn_context_message(ctx), want);
    limn_mpi_mesh_destroy(m);
}

/* A face index past the vertices in the last rank's slice, and a missing
   file: every rank fails with the same message, and nothing is written. */
static void errors(limn_context *ctx)
{
    char in[320], out[320];
    snprintf(in, sizeof in, "%s/bad.obj", dir);
    snprintf(out, sizeof out, "%s/bad_out.ply", dir);
    if (rank == 0) {
        FILE *f = fopen(in, "w");
        for (int i = 0; i < 40; i++)
            fprintf(f, "v %d 0 %d\n", i % 7, i / 7);
        for (int i = 0; i < 30; i++)
            fprintf(f, "f %d %d %d\n", i + 1, i + 2, i == 29 ? 99 : i + 8);
        fclose(f);
    }
    MPI_Barrier(MPI_COMM_WORLD);
    limn_interpolate_options o;
    limn_interpolate_options_default(&o);
    limn_report r = {.size = sizeof r};
    limn_status st = distributed(ctx, in, &o, out, NULL, &r);
    char msg[512];
    snprintf(msg, sizeof msg, "%s", limn_context_message(ctx));
    char root_msg[512];
    memcpy(root_msg, msg, sizeof msg);
    MPI_Bcast(root_msg, sizeof root_msg, MPI_CHAR, 0, MPI_COMM_WORLD);
    CHECK(st != LIMN_OK && strstr(msg, "99") && strcmp(msg, root_msg) == 0,
          "bad index: status %d, message '%s' (rank 0: '%s')", (int)st, msg, root_msg);
    CHECK(!test_file_exists(out), "bad index: %s was written", out);
    char missing[320];
    snprintf(missing, sizeof missing, "%s/missing.ply", dir);
    st = distributed(ctx, missing, &o, out, NULL, &r);
    CHECK(st != LIMN_OK && strstr(limn_context_message(ctx), "missing.ply"),
          "missing file: status %d, '%s'", (int)st, limn_context_message(ctx));
    MPI_Barrier(MPI_COMM_WORLD);
    if (rank == 0)
        unlink(in);
    created_index_error(ctx);
}

/* The series filters of the distributed path (limn_mpi_mesh_smooth etc.). */
enum series_kind { SMOOTH, DENOISE, SHARPEN };
static const char *const series_names[] = {"smooth", "denoise", "sharpen"};

/* The single process's filter on rank 0 (read, repair, filter, write). */
static int series_single(limn_context *ctx, enum series_kind k, const char *in,
                         const limn_series_options *o, const char *out)
{
    limn_mesh *m = NULL, *f = NULL;
    limn_series_report r = {.size = sizeof r};
    int ok = limn_mesh_read(ctx, in, LIMN_FORMAT_AUTO, &m) == LIMN_OK &&
             limn_mesh_repair(ctx, m, NULL, NULL) == LIMN_OK;
    if (ok && k == SMOOTH)
        ok = limn_smooth(ctx, m, o, 3, &f, &r) == LIMN_OK;
    else if (ok && k == DENOISE)
        ok = limn_denoise(ctx, m, o, 2, 3, 0, &f, &r) == LIMN_OK;
    else if (ok)
        ok = limn_sharpen(ctx, m, o, 1, 3, 2, &f, &r) == LIMN_OK;
    ok = ok && limn_mesh_write(ctx, f, out, LIMN_FORMAT_AUTO) == LIMN_OK;
    CHECK(ok, "single process %s on %s: %s", series_names[k], in, limn_context_message(ctx));
    limn_mesh_destroy(m);
    limn_mesh_destroy(f);
    return ok;
}

/* Every rank: read, repair, the distributed filter, the parallel write. */
static limn_status series_distributed(limn_context *ctx, enum series_kind k, const char *in,
                                      const limn_series_options *o, const char *out)
{
    limn_mpi_mesh *m = NULL, *f = NULL;
    limn_series_report r = {.size = sizeof r};
    limn_status st = limn_mpi_mesh_read(ctx, MPI_COMM_WORLD, in, LIMN_FORMAT_AUTO, &m);
    if (!st)
        st = limn_mpi_mesh_repair(ctx, m, NULL, NULL);
    if (!st && k == SMOOTH)
        st = limn_mpi_mesh_smooth(ctx, m, o, 3, &f, &r, NULL, NULL);
    else if (!st && k == DENOISE)
        st = limn_mpi_mesh_denoise(ctx, m, o, 2, 3, 0, &f, &r, NULL, NULL);
    else if (!st)
        st = limn_mpi_mesh_sharpen(ctx, m, o, 1, 3, 2, &f, &r, NULL, NULL);
    if (!st)
        st = limn_mpi_mesh_write(ctx, f, out, LIMN_FORMAT_AUTO, NULL, NULL);
    limn_mpi_mesh_destroy(m);
    limn_mpi_mesh_destroy(f);
    return st;
}

/* One mesh and filter: both routes, the same bytes. */
static void series_case(limn_context *ctx, const char *name, const limn_mesh *mesh,
                        enum series_kind k, limn_scheme scheme, double alpha)
{
    char in[320], ref[320], out[320];
    snprintf(in, sizeof in, "%s/series_in.ply", dir);
    snprintf(ref, sizeof ref, "%s/series_ref.ply", dir);
    snprintf(out, sizeof out, "%s/series_out.ply", dir);
    limn_series_options o;
    limn_series_options_default(&o);
    o.scheme = scheme;
    o.alpha = alpha;
    int ok = 1;
    if (rank == 0) {
        ok = limn_mesh_write(ctx, mesh, in, LIMN_FORMAT_AUTO) == LIMN_OK;
        CHECK(ok, "%s: writing %s: %s", name, in, limn_context_message(ctx));
        ok = ok && series_single(ctx, k, in, &o, ref);
    }
    MPI_Bcast(&ok, 1, MPI_INT, 0, MPI_COMM_WORLD);
    if (!ok)
        return;
    limn_status st = series_distributed(ctx, k, in, &o, out);
    CHECK(st == LIMN_OK, "%s (%s): %s", name, series_names[k], limn_context_message(ctx));
    if (rank == 0 && st == LIMN_OK)
        CHECK(test_same_bytes(ref, out), "%s (%s, %d ranks): output differs from one process's",
              name, series_names[k], size);
    MPI_Barrier(MPI_COMM_WORLD);
    if (rank == 0) {
        unlink(in);
        unlink(ref);
        unlink(out);
    }
}

/* limn_mpi_mesh_bands: every band and the remainder, written in parallel,
   are the bytes of rank 0's limn_bands written whole; the energies its bits. */
static void bands_case(limn_context *ctx, const char *name, const limn_mesh *mesh, int count)
{
    char in[320], a[320], b[320];
    snprintf(in, sizeof in, "%s/bands_in.ply", dir);
    limn_series_options o;
    limn_series_options_default(&o);
    double energy_ref[4] = {0}, energy[4] = {-1, -1, -1, -1};
    int ok = 1;
    limn_mesh *m = NULL, *band = NULL;
    double *ref = NULL;
    if (rank == 0) {
        limn_series_report r = {.size = sizeof r};
        ok = limn_mesh_write(ctx, mesh, in, LIMN_FORMAT_AUTO) == LIMN_OK &&
             limn_mesh_read(ctx, in, LIMN_FORMAT_AUTO, &m) == LIMN_OK &&
             limn_mesh_repair(ctx, m, NULL, NULL) == LIMN_OK &&
             limn_mesh_copy(ctx, m, &band) == LIMN_OK;
        size_t n3 = ok ? 3 * limn_mesh_vertex_count(m) : 0;
        ref = malloc(((size_t)count + 1) * (n3 ? n3 : 1) * sizeof *ref);
        ok = ok && ref && limn_bands(ctx, m, &o, count, ref, energy_ref, &r) == LIMN_OK;
        for (int i = 0; ok && i <= count; i++) {
            snprintf(a, sizeof a, "%s/band_ref%d.ply", dir, i);
            memcpy(limn_mesh_positions_mutable(band), ref + (size_t)i * n3, n3 * sizeof *ref);
            ok = limn_mesh_write(ctx, band, a, LIMN_FORMAT_AUTO) == LIMN_OK;
        }
        CHECK(ok, "%s: single process bands: %s", name, limn_context_message(ctx));
    }
    MPI_Bcast(&ok, 1, MPI_INT, 0, MPI_COMM_WORLD);
    MPI_Bcast(energy_ref, 4, MPI_DOUBLE, 0, MPI_COMM_WORLD);
    limn_mpi_mesh *dm = NULL, *bands[4] = {NULL, NULL, NULL, NULL};
    limn_status st = ok ? limn_mpi_mesh_read(ctx, MPI_COMM_WORLD, in, LIMN_FORMAT_AUTO, &dm)
                        : LIMN_ERR_ARGUMENT;
    if (!st)
        st = limn_mpi_mesh_repair(ctx, dm, NULL, NULL);
    if (!st)
        st = limn_mpi_mesh_bands(ctx, dm, &o, count, bands, energy, NULL, NULL, NULL);
    CHECK(!ok || st == LIMN_OK, "%s: limn_mpi_mesh_bands: %s", name, limn_context_message(ctx));
    for (int i = 0; ok && !st && i <= count; i++) {
        snprintf(b, sizeof b, "%s/band%d.ply", dir, i);
        st = limn_mpi_mesh_write(ctx, bands[i], b, LIMN_FORMAT_AUTO, NULL, NULL);
        CHECK(st == LIMN_OK, "%s: writing band %d: %s", name, i, limn_context_message(ctx));
        CHECK(memcmp(&energy[i], &energy_ref[i], sizeof energy[i]) == 0,
              "%s (%d ranks): band %d's energy %.17g, one process %.17g", name, size, i,
              energy[i], energy_ref[i]);
        snprintf(a, sizeof a, "%s/band_ref%d.ply", dir, i);
        if (rank == 0 && !st)
            CHECK(test_same_bytes(a, b), "%s (%d ranks): band %d differs from one process's", name,
                  size, i);
    }
    for (int i = 0; i <= count; i++)
        limn_mpi_mesh_destroy(bands[i]);
    limn_mpi_mesh_destroy(dm);
    MPI_Barrier(MPI_COMM_WORLD);
    if (rank == 0) {
        for (int i = 0; i <= count; i++) {
            snprintf(a, sizeof a, "%s/band_ref%d.ply", dir, i);
            snprintf(b, sizeof b, "%s/band%d.ply", dir, i);
            unlink(a);
            unlink(b);
        }
        unlink(in);
    }
    limn_mesh_destroy(m);
    limn_mesh_destroy(band);
    free(ref);
}

/* keep_volume on an open mesh is refused on every rank with one message,
   nothing made (test_mpi_measure: the single process's message). */
static void series_errors(limn_context *ctx, const limn_mesh *mesh)
{
    char in[320];
    snprintf(in, sizeof in, "%s/series_err.ply", dir);
    if (rank == 0)
        limn_mesh_write(ctx, mesh, in, LIMN_FORMAT_AUTO);
    MPI_Barrier(MPI_COMM_WORLD);
    limn_mpi_mesh *m = NULL, *f = NULL;
    limn_status st = limn_mpi_mesh_read(ctx, MPI_COMM_WORLD, in, LIMN_FORMAT_AUTO, &m);
    CHECK(st == LIMN_OK, "series_errors: reading %s: %s", in, limn_context_message(ctx));
    if (!st) {
        st = limn_mpi_mesh_denoise(ctx, m, NULL, 2, 3, 1, &f, NULL, NULL, NULL);
        CHECK(st == LIMN_ERR_TOPOLOGY && f == NULL &&
                  strstr(limn_context_message(ctx), "needs a closed mesh"),
              "keep_volume: status %d, '%s'", (int)st, limn_context_message(ctx));
    }
    limn_mpi_mesh_destroy(m);
    MPI_Barrier(MPI_COMM_WORLD);
    if (rank == 0)
        unlink(in);
}

/* The shared mesh real[k] of main (mpi_check_shared): the pipeline, one
   series filter in turn, bands on the last. */
static void shared_case(limn_context *ctx, size_t k, const char *path, limn_mesh *m)
{
    pipeline_case(ctx, path, m, "ply", LIMN_SCHEME_AUTO, 0.0, LIMN_METHOD_AUTO);
    series_case(ctx, path, m, (enum series_kind)(k % 3), LIMN_SCHEME_AUTO, 0.0);
    if (k == 4) /* bob_quad: several chunks of rows, blocks not on their edges */
        bands_case(ctx, path, m, 2);
}

int main(int argc, char **argv)
{
    MPI_Init(&argc, &argv);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    mpi_test_scratch_dir(dir, sizeof dir, "test_mpi_mesh");
    if (rank == 0)
        printf("test_mpi_mesh: %d ranks\n", size);
    limn_context *ctx = limn_context_create();
    limn_mesh *tri = mpi_test_composite(ctx, 1), *quad = mpi_test_composite(ctx, 0);
    static const char *const exts[] = {"ply", "obj", "off"};
    for (size_t e = 0; e < 3; e++) {
        pipeline_case(ctx, "composite tri", tri, exts[e], LIMN_SCHEME_LOOP, 0.0,
                      LIMN_METHOD_AUTO);
        pipeline_case(ctx, "composite quad", quad, exts[e], LIMN_SCHEME_CATMARK, 0.5,
                      LIMN_METHOD_AUTO);
    }
    pipeline_case(ctx, "composite tri", tri, "ply", LIMN_SCHEME_LOOP, 0.0, LIMN_METHOD_PAPER);
    pipeline_case(ctx, "composite quad", quad, "ply", LIMN_SCHEME_CATMARK, 0.0,
                  LIMN_METHOD_PAPER);
    repair_case(ctx);
    for (int k = SMOOTH; k <= SHARPEN; k++) {
        series_case(ctx, "composite tri", tri, (enum series_kind)k, LIMN_SCHEME_LOOP, 0.0);
        series_case(ctx, "composite quad", quad, (enum series_kind)k, LIMN_SCHEME_CATMARK, 0.5);
    }
    series_errors(ctx, quad);
    bands_case(ctx, "composite tri", tri, 3);
    bands_case(ctx, "composite quad", quad, 2);
    split_and_create(ctx, quad);
    errors(ctx);
    static const char *const real[] = {"small/suzanne.obj", "small/bun_zipper_res4.ply",
                                       "small/cow.obj", "opensubdiv/catmark_nonman_edges.obj",
                                       "medium/bob_quad.obj"};
    mpi_check_shared(ctx, real, sizeof real / sizeof *real, shared_case);
    limn_mesh_destroy(tri);
    limn_mesh_destroy(quad);
    limn_context_destroy(ctx);
    return mpi_check_finish("test_mpi_mesh", dir, checks, failures);
}
