/* SPDX-License-Identifier: MIT */
/* The parallel write (mpi_write.h): the checks, the results moved to their
   vertex blocks, the layout of the whole mesh, STL's corner positions, the
   formatting of this rank's parts; the file itself is mpi_write_io.c's. */
#include "mpi/mpi_write_io.h"
#include "base/large_alloc.h"

#include "base/context.h"
#include "base/sorted_search.h"
#include "mesh/check.h"
#include "mesh/io/dispatch.h"
#include "mpi/mpi_part.h"

#include <limits.h>
#include <stdlib.h>
#include <string.h>

/* vtxdist and the counts travel as MPI_UINT64_T */
_Static_assert(sizeof(size_t) == sizeof(uint64_t), "size_t is not 64 bits");

limn_status mpi_writer_agree(mpi_writer *w, limn_status st)
{
    return mpi_agree_comm(w->ctx, w->comm, w->rank, w->size, 0, st);
}

/* The rank whose block holds vertex id (id < vtxdist[size]; empty blocks skipped). */
static int block_of(const size_t *vtxdist, int size, size_t id)
{
    return (int)sorted_last_at_most_size(vtxdist, (size_t)size, id);
}

static limn_status bad(mpi_writer *w, const char *what)
{
    return ctx_fail(w->ctx, LIMN_ERR_ARGUMENT, "mpi_write_mesh: rank %d: %s", w->rank, what);
}

/* This rank's arguments, on their own. */
static limn_status check_local(mpi_writer *w)
{
    const mpi_write_part *in = w->in;
    const size_t *d = in->vtxdist;
    if (!d)
        return bad(w, "vtxdist is NULL");
    if (d[0] != 0)
        return bad(w, "vtxdist[0] is not 0");
    for (int r = 0; r < w->size; r++)
        if (d[r + 1] < d[r])
            return bad(w, "vtxdist decreases");
    size_t total = d[w->size];
    if (total > (size_t)UINT32_MAX + 1)
        return bad(w, "more vertices than 32-bit indices number");
    if ((in->n_owned && (!in->owned_ids || !in->pos)) || (in->face_count && !in->face_offsets))
        return bad(w, "owned_ids, pos or face_offsets is NULL");
    for (size_t i = 0; i < in->n_owned; i++)
        if (in->owned_ids[i] >= total)
            return ctx_fail(w->ctx, LIMN_ERR_ARGUMENT,
                            "mpi_write_mesh: rank %d: owned vertex %u is past the mesh's %zu "
                            "vertices", w->rank, in->owned_ids[i], total);
    const uint32_t *off = in->face_offsets;
    for (size_t f = 0; f < in->face_count; f++)
        if (off[f + 1] < off[f] + 1 || (f == 0 && off[0] != 0))
            return bad(w, "face_offsets do not start at 0 and increase");
    size_t corners = in->face_count ? off[in->face_count] : 0;
    if (corners && !in->face_indices)
        return bad(w, "face_indices is NULL");
    for (size_t k = 0; k < corners; k++)
        if (in->face_indices[k] >= total)
            return ctx_fail(w->ctx, LIMN_ERR_ARGUMENT,
                            "mpi_write_mesh: rank %d: face %zu uses vertex %u, past the mesh's "
                            "%zu vertices", w->rank,
                            in->face_begin +
                                sorted_last_at_most_u32(off, in->face_count, (uint32_t)k),
                            in->face_indices[k], total);
    return LIMN_OK;
}

