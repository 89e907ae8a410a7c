/* SPDX-License-Identifier: MIT */
/*
 * The parallel write (host/mpi/mpi_write.c) under mpirun with 1, 2, 3 and 5
 * ranks (tests/CMakeLists.txt): every rank holds the results of a scattered
 * set of owned vertices (not a block) and an uneven block of faces, vtxdist
 * is uneven (with empty blocks from 3 ranks on); the file written must be
 * the bytes limn_mesh_write writes of the whole mesh (rank 0, the
 * independent route) in every format: OBJ, OFF, PLY binary little and big
 * endian, PLY ascii, the float32 PLYs, STL. Meshes: grids with boundaries
 * (quads, triangles), an icosahedron, a pyramid, n-gons with a 300-gon (PLY's
 * uint count), isolated vertices, colours; shared real meshes when present.
 * Failures with real causes: a path whose parent is a file, a non-finite
 * position and a coordinate outside STL's float in the last rank's block, a
 * vertex owned twice, a file-size limit (RLIMIT_FSIZE) on one rank's
 * process: every rank returns the same status and message (the single
 * process's message where it has one), the target is untouched and no
 * temporary file is left. Straight-through targets (/dev/null, a FIFO read
 * by a thread of rank 0) and symlinks.
 *
 * Not cmocka (an assertion jumping out on one rank would leave the others
 * in a collective): failures are counted and agreed at the end.
 */
#include "slurp.h"
#include "mpi_check.h"
#include "support.h"

#include "mpi/mpi_write.h"

#include <dirent.h>
#include <math.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

MPI_CHECK_STATE;
static char dir[256];

/* ------------------------------------------------------------------ meshes */

/* A 300-gon, a pentagon, a hexagon and an isolated vertex. */
static limn_mesh *ngons(limn_context *ctx)
{
    enum { BIG = 300, NV = BIG + 5 + 6 + 1, NI = BIG + 5 + 6 };
    double pos[3 * NV];
    uint32_t off[4] = {0, BIG, BIG + 5, NI}, idx[NI];
    for (int k = 0; k < NV; k++) {
        pos[3 * k] = 0.01 * k * (k % 3 ? 1 : -1);
        pos[3 * k + 1] = 1.0 / (k + 1);
        pos[3 * k + 2] = 0.1 * (k % 7) - 1e-7 * k;
    }
    for (int k = 0; k < NI; k++)
        idx[k] = (uint32_t)k;
    limn_mesh *m = NULL;
    limn_mesh_create(ctx, NV, pos, 3, off, idx, &m);
    return m;
}

static limn_mesh *colored(limn_context *ctx, limn_mesh *m)
{
    size_t n = limn_mesh_vertex_count(m);
    uint8_t *rgb = malloc(3 * n);
    for (size_t i = 0; i < 3 * n; i++)
        rgb[i] = (uint8_t)(i * 37 + 11);
    limn_mesh_set_colors(ctx, m, rgb);
    free(rgb);
    return m;
}

/* ------------------------------------------------------------- the parts */

/* An uneven split of n into size blocks (block r has weight w[r]; from 3
   ranks on block 1 is empty). */
static void split(size_t n, int reverse, size_t *d)
{
    double total = 0, acc = 0, w[64];
    for (int r = 0; r < size; r++) {
        int k = reverse ? size - 1 - r : r;
        w[r] = size >= 3 && r == 1 ? 0.0 : (double)((k + 1) * (k + 1));
        total += w[r];
    }
    d[0] = 0;
    for (int r = 0; r < size; r++) {
        acc += w[r];
        d[r + 1] = r + 1 == size ? n : (size_t)((double)n * acc / total);
    }
}

/* The rank owning vertex v: scattered, not blocks. */
static int owner(size_t v) { return (int)(((v * 2654435761u) >> 7) % (unsigned)size); }

typedef struct part_data {
    size_t vtxdist[65], fdist[65];
    uint32_t *ids, *off;
    double *pos;
    uint8_t *rgb;
    mpi_write_part part;
} part_data;

