/* SPDX-License-Identifier: MIT */
/*
 * The space-filling-curve partition (host/mpi/mpi_sfc.c) under mpirun with
 * 1, 2, 3 and 5 ranks (tests/CMakeLists.txt). Asserted:
 *   - the Hilbert key: on the 2^k-cube (k = 1..4) the keys are 0 .. 8^k - 1,
 *     each once, and cells of consecutive keys are face neighbours (the
 *     curve's defining property, checked by brute force); so on aligned
 *     16-cubes far from the origin (the high bits) and the largest cell;
 *   - the parts, for 1, 4, 7 parts and as many as ranks, on two vertex
 *     distributions (even blocks; uneven ones with empty blocks): every
 *     vertex gets exactly one part, and it is the one a serial route gives
 *     (rank 0 quantizes the gathered positions, sorts (key, id) with qsort
 *     and cuts the sorted list into parts of n (q + 1) / P - n q / P): so
 *     every part has its exact share (largest - smallest <= 1 vertex), and
 *     the parts do not depend on the distribution nor on the call;
 *   - the edge cut (rank 0, the whole mesh) within CUT_FACTOR of METIS's on
 *     meshes of 1,000 vertices or more;
 *   - refusals on every rank with one message: 0 parts; a bad
 *     LIMN_MPI_PARTITION or limn_mpi_options.partition; the option wins over
 *     the environment.
 * Point sets: a triangle grid, 5,000 pseudo-random points with repeated
 * positions and non-finite coordinates, 37 copies of one point (no extent:
 * the ids decide), 3 points in 7 parts, no points; shared meshes when
 * ../shared/meshes is there.
 */
#include "mpi_check.h"
#include "support.h"

#include "mpi/mpi_part.h"
#include "mpi/mpi_sfc.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Measured with 1, 2, 3 and 5 ranks: the curve's cut is 1.45-3.3x METIS's on
   the meshes of 1,000 vertices or more (3.3x: small/horse_quad.obj, 2 parts:
   132 edges against 40), up to 3.4x on the 507 vertices of small/suzanne.obj;
   a cut, not a result: the rows, and so the bytes, do not depend on it. */
#define CUT_FACTOR 3.5

MPI_CHECK_STATE;

/* The cube of side 2^k at corner o (a multiple of 2^k on each axis): its
   keys are 8^k consecutive values, each once, consecutive ones at
   neighbouring cells, as an aligned sub-cube of a Hilbert curve is. */
static void hilbert_cube(int k, const uint32_t o[3])
{
    uint32_t side = 1u << k;
    size_t cells = (size_t)side * side * side, bad = 0;
    uint64_t low = UINT64_MAX;
    for (uint32_t x = 0; x < side; x++)
        for (uint32_t y = 0; y < side; y++)
            for (uint32_t z = 0; z < side; z++) {
                uint64_t key = mpi_sfc_hilbert(o[0] + x, o[1] + y, o[2] + z);
                low = key < low ? key : low;
            }
    uint32_t(*at)[3] = malloc(cells * sizeof *at);
    unsigned char *seen = calloc(cells, 1);
    for (uint32_t x = 0; x < side; x++)
        for (uint32_t y = 0; y < side; y++)
            for (uint32_t z = 0; z < side; z++) {
                uint64_t key = mpi_sfc_hilbert(o[0] + x, o[1] + y, o[2] + z) - low;
                if (key >= cells || seen[key]++) {
                    bad++;
                    continue;
                }
                at[key][0] = x;
                at[key][1] = y;
                at[key][2] = z;
            }
    CHECK(!bad, "Hilbert, side %u at %u %u %u: %zu keys out of range or repeated", side, o[0],
          o[1], o[2], bad);
    for (size_t i = 1; !bad && i < cells; i++) {
        long d = 0;
        for (int a = 0; a < 3; a++)
            d += labs((long)at[i][a] - (long)at[i - 1][a]);
        bad += d != 1;
    }
    CHECK(!bad, "Hilbert, side %u at %u %u %u: %zu steps between cells that are not neighbours",
          side, o[0], o[1], o[2], bad);
    CHECK(o[0] || o[1] || o[2] || low == 0, "Hilbert: the origin's cube starts at %llu",
          (unsigned long long)low);
    free(at);
    free(seen);
}

