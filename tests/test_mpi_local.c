/* SPDX-License-Identifier: MIT */
/*
 * Local rows (host/mpi/mpi_local.c) against the root path (mpi_distribute),
 * run under mpirun with 1, 2, 3 and 5 ranks (tests/CMakeLists.txt). Both
 * build an mpi_part from the same partition (METIS on the repaired mesh,
 * computed on rank 0 and given to both): the root path from the whole
 * repaired mesh on rank 0, the local path from vertex blocks and uneven face
 * ranges of the unrepaired mesh (in rank order, and reversed), no rank
 * holding the whole of it. Asserted
 * equal: the global numbers (vertices, repaired faces, entries, edge cut,
 * scheme, alpha, diagonal), each rank's owned and ghost ids in order, the
 * four class bounds, rules and row scales, every row (columns mapped to
 * global ids) and its weights bit for bit, and the halo lists. Per-rank
 * memory: on 2 ranks or more no array the build allocates per vertex has the
 * mesh's vertex count (mpi_local_stats, counted where the build allocates).
 * Then a bad partition on one rank, blocks not starting at 0 and repair off
 * (the single process's message) reach every rank with one message.
 *
 * Not cmocka: a failed check on one rank must not leave the others waiting.
 */
#include "mpi_check.h"
#include "support.h"

#include "mpi/mpi_local.h"
#include "stencil/sgs_table.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

MPI_CHECK_STATE;

/* ------------------------------------------------------------------ meshes */

typedef struct builder {
    double *pos;
    uint32_t *off, *idx;
    size_t nv, nf, ni;
} builder;

static uint32_t add_vertex(builder *b, double x, double y, double z)
{
    b->pos = realloc(b->pos, 3 * (b->nv + 1) * sizeof *b->pos);
    b->pos[3 * b->nv] = x;
    b->pos[3 * b->nv + 1] = y;
    b->pos[3 * b->nv + 2] = z;
    return (uint32_t)b->nv++;
}

static void add_face(builder *b, const uint32_t *v, size_t d)
{
    b->off = realloc(b->off, (b->nf + 2) * sizeof *b->off);
    b->idx = realloc(b->idx, (b->ni + d) * sizeof *b->idx);
    b->off[0] = 0;
    memcpy(b->idx + b->ni, v, d * sizeof *v);
    b->ni += d;
    b->off[++b->nf] = (uint32_t)b->ni;
}

/* An nx x ny grid of cells at x offset dx (bumped in z), of quads, of
   triangles (tri), or of hexagons made of two quads with quads between (hex). */
static uint32_t add_grid(builder *b, int nx, int ny, int tri, int hex, double dx)
{
    uint32_t v0 = (uint32_t)b->nv;
    for (int j = 0; j <= ny; j++)
        for (int i = 0; i <= nx; i++)
            add_vertex(b, dx + i, j, 0.1 * sin(i * 0.7) * cos(j * 0.5));
    for (int j = 0; j < ny; j++)
        for (int i = 0; i < nx; i++) {
            uint32_t a = v0 + (uint32_t)(j * (nx + 1) + i), c = a + (uint32_t)(nx + 1);
            if (tri) {
                uint32_t t1[3] = {a, a + 1, c + 1}, t2[3] = {a, c + 1, c};
                add_face(b, t1, 3);
                add_face(b, t2, 3);
            } else if (hex && i % 3 == 0 && i + 1 < nx) {
                uint32_t h[6] = {a, a + 1, a + 2, c + 2, c + 1, c};
                add_face(b, h, 6);
                i++;
            } else {
                uint32_t q[4] = {a, a + 1, c + 1, c};
                add_face(b, q, 4);
            }
        }
    return v0;
}

static limn_mesh *finish(limn_context *ctx, builder *b)
{
    limn_mesh *m = NULL;
    uint32_t zero = 0;
    if (limn_mesh_create(ctx, b->nv, b->pos, b->nf, b->nf ? b->off : &zero, b->idx, &m))
        fprintf(stderr, "mesh: %s\n", limn_context_message(ctx));
    free(b->pos);
    free(b->off);
    free(b->idx);
    memset(b, 0, sizeof *b);
    return m;
}

/* A grid whose vertices are renumbered at random: its rows hop around
   memory, so the single process's paper iteration reorders (RCM). */