/* This rank's share of m (which every rank holds whole, to cut it). */
static void make_part(const limn_mesh *m, part_data *d, int dup)
{
    size_t n = limn_mesh_vertex_count(m), nf = limn_mesh_face_count(m);
    const double *p = limn_mesh_positions(m);
    const uint8_t *c = limn_mesh_colors(m);
    const uint32_t *off = limn_mesh_face_offsets(m), *idx = limn_mesh_face_indices(m);
    split(n, 0, d->vtxdist);
    split(nf, 1, d->fdist);
    d->ids = malloc((n + 1) * sizeof *d->ids);
    d->pos = malloc((3 * n + 3) * sizeof *d->pos);
    d->rgb = c ? malloc(3 * n + 3) : NULL;
    size_t k = 0;
    for (size_t v = n; v-- > 0;) /* descending: any order will do */
        if (owner(v) == rank) {
            d->ids[k] = (uint32_t)v;
            memcpy(d->pos + 3 * k, p + 3 * v, 3 * sizeof *p);
            if (c)
                memcpy(d->rgb + 3 * k, c + 3 * v, 3);
            k++;
        }
    if (dup && rank == size - 1) { /* vertex 0 owned twice */
        d->ids[k] = 0;
        memcpy(d->pos + 3 * k, p, 3 * sizeof *p);
        k++;
    }
    size_t fb = d->fdist[rank], fc = d->fdist[rank + 1] - fb;
    d->off = malloc((fc + 1) * sizeof *d->off);
    for (size_t f = 0; f <= fc; f++)
        d->off[f] = off[fb + f] - off[fb];
    d->part = (mpi_write_part){d->vtxdist, k,      d->ids, d->pos, d->rgb,
                               fb,         fc,     d->off, idx + off[fb]};
}

static void free_part(part_data *d)
{
    free(d->ids);
    free(d->pos);
    free(d->rgb);
    free(d->off);
}

/* ------------------------------------------------------------ file checks */

static char *slurp_file(const char *path, size_t *n)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    fseek(f, 0, SEEK_END);
    long len = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *b = malloc((size_t)len + 1);
    *n = fread(b, 1, (size_t)len, f);
    fclose(f);
    return b;
}

/* Rank 0: temporary files left in dir. */
static int leftovers(void)
{
    DIR *d = opendir(dir);
    int n = 0;
    struct dirent *e;
    while (d && (e = readdir(d)))
        n += strstr(e->d_name, ".limn-tmp.") != NULL;
    if (d)
        closedir(d);
    return n;
}

/* Every rank got rank 0's status and message. */
static void check_agreed(limn_context *ctx, limn_status st, const char *what)
{
    char msg[1024], root_msg[1024];
    snprintf(msg, sizeof msg, "%s", limn_context_message(ctx));
    memcpy(root_msg, msg, sizeof msg);
    int root_st = (int)st;
    MPI_Bcast(&root_st, 1, MPI_INT, 0, MPI_COMM_WORLD);
    MPI_Bcast(root_msg, sizeof root_msg, MPI_CHAR, 0, MPI_COMM_WORLD);
    CHECK((int)st == root_st && strcmp(msg, root_msg) == 0,
          "%s: status %d '%s' but rank 0 has %d '%s'", what, (int)st, msg, root_st, root_msg);
}

/* ------------------------------------------------------------------ cases */

typedef struct format_case {
    const char *ext;
    limn_format format;
    int single;
} format_case;

static const format_case formats[] = {
    {"obj", LIMN_FORMAT_OBJ, 0},          {"off", LIMN_FORMAT_OFF, 0},
    {"ply", LIMN_FORMAT_PLY, 0},          {"ply", LIMN_FORMAT_PLY, 1},
    {"ply", LIMN_FORMAT_PLY_BINARY_BE, 0}, {"ply", LIMN_FORMAT_PLY_BINARY_BE, 1},
    {"ply", LIMN_FORMAT_PLY_ASCII, 0},    {"ply", LIMN_FORMAT_PLY_ASCII, 1},
    {"stl", LIMN_FORMAT_STL, 0},
};

