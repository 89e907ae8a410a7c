/* SPDX-License-Identifier: MIT */
/*
 * What every distributed call shares: the communicator, agreement on a
 * status before each collective phase, global norms, vectors scattered from
 * and gathered to the root, and the device of each rank.
 */
#define _GNU_SOURCE /* sched_getaffinity: the cores this rank may use */
#include "mpi/mpi_part.h"
#include "base/large_alloc.h"

#include "base/context.h"
#include "mesh/mesh.h"
#include "device/choice/choice.h"

#include <limits.h>
#include <sched.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

void limn_mpi_options_default(limn_mpi_options *o)
{
    abi_default(&abi_mpi_options, o);
}

#define ABI_END(type, field) (offsetof(type, field) + sizeof(((type *)0)->field))

static const limn_mpi_options mpi_defaults = {.size = sizeof(limn_mpi_options), .root = 0};

const abi_layout abi_mpi_options = {"limn_mpi_options",
                                    "limn_mpi_options_default()",
                                    sizeof(limn_mpi_options),
                                    ABI_END(limn_mpi_options, keep_piece),
                                    NULL,
                                    &mpi_defaults};
const abi_layout abi_mpi_stats = {"limn_mpi_stats",
                                  "sizeof(limn_mpi_stats)",
                                  sizeof(limn_mpi_stats),
                                  ABI_END(limn_mpi_stats, device),
                                  NULL,
                                  NULL};
const abi_layout abi_mpi_result = {
    "limn_mpi_result",       "sizeof(limn_mpi_result)",
    sizeof(limn_mpi_result), ABI_END(limn_mpi_result, piece_vertices),
    &abi_mpi_stats,          NULL};
_Static_assert(offsetof(limn_mpi_result, stats) == sizeof(size_t), "stats first");
_Static_assert(offsetof(limn_mpi_result, piece) == sizeof(size_t) + sizeof(limn_mpi_stats),
               "piece after stats");

limn_status mpi_abi_begin(limn_context *ctx, MPI_Comm comm, const char *fn, limn_status st,
                          const limn_mpi_options *mpi, limn_mpi_options *mpi_sized,
                          const limn_mpi_result *result, limn_mpi_result *result_sized)
{
    limn_mpi_options_default(mpi_sized);
    if (!st)
        st = abi_options_in(ctx, fn, "mpi", &abi_mpi_options, mpi, mpi_sized);
    limn_status rs =
        abi_report_begin(ctx, fn, "result", &abi_mpi_result, st ? NULL : result, result_sized);
    if (!st)
        st = rs;
    int initialized = 0, finalized = 0;
    MPI_Initialized(&initialized);
    MPI_Finalized(&finalized);
    if (!initialized || finalized || comm == MPI_COMM_NULL)
        return st; /* mpi_part_begin refuses on every rank */
    int bad = st != LIMN_OK, any = 0;
    MPI_Allreduce(&bad, &any, 1, MPI_INT, MPI_MAX, comm);
    if (any && !st)
        st = ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                       "%s: another rank refused the size of its options, report or result "
                       "(its message says which)",
                       fn);
    return st;
}

/* The end of the piece fields in this library's limn_mpi_result. */
#define PIECE_END ABI_END(limn_mpi_result, piece_vertices)

void mpi_abi_end(limn_mpi_result *result, limn_mpi_result *result_sized)
{
    if (!result || !abi_report_holds(&abi_mpi_result, result, PIECE_END)) {
        limn_mesh_destroy(result_sized->piece);
        free(result_sized->piece_vertices);
        result_sized->piece = NULL;
        result_sized->piece_vertices = NULL;
        result_sized->piece_owned = 0;
    }
    abi_report_end(&abi_mpi_result, result, result_sized);
}