static limn_mesh *shuffled(limn_context *ctx, int tri)
{
    builder b = {0};
    add_grid(&b, 90, 60, tri, 0, 0.0);
    return test_mesh_shuffle(ctx, finish(ctx, &b), 99);
}

/* Two components and an isolated vertex. */
static limn_mesh *components(limn_context *ctx, int tri)
{
    builder b = {0};
    add_grid(&b, 14, 9, tri, 0, 0.0);
    add_vertex(&b, -5.0, 2.0, 1.0);
    add_grid(&b, 6, 11, tri, 0, 30.0);
    return finish(ctx, &b);
}

/* A grid with a fin (three faces on one edge), a fan of faces pinched at one
   vertex, a duplicate face and faces with repeated corners (repair: a lost
   corner, a split, a degenerate face dropped). */
static limn_mesh *nonmanifold(limn_context *ctx, int tri)
{
    builder b = {0};
    uint32_t g = add_grid(&b, 12, 8, tri, 0, 0.0), s = 13;
    uint32_t apex = add_vertex(&b, 5.5, 4.0, 2.0);
    uint32_t fin[3] = {g + 5 + 4 * s, g + 6 + 4 * s, apex};
    add_face(&b, fin, 3);
    uint32_t c = g + 12 + 8 * s; /* a corner: pinch another fan there */
    uint32_t p1 = add_vertex(&b, 13.0, 9.0, 1.0), p2 = add_vertex(&b, 13.0, 10.0, 1.0);
    uint32_t p3 = add_vertex(&b, 12.0, 10.0, 1.0);
    uint32_t t1[3] = {c, p1, p2}, t2[3] = {c, p2, p3};
    add_face(&b, t1, 3);
    add_face(&b, t2, 3);
    add_face(&b, t1, 3); /* duplicate */
    if (!tri) {
        uint32_t q1 = add_vertex(&b, -2.0, 0.0, 0.0), q2 = add_vertex(&b, -2.0, 1.0, 0.0);
        uint32_t q3 = add_vertex(&b, -3.0, 1.0, 0.0), q4 = add_vertex(&b, -3.0, 0.0, 0.0);
        uint32_t rep[5] = {q1, q2, q2, q3, q4};            /* a lost corner */
        uint32_t split[6] = {g, g + s, q1, g, q3, q4};     /* split at g */
        uint32_t degenerate[4] = {q1, q1, q2, q2};         /* dropped */
        add_face(&b, rep, 5);
        add_face(&b, split, 6);
        add_face(&b, degenerate, 4);
    }
    return finish(ctx, &b);
}

/* ------------------------------------------------------------- comparison */

/* Rank 0's METIS partition of the repaired mesh, on every rank. */
static uint32_t *partition(limn_context *ctx, const limn_mesh *repaired)
{
    size_t n = limn_mesh_vertex_count(repaired), cut = 0;
    uint32_t *part = calloc(n ? n : 1, sizeof *part);
    int ok = 1;
    if (rank == 0)
        ok = mpi_partition(ctx, repaired, size, part, &cut) == LIMN_OK;
    MPI_Bcast(&ok, 1, MPI_INT, 0, MPI_COMM_WORLD);
    CHECK(ok, "METIS: %s", limn_context_message(ctx));
    MPI_Bcast(part, (int)n, MPI_UINT32_T, 0, MPI_COMM_WORLD);
    return part;
}

/* Compares a's and b's arrays of n elements of elem bytes. */
static void same(const char *name, const char *what, const void *a, const void *b, size_t n,
                 size_t elem)
{
    CHECK(n == 0 || memcmp(a, b, n * elem) == 0, "%s: %s differ", name, what);
}