/* What must agree between the ranks: vtxdist, the face blocks' order, colours. */
static limn_status check_shared(mpi_writer *w)
{
    const mpi_write_part *in = w->in;
    size_t n = (size_t)w->size + 1;
    size_t *root = large_malloc(n * sizeof *root);
    /* agreed before the broadcast, which a rank out of memory would not enter */
    limn_status st = mpi_writer_agree(
        w, root ? LIMN_OK : ctx_fail(w->ctx, LIMN_ERR_MEMORY, "out of memory"));
    if (st) {
        free(root);
        return st;
    }
    memcpy(root, in->vtxdist, n * sizeof *root);
    MPI_Bcast(root, (int)n, MPI_UINT64_T, 0, w->comm);
    int same_dist = memcmp(root, in->vtxdist, n * sizeof *root) == 0;
    free(root);
    uint64_t count = in->face_count, before = 0;
    MPI_Exscan(&count, &before, 1, MPI_UINT64_T, MPI_SUM, w->comm);
    if (w->rank == 0)
        before = 0;
    if (!same_dist)
        st = bad(w, "vtxdist differs from rank 0's");
    else if (before != in->face_begin)
        st = ctx_fail(w->ctx, LIMN_ERR_ARGUMENT,
                      "mpi_write_mesh: rank %d: its faces begin at %zu, but the ranks before it "
                      "hold %llu faces", w->rank, in->face_begin, (unsigned long long)before);
    st = mpi_writer_agree(w, st);
    int colored[2] = {in->colors != NULL, in->colors == NULL}, all[2];
    MPI_Allreduce(colored, all, 2, MPI_INT, MPI_MIN, w->comm);
    if (!st && !all[0] && !all[1])
        st = ctx_fail(w->ctx, LIMN_ERR_ARGUMENT,
                      "mpi_write_mesh: colours given on some ranks but not on others");
    w->layout.colors = all[0];
    return st;
}

/* Puts vertex id's position (and colours) in the block; refuses a second one. */
static limn_status put_vertex(mpi_writer *w, unsigned char *seen, size_t id, const double *xyz,
                              const uint8_t *rgb)
{
    size_t v = id - w->vbegin;
    if (seen[v]++)
        return ctx_fail(w->ctx, LIMN_ERR_ARGUMENT,
                        "mpi_write_mesh: vertex %zu is owned by more than one rank", id);
    memcpy(w->pos + 3 * v, xyz, 3 * sizeof *w->pos);
    if (rgb)
        memcpy(w->colors + 3 * v, rgb, 3);
    return LIMN_OK;
}

/* Places the received records (id, x, y, z) and colours; then every vertex
   of the block must have come (from this rank or another). */
static limn_status place(mpi_writer *w, unsigned char *seen, const double *rec,
                         const uint8_t *rgb, size_t n, limn_status st)
{
    for (size_t k = 0; k < n && !st; k++)
        st = put_vertex(w, seen, (size_t)rec[4 * k], rec + 4 * k + 1, rgb ? rgb + 3 * k : NULL);
    for (size_t v = 0; v < w->vcount && !st; v++)
        if (!seen[v])
            st = ctx_fail(w->ctx, LIMN_ERR_ARGUMENT,
                          "mpi_write_mesh: vertex %zu is owned by no rank", w->vbegin + v);
    return st;
}

typedef struct exchange {
    int *scount, *sdisp, *rcount, *rdisp; /* in items */
    size_t sent, received;
} exchange;

static void exchange_free(exchange *x)
{
    free(x->scount);
    memset(x, 0, sizeof *x);
}

/* Counts in items to every rank -> the plan both ways (one Alltoall). */
static limn_status exchange_plan(mpi_writer *w, exchange *x, size_t width)
{
    int P = w->size;
    int *a = x->scount;
    x->sdisp = a + P;
    x->rcount = a + 2 * P;
    x->rdisp = a + 3 * P;
    MPI_Alltoall(x->scount, 1, MPI_INT, x->rcount, 1, MPI_INT, w->comm);
    x->sent = x->received = 0;
    for (int r = 0; r < P; r++) {
        x->sdisp[r] = (int)x->sent;
        x->rdisp[r] = (int)x->received;
        x->sent += (size_t)x->scount[r];
        x->received += (size_t)x->rcount[r];
    }
    if (x->sent * width > INT_MAX || x->received * width > INT_MAX)
        return ctx_fail(w->ctx, LIMN_ERR_ARGUMENT,
                        "mpi_write_mesh: rank %d: more than %d values in one exchange", w->rank,
                        INT_MAX);
    return LIMN_OK;
}

/* Counts and displacements times width (in place). */
static void exchange_scale(exchange *x, int size, int width)
{
    for (int r = 0; r < 4 * size; r++)
        x->scount[r] *= width;
}