static void hilbert_curve(void)
{
    const uint32_t origin[3] = {0, 0, 0};
    for (int k = 1; k <= 4; k++)
        hilbert_cube(k, origin);
    /* high bits: cubes far from the origin, up to the largest cell */
    const uint32_t far[3][3] = {{0x155550, 0x0aaaa0, 0x1ffff0},
                                {0x100000, 0x000000, 0x0fff00},
                                {0x1ffff0, 0x1ffff0, 0x1ffff0}};
    for (int c = 0; c < 3; c++)
        hilbert_cube(4, far[c]);
    const uint32_t big[3] = {0x0c0000, 0x1c0000, 0x040000}; /* side 2^18: the top 3 bits */
    uint64_t a = mpi_sfc_hilbert(big[0], big[1], big[2]);
    uint64_t b = mpi_sfc_hilbert(big[0] + 0x3ffff, big[1] + 0x3ffff, big[2] + 0x3ffff);
    CHECK(a >> 54 == b >> 54, "Hilbert: one top-level octant spans two key ranges");
    uint32_t top = (1u << 21) - 1;
    CHECK(mpi_sfc_hilbert(top, top, top) < (uint64_t)1 << 63, "Hilbert: more than 63 bits");
}

/* The partition's table-driven keys (mpi_sfc_hilbert_table) against
   Skilling's transform (mpi_sfc_hilbert) on every cell of a small cube at
   the origin and at the top corner, and on 2e6 random cells (xorshift,
   fixed seed), a quarter of them with small x (long runs of zero bits);
   the four-wide keys (mpi_sfc_hilbert_table4) against the single ones on
   4 cells around each random one. */
static void hilbert_table(void)
{
    mpi_sfc_table t;
    mpi_sfc_table_init(&t);
    size_t bad = 0, tried = 0;
    uint32_t first[3] = {0, 0, 0};
    const uint32_t top = (1u << 21) - 1;
    for (uint32_t x = 0; x < 16; x++)
        for (uint32_t y = 0; y < 16; y++)
            for (uint32_t z = 0; z < 16; z++)
                for (int corner = 0; corner < 2; corner++) {
                    uint32_t q[3] = {corner ? top - x : x, corner ? top - y : y,
                                     corner ? top - z : z};
                    int differ = mpi_sfc_hilbert(q[0], q[1], q[2]) !=
                                 mpi_sfc_hilbert_table(&t, q[0], q[1], q[2]);
                    if (differ && !bad++)
                        memcpy(first, q, sizeof q);
                    tried++;
                }
    uint64_t r = 88172645463325252ull;
    for (size_t i = 0; i < 2000000; i++, tried++) {
        r ^= r << 13;
        r ^= r >> 7;
        r ^= r << 17;
        uint32_t q[3] = {(uint32_t)r & top, (uint32_t)(r >> 21) & top, (uint32_t)(r >> 42) & top};
        if (i % 4 == 1)
            q[0] &= 0xffu;
        int differ =
            mpi_sfc_hilbert(q[0], q[1], q[2]) != mpi_sfc_hilbert_table(&t, q[0], q[1], q[2]);
        if (differ && !bad++)
            memcpy(first, q, sizeof q);
        /* the four-wide keys: this cell in lane 0, lanes 1-3 cells 977 apart
           along x from it (wrapping within the grid) */
        uint32_t cell[12];
        uint64_t key[4];
        for (int j = 0; j < 4; j++) {
            cell[3 * j] = (q[0] + (uint32_t)j * 977u) & top;
            cell[3 * j + 1] = q[1];
            cell[3 * j + 2] = q[2];
        }
        mpi_sfc_hilbert_table4(&t, cell, key);
        for (int j = 0; j < 4; j++) {
            const uint32_t *c = cell + 3 * j;
            differ = key[j] != mpi_sfc_hilbert_table(&t, c[0], c[1], c[2]);
            if (differ && !bad++)
                memcpy(first, c, sizeof first);
        }
    }
    CHECK(bad == 0,
          "Hilbert table: %zu of %zu keys differ from mpi_sfc_hilbert (first at %u %u %u)", bad,
          tried, first[0], first[1], first[2]);
}