static void compare_halo(const char *name, const mpi_halo *a, const mpi_halo *b)
{
    CHECK(a->n_recv == b->n_recv && a->n_send == b->n_send,
          "%s: halo of %d/%d neighbours (root path), %d/%d (local)", name, a->n_recv, a->n_send,
          b->n_recv, b->n_send);
    if (a->n_recv != b->n_recv || a->n_send != b->n_send)
        return;
    size_t nr = (size_t)a->n_recv, ns = (size_t)a->n_send;
    same(name, "receive ranks", a->recv_rank, b->recv_rank, nr, sizeof(int));
    same(name, "receive offsets", a->recv_off, b->recv_off, nr, sizeof(size_t));
    same(name, "receive counts", a->recv_cnt, b->recv_cnt, nr, sizeof(size_t));
    same(name, "send ranks", a->send_rank, b->send_rank, ns, sizeof(int));
    same(name, "send offsets", a->send_off, b->send_off, ns, sizeof(size_t));
    same(name, "send counts", a->send_cnt, b->send_cnt, ns, sizeof(size_t));
    if (ns && !memcmp(a->send_cnt, b->send_cnt, ns * sizeof(size_t)))
        same(name, "send lists", a->send_idx, b->send_idx,
             a->send_off[ns - 1] + a->send_cnt[ns - 1], sizeof(uint32_t));
}

/* Global id of local column c of part d. */
static uint32_t column_id(const mpi_part *d, uint32_t c)
{
    return c < d->n_owned ? d->owned_ids[c] : d->ghost_ids[c - d->n_owned];
}

static void compare_rows(const char *name, const mpi_part *a, const mpi_part *b)
{
    size_t no = a->n_owned;
    same(name, "row offsets", a->host.row_offsets, b->host.row_offsets, no + 1,
         sizeof(uint32_t));
    if (memcmp(a->host.row_offsets, b->host.row_offsets, (no + 1) * sizeof(uint32_t)))
        return;
    size_t bad = 0, nnz = a->host.row_offsets[no];
    for (size_t e = 0; e < nnz; e++)
        bad += column_id(a, a->host.columns[e]) != column_id(b, b->host.columns[e]);
    CHECK(bad == 0, "%s: %zu of %zu columns differ", name, bad, nnz);
    same(name, "weights", a->host.weights, b->host.weights, nnz, sizeof(double));
}

static void compare(const char *name, const mpi_part *a, const mpi_part *b)
{
    CHECK(a->n_global == b->n_global && a->faces_global == b->faces_global &&
              a->nnz_global == b->nnz_global && a->edge_cut == b->edge_cut &&
              a->scheme == b->scheme && a->reordered == b->reordered,
          "%s: globals (%zu v, %zu f, %zu nnz, cut %zu, scheme %d) root path, (%zu, %zu, %zu, "
          "%zu, %d) local",
          name, a->n_global, a->faces_global, a->nnz_global, a->edge_cut, (int)a->scheme,
          b->n_global, b->faces_global, b->nnz_global, b->edge_cut, (int)b->scheme);
    same(name, "alpha", &a->alpha, &b->alpha, 1, sizeof(double));
    same(name, "diagonal", &a->diag, &b->diag, 1, sizeof(double));
    CHECK(a->n_owned == b->n_owned && a->n_ghost == b->n_ghost &&
              a->n_interior == b->n_interior && a->send_begin == b->send_begin &&
              a->send_end == b->send_end,
          "%s: owned %zu ghosts %zu classes %zu %zu %zu (root path), %zu %zu %zu %zu %zu "
          "(local)",
          name, a->n_owned, a->n_ghost, a->send_begin, a->n_interior, a->send_end, b->n_owned,
          b->n_ghost, b->send_begin, b->n_interior, b->send_end);
    if (a->n_owned != b->n_owned || a->n_ghost != b->n_ghost)
        return;
    same(name, "owned ids", a->owned_ids, b->owned_ids, a->n_owned, sizeof(uint32_t));
    same(name, "ghost ids", a->ghost_ids, b->ghost_ids, a->n_ghost, sizeof(uint32_t));
    same(name, "owned rules", a->owned_rule, b->owned_rule, a->n_owned, 1);
    same(name, "ghost rules", a->ghost_rule, b->ghost_rule, a->n_ghost, 1);
    same(name, "row scales", a->owned_scale, b->owned_scale, a->n_owned, sizeof(double));
    compare_rows(name, a, b);
    compare_halo(name, &a->halo, &b->halo);
}

/* Collective: limn_interpolate on rank 0 (default options: the paper
   iteration reorders where rows hop around memory) against
   mpi_interpolate_part on the local rows b (m4: its owned positions); the
   same bits for the paper iteration and Chebyshev (a permuted row keeps its
   entries' order, stencil_permute), 1e-12 of the scale for CG (its dot
   products are reduced over ranks). */
