/* SPDX-License-Identifier: MIT */
/*
 * The compute backend: a small table of operations over device buffers.
 * Two implementations: OpenCL (device_opencl.c) and plain C (device_ref.c).
 * Vectors are stored as 4 doubles per vertex (x, y, z, unused) because a
 * 32-byte record per row streams faster than three separate arrays.
 * Reductions are split into fixed chunks of rows (DEVICE_ROWS_PER_ITEM; on
 * OpenCL in the gpu kernel shape, a work-group's rows, device/opencl/
 * opencl_shape.h); each chunk's partial result is finished on the host in
 * chunk order, so the result does not depend on the number of threads.
 */
#ifndef LIMN_DEVICE_H
#define LIMN_DEVICE_H

#include "limn.h"
#include "stencil/sgs_table.h"
#include "stencil/stencil.h"
#include "stencil/stencil_sell.h"

#define DEVICE_ROWS_PER_ITEM 256
#define DEVICE_WORKGROUP 8

typedef struct device_buffer device_buffer;
struct device;

/* A CSR table resident on the device. An op computes the rows
   [row_begin, row_begin + rows); row_begin is 0 for a whole table. A row range
   (for MPI: rows free of ghost columns first, the rest after the halo arrives)
   is a copy of the struct with row_begin a multiple of DEVICE_ROWS_PER_ITEM,
   so its reduction chunks are the table's own; row_offsets stay indexed by
   the table's row and outputs land in the same rows of y. */
typedef struct device_csr {
    size_t rows;
    size_t nonzeros;
    size_t row_begin;
    device_buffer *row_offsets;  /* uint32, rows + 1; SELL (device.sell_slice): slices + 1 */
    device_buffer *columns;      /* uint32, nonzeros (SELL: entries with padding) */
    device_buffer *weights;      /* double, nonzeros */
    device_buffer *weights_f;    /* float copy for the float path (device_csr_add_float);
                                    NULL until then */
    int gather_ahead;            /* the gathers scatter over memory: the solve kernels
                                    prefetch them (kernels/stencil.cl, GATHER_AHEAD) */
} device_csr;

/* Per-chunk partial norms of a residual r (per vertex Euclidean length). */
typedef struct device_norms {
    double max;       /* max |r_i| */
    double sum;       /* sum |r_i| */
    double sum_sq;    /* sum |r_i|^2 */
} device_norms;

/* The table of the multicolour symmetric Gauss-Seidel sweeps (host/stencil/sgs_table.c,
   kernels/sgs.cl) for S = D_A^-1 A on one solver block. Rows are in colour
   order, colour c owning rows [colour_begin[c], colour_begin[c + 1]); no
   entry joins two rows of one colour. Row i's off-diagonal entries are
   [row_offsets[i], row_offsets[i + 1]): columns of lower colours first, the
   higher ones from split[i]. info: 4 doubles a row, (d_i, sqrt d_i, scale_i,
   0) with d_i = S_ii and scale_i the row scale (A = scale S). */
typedef struct device_sgs {
    size_t rows, colours;
    size_t *colour_begin;         /* host array, colours + 1 */
    device_buffer *row_offsets;   /* uint32, rows + 1 */
    device_buffer *split;         /* uint32, rows */
    device_buffer *columns;       /* uint32 */
    device_buffer *weights;       /* double */
    device_buffer *info;          /* 4 doubles a row */
} device_sgs;

/* The vectors of the SGS-preconditioned conjugate gradients (host/solve/solve_sgs.c),
   4 doubles a row: right-hand side b (of S x = b), iterate x, residual
   r = b - S x, the transformed residual rhat and direction phat, and the
   sweeps' t, u and st = S t. */
typedef struct sgs_vectors {
    device_buffer *b, *x, *r, *rhat, *phat, *t, *u, *st;
} sgs_vectors;

/* The per-solver families: each backend fills one table of each (a solver
   that needs a fused kernel adds its family here, not to device_ops). */