/* Even blocks (uneven = 0) or a share growing with the rank, rank 0 empty. */
static void blocks(size_t n, int uneven, size_t *dist)
{
    size_t weight = 0;
    for (int r = 0; r < size; r++)
        weight += uneven ? (size_t)r : 1;
    dist[0] = 0;
    for (int r = 0, acc = 0; r < size; r++) {
        acc += uneven ? r : 1;
        dist[r + 1] = weight ? n * (size_t)acc / weight : n;
    }
}

/* The parts of all n vertices, gathered on every rank in id order. */
static uint32_t *partition_all(mpi_part *p, const double *pos, size_t n, const size_t *dist,
                               int parts, mpi_sfc_stats *st)
{
    uint32_t *mine = NULL, *all = malloc((n + 1) * sizeof *all);
    limn_status s = mpi_sfc_partition(p, dist, pos + 3 * dist[rank], parts, &mine, st);
    CHECK(s == LIMN_OK, "partition: %s", limn_context_message(p->ctx));
    if (s) {
        free(all);
        return NULL;
    }
    int *cnt = malloc(2 * (size_t)size * sizeof *cnt), *disp = cnt + size;
    for (int r = 0; r < size; r++) {
        cnt[r] = (int)(dist[r + 1] - dist[r]);
        disp[r] = (int)dist[r];
    }
    MPI_Allgatherv(mine, cnt[rank], MPI_UINT32_T, all, cnt, disp, MPI_UINT32_T, MPI_COMM_WORLD);
    free(cnt);
    free(mine);
    return all;
}

typedef struct keyed {
    uint64_t key;
    size_t id;
} keyed;

static int cmp_keyed(const void *a, const void *b)
{
    const keyed *x = a, *y = b;
    if (x->key != y->key)
        return x->key < y->key ? -1 : 1;
    return x->id < y->id ? -1 : x->id > y->id;
}

/* The serial route: the bounding cube, keys, qsort, exact shares. */
static uint32_t *serial_parts(const double *pos, size_t n, int parts)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t v = 0; v < 3 * n; v++)
        if (isfinite(pos[v])) {
            lo[v % 3] = fmin(lo[v % 3], pos[v]);
            hi[v % 3] = fmax(hi[v % 3], pos[v]);
        }
    double ext = 0;
    for (int a = 0; a < 3; a++)
        ext = isfinite(lo[a]) ? fmax(ext, hi[a] - lo[a]) : ext;
    double cells = (double)((1u << 21) - 1), scale = ext > 0 ? cells / ext : 0;
    keyed *k = malloc((n + 1) * sizeof *k);
    for (size_t v = 0; v < n; v++) {
        uint32_t q[3];
        for (int a = 0; a < 3; a++) {
            double t = (pos[3 * v + a] - (isfinite(lo[a]) ? lo[a] : 0)) * scale;
            q[a] = !(t > 0) ? 0 : t >= cells ? (uint32_t)cells : (uint32_t)t;
        }
        k[v] = (keyed){mpi_sfc_hilbert(q[0], q[1], q[2]), v};
    }
    qsort(k, n, sizeof *k, cmp_keyed);
    uint32_t *part = malloc((n + 1) * sizeof *part);
    for (size_t i = 0, q = 0; i < n; i++) {
        while (q + 1 < (size_t)parts && n * (q + 1) / (size_t)parts <= i)
            q++;
        part[k[i].id] = (uint32_t)q;
    }
    free(k);
    return part;
}

/* Edges of the faces with ends in different parts (each edge once). */
static size_t edge_cut(limn_context *ctx, const limn_mesh *m, int parts, const uint32_t *part)
{
    size_t cut = 0;
    CHECK(mpi_edge_cut(ctx, m, parts, part, &cut) == LIMN_OK, "edge cut: %s",
          limn_context_message(ctx));
    return cut;
}