static void solve_case(limn_context *ctx, const char *name, const limn_mesh *rep, mpi_part *b,
                       const double *m4, limn_scheme scheme, double alpha, limn_method method)
{
    limn_interpolate_options o;
    limn_interpolate_options_default(&o);
    o.scheme = scheme;
    o.alpha = alpha;
    o.method = method;
    limn_mesh *single = NULL;
    limn_report rs = {.size = sizeof rs}, rd = {.size = sizeof rd};
    limn_status ss = rank == 0 ? limn_interpolate(ctx, rep, &o, &single, &rs) : LIMN_OK;
    MPI_Bcast(&ss, 1, MPI_INT, 0, MPI_COMM_WORLD);
    CHECK(ss == LIMN_OK, "%s: single process: %s", name, limn_context_message(ctx));
    size_t no = b->n_owned, nl = no + b->n_ghost, n = b->n_global;
    double *p4 = calloc(4 * (nl ? nl : 1), sizeof *p4), *xyz = malloc(3 * (no ? no : 1) * 8);
    limn_status st = ss ? ss : mpi_interpolate_part(b, &o, m4, p4, &rd);
    CHECK(st == LIMN_OK, "%s: local rows: %s", name, limn_context_message(ctx));
    int cnt = (int)no, *cnts = calloc((size_t)size, sizeof *cnts), *displ = calloc((size_t)size, sizeof *displ);
    int *c3 = calloc((size_t)size, sizeof *c3), *d3 = calloc((size_t)size, sizeof *d3);
    for (size_t i = 0; i < no; i++)
        memcpy(xyz + 3 * i, p4 + 4 * i, 3 * sizeof *xyz);
    MPI_Gather(&cnt, 1, MPI_INT, cnts, 1, MPI_INT, 0, MPI_COMM_WORLD);
    for (int r = 1; r < size; r++)
        displ[r] = displ[r - 1] + cnts[r - 1];
    for (int r = 0; r < size; r++) {
        c3[r] = 3 * cnts[r];
        d3[r] = 3 * displ[r];
    }
    uint32_t *ids = malloc((n ? n : 1) * sizeof *ids);
    double *got = malloc(3 * (n ? n : 1) * sizeof *got), *out = malloc(3 * (n ? n : 1) * 8);
    MPI_Gatherv(b->owned_ids, cnt, MPI_UINT32_T, ids, cnts, displ, MPI_UINT32_T, 0,
                MPI_COMM_WORLD);
    MPI_Gatherv(xyz, 3 * cnt, MPI_DOUBLE, got, c3, d3, MPI_DOUBLE, 0, MPI_COMM_WORLD);
    if (rank == 0 && !st && !ss) {
        for (size_t i = 0; i < n; i++)
            memcpy(out + 3 * (size_t)ids[i], got + 3 * i, 3 * sizeof *out);
        const double *ref = limn_mesh_positions(single);
        size_t differ = 0;
        double worst = 0, scale = 0;
        for (size_t i = 0; i < 3 * n; i++) {
            differ += out[i] != ref[i];
            worst = fmax(worst, fabs(out[i] - ref[i]));
            scale = fmax(scale, fabs(ref[i]));
        }
        /* cg, sgs: dot products reduced over the ranks; sgs after one process's RCM:
           another colouring, so the tolerance's bound */
        int exact = strcmp(rd.method, "cg") != 0 && strcmp(rd.method, "sgs") != 0;
        int other = !strcmp(rd.method, "sgs") && rs.reordered;
        if (strstr(name, "(RCM)") && method == LIMN_METHOD_PAPER)
            CHECK(rs.reordered, "%s: the single process did not reorder", name);
        CHECK((other || rd.iterations == rs.iterations) && !strcmp(rd.method, rs.method),
              "%s: %s, %d iterations; single process %s, %d", name, rd.method, rd.iterations,
              rs.method, rs.iterations);
        CHECK(exact ? differ == 0 : worst <= (other ? 1e-6 : 1e-12) * scale,
              "%s %s: %zu of %zu values differ from the single process (by %.3g of %.3g)", name,
              rd.method, differ, 3 * n, worst, scale);
        printf("    solve %-10s %d iterations, %zu/%zu values bit-identical%s\n", rd.method,
               rd.iterations, 3 * n - differ, 3 * n,
               rs.reordered ? " (one process reordered)" : "");
    }
    limn_mesh_destroy(single);
    free(p4);
    free(xyz);
    free(cnts);
    free(displ);
    free(c3);
    free(d3);
    free(ids);
    free(got);
    free(out);
}