limn_status mpi_enter(mpi_call *c, limn_context *ctx, MPI_Comm comm, const char *fn,
                      const abi_layout *options_layout, const void *options,
                      const abi_layout *report_layout, void *report, const limn_mpi_options *mpi,
                      limn_mpi_result *result, limn_mesh **out)
{
    if (!ctx)
        return LIMN_ERR_ARGUMENT;
    limn_status st =
        abi_enter(&c->abi, ctx, fn, options_layout, options, report_layout, report, out);
    c->caller_result = result;
    c->mpi = mpi ? &c->mo : NULL;
    c->result = result ? &c->res : NULL;
    return mpi_abi_begin(ctx, comm, fn, st, mpi, &c->mo, result, &c->res);
}

limn_status mpi_leave(mpi_call *c, limn_status st)
{
    abi_leave(&c->abi, st);
    mpi_abi_end(c->caller_result, &c->res);
    return st;
}

void limn_mpi_result_free(limn_mpi_result *r)
{
    /* a struct too short for the piece fields never received a piece */
    if (!r || !abi_report_holds(&abi_mpi_result, r, PIECE_END))
        return;
    limn_mesh_destroy(r->piece);
    free(r->piece_vertices);
    r->piece = NULL;
    r->piece_vertices = NULL;
    r->piece_owned = 0;
}

/* The partition of a distributed mesh: the option, else LIMN_MPI_PARTITION
   (sfc | scotch), else the space-filling curve. Every rank decides alike
   when the launcher gives them the same environment (mpirun does); a rank
   that decides otherwise is refused, not left in another partitioner's
   collectives. */
static limn_status part_partition(mpi_part *p, int want)
{
    const char *env = getenv("LIMN_MPI_PARTITION");
    limn_status st = LIMN_OK;
    if (want == LIMN_MPI_PARTITION_AUTO && env && *env) {
        want = !strcmp(env, "sfc")      ? LIMN_MPI_PARTITION_SFC
               : !strcmp(env, "scotch") ? LIMN_MPI_PARTITION_SCOTCH
                                        : -1;
        if (want < 0)
            st = ctx_fail(p->ctx, LIMN_ERR_ARGUMENT,
                          "LIMN_MPI_PARTITION is '%s': sfc or scotch (or unset: sfc)", env);
    } else if (want != LIMN_MPI_PARTITION_AUTO && want != LIMN_MPI_PARTITION_SFC &&
               want != LIMN_MPI_PARTITION_SCOTCH) {
        st = ctx_fail(p->ctx, LIMN_ERR_ARGUMENT,
                      "limn_mpi_options.partition is %d: LIMN_MPI_PARTITION_AUTO, _SFC or _SCOTCH",
                      want);
    }
    p->partition = want == LIMN_MPI_PARTITION_SCOTCH ? LIMN_MPI_PARTITION_SCOTCH
                                                      : LIMN_MPI_PARTITION_SFC;
    int lo = st ? -1 : p->partition, hi = lo;
    MPI_Allreduce(MPI_IN_PLACE, &lo, 1, MPI_INT, MPI_MIN, p->comm);
    MPI_Allreduce(MPI_IN_PLACE, &hi, 1, MPI_INT, MPI_MAX, p->comm);
    if (!st && lo >= 0 && lo != hi)
        st = ctx_fail(p->ctx, LIMN_ERR_ARGUMENT,
                      "the ranks chose different partitions (LIMN_MPI_PARTITION differs "
                      "between them): give every rank the same");
    return st;
}