static limn_status exchange_begin(mpi_writer *w, exchange *x)
{
    memset(x, 0, sizeof *x);
    x->scount = calloc(4 * (size_t)w->size, sizeof *x->scount);
    return x->scount ? LIMN_OK : ctx_fail(w->ctx, LIMN_ERR_MEMORY, "out of memory");
}

/* The owned results to their vertex blocks: (id, x, y, z) records, colours aside. */
static limn_status move_to_blocks(mpi_writer *w)
{
    const mpi_write_part *in = w->in;
    exchange x;
    limn_status st = exchange_begin(w, &x);
    for (size_t i = 0; !st && i < in->n_owned; i++) { /* this rank's own block: no message */
        int r = block_of(in->vtxdist, w->size, in->owned_ids[i]);
        x.scount[r] += r != w->rank;
    }
    if (!st && in->n_owned > INT_MAX / 4)
        st = bad(w, "too many owned vertices for one exchange");
    st = mpi_writer_agree(w, st);
    if (!st)
        st = mpi_writer_agree(w, exchange_plan(w, &x, 4));
    if (st) {
        exchange_free(&x);
        return st;
    }
    int *fill = large_malloc((size_t)w->size * sizeof *fill);
    double *send = large_malloc((4 * x.sent + 1) * sizeof *send);
    double *recv = large_malloc((4 * x.received + 1) * sizeof *recv);
    uint8_t *srgb = w->layout.colors ? large_malloc(3 * x.sent + 1) : NULL;
    uint8_t *rrgb = w->layout.colors ? large_malloc(3 * x.received + 1) : NULL;
    w->pos = large_malloc((3 * w->vcount + 1) * sizeof *w->pos);
    w->colors = w->layout.colors ? large_malloc(3 * w->vcount + 1) : NULL;
    unsigned char *seen = calloc(w->vcount + 1, 1);
    int oom = !fill || !send || !recv || !w->pos || !seen ||
              (w->layout.colors && (!srgb || !rrgb || !w->colors));
    st = mpi_writer_agree(w, oom ? ctx_fail(w->ctx, LIMN_ERR_MEMORY, "out of memory") : LIMN_OK);
    if (!st) {
        memcpy(fill, x.sdisp, (size_t)w->size * sizeof *fill);
        limn_status own = LIMN_OK;
        for (size_t i = 0; i < in->n_owned; i++) {
            int r = block_of(in->vtxdist, w->size, in->owned_ids[i]);
            if (r == w->rank) {
                if (!own)
                    own = put_vertex(w, seen, in->owned_ids[i], in->pos + 3 * i,
                                     in->colors ? in->colors + 3 * i : NULL);
                continue;
            }
            int k = fill[r]++;
            send[4 * (size_t)k] = (double)in->owned_ids[i];
            memcpy(send + 4 * (size_t)k + 1, in->pos + 3 * i, 3 * sizeof *send);
            if (srgb)
                memcpy(srgb + 3 * (size_t)k, in->colors + 3 * i, 3);
        }
        exchange_scale(&x, w->size, 4);
        MPI_Alltoallv(send, x.scount, x.sdisp, MPI_DOUBLE, recv, x.rcount, x.rdisp, MPI_DOUBLE,
                      w->comm);
        if (srgb) {
            for (int r = 0; r < 4 * w->size; r++)
                x.scount[r] = x.scount[r] / 4 * 3;
            MPI_Alltoallv(srgb, x.scount, x.sdisp, MPI_BYTE, rrgb, x.rcount, x.rdisp, MPI_BYTE,
                          w->comm);
        }
        st = mpi_writer_agree(w, place(w, seen, recv, rrgb, x.received, own));
    }
    free(seen);
    free(fill);
    free(send);
    free(recv);
    free(srgb);
    free(rrgb);
    exchange_free(&x);
    return st;
}

static int cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return (x > y) - (x < y);
}

/* STL: the positions of every vertex this rank's faces use, asked of their
   blocks' ranks; the faces renumbered into them (corner_idx). */