/* Collective: the Gauss-Seidel colouring of the local rows b, computed rank
   by rank (mpi_sgs_colour_local), is sgs_colour_rows's on the root path's
   global operator a (not reordered: the input order), row for row. */
static void colour_case(const char *name, const mpi_part *a, mpi_part *b)
{
    size_t no = b->n_owned, nl = no + b->n_ghost, n = b->n_global, counts[3];
    uint32_t *colour = malloc((nl ? nl : 1) * sizeof *colour);
    limn_status st = mpi_sgs_colour_local(b, colour, counts);
    CHECK(st == LIMN_OK, "%s: colouring: %s", name, limn_context_message(b->ctx));
    int cnt = (int)no, *cnts = calloc((size_t)size, sizeof *cnts);
    int *displ = calloc((size_t)size, sizeof *displ);
    MPI_Gather(&cnt, 1, MPI_INT, cnts, 1, MPI_INT, 0, MPI_COMM_WORLD);
    for (int r = 1; r < size; r++)
        displ[r] = displ[r - 1] + cnts[r - 1];
    uint32_t *ids = malloc((n ? n : 1) * sizeof *ids), *got = malloc((n ? n : 1) * sizeof *got);
    MPI_Gatherv(b->owned_ids, cnt, MPI_UINT32_T, ids, cnts, displ, MPI_UINT32_T, 0,
                MPI_COMM_WORLD);
    MPI_Gatherv(colour, cnt, MPI_UINT32_T, got, cnts, displ, MPI_UINT32_T, 0, MPI_COMM_WORLD);
    if (rank == 0 && !st) {
        const stencil_operator *op = &a->global;
        int8_t *tier = malloc(n ? n : 1);
        uint32_t *want = malloc((n ? n : 1) * sizeof *want);
        size_t differ = 0, most[3] = {0, 0, 0};
        for (size_t i = 0; i < n; i++)
            tier[i] = (int8_t)mpi_tier_of(op->topo.vertex_rule[i]);
        CHECK(op->order == NULL && sgs_colour_rows(&op->host, tier, want) > 0,
              "%s: the reference colouring", name);
        for (size_t i = 0; i < n; i++) {
            differ += got[i] != want[ids[i]];
            if (want[ids[i]] + 1 > most[tier[ids[i]]])
                most[tier[ids[i]]] = want[ids[i]] + 1;
        }
        CHECK(differ == 0 && !memcmp(most, counts, sizeof most),
              "%s: %zu of %zu rows coloured otherwise than one process's greedy", name, differ,
              n);
        printf("    sgs colouring: %zu + %zu + %zu colours, %zu/%zu rows as one process\n",
               counts[0], counts[1], counts[2], n - differ, n);
        free(tier);
        free(want);
    }
    free(colour);
    free(cnts);
    free(displ);
    free(ids);
    free(got);
}

/* Rank r's faces: uneven ranges (rank r gets a share growing with r). */
static int reversed; /* 1: rank r takes the r-th range from the end */

static void face_range(size_t nf, size_t *begin, size_t *count)
{
    size_t r = reversed ? (size_t)(size - 1 - rank) : (size_t)rank;
    size_t total = (size_t)size * (size_t)(size + 1) / 2, before = r * (r + 1) / 2;
    *begin = nf * before / total;
    *count = nf * (before + r + 1) / total - *begin;
}

/* The local path from blocks and face ranges of the unrepaired mesh. */
static limn_status local_path(limn_context *ctx, const limn_mesh *mesh, const uint32_t *part,
                              limn_scheme scheme, double alpha,
                              const limn_repair_options *repair, mpi_part *b, double **m4,
                              mpi_local_stats *stats)
{
    size_t n = limn_mesh_vertex_count(mesh), nf = limn_mesh_face_count(mesh), fb, fc;
    size_t *vtxdist = malloc(((size_t)size + 1) * sizeof *vtxdist);
    for (int r = 0; r <= size; r++)
        vtxdist[r] = n * (size_t)r / (size_t)size;
    face_range(nf, &fb, &fc);
    const uint32_t *off = limn_mesh_face_offsets(mesh), *idx = limn_mesh_face_indices(mesh);
    uint32_t *off2 = malloc((fc + 1) * sizeof *off2);
    for (size_t f = 0; f <= fc; f++)
        off2[f] = off[fb + f] - off[fb];
    limn_status st = mpi_part_begin(ctx, MPI_COMM_WORLD, NULL, b);
    if (!st)
        st = mpi_local_build(b, vtxdist, limn_mesh_positions(mesh) + 3 * vtxdist[rank],
                             part + vtxdist[rank], fb, fc, off2, idx + off[fb], scheme, alpha,
                             repair, m4, stats);
    free(vtxdist);
    free(off2);
    return st;
}