limn_status mpi_part_begin(limn_context *ctx, MPI_Comm comm, const limn_mpi_options *mpi,
                           mpi_part *p)
{
    memset(p, 0, sizeof *p);
    p->ctx = ctx;
    p->comm = MPI_COMM_NULL;
    int initialized = 0, finalized = 0;
    MPI_Initialized(&initialized);
    MPI_Finalized(&finalized);
    if (!initialized || finalized)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                         "MPI is not running (call MPI_Init before the limn_*_mpi calls, and "
                         "MPI_Finalize after)");
    if (comm == MPI_COMM_NULL)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "the communicator is MPI_COMM_NULL");
    /* a private copy: our messages never match the caller's */
    MPI_Comm_dup(comm, &p->comm);
    MPI_Comm_rank(p->comm, &p->rank);
    MPI_Comm_size(p->comm, &p->size);
    MPI_Comm node;
    MPI_Comm_split_type(p->comm, MPI_COMM_TYPE_SHARED, p->rank, MPI_INFO_NULL, &node);
    MPI_Comm_rank(node, &p->stats.local_rank);
    MPI_Comm_size(node, &p->local_size);
    MPI_Comm_free(&node);
    p->stats.ranks = p->size;
    p->stats.rank = p->rank;
    p->root = mpi ? mpi->root : 0;
    limn_status st = LIMN_OK;
    if (p->root < 0 || p->root >= p->size)
        st = ctx_fail(ctx, LIMN_ERR_ARGUMENT, "the root rank is %d; the communicator has %d",
                       p->root, p->size);
    if (!st)
        st = part_partition(p, mpi ? mpi->partition : LIMN_MPI_PARTITION_AUTO);
    return mpi_agree(p, st);
}

void mpi_part_drop_rows(mpi_part *p)
{
    if (p->dev)
        device_csr_release(p->dev, &p->all);
    stencil_free(&p->host);
}

int mpi_part_ids_alloc(mpi_part *p, size_t no, size_t ng)
{
    p->owned_ids = large_malloc((no ? no : 1) * sizeof *p->owned_ids);
    p->owned_rule = large_malloc(no ? no : 1);
    p->owned_scale = large_malloc((no ? no : 1) * sizeof *p->owned_scale);
    p->ghost_ids = large_malloc((ng ? ng : 1) * sizeof *p->ghost_ids);
    p->ghost_rule = large_malloc(ng ? ng : 1);
    return p->owned_ids && p->owned_rule && p->owned_scale && p->ghost_ids && p->ghost_rule;
}

int mpi_part_rows_alloc(mpi_part *p, size_t no, size_t ng, size_t nnz)
{
    int ids = mpi_part_ids_alloc(p, no, ng);
    p->host.row_offsets = large_malloc((no + 1) * sizeof *p->host.row_offsets);
    p->host.columns = large_malloc((nnz ? nnz : 1) * sizeof *p->host.columns);
    p->host.weights = large_malloc((nnz ? nnz : 1) * sizeof *p->host.weights);
    return ids && p->host.row_offsets && p->host.columns && p->host.weights;
}

void mpi_part_end(mpi_part *p)
{
    mpi_part_drop_rows(p);
    mpi_halo_free(&p->halo);
    free(p->owned_ids);
    free(p->ghost_ids);
    free(p->owned_rule);
    free(p->owned_scale);
    free(p->ghost_rule);
    if (p->has_global)
        operator_free(&p->global);
    free(p->root_off);
    free(p->root_ids);
    free(p->part_of);
    free(p->root_buf);
    if (p->comm != MPI_COMM_NULL)
        MPI_Comm_free(&p->comm);
    memset(p, 0, sizeof *p);
    p->comm = MPI_COMM_NULL;
}

limn_status mpi_agree_comm(limn_context *ctx, MPI_Comm comm, int rank, int size, int echo,
                           limn_status st)
{
    /* real failures rank before echoes of another rank's, then by rank */
    int key = st == LIMN_OK ? 2 * size : (echo ? size + rank : rank), first;
    MPI_Allreduce(&key, &first, 1, MPI_INT, MPI_MIN, comm);
    if (first == 2 * size)
        return LIMN_OK;
    int who = first >= size ? first - size : first;
    int status = (int)st;
    MPI_Bcast(&status, 1, MPI_INT, who, comm);
    MPI_Bcast(ctx->message, (int)sizeof ctx->message, MPI_CHAR, who, comm);
    ctx->message[sizeof ctx->message - 1] = '\0';
    return (limn_status)status;
}

limn_status mpi_agree(mpi_part *p, limn_status st)
{
    int echo = p->echo;
    p->echo = 0;
    return mpi_agree_comm(p->ctx, p->comm, p->rank, p->size, echo, st);
}