static void one_case(mpi_part *p, const char *name, const double *pos, size_t n,
                     const limn_mesh *mesh, int parts)
{
    size_t dist[2][64];
    blocks(n, 0, dist[0]);
    blocks(n, 1, dist[1]);
    mpi_sfc_stats s1, s2, s3;
    uint32_t *a = partition_all(p, pos, n, dist[0], parts, &s1);
    uint32_t *b = partition_all(p, pos, n, dist[0], parts, &s2);
    uint32_t *c = partition_all(p, pos, n, dist[1], parts, &s3);
    if (!a || !b || !c)
        goto done;
    CHECK(!memcmp(a, b, n * sizeof *a), "%s, %d parts: a second call differs", name, parts);
    CHECK(!memcmp(a, c, n * sizeof *a), "%s, %d parts: other blocks, other parts", name, parts);
    uint32_t *want = serial_parts(pos, n, parts);
    size_t differ = 0;
    for (size_t v = 0; v < n; v++)
        differ += a[v] != want[v];
    CHECK(!differ, "%s, %d parts: %zu vertices differ from the serial route", name, parts,
          differ);
    free(want);
    size_t small = n / (size_t)parts, large = small + (n % (size_t)parts != 0);
    CHECK(s1.part_max == large && s1.part_min == small,
          "%s, %d parts: parts of %zu..%zu vertices, want %zu..%zu", name, parts, s1.part_min,
          s1.part_max, small, large);
    if (rank == 0 && mesh) {
        size_t cut = edge_cut(p->ctx, mesh, parts, a), mc = 0;
        uint32_t *mp = malloc((n + 1) * sizeof *mp);
        CHECK(mpi_partition(p->ctx, mesh, parts, mp, &mc) == LIMN_OK, "METIS: %s",
              limn_context_message(p->ctx));
        CHECK(n < 1000 || (double)cut <= CUT_FACTOR * (double)mc,
              "%s, %d parts: cut %zu against METIS's %zu", name, parts, cut, mc);
        printf("  %-36s %2d parts: %7zu vertices, cut %6zu (METIS %6zu, %.2fx), "
               "imbalance %.3f, %.3f s\n",
               name, parts, n, cut, mc, mc ? (double)cut / (double)mc : 0.0, s1.imbalance,
               s1.seconds);
        free(mp);
    }
done:
    free(a);
    free(b);
    free(c);
}

static void cases(mpi_part *p, const char *name, const double *pos, size_t n,
                  const limn_mesh *mesh)
{
    int list[] = {1, size, 4, 7};
    for (int k = 0; k < 4; k++) {
        int dup = 0;
        for (int j = 0; j < k; j++)
            dup |= list[j] == list[k];
        if (!dup)
            one_case(p, name, pos, n, mesh, list[k]);
    }
}

static void point_sets(mpi_part *p)
{
    limn_mesh *grid = test_mesh_grid(p->ctx, 40, 30, 1);
    cases(p, "triangle grid 40 x 30", limn_mesh_positions(grid), limn_mesh_vertex_count(grid),
          grid);
    limn_mesh_destroy(grid);
    size_t n = 5000;
    double *pos = malloc(3 * n * sizeof *pos);
    unsigned long long s = 12345;
    for (size_t i = 0; i < 3 * n; i++) {
        s = s * 6364136223846793005ULL + 1442695040888963407ULL;
        pos[i] = (double)(s >> 11) * 0x1p-53 * 20.0 - 7.0;
    }
    for (size_t v = 100; v < 200; v++) /* repeated positions: the ids decide */
        memcpy(pos + 3 * v, pos + 3 * 50, 3 * sizeof *pos);
    pos[3 * 7] = NAN;
    pos[3 * 8 + 1] = INFINITY;
    pos[3 * 9 + 2] = -INFINITY;
    cases(p, "5,000 random points", pos, n, NULL);
    for (size_t i = 0; i < 3 * 37; i++)
        pos[i] = 1.5;
    cases(p, "37 copies of one point", pos, 37, NULL);
    cases(p, "3 points", pos + 3 * 200, 3, NULL);
    cases(p, "no points", pos, 0, NULL);
    free(pos);
}