static void local_case(limn_context *ctx, const char *name, const limn_mesh *mesh,
                       limn_scheme scheme, double alpha)
{
    limn_mesh *rep = NULL;
    int ok = limn_mesh_copy(ctx, mesh, &rep) == LIMN_OK &&
             limn_mesh_repair(ctx, rep, NULL, NULL) == LIMN_OK;
    CHECK(ok, "%s: repair: %s", name, limn_context_message(ctx));
    if (!ok)
        return;
    uint32_t *part = partition(ctx, rep);
    mpi_part a, b;
    limn_status sa = mpi_part_begin(ctx, MPI_COMM_WORLD, NULL, &a);
    if (!sa)
        sa = mpi_distribute_part(&a, rank == 0 ? rep : NULL, scheme, alpha, 0,
                                 rank == 0 ? part : NULL);
    CHECK(sa == LIMN_OK, "%s: root path: %s", name, limn_context_message(ctx));
    mpi_local_stats stats;
    double *m4 = NULL;
    limn_status sb = local_path(ctx, mesh, part, scheme, alpha, NULL, &b, &m4, &stats);
    CHECK(sb == LIMN_OK, "%s: local path: %s", name, limn_context_message(ctx));
    if (!sa && !sb)
        compare(name, &a, &b);
    size_t n = limn_mesh_vertex_count(mesh);
    if (size > 1 && n >= 100)
        CHECK(stats.largest_vertex_array < n && stats.sub_vertices < n,
              "%s: a per-vertex array of %zu entries (sub-mesh %zu) on %zu vertices", name,
              stats.largest_vertex_array, stats.sub_vertices, n);
    /* what the build holds while the sub-mesh's operator is built (its
       peak), counted from its live arrays: the sub-mesh's ids, parts (4 B
       each), positions (24 B) and owned list (4 B each) only; the received
       face records, the referenced lists and the CSR are freed by then */
    if (!sb) {
        size_t want = 32 * stats.sub_vertices + 4 * b.n_owned;
        CHECK(stats.bytes_held_at_operator == want,
              "%s: %zu bytes held at the operator build, want %zu (%zu sub-mesh vertices, "
              "%zu owned): an array outlives its last reader",
              name, stats.bytes_held_at_operator, want, stats.sub_vertices, b.n_owned);
    }
    unsigned long long big = stats.largest_vertex_array, worst = 0;
    MPI_Reduce(&big, &worst, 1, MPI_UNSIGNED_LONG_LONG, MPI_MAX, 0, MPI_COMM_WORLD);
    if (rank == 0)
        printf("  %-44s %-7s alpha %.1f: %zu vertices, %zu rows here, largest per-vertex "
               "array %llu (%.2f of n)\n",
               name, limn_scheme_name(a.scheme), alpha, n, a.n_owned, worst,
               n ? (double)worst / (double)n : 0.0);
    if (!sa && !sb)
        colour_case(name, &a, &b);
    static const limn_method methods[] = {LIMN_METHOD_PAPER, LIMN_METHOD_CHEBYSHEV,
                                          LIMN_METHOD_CG, LIMN_METHOD_SGS};
    for (size_t k = 0; !sb && k < sizeof methods / sizeof *methods; k++)
        solve_case(ctx, name, rep, &b, m4, scheme, alpha, methods[k]);
    mpi_part_end(&a);
    mpi_part_end(&b);
    free(m4);
    free(part);
    limn_mesh_destroy(rep);
}