/* ------------------------------------------------------------------ norms */

/* One element of the reduction: max, failure flag, two double-double sums. */
enum { RED_MAX, RED_FAIL, RED_SUM_HI, RED_SUM_LO, RED_SQ_HI, RED_SQ_LO, RED_WIDTH };

/* a + b of two double-double numbers (Dekker / Knuth TwoSum, then a fast
   renormalisation): exact to ~2^-104 whatever the order of the additions,
   so every rank rounds the total to the same double. Needs -ffp-contract=off. */
static void dd_add(double *hi, double *lo, double bh, double bl)
{
    double s = *hi + bh, v = s - *hi;
    double e = (*hi - (s - v)) + (bh - v);
    e += *lo + bl;
    *hi = s + e;
    *lo = e - (*hi - s);
}

static void reduce_fn(void *in, void *inout, int *len, MPI_Datatype *type)
{
    (void)type;
    const double *a = in;
    double *b = inout;
    for (int k = 0; k < *len; k++, a += RED_WIDTH, b += RED_WIDTH) {
        b[RED_MAX] = a[RED_MAX] > b[RED_MAX] ? a[RED_MAX] : b[RED_MAX];
        b[RED_FAIL] = a[RED_FAIL] > b[RED_FAIL] ? a[RED_FAIL] : b[RED_FAIL];
        dd_add(&b[RED_SUM_HI], &b[RED_SUM_LO], a[RED_SUM_HI], a[RED_SUM_LO]);
        dd_add(&b[RED_SQ_HI], &b[RED_SQ_LO], a[RED_SQ_HI], a[RED_SQ_LO]);
    }
}

static void reduce(mpi_part *p, double v[RED_WIDTH])
{
    MPI_Datatype t;
    MPI_Op op;
    MPI_Type_contiguous(RED_WIDTH, MPI_DOUBLE, &t);
    MPI_Type_commit(&t);
    MPI_Op_create(reduce_fn, 1, &op);
    double out[RED_WIDTH];
    double t0 = MPI_Wtime();
    MPI_Allreduce(v, out, 1, t, op, p->comm);
    p->stats.seconds_reduce += MPI_Wtime() - t0;
    MPI_Op_free(&op);
    MPI_Type_free(&t);
    memcpy(v, out, sizeof out);
}

limn_status mpi_reduce_norms(mpi_part *p, limn_status local, const device_norms *in,
                             device_norms *out)
{
    double v[RED_WIDTH] = {in->max, local ? 1.0 : 0.0, in->sum, 0.0, in->sum_sq, 0.0};
    reduce(p, v);
    out->max = v[RED_MAX];
    out->sum = v[RED_SUM_HI] + v[RED_SUM_LO];
    out->sum_sq = v[RED_SQ_HI] + v[RED_SQ_LO];
    if (local)
        return local;
    if (v[RED_FAIL] > 0.0) {
        p->echo = 1;
        return ctx_fail(p->ctx, LIMN_ERR_DEVICE, "another rank failed");
    }
    return LIMN_OK;
}

double mpi_sum(mpi_part *p, double x)
{
    double v[RED_WIDTH] = {0.0, 0.0, x, 0.0, 0.0, 0.0};
    reduce(p, v);
    return v[RED_SUM_HI] + v[RED_SUM_LO];
}

/* -------------------------------------------------------- scatter, gather */

/* Counts and displacements (in doubles) of each rank's owned rows on root. */
static limn_status root_counts(mpi_part *p, int **counts, int **displs)
{
    *counts = NULL;
    *displs = NULL;
    if (p->rank != p->root)
        return LIMN_OK;
    *counts = large_malloc((size_t)p->size * sizeof **counts);
    *displs = large_malloc((size_t)p->size * sizeof **displs);
    if (!*counts || !*displs)
        return ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %d ranks", p->size);
    for (int r = 0; r < p->size; r++) {
        (*counts)[r] = (int)(3 * (p->root_off[r + 1] - p->root_off[r]));
        (*displs)[r] = (int)(3 * p->root_off[r]);
    }
    return LIMN_OK;
}