/* The stationary and semi-iterative methods (solve/iterate.c). */
typedef struct device_stationary_ops {
    /* r = m - A p; p_next = p + omega r; norms of r (over all rows).
       omega = 1 is the seeds' iteration, bit for bit. */
    limn_status (*interp_step)(struct device *dev, const device_csr *a,
                               device_buffer *m, device_buffer *p, device_buffer *p_next,
                               double omega, device_norms *norms);
    /* r = m - A p; prev_next = p + c1 (p - prev_next) + c2 r (x_{k-1} in,
       x_{k+1} out: the Chebyshev recurrence); norms of r. c1 = 0, c2 = omega
       gives interp_step's update (kernels/solve.cl). */
    limn_status (*cheb_step)(struct device *dev, const device_csr *a, device_buffer *m,
                             device_buffer *p, device_buffer *prev_next, double c1, double c2,
                             device_norms *norms);
} device_stationary_ops;

/* The D-preconditioned conjugate gradients (solve/solve_cg.c, mpi/mpi_cg.c). */
typedef struct device_cg_ops {
    /* y = A x and dot = sum_i dinv_i (x_i . y_i) (kernels/solve.cl). */
    limn_status (*spmv_dot)(struct device *dev, const device_csr *a, device_buffer *x,
                            device_buffer *y, device_buffer *dinv, double *dot);
    /* x += alpha p; z -= alpha q; norms->max = max |z_i|, norms->sum =
       sum dinv_i |z_i|^2, norms->sum_sq = sum |z_i|^2. */
    limn_status (*pcg_update)(struct device *dev, size_t rows, double alpha,
                              device_buffer *p, device_buffer *q, device_buffer *x,
                              device_buffer *z, device_buffer *dinv, device_norms *norms);
} device_cg_ops;

typedef struct device_mixed_ops {
    /* Mixed-precision refinement (kernels/mixed.cl, host/solve/solve_mixed.c).
       Float vectors are 4 floats per row. residual_f: r = m - A p in double,
       stored rounded to float in r_f; norms of the double r. */
    limn_status (*residual_f)(struct device *dev, const device_csr *a, device_buffer *m,
                              device_buffer *p, device_buffer *r_f, device_norms *norms);
    /* One float step on the correction system A d = b with the float weights:
       s = b - A_f d and next = d + c1 (d - prev) + c2 s in float (Chebyshev;
       c1 = 0, c2 = omega: the seeds' or weighted step); norms of s in double.
       prev and next may be one buffer, prev may be d; next is not d. */
    limn_status (*step_f)(struct device *dev, const device_csr *a, device_buffer *b,
                          device_buffer *d, device_buffer *prev, device_buffer *next, float c1,
                          float c2, device_norms *norms);
    /* p += d over `rows` (d float, widened exactly to double). */
    limn_status (*add_f)(struct device *dev, size_t rows, device_buffer *p,
                         device_buffer *d);
    /* w_f = w rounded to float, `count` values. */
    limn_status (*to_float)(struct device *dev, size_t count, device_buffer *w,
                            device_buffer *w_f);
} device_mixed_ops;

typedef struct device_sgs_ops {
    /* SGS-preconditioned CG (host/solve/solve_sgs.c, kernels/sgs.cl; C = (D + L)
       D^-1/2 with S = L + D + U, steps on C^-1 S C^-T).
       The backward sweep, colours high to low: phat = rhat + beta phat, then
       t = (D + U)^-1 D^1/2 phat. */
    limn_status (*sgs_upper)(struct device *dev, const device_sgs *a, double beta,
                             const sgs_vectors *v);
    /* The forward sweep, colours low to high. start: r = b - S x, u =
       (D + L)^-1 r, rhat = D^1/2 u; out->max = max scale_i |r_i| (the
       residual of A), out->sum = rhat . rhat. Otherwise u = (D + L)^-1
       (D^1/2 phat - D t), st = S t, out->sum = phat . q with q = D^1/2
       (t + u). Each entry is read once either way. */
    limn_status (*sgs_lower)(struct device *dev, const device_sgs *a, int start,
                             const sgs_vectors *v, device_norms *out);
    /* x += alpha t; r -= alpha st; rhat -= alpha q; norms->max = max scale_i
       |r_i|, norms->sum = rhat . rhat. */
    limn_status (*sgs_update)(struct device *dev, const device_sgs *a, double alpha,
                              const sgs_vectors *v, device_norms *norms);
} device_sgs_ops;