/* One mesh in every format: the parallel file against limn_mesh_write's. */
static void same_bytes(limn_context *ctx, const char *name, const limn_mesh *m)
{
    part_data d;
    make_part(m, &d, 0);
    for (size_t k = 0; k < sizeof formats / sizeof *formats; k++) {
        const format_case *fc = &formats[k];
        char ref[512], out[512];
        snprintf(ref, sizeof ref, "%s/ref.%s", dir, fc->ext);
        snprintf(out, sizeof out, "%s/out.%s", dir, fc->ext);
        limn_write_options o;
        limn_write_options_default(&o);
        o.precision = fc->single ? LIMN_OUTPUT_FLOAT : LIMN_OUTPUT_DOUBLE;
        limn_status one = LIMN_OK;
        if (rank == 0)
            one = limn_mesh_write_with(ctx, m, ref, fc->format, &o, NULL);
        MPI_Bcast(&one, 1, MPI_INT, 0, MPI_COMM_WORLD);
        limn_status st =
            mpi_write_mesh_part(ctx, MPI_COMM_WORLD, out, fc->format, &o, &d.part, NULL);
        check_agreed(ctx, st, name);
        CHECK(st == one, "%s, format %d single %d: status %d, single process %d (%s)", name,
              (int)fc->format, fc->single, (int)st, (int)one, limn_context_message(ctx));
        if (rank == 0 && !st && !one) {
            size_t na = 0, nb = 0;
            char *a = slurp_file(ref, &na), *b = slurp_file(out, &nb);
            CHECK(a && b && na == nb && memcmp(a, b, na) == 0,
                  "%s, format %d single %d: %zu bytes, the single process wrote %zu%s", name,
                  (int)fc->format, fc->single, nb, na,
                  na == nb ? " (same size, other bytes)" : "");
            free(a);
            free(b);
            CHECK(leftovers() == 0, "%s: a temporary file was left", name);
            unlink(ref);
            unlink(out);
        }
        MPI_Barrier(MPI_COMM_WORLD);
    }
    free_part(&d);
}

static void case_mesh(limn_context *ctx, const char *name, limn_mesh *m)
{
    if (!m) {
        CHECK(0, "%s: no mesh", name);
        return;
    }
    same_bytes(ctx, name, m);
    limn_mesh_destroy(m);
}

/* ---------------------------------------------------------------- failures */

/* Writes "old" to path (rank 0) */
static void old_file(const char *path)
{
    if (rank == 0)
        test_write_text(path, "old");
    MPI_Barrier(MPI_COMM_WORLD);
}

static void check_old(const char *path, const char *what)
{
    if (rank != 0)
        return;
    size_t n = 0;
    char *b = slurp_file(path, &n);
    CHECK(b && n == 3 && memcmp(b, "old", 3) == 0, "%s: the target was changed", what);
    free(b);
    CHECK(leftovers() == 0, "%s: a temporary file was left", what);
}

/* Rank 0's limn_mesh_write of m to path: its status and message on every rank. */
static limn_status single_write(limn_context *ctx, const limn_mesh *m, const char *path,
                                char *msg, size_t cap)
{
    int one = LIMN_OK;
    msg[0] = '\0';
    if (rank == 0) {
        one = (int)limn_mesh_write(ctx, m, path, LIMN_FORMAT_AUTO);
        snprintf(msg, cap, "%s", limn_context_message(ctx));
    }
    MPI_Bcast(&one, 1, MPI_INT, 0, MPI_COMM_WORLD);
    MPI_Bcast(msg, (int)cap, MPI_CHAR, 0, MPI_COMM_WORLD);
    return (limn_status)one;
}

/* m with vertex v set to value (every rank the same). */
static limn_mesh *with_value(limn_context *ctx, const limn_mesh *m, size_t v, double value)
{
    limn_mesh *c = NULL;
    limn_mesh_create(ctx, limn_mesh_vertex_count(m), limn_mesh_positions(m),
                     limn_mesh_face_count(m), limn_mesh_face_offsets(m),
                     limn_mesh_face_indices(m), &c);
    double *p = limn_mesh_positions_mutable(c);
    p[3 * v + 1] = value;
    return c;
}