/* The scratch of a scatter or gather: the root's counts and displacements,
   this rank's rows as 3 doubles each; agreed over the ranks. */
typedef struct rows_msg {
    int *counts, *displs;
    double *mine;
} rows_msg;

static limn_status rows_msg_open(mpi_part *p, rows_msg *m)
{
    limn_status st = root_counts(p, &m->counts, &m->displs);
    m->mine = large_malloc((p->n_owned ? 3 * p->n_owned : 1) * sizeof *m->mine);
    if (!m->mine)
        st = ctx_fail(p->ctx, LIMN_ERR_MEMORY, "out of memory for %zu vertices", p->n_owned);
    return mpi_agree(p, st);
}

static limn_status rows_msg_close(rows_msg *m, limn_status st)
{
    free(m->mine);
    free(m->counts);
    free(m->displs);
    return st;
}

limn_status mpi_scatter_rows(mpi_part *p, const double *xyz_root, double *rows4)
{
    rows_msg m;
    limn_status st = rows_msg_open(p, &m);
    if (!st) {
        if (p->rank == p->root)
            for (size_t k = 0; k < p->n_global; k++)
                memcpy(p->root_buf + 3 * k, xyz_root + 3 * (size_t)p->root_ids[k],
                       3 * sizeof(double));
        MPI_Scatterv(p->root_buf, m.counts, m.displs, MPI_DOUBLE, m.mine, (int)(3 * p->n_owned),
                     MPI_DOUBLE, p->root, p->comm);
        for (size_t i = 0; i < p->n_owned; i++) {
            memcpy(rows4 + 4 * i, m.mine + 3 * i, 3 * sizeof(double));
            rows4[4 * i + 3] = 0.0;
        }
    }
    return rows_msg_close(&m, st);
}

limn_status mpi_gather_rows(mpi_part *p, const double *rows4, double *xyz_root)
{
    rows_msg m;
    limn_status st = rows_msg_open(p, &m);
    if (!st) {
        for (size_t i = 0; i < p->n_owned; i++)
            memcpy(m.mine + 3 * i, rows4 + 4 * i, 3 * sizeof(double));
        MPI_Gatherv(m.mine, (int)(3 * p->n_owned), MPI_DOUBLE, p->root_buf, m.counts, m.displs,
                    MPI_DOUBLE, p->root, p->comm);
        if (p->rank == p->root)
            for (size_t k = 0; k < p->n_global; k++)
                memcpy(xyz_root + 3 * (size_t)p->root_ids[k], p->root_buf + 3 * k,
                       3 * sizeof(double));
    }
    return rows_msg_close(&m, st);
}

/* ------------------------------------------------------------------ device */

/* PoCL ignores the process's CPU binding; limn gives it the cores inside the
   binding (threads.c, hwloc). A rank that is not bound (mpirun --bind-to none,
   or more ranks than cores) sees the whole node there, so unless the caller
   asked for a count, such a rank takes its share of the node instead. */
static void share_cores(mpi_part *p)
{
    long online = sysconf(_SC_NPROCESSORS_ONLN);
    cpu_set_t set;
    if (p->local_size <= 1 || p->ctx->threads_request != LIMN_THREADS_FROM_BINDING ||
        online <= 0 || sched_getaffinity(0, sizeof set, &set) != 0 || CPU_COUNT(&set) < online)
        return;
    long share = online / p->local_size;
    p->ctx->threads_request = share > 0 ? (int)share : 1;
}

limn_status mpi_open_device(mpi_part *p)
{
    if (!p->ctx->device) /* an open device stays the caller's choice */
        p->ctx->device_slot = p->stats.local_rank;
    share_cores(p);
    limn_status st = device_get(p->ctx, &p->dev);
    if (!st)
        snprintf(p->stats.device, sizeof p->stats.device, "%s", p->dev->name);
    return st;
}