/* The series filters (host/series, mpi/mpi_series.c). */
typedef struct device_series_ops {
    /* One term of the series (seed 000 eq. 6; kernels/series.cl): ax = A x and
       x_next = x - ax = (E - A) x; ax is stored when flags has SERIES_STORE_AX,
       x_next when SERIES_STORE_NEXT (unused buffers may be NULL); acc is
       updated by acc_mode (SERIES_ACC_*; acc may be NULL with ACC_NONE).
       norms: of ax (max, sum of lengths, sum of squares over x, y, z). */
    limn_status (*series_step)(struct device *dev, const device_csr *a, device_buffer *x,
                               device_buffer *x_next, device_buffer *ax, device_buffer *acc,
                               int flags, int acc_mode, device_norms *norms);
} device_series_ops;

/* The primitive operations every solver may use, and the families. */
typedef struct device_ops {
    const char *kind;   /* "opencl" or "reference" */
    limn_status (*buffer_create)(struct device *dev, size_t bytes, const void *init,
                                 device_buffer **out);
    limn_status (*buffer_write)(struct device *dev, device_buffer *buf, size_t bytes,
                                const void *src);
    limn_status (*buffer_read)(struct device *dev, device_buffer *buf, size_t bytes,
                               void *dst);
    void (*buffer_release)(struct device *dev, device_buffer *buf);
    /* A buffer of host memory that outlives it and that the host does not
       write while it lives: used in place where the device shares host memory
       (the reference backend, OpenCL CPU devices), else a copy as
       buffer_create. Kernels may write it; buffer_read into that same memory
       then makes it current (in place: no copy). Vectors the kernels read
       whole (double4 rows) must come from device_host_alloc: aligned loads. */
    limn_status (*buffer_share)(struct device *dev, size_t bytes, const void *host,
                                device_buffer **out);
    /* A buffer whose contents are undefined until written: for one that a
       kernel writes whole before anything reads it (no zero fill). */
    limn_status (*buffer_scratch)(struct device *dev, size_t bytes, device_buffer **out);
    /* Part of a buffer: bytes at byte offset `offset` (MPI halo rows). */
    limn_status (*buffer_write_at)(struct device *dev, device_buffer *buf, size_t offset,
                                   size_t bytes, const void *src);
    limn_status (*buffer_read_at)(struct device *dev, device_buffer *buf, size_t offset,
                                  size_t bytes, void *dst);
    /* y = A x */
    limn_status (*spmv)(struct device *dev, const device_csr *a, device_buffer *x,
                        device_buffer *y);
    /* out = a x + b y over `rows` 4-vectors ((a x) + (b y), all four
       components); out may be x or y. */
    limn_status (*axpby)(struct device *dev, size_t rows, double a, device_buffer *x,
                         double b, device_buffer *y, device_buffer *out);
    /* Norms of x (x, y, z of each of `rows` vectors), finished in chunk order. */
    limn_status (*norms)(struct device *dev, size_t rows, device_buffer *x,
                         device_norms *out);
    void (*close)(struct device *dev);
    const device_stationary_ops *stationary;
    const device_cg_ops *cg;
    const device_mixed_ops *mixed;
    const device_sgs_ops *sgs;
    const device_series_ops *series;
} device_ops;

/* series_step flags and accumulation modes. */
enum { SERIES_STORE_AX = 1, SERIES_STORE_NEXT = 2 };
enum {
    SERIES_ACC_NONE = 0,    /* acc untouched */
    SERIES_ACC_SET_AX = 1,  /* acc = ax */
    SERIES_ACC_ADD_AX = 2,  /* acc = acc + ax */
    SERIES_ACC_ADD_X = 3    /* acc = acc + x */
};