/* A failure found on one rank only (its block's vertex): the single
   process's status and message on every rank, nothing written. */
static void bad_value(limn_context *ctx, const limn_mesh *m, const char *ext, double value,
                      const char *what)
{
    part_data d0;
    make_part(m, &d0, 0);
    size_t v = d0.vtxdist[size - 1]; /* the last block's first vertex */
    free_part(&d0);
    limn_mesh *bad = with_value(ctx, m, v, value);
    char path[512];
    snprintf(path, sizeof path, "%s/keep.%s", dir, ext);
    old_file(path);
    char one_msg[1024];
    limn_status one = single_write(ctx, bad, path, one_msg, sizeof one_msg);
    part_data d;
    make_part(bad, &d, 0);
    limn_status st = mpi_write_mesh(ctx, MPI_COMM_WORLD, path, NULL, d.vtxdist, d.part.n_owned,
                                    d.ids, d.pos, d.part.face_begin, d.part.face_count, d.off,
                                    d.part.face_indices);
    CHECK(one != LIMN_OK && st == one && strcmp(limn_context_message(ctx), one_msg) == 0,
          "%s: status %d '%s', the single process %d '%s'", what, (int)st,
          limn_context_message(ctx), (int)one, one_msg);
    check_old(path, what);
    free_part(&d);
    limn_mesh_destroy(bad);
}

/* A path whose parent is a regular file: the single process's message. */
static void parent_is_file(limn_context *ctx, const limn_mesh *m)
{
    char parent[512], path[600];
    snprintf(parent, sizeof parent, "%s/afile", dir);
    snprintf(path, sizeof path, "%s/out.ply", parent);
    old_file(parent);
    char one_msg[1024];
    limn_status one = single_write(ctx, m, path, one_msg, sizeof one_msg);
    part_data d;
    make_part(m, &d, 0);
    limn_status st = mpi_write_mesh_part(ctx, MPI_COMM_WORLD, path, LIMN_FORMAT_AUTO, NULL,
                                         &d.part, NULL);
    CHECK(one != LIMN_OK && st == one && strcmp(limn_context_message(ctx), one_msg) == 0,
          "parent is a file: status %d '%s', the single process %d '%s'", (int)st,
          limn_context_message(ctx), (int)one, one_msg);
    check_old(parent, "parent is a file");
    free_part(&d);
    if (rank == 0)
        unlink(parent);
}

/* Vertex 0 owned by two ranks: refused on every rank, nothing written. */
static void owned_twice(limn_context *ctx, const limn_mesh *m)
{
    char path[512];
    snprintf(path, sizeof path, "%s/twice.obj", dir);
    old_file(path);
    part_data d;
    make_part(m, &d, 1);
    limn_status st = mpi_write_mesh_part(ctx, MPI_COMM_WORLD, path, LIMN_FORMAT_AUTO, NULL,
                                         &d.part, NULL);
    check_agreed(ctx, st, "owned twice");
    CHECK(st == LIMN_ERR_ARGUMENT &&
              strstr(limn_context_message(ctx), "vertex 0 is owned by more than one rank"),
          "owned twice: status %d '%s'", (int)st, limn_context_message(ctx));
    check_old(path, "owned twice");
    free_part(&d);
}

/* A corner past every rank's vertices in the middle of the last rank's face
   block: every rank names that face (its number in the whole mesh), nothing
   written. */