static limn_status fetch_corners(mpi_writer *w)
{
    const mpi_write_part *in = w->in;
    size_t n_idx = in->face_count ? in->face_offsets[in->face_count] : 0;
    uint32_t *ids = large_malloc((n_idx + 1) * sizeof *ids);
    w->corner_idx = large_malloc((n_idx + 1) * sizeof *w->corner_idx);
    exchange x;
    limn_status st = exchange_begin(w, &x);
    if (!st && (!ids || !w->corner_idx))
        st = ctx_fail(w->ctx, LIMN_ERR_MEMORY, "out of memory");
    size_t nu = 0;
    if (!st) {
        memcpy(ids, in->face_indices, n_idx * sizeof *ids);
        qsort(ids, n_idx, sizeof *ids, cmp_u32);
        for (size_t k = 0; k < n_idx; k++)
            if (nu == 0 || ids[nu - 1] != ids[k])
                ids[nu++] = ids[k];
        for (size_t k = 0; k < nu; k++)
            x.scount[block_of(in->vtxdist, w->size, ids[k])]++;
        if (nu > INT_MAX / 3)
            st = bad(w, "too many corners for one exchange");
    }
    st = mpi_writer_agree(w, st);
    if (!st)
        st = mpi_writer_agree(w, exchange_plan(w, &x, 3));
    uint32_t *asked = NULL;
    double *answer = NULL;
    if (!st) {
        asked = large_malloc((x.received + 1) * sizeof *asked);
        answer = large_malloc((3 * x.received + 1) * sizeof *answer);
        w->corners = large_malloc((3 * nu + 1) * sizeof *w->corners);
        int oom = !asked || !answer || !w->corners;
        st = mpi_writer_agree(w, oom ? ctx_fail(w->ctx, LIMN_ERR_MEMORY, "out of memory") : 0);
    }
    if (!st) {
        MPI_Alltoallv(ids, x.scount, x.sdisp, MPI_UINT32_T, asked, x.rcount, x.rdisp,
                      MPI_UINT32_T, w->comm);
        for (size_t k = 0; k < x.received; k++)
            memcpy(answer + 3 * k, w->pos + 3 * (asked[k] - w->vbegin), 3 * sizeof *answer);
        exchange_scale(&x, w->size, 3);
        /* back: what was received is sent, and the other way round */
        MPI_Alltoallv(answer, x.rcount, x.rdisp, MPI_DOUBLE, w->corners, x.scount, x.sdisp,
                      MPI_DOUBLE, w->comm);
        for (size_t k = 0; k < n_idx; k++)
            w->corner_idx[k] = (uint32_t)((uint32_t *)bsearch(in->face_indices + k, ids, nu,
                                                              sizeof *ids, cmp_u32) -
                                          ids);
        w->n_corners = nu;
    }
    free(ids);
    free(asked);
    free(answer);
    exchange_free(&x);
    return st;
}

/* The whole mesh's figures and limn_mesh_write's checks of them; this
   rank's positions checked (the lowest failing rank names the lowest vertex,
   as the single process would). */
static limn_status layout(mpi_writer *w, limn_format format, int single)
{
    const mpi_write_part *in = w->in;
    mesh_layout *l = &w->layout;
    l->format = format;
    l->single = single;
    l->vertex_total = in->vtxdist[w->size];
    uint64_t mine[3] = {in->face_count, 0, check_polygons(in->face_offsets, in->face_count)};
    uint64_t sums[3];
    uint32_t most;
    mesh_layout_faces(in->face_offsets, in->face_count, &most, &mine[1]);
    MPI_Allreduce(mine, sums, 3, MPI_UINT64_T, MPI_SUM, w->comm);
    MPI_Allreduce(&most, &l->max_face, 1, MPI_UINT32_T, MPI_MAX, w->comm);
    l->face_total = (size_t)sums[0];
    l->triangles = sums[1];
    limn_status st = check_positions_from(w->ctx, "limn_mesh_write", w->pos, w->vcount,
                                          w->vbegin);
    st = mpi_writer_agree(w, st);
    if (!st)
        st = check_writable_counts(w->ctx, format, l->vertex_total, l->face_total, l->colors,
                                   (size_t)sums[2]);
    if (!st)
        st = mesh_layout_check(w->ctx, w->path, l);
    return st; /* the same on every rank */
}