/* A part out of range on the last rank: every rank fails with its message. */
static void bad_partition(limn_context *ctx, const limn_mesh *mesh)
{
    size_t n = limn_mesh_vertex_count(mesh);
    uint32_t *part = calloc(n, sizeof *part);
    part[n - 1] = (uint32_t)size; /* in the last rank's block */
    mpi_part b;
    mpi_local_stats stats;
    limn_status st = local_path(ctx, mesh, part, LIMN_SCHEME_CATMARK, 0.0, NULL, &b, NULL, &stats);
    char want[128];
    snprintf(want, sizeof want, "vertex %zu is given to part %d", n - 1, size);
    CHECK(st == LIMN_ERR_ARGUMENT && strstr(limn_context_message(ctx), want),
          "bad partition: status %d, message \"%s\"", (int)st, limn_context_message(ctx));
    mpi_part_end(&b);
    free(part);
}

/* Vertex blocks that do not start at 0: refused on every rank. */
static void bad_blocks(limn_context *ctx)
{
    size_t *vtxdist = malloc(((size_t)size + 1) * sizeof *vtxdist);
    for (int r = 0; r <= size; r++)
        vtxdist[r] = 1 + (size_t)r;
    static const double pos[3 * 8] = {0};
    static const uint32_t part[8] = {0}, off[1] = {0};
    mpi_part b;
    limn_status st = mpi_part_begin(ctx, MPI_COMM_WORLD, NULL, &b);
    if (!st)
        st = mpi_local_build(&b, vtxdist, pos, part, 0, 0, off, NULL, LIMN_SCHEME_AUTO, 0.0,
                             NULL, NULL, NULL);
    CHECK(st == LIMN_ERR_ARGUMENT && strstr(limn_context_message(ctx), "must start at 0"),
          "bad blocks: status %d, message \"%s\"", (int)st, limn_context_message(ctx));
    mpi_part_end(&b);
    free(vtxdist);
}

/* Repair off and a face using a vertex twice: every rank gets the single
   process's message (input face numbering). */
static void repair_off(limn_context *ctx, const limn_mesh *mesh)
{
    limn_repair_options ro;
    limn_repair_options_default(&ro);
    ro.repeated_vertices = 0;
    limn_mesh *copy = NULL;
    limn_mesh_copy(ctx, mesh, &copy);
    limn_status want = limn_mesh_repair(ctx, copy, &ro, NULL);
    char msg[512];
    snprintf(msg, sizeof msg, "%s", limn_context_message(ctx));
    limn_mesh_destroy(copy);
    uint32_t *part = calloc(limn_mesh_vertex_count(mesh), sizeof *part);
    mpi_part b;
    limn_status st = local_path(ctx, mesh, part, LIMN_SCHEME_CATMARK, 0.0, &ro, &b, NULL, NULL);
    if (rank == 0)
        printf("  repair off: \"%s\"\n", limn_context_message(ctx));
    CHECK(want == LIMN_ERR_TOPOLOGY && st == want && !strcmp(msg, limn_context_message(ctx)),
          "repair off: status %d, message \"%s\"; single process %d, \"%s\"", (int)st,
          limn_context_message(ctx), (int)want, msg);
    mpi_part_end(&b);
    free(part);
}