static void index_past_end(limn_context *ctx, const limn_mesh *m)
{
    char path[512];
    snprintf(path, sizeof path, "%s/index.obj", dir);
    old_file(path);
    part_data d;
    make_part(m, &d, 0);
    size_t fc = d.part.face_count, corners = fc ? d.off[fc] : 0;
    uint32_t *idx = malloc((corners + 1) * sizeof *idx);
    memcpy(idx, d.part.face_indices, corners * sizeof *idx);
    size_t last = d.fdist[size] - d.fdist[size - 1]; /* the last rank's face count */
    size_t total = d.vtxdist[size], face = d.fdist[size - 1] + last / 2;
    if (rank == size - 1 && fc)
        idx[d.off[fc / 2] + 1] = (uint32_t)total + 5;
    d.part.face_indices = idx;
    limn_status st = mpi_write_mesh_part(ctx, MPI_COMM_WORLD, path, LIMN_FORMAT_AUTO, NULL,
                                         &d.part, NULL);
    check_agreed(ctx, st, "index past the end");
    char want[128];
    snprintf(want, sizeof want, "face %zu uses vertex %zu, past the mesh's %zu vertices", face,
             total + 5, total);
    CHECK(st == LIMN_ERR_ARGUMENT && strstr(limn_context_message(ctx), want),
          "index past the end: status %d '%s', wanted '%s'", (int)st, limn_context_message(ctx),
          want);
    check_old(path, "index past the end");
    free(idx);
    free_part(&d);
}

/* A full disk for some ranks: their processes may write files of at most 64
   bytes (RLIMIT_FSIZE; write() fails with EFBIG). Which ranks write in a
   collective write is the MPI-IO library's choice (Open MPI's two-phase
   components let a few aggregators write everyone's bytes), so by default
   every rank is limited (Open MPI 4.1's vulcan then loses the failed write
   without an error: the writer finds the file short); with Open MPI's own OMPI_MCA_fcoll=individual
   (every rank writes its own bytes: test_mpi_write_np3_individual) only the
   last rank is, a failure on that rank alone. Either way: the same status
   and message on every rank, the target untouched, nothing left. */
static void file_size_limit(limn_context *ctx, const limn_mesh *m)
{
    const char *fcoll = getenv("OMPI_MCA_fcoll");
    char lib[MPI_MAX_LIBRARY_VERSION_STRING];
    int len = 0;
    MPI_Get_library_version(lib, &len);
    int one_rank = fcoll && strcmp(fcoll, "individual") == 0 && strstr(lib, "Open MPI");
    int limited = !one_rank || rank == size - 1;
    char path[512];
    snprintf(path, sizeof path, "%s/limited.ply", dir);
    old_file(path);
    struct rlimit saved, low;
    getrlimit(RLIMIT_FSIZE, &saved);
    if (limited) {
        signal(SIGXFSZ, SIG_IGN); /* write() fails with EFBIG instead */
        low = saved;
        low.rlim_cur = 64;
        setrlimit(RLIMIT_FSIZE, &low);
    }
    part_data d;
    make_part(m, &d, 0);
    limn_status st = mpi_write_mesh_part(ctx, MPI_COMM_WORLD, path, LIMN_FORMAT_PLY_ASCII, NULL,
                                         &d.part, NULL);
    if (limited)
        setrlimit(RLIMIT_FSIZE, &saved);
    check_agreed(ctx, st, "file size limit");
    CHECK(st == LIMN_ERR_IO && strstr(limn_context_message(ctx), "cannot write"),
          "file size limit (%s): status %d '%s'", one_rank ? "last rank" : "every rank", (int)st,
          limn_context_message(ctx));
    if (one_rank && size > 1) {
        char own[32];
        snprintf(own, sizeof own, "(rank %d)", size - 1);
        CHECK(strstr(limn_context_message(ctx), own) != NULL,
              "file size limit on the last rank: the message is not that rank's: %s",
              limn_context_message(ctx));
    }
    if (rank == 0)
        printf("  file size limit on %s: %s\n", one_rank ? "the last rank" : "every rank",
               limn_context_message(ctx));
    check_old(path, "file size limit");
    free_part(&d);
}

/* /dev/null (a character device: bytes through rank 0, left a device) and a
   symlink (the file it names replaced, the link kept). */