/* This rank's bytes: rank 0's header, the vertex block, the face block. */
static limn_status format_parts(mpi_writer *w)
{
    const mpi_write_part *in = w->in;
    block_sink vs = block_sink_memory(&w->vbytes), fs = block_sink_memory(&w->fbytes);
    mesh_block vb = {w->vcount, w->pos, w->colors, 0, NULL, NULL};
    mesh_block fb = {0, NULL, NULL, in->face_count, in->face_offsets, in->face_indices};
    limn_status st = LIMN_OK;
    if (w->layout.format == LIMN_FORMAT_STL) {
        st = mesh_part_vertices(w->ctx, w->path, &w->layout, &vb, w->vbegin, &vs);
        st = mpi_writer_agree(w, st);
        if (!st)
            st = fetch_corners(w);
        fb.vertex_count = w->n_corners;
        fb.positions = w->corners;
        fb.face_indices = w->corner_idx;
    }
    if (!st && w->rank == 0)
        st = mesh_part_header(w->ctx, w->path, &w->layout, &vs);
    if (!st && w->layout.format != LIMN_FORMAT_STL)
        st = mesh_part_vertices(w->ctx, w->path, &w->layout, &vb, w->vbegin, &vs);
    if (!st && in->face_count)
        st = mesh_part_faces(w->ctx, w->path, &w->layout, &fb, &fs);
    return mpi_writer_agree(w, st);
}

static limn_status run(mpi_writer *w, limn_format format, const limn_write_options *options)
{
    limn_write_options defaults;
    limn_write_options_default(&defaults);
    const limn_write_options *o = options ? options : &defaults;
    limn_status st = !w->path || !*w->path
                         ? ctx_fail(w->ctx, LIMN_ERR_ARGUMENT,
                                    "limn_mesh_write: path is NULL or empty")
                     : !w->in ? bad(w, "part is NULL")
                              : check_local(w);
    if (!st)
        st = mesh_write_format(w->ctx, w->path, o, &format);
    st = mpi_writer_agree(w, st);
    if (!st)
        st = check_shared(w);
    if (st)
        return st;
    w->vbegin = w->in->vtxdist[w->rank];
    w->vcount = w->in->vtxdist[w->rank + 1] - w->vbegin;
    st = move_to_blocks(w);
    if (!st)
        st = layout(w, format, o->precision == LIMN_OUTPUT_FLOAT);
    if (!st)
        st = format_parts(w);
    return st ? st : mpi_writer_output(w);
}

limn_status mpi_write_mesh_part(limn_context *ctx, MPI_Comm comm, const char *path,
                                limn_format format, const limn_write_options *options,
                                const mpi_write_part *part, limn_output_set *stage)
{
    ctx_clear(ctx);
    mpi_writer w;
    memset(&w, 0, sizeof w);
    w.ctx = ctx;
    w.path = path;
    w.in = part;
    w.stage = stage;
    w.fh = MPI_FILE_NULL;
    w.file_comm = MPI_COMM_NULL;
    MPI_Comm_dup(comm, &w.comm);
    MPI_Comm_rank(w.comm, &w.rank);
    MPI_Comm_size(w.comm, &w.size);
    limn_status st = run(&w, format, options);
    free(w.pos);
    free(w.colors);
    free(w.corners);
    free(w.corner_idx);
    growbuf_free(&w.vbytes);
    growbuf_free(&w.fbytes);
    MPI_Comm_free(&w.comm);
    return st;
}

limn_status mpi_write_mesh(limn_context *ctx, MPI_Comm comm, const char *path,
                           const limn_write_options *options, const size_t *vtxdist,
                           size_t n_owned, const uint32_t *owned_ids, const double *pos,
                           size_t face_begin, size_t face_count, const uint32_t *face_offsets,
                           const uint32_t *face_indices)
{
    mpi_write_part part = {vtxdist, n_owned, owned_ids, pos, NULL,
                           face_begin, face_count, face_offsets, face_indices};
    return mpi_write_mesh_part(ctx, comm, path, LIMN_FORMAT_AUTO, options, &part, NULL);
}