static void shared_meshes(mpi_part *p)
{
    static const char *paths[] = {"small/suzanne.obj", "small/horse_quad.obj",
                                  "medium/bun_zipper.ply"};
    int have = test_shared_meshes() != NULL;
    MPI_Allreduce(MPI_IN_PLACE, &have, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    if (!have && rank == 0)
        printf("  (shared meshes not found: generated point sets only)\n");
    for (size_t k = 0; have && k < sizeof paths / sizeof *paths; k++) {
        limn_mesh *m = NULL;
        int ok = limn_mesh_read(p->ctx, test_shared_path(paths[k]), LIMN_FORMAT_AUTO, &m) ==
                 LIMN_OK;
        CHECK(ok, "%s: %s", paths[k], limn_context_message(p->ctx));
        MPI_Allreduce(MPI_IN_PLACE, &ok, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
        if (ok)
            cases(p, paths[k], limn_mesh_positions(m), limn_mesh_vertex_count(m), m);
        limn_mesh_destroy(m);
    }
}

/* Every rank got the status and the message rank 0 has. */
static void same_refusal(limn_context *ctx, limn_status s, const char *what, const char *words)
{
    char msg[2048];
    snprintf(msg, sizeof msg, "%s", limn_context_message(ctx));
    MPI_Bcast(msg, (int)sizeof msg, MPI_CHAR, 0, MPI_COMM_WORLD);
    CHECK(s == LIMN_ERR_ARGUMENT, "%s: status %d", what, (int)s);
    CHECK(!strcmp(msg, limn_context_message(ctx)) && strstr(msg, words),
          "%s: message \"%s\" (rank 0: \"%s\")", what, limn_context_message(ctx), msg);
}

/* The choice of partition: the option, else LIMN_MPI_PARTITION, else sfc. */
static int chosen(limn_context *ctx, const char *env, int option, limn_status *st)
{
    if (env)
        setenv("LIMN_MPI_PARTITION", env, 1);
    else
        unsetenv("LIMN_MPI_PARTITION");
    limn_mpi_options o;
    limn_mpi_options_default(&o);
    o.partition = option;
    mpi_part q;
    *st = mpi_part_begin(ctx, MPI_COMM_WORLD, &o, &q);
    int got = q.partition;
    mpi_part_end(&q);
    unsetenv("LIMN_MPI_PARTITION");
    return got;
}

static void refusals(mpi_part *p)
{
    size_t dist[64];
    blocks(10, 0, dist);
    double pos[30] = {0};
    uint32_t *part = (uint32_t *)pos;
    limn_status s = mpi_sfc_partition(p, dist, pos, 0, &part, NULL);
    same_refusal(p->ctx, s, "0 parts", "0 parts (needs >= 1)");
    CHECK(part == NULL, "0 parts: a result");
    limn_context *ctx = p->ctx;
    CHECK(chosen(ctx, NULL, LIMN_MPI_PARTITION_AUTO, &s) == LIMN_MPI_PARTITION_SFC && !s,
          "default: not sfc");
    CHECK(chosen(ctx, "scotch", LIMN_MPI_PARTITION_AUTO, &s) == LIMN_MPI_PARTITION_SCOTCH && !s,
          "LIMN_MPI_PARTITION=scotch: not scotch");
    CHECK(chosen(ctx, "sfc", LIMN_MPI_PARTITION_AUTO, &s) == LIMN_MPI_PARTITION_SFC && !s,
          "LIMN_MPI_PARTITION=sfc: not sfc");
    CHECK(chosen(ctx, "scotch", LIMN_MPI_PARTITION_SFC, &s) == LIMN_MPI_PARTITION_SFC && !s,
          "the option does not win over the environment");
    chosen(ctx, "metis", LIMN_MPI_PARTITION_AUTO, &s);
    same_refusal(ctx, s, "LIMN_MPI_PARTITION=metis", "LIMN_MPI_PARTITION is 'metis'");
    chosen(ctx, NULL, 9, &s);
    same_refusal(ctx, s, "partition 9", "limn_mpi_options.partition is 9");
    if (size > 1) { /* one rank told otherwise: refused on every rank */
        chosen(ctx, rank == size - 1 ? "scotch" : "sfc", LIMN_MPI_PARTITION_AUTO, &s);
        same_refusal(ctx, s, "ranks disagreeing", "the ranks chose different partitions");
    }
}

int main(int argc, char **argv)
{
    MPI_Init(&argc, &argv);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    limn_context *ctx = limn_context_create();
    mpi_part p;
    int ok = size < 64 && mpi_part_begin(ctx, MPI_COMM_WORLD, NULL, &p) == LIMN_OK;
    CHECK(ok, "mpi_part_begin: %s (at most 63 ranks here)", limn_context_message(ctx));
    if (ok) {
        hilbert_curve();
        hilbert_table();
        point_sets(&p);
        shared_meshes(&p);
        refusals(&p);
        mpi_part_end(&p);
    }
    limn_context_destroy(ctx);
    return mpi_check_finish("test_mpi_sfc", NULL, checks, failures);
}