static void shared_meshes(limn_context *ctx)
{
    int shared = rank == 0 ? test_shared_meshes() != NULL : 0;
    MPI_Bcast(&shared, 1, MPI_INT, 0, MPI_COMM_WORLD);
    static const struct {
        const char *path;
        limn_scheme scheme;
        double alpha;
    } real[] = {{"small/suzanne.obj", LIMN_SCHEME_CATMARK, 0.0},
                {"small/bun_zipper_res4.ply", LIMN_SCHEME_LOOP, 0.0},
                {"small/bun_zipper_res4.ply", LIMN_SCHEME_CATMARK, 0.5},
                {"small/cow.obj", LIMN_SCHEME_LOOP, 0.0},
                {"opensubdiv/catmark_nonman_edges.obj", LIMN_SCHEME_CATMARK, 0.5},
                {"opensubdiv/catmark_nonman_verts.obj", LIMN_SCHEME_CATMARK, 0.0},
                {"opensubdiv/loop_nonman_edges.obj", LIMN_SCHEME_LOOP, 0.0},
                {"medium/bun_zipper.ply", LIMN_SCHEME_LOOP, 0.0}};
    for (size_t k = 0; shared && k < sizeof real / sizeof *real; k++) {
        limn_mesh *m = NULL;
        int ok = limn_mesh_read(ctx, test_shared_path(real[k].path), LIMN_FORMAT_AUTO, &m) ==
                 LIMN_OK, all = 0;
        MPI_Allreduce(&ok, &all, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
        if (all)
            local_case(ctx, real[k].path, m, real[k].scheme, real[k].alpha);
        limn_mesh_destroy(m);
    }
    if (!shared && rank == 0)
        printf("  (shared meshes not found: generated meshes only)\n");
}

int main(int argc, char **argv)
{
    MPI_Init(&argc, &argv);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    limn_context *ctx = limn_context_create();
    limn_context_set_device(ctx, "reference");
    if (rank == 0)
        printf("test_mpi_local: %d ranks\n", size);
    limn_mesh *tri = test_mesh_grid(ctx, 25, 17, 1), *quad = test_mesh_grid(ctx, 25, 17, 0);
    builder hb = {0};
    add_grid(&hb, 16, 11, 0, 1, 0.0);
    limn_mesh *hex = finish(ctx, &hb);
    limn_mesh *comp_t = components(ctx, 1), *comp_q = components(ctx, 0);
    limn_mesh *nm_t = nonmanifold(ctx, 1), *nm_q = nonmanifold(ctx, 0);
    limn_mesh *fan = test_mesh_fan(ctx, 7, 0), *pyr = test_mesh_pyramid(ctx);
    limn_mesh *shuf_t = shuffled(ctx, 1), *shuf_q = shuffled(ctx, 0);
    local_case(ctx, "triangle grid (boundary)", tri, LIMN_SCHEME_LOOP, 0.0);
    local_case(ctx, "triangle grid, scheme auto", tri, LIMN_SCHEME_AUTO, 0.0);
    local_case(ctx, "quad grid (boundary)", quad, LIMN_SCHEME_CATMARK, 0.0);
    local_case(ctx, "quad grid (boundary)", quad, LIMN_SCHEME_CATMARK, 0.5);
    local_case(ctx, "hexagons and quads (n-gons)", hex, LIMN_SCHEME_CATMARK, 0.0);
    local_case(ctx, "hexagons and quads (n-gons)", hex, LIMN_SCHEME_CATMARK, 0.5);
    local_case(ctx, "two components + isolated vertex", comp_t, LIMN_SCHEME_LOOP, 0.0);
    local_case(ctx, "two components + isolated vertex", comp_q, LIMN_SCHEME_CATMARK, 0.5);
    reversed = 1; /* face ranges against the rank order: records arrive unsorted */
    local_case(ctx, "the same, face ranges reversed", comp_q, LIMN_SCHEME_CATMARK, 0.5);
    local_case(ctx, "fin, pinch, ..., face ranges reversed", nm_q, LIMN_SCHEME_CATMARK, 0.0);
    reversed = 0;
    local_case(ctx, "fin, pinched fan, duplicate face", nm_t, LIMN_SCHEME_LOOP, 0.0);
    local_case(ctx, "fin, pinch, duplicate, repeated corners", nm_q, LIMN_SCHEME_CATMARK, 0.0);
    local_case(ctx, "fin, pinch, duplicate, repeated corners", nm_q, LIMN_SCHEME_CATMARK, 0.5);
    local_case(ctx, "quad fan (valence 7)", fan, LIMN_SCHEME_CATMARK, 0.5);
    local_case(ctx, "pyramid (fewer vertices than 5 ranks)", pyr, LIMN_SCHEME_AUTO, 0.0);
    local_case(ctx, "shuffled triangle grid (RCM)", shuf_t, LIMN_SCHEME_LOOP, 0.0);
    local_case(ctx, "shuffled quad grid (RCM)", shuf_q, LIMN_SCHEME_CATMARK, 0.5);
    bad_partition(ctx, quad);
    repair_off(ctx, nm_q);
    bad_blocks(ctx);
    shared_meshes(ctx);
    limn_mesh *all[] = {tri, quad, hex, comp_t, comp_q, nm_t, nm_q, fan, pyr, shuf_t, shuf_q};
    for (size_t k = 0; k < sizeof all / sizeof *all; k++)
        limn_mesh_destroy(all[k]);
    limn_context_destroy(ctx);
    return mpi_check_finish("test_mpi_local", NULL, checks, failures);
}