/* Seconds the OpenCL back end spent setting up (all zero for the reference
   one): platform query and device choice, context and queue, program build
   (from PoCL's kernel cache when warm), and the compiles PoCL does on each
   kernel's first launch (a warm cache holds those too). */
typedef struct device_setup_times {
    double platform, context, build, kernels;
} device_setup_times;

struct device {
    const device_ops *ops;
    limn_context *ctx;        /* for error messages */
    char name[256];
    void *impl;
    device_setup_times setup; /* accumulated over the device's life */
    size_t sell_slice;        /* 0: tables upload as CSR; C: in SELL-C slices (the OpenCL
                                 gpu kernel shape, opencl_shape.h, stencil/stencil_sell.h) */
    int host_shared;          /* buffer_share uses host memory in place (the reference
                                 backend, OpenCL devices with CL_DEVICE_HOST_UNIFIED_MEMORY);
                                 0: a discrete device, where it copies */
};

/*
 * Test-only fault injection (tests/test_faults.c): LIMN_TEST_FAULT holds a
 * comma-separated list of no-platform, no-device, build, alloc, enqueue; the
 * OpenCL backend then fails as if clGetPlatformIDs found no ICD, no device
 * matched, the program did not build, clCreateBuffer ran out of device
 * memory, or a kernel launch failed. Also (tests/test_opencl.c): no-fp64,
 * device 0.0 reports no double precision; prefetch, a kernel built with
 * prefetching cannot be created (as on Oclgrind before the SPIR test). Compiled in always, inert unless set.
 * The readers have their own (mesh/io/mesh_ply.h): LIMN_TEST_PLY_GENERAL=1
 * reads binary PLY with the general reader only, never the fast path.
 */
int device_test_fault(const char *name);
/* Whether the context allows the reference fallback (API, else LIMN_FALLBACK). */
int device_fallback_allowed(const limn_context *ctx);

/* The set-up times of the context's device (zero when none is open). */
device_setup_times device_setup_of(const limn_context *ctx);
/* Fills r's seconds_opencl_* with the set-up since `before` and takes the
   kernels' first-launch compiles out of r->seconds_solve. */
void device_setup_report(const limn_context *ctx, const device_setup_times *before,
                         limn_report *r);

void device_close(struct device *dev);

/* Uploads a host CSR table; releases it with device_csr_release. */
limn_status device_csr_upload(struct device *dev, const stencil_csr *host, device_csr *out);
/* Adds the float copy of the weights, made on the device (once; a no-op
   when present). */
limn_status device_csr_add_float(struct device *dev, device_csr *csr);
void device_csr_release(struct device *dev, device_csr *csr);
/* Host memory for vectors a device buffer may use in place (buffer_share):
   page aligned, so above any device's base address alignment (from
   LARGE_ALLOC_HUGE bytes up 2 MiB aligned and advised for huge pages:
   large_malloc); contents undefined; free() it. NULL when out of memory. */
void *device_host_alloc(size_t bytes);

/* A vector the kernels compute in (an iterate), its bytes init's or zeros:
   where the device shares host memory, a block of device_host_alloc used in
   place, filled over ctx's threads, so its huge pages are first touched
   there and not the runtime's own 4 KiB pages by a copy (*host: free() it
   after releasing *out); else a device buffer (*host NULL). */
limn_status device_vector_create(struct device *dev, limn_context *ctx, size_t bytes,
                                 const void *init, void **host, device_buffer **out);

/* device_csr_upload through buffer_share: `host` outlives the device table
   and is not changed while it lives (the operator's own table). */
limn_status device_csr_share(struct device *dev, const stencil_csr *host, device_csr *out);

/* Uploads a Gauss-Seidel table (sgs_table_build); releases it with
   device_sgs_release. */
limn_status device_sgs_upload(struct device *dev, const sgs_table *t, device_sgs *out);
void device_sgs_release(struct device *dev, device_sgs *d);

/* Finishes per-chunk partial norms in chunk order. */
void device_norms_finish(const double *partials, size_t chunks, device_norms *out);

#endif