static void special_targets(limn_context *ctx, const limn_mesh *m)
{
    part_data d;
    make_part(m, &d, 0);
    limn_status st = mpi_write_mesh_part(ctx, MPI_COMM_WORLD, "/dev/null", LIMN_FORMAT_PLY,
                                         NULL, &d.part, NULL);
    struct stat sb;
    CHECK(st == LIMN_OK && stat("/dev/null", &sb) == 0 && S_ISCHR(sb.st_mode),
          "/dev/null: status %d '%s'", (int)st, limn_context_message(ctx));
    char target[512], link[512], ref[512];
    snprintf(target, sizeof target, "%s/target.off", dir);
    snprintf(link, sizeof link, "%s/link.off", dir);
    snprintf(ref, sizeof ref, "%s/ref.off", dir);
    old_file(target);
    if (rank == 0) {
        CHECK(symlink("target.off", link) == 0, "symlink");
        CHECK(limn_mesh_write(ctx, m, ref, LIMN_FORMAT_AUTO) == LIMN_OK, "reference");
    }
    MPI_Barrier(MPI_COMM_WORLD);
    st = mpi_write_mesh_part(ctx, MPI_COMM_WORLD, link, LIMN_FORMAT_AUTO, NULL, &d.part, NULL);
    CHECK(st == LIMN_OK, "symlink: status %d '%s'", (int)st, limn_context_message(ctx));
    if (rank == 0) {
        size_t na = 0, nb = 0;
        char *a = slurp_file(ref, &na), *b = slurp_file(target, &nb);
        CHECK(lstat(link, &sb) == 0 && S_ISLNK(sb.st_mode), "the symlink was replaced");
        CHECK(a && b && na == nb && memcmp(a, b, na) == 0, "symlink: the target's bytes");
        free(a);
        free(b);
        unlink(link);
        unlink(target);
        unlink(ref);
    }
    free_part(&d);
}

/* A FIFO: its reader (a thread of rank 0) gets the single process's bytes,
   the FIFO stays a FIFO. */
typedef struct fifo_reader {
    const char *path;
    char *bytes;
    size_t n;
} fifo_reader;

static void *read_fifo(void *arg)
{
    fifo_reader *r = arg;
    FILE *f = fopen(r->path, "rb"); /* waits for the writer */
    r->bytes = f ? test_read_stream(f, &r->n) : NULL;
    if (f)
        fclose(f);
    return NULL;
}

static void fifo_target(limn_context *ctx, const limn_mesh *m)
{
    char fifo[512], ref[512];
    snprintf(fifo, sizeof fifo, "%s/pipe.ply", dir);
    snprintf(ref, sizeof ref, "%s/ref_pipe.ply", dir);
    fifo_reader r = {fifo, NULL, 0};
    pthread_t reader;
    int ok = 1;
    if (rank == 0) {
        ok = mkfifo(fifo, 0600) == 0 &&
             limn_mesh_write(ctx, m, ref, LIMN_FORMAT_AUTO) == LIMN_OK &&
             pthread_create(&reader, NULL, read_fifo, &r) == 0;
        CHECK(ok, "FIFO set-up");
    }
    MPI_Bcast(&ok, 1, MPI_INT, 0, MPI_COMM_WORLD);
    if (!ok)
        return;
    part_data d;
    make_part(m, &d, 0);
    limn_status st = mpi_write_mesh_part(ctx, MPI_COMM_WORLD, fifo, LIMN_FORMAT_AUTO, NULL,
                                         &d.part, NULL);
    CHECK(st == LIMN_OK, "FIFO: status %d '%s'", (int)st, limn_context_message(ctx));
    if (rank == 0) {
        if (st) { /* nothing was written: let the reader go */
            FILE *unblock = fopen(fifo, "wb");
            if (unblock)
                fclose(unblock);
        }
        pthread_join(reader, NULL);
        size_t n = 0;
        char *a = slurp_file(ref, &n);
        struct stat sb;
        CHECK(a && r.bytes && r.n == n && memcmp(a, r.bytes, n) == 0,
              "FIFO: the reader got %zu bytes, the single process wrote %zu", r.n, n);
        CHECK(stat(fifo, &sb) == 0 && S_ISFIFO(sb.st_mode), "the FIFO is no longer a FIFO");
        free(a);
        free(r.bytes);
        unlink(fifo);
        unlink(ref);
    }
    free_part(&d);
}

/* ------------------------------------------------------------------- main */

static limn_mesh *triangle(limn_context *ctx)
{
    const double pos[9] = {0, 0, 0, 1, 0, 0.5, 0, 1, -0.25};
    const uint32_t off[2] = {0, 3}, idx[3] = {0, 1, 2};
    limn_mesh *m = NULL;
    limn_mesh_create(ctx, 3, pos, 1, off, idx, &m);
    return m;
}

static void shared_meshes(limn_context *ctx)
{
    static const char *real[] = {"small/suzanne.obj", "small/bun_zipper_res4.ply",
                                 "small/fandisk_quads.off", "small/cow.obj",
                                 "opensubdiv/catmark_nonman_edges.obj"};
    int shared = test_shared_meshes() != NULL;
    int all = 0;
    MPI_Allreduce(&shared, &all, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    for (size_t k = 0; all && k < sizeof real / sizeof *real; k++) {
        limn_mesh *m = NULL;
        int ok = limn_mesh_read(ctx, test_shared_path(real[k]), LIMN_FORMAT_AUTO, &m) == LIMN_OK,
            every = 0;
        MPI_Allreduce(&ok, &every, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
        if (every)
            same_bytes(ctx, real[k], m);
        else if (rank == 0)
            printf("  (%s not read: %s)\n", real[k], limn_context_message(ctx));
        limn_mesh_destroy(m);
    }
    if (!all && rank == 0)
        printf("  (shared meshes not found: generated meshes only)\n");
}

int main(int argc, char **argv)
{
    MPI_Init(&argc, &argv);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    limn_context *ctx = limn_context_create();
    if (rank == 0) {
        snprintf(dir, sizeof dir, "%s/limn_mpi_write.XXXXXX",
                 getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp");
        if (!mkdtemp(dir))
            dir[0] = '\0';
    }
    MPI_Bcast(dir, sizeof dir, MPI_CHAR, 0, MPI_COMM_WORLD);
    if (!ctx || !dir[0] || size > 64) {
        fprintf(stderr, "test_mpi_write: no context or temporary directory\n");
        MPI_Abort(MPI_COMM_WORLD, 1);
    }
    case_mesh(ctx, "grid 30x20 quads", test_mesh_grid(ctx, 30, 20, 0));
    case_mesh(ctx, "grid 17x9 triangles", test_mesh_grid(ctx, 17, 9, 1));
    case_mesh(ctx, "icosahedron", test_mesh_icosahedron(ctx));
    case_mesh(ctx, "pyramid", test_mesh_pyramid(ctx));
    case_mesh(ctx, "n-gons", ngons(ctx));
    case_mesh(ctx, "coloured grid", colored(ctx, test_mesh_grid(ctx, 12, 7, 0)));
    case_mesh(ctx, "coloured n-gons", colored(ctx, ngons(ctx)));
    case_mesh(ctx, "one triangle", triangle(ctx));
    shared_meshes(ctx);

    limn_mesh *grid = test_mesh_grid(ctx, 20, 10, 0);
    parent_is_file(ctx, grid);
    bad_value(ctx, grid, "ply", NAN, "non-finite position on the last rank");
    bad_value(ctx, grid, "stl", 1e300, "STL float overflow on the last rank");
    owned_twice(ctx, grid);
    index_past_end(ctx, grid);
    file_size_limit(ctx, grid);
    special_targets(ctx, grid);
    fifo_target(ctx, grid);
    limn_mesh_destroy(grid);

    int total = 0;
    MPI_Allreduce(&failures, &total, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
    if (rank == 0) {
        rmdir(dir);
        printf("test_mpi_write (%d ranks): %d checks on rank 0, %d failures on all ranks\n", size,
               checks, total);
    }
    limn_context_destroy(ctx);
    MPI_Finalize();
    return total ? 1 : 0;
}
