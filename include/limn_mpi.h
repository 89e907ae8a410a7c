/* SPDX-License-Identifier: MIT */
/*
 * limn over MPI (optional, built with -DLIMN_MPI=ON): the interpolation and
 * the series filters (bands, smooth, denoise, sharpen, morph) of limn.h with
 * the mesh's vertices split across the ranks of the caller's communicator
 * (README "MPI").
 *
 * Every call here is collective over comm: every rank calls it, with the same
 * options; the input mesh is read only on the root rank (others pass NULL)
 * and the result arrives on the root only. The root partitions the vertices
 * (METIS), builds the limit operator once and sends each rank the rows of its
 * owned vertices; each rank then computes its rows on its own device
 * (limn_context_set_device; with several GPUs on a node the ranks of the node
 * take the matching devices in turn), exchanging ghost values with its
 * neighbours before each stencil product. Results equal the single-process
 * calls of limn.h: the paper and Chebyshev iterations and the series bit for
 * bit, the weighted iteration to rounding (same iteration count).
 *
 * A failure on any rank is returned on every rank, with the failing rank's
 * message in every context, and nothing is left half done: no rank waits for
 * a message that will not come. The communicator is duplicated internally,
 * so these calls never match the caller's own messages.
 *
 * The structs here follow limn.h's ABI rule: limn_mpi_options from
 * limn_mpi_options_default(), a limn_mpi_result zeroed with size and
 * stats.size set (`limn_mpi_result r = {.size = sizeof r, .stats.size =
 * sizeof r.stats};`). A size refused on one rank is refused on every rank (one
 * Allreduce over comm before any other work). A result too short to hold the
 * piece fields gets no piece.
 *
 * Installed (docs/mpi.md "Installing the MPI layer"): liblimn_mpi.so / .a,
 * linked together with liblimn.so / .a of the same install
 * (find_package(limn COMPONENTS mpi): limn::mpi; pkg-config limn-mpi).
 */
#ifndef LIMN_MPI_H
#define LIMN_MPI_H

#include "limn.h"
#include <mpi.h>

#ifdef __cplusplus
extern "C" {
#endif

/* How a distributed mesh's vertices are split over the ranks (limn_mpi_mesh_*). */
typedef enum limn_mpi_partition {
    LIMN_MPI_PARTITION_AUTO = 0,   /* the environment's LIMN_MPI_PARTITION (sfc | scotch), else sfc */
    LIMN_MPI_PARTITION_SFC = 1,    /* a Hilbert curve through the positions: fast, even parts */
    LIMN_MPI_PARTITION_SCOTCH = 2  /* PT-Scotch on the edge graph: a smaller cut, slower */
} limn_mpi_partition;

typedef struct limn_mpi_options {
    size_t size;              /* sizeof, set by limn_mpi_options_default() */
    int root;                 /* rank holding the input and receiving the result; default 0 */
    int keep_piece;           /* 1: return this rank's piece in limn_mpi_result; default 0 */
    int partition;            /* limn_mpi_partition; default AUTO (added after keep_piece:
                                 callers built before it get AUTO) */
} limn_mpi_options;

LIMN_API void limn_mpi_options_default(limn_mpi_options *options);

/* What one rank did (each rank fills its own). */
typedef struct limn_mpi_stats {
    size_t size;              /* sizeof, set by the caller (limn.h's ABI rule) */
    int ranks, rank;
    int local_rank;           /* among the ranks sharing this node */
    int neighbours;           /* ranks this one exchanges ghost values with */
    size_t owned, ghosts;     /* vertices of this rank */
    size_t interior_rows;     /* owned rows without ghost columns: computed while the
                                 halo is in flight */
    size_t edge_cut;          /* edges of the vertex graph between parts (all ranks) */
    size_t halo_bytes_sent, halo_bytes_received; /* per exchange, this rank */
    long long exchanges;      /* halo exchanges run */
    double seconds_partition; /* root path: the root's operator and METIS, others 0;
                                 distributed mesh: this call's partition (0 when
                                 its rows came from the sub-mesh limn_mpi_mesh_repair
                                 left: the partition ran there) */
    double seconds_distribute;/* sending / receiving the rows */
    double seconds_solve;     /* the iteration or the series products, wall clock */
    double seconds_compute;   /* device work on this rank's rows */
    double seconds_halo;      /* reading, sending, waiting for and writing ghost values */
    double seconds_wait;      /* the part of seconds_halo spent in MPI_Waitall: the
                                 transfer not hidden, and waiting for slower ranks */
    double seconds_reduce;    /* global norms (one Allreduce per step) */
    char device[256];
} limn_mpi_stats;

typedef struct limn_mpi_result {
    size_t size;              /* sizeof, set by the caller, and stats.size (limn.h's ABI rule) */
    limn_mpi_stats stats;
    /* With keep_piece: this rank's owned vertices (in input order), then the
       other vertices of the faces incident to them (in input order), with the
       result's positions; those faces, in input order. piece_vertices[i] is
       the input index of piece vertex i. Free with limn_mpi_result_free. */
    limn_mesh *piece;
    size_t piece_owned;
    uint32_t *piece_vertices;
} limn_mpi_result;

LIMN_API void limn_mpi_result_free(limn_mpi_result *result);

/*
 * limn_interpolate over comm. mesh: the input on root (NULL elsewhere);
 * *control: the control mesh on root (NULL elsewhere). report (may be NULL)
 * is filled on every rank with the global figures. mpi and result may be
 * NULL. Methods as limn_interpolate (auto = chebyshev): paper, chebyshev and
 * weighted take the single process's iteration count (paper and chebyshev
 * its bits), in double and in float (precision chosen as limn_interpolate
 * does, on the whole mesh's vertex count); cg and sgs reduce their dot
 * products over the ranks in double-double, but each rank first sums its own
 * rows, so they agree with the single process to rounding (README "MPI" has
 * the measured gap); sgs sweeps with the root's colouring.
 */
LIMN_API limn_status limn_interpolate_mpi(limn_context *ctx, MPI_Comm comm,
                                          const limn_mesh *mesh,
                                          const limn_interpolate_options *options,
                                          limn_mesh **control, limn_report *report,
                                          const limn_mpi_options *mpi, limn_mpi_result *result);

/* limn_smooth over comm (input and *out on root). */
LIMN_API limn_status limn_smooth_mpi(limn_context *ctx, MPI_Comm comm, const limn_mesh *mesh,
                                     const limn_series_options *options, int terms, limn_mesh **out,
                                     limn_series_report *report, const limn_mpi_options *mpi,
                                     limn_mpi_result *result);

/* limn_denoise over comm (input and *out on root). */
LIMN_API limn_status limn_denoise_mpi(limn_context *ctx, MPI_Comm comm, const limn_mesh *mesh,
                                      const limn_series_options *options, int m, int steps,
                                      int keep_volume, limn_mesh **out, limn_series_report *report,
                                      const limn_mpi_options *mpi, limn_mpi_result *result);

/* limn_denoise_sure over comm (input, *out and *sigma on root; *sigma, may
   be NULL, on every rank): the products distributed, the fit on the root
   after a gather of each; the single process's bits. */
LIMN_API limn_status limn_denoise_sure_mpi(limn_context *ctx, MPI_Comm comm,
                                           const limn_mesh *mesh,
                                           const limn_series_options *options, int products,
                                           int keep_volume, limn_mesh **out, double *sigma,
                                           limn_series_report *report,
                                           const limn_mpi_options *mpi, limn_mpi_result *result);

/* limn_sharpen over comm (input and *out on root): the single process's bits. */
LIMN_API limn_status limn_sharpen_mpi(limn_context *ctx, MPI_Comm comm, const limn_mesh *mesh,
                                      const limn_series_options *options, int from, int to,
                                      int steps, limn_mesh **out, limn_series_report *report,
                                      const limn_mpi_options *mpi, limn_mpi_result *result);

/* limn_bands over comm: mesh, bands ((count + 1) * 3 * vertices doubles) and
   energy (count + 1) on root (bands and energy may be NULL there; ignored
   elsewhere). Bands and energies are the single process's bits: each band
   is gathered to the root, which sums its energy as the single process's
   device does. keep_piece is ignored. */
LIMN_API limn_status limn_bands_mpi(limn_context *ctx, MPI_Comm comm, const limn_mesh *mesh,
                                    const limn_series_options *options, int count, double *bands,
                                    double *energy, limn_series_report *report,
                                    const limn_mpi_options *mpi, limn_mpi_result *result);

/* limn_morph over comm: FROM and TO on root; fn is called on root only, once
   per frame in order (its failure stops every rank). keep_piece is ignored. */
LIMN_API limn_status limn_morph_mpi(limn_context *ctx, MPI_Comm comm, const limn_mesh *from,
                                    const limn_mesh *to, const limn_morph_options *options,
                                    limn_morph_frame_fn fn, void *user, limn_series_report *report,
                                    const limn_mpi_options *mpi, limn_mpi_result *result);


/* ------------------------------------------------------- distributed meshes
 *
 * A mesh spread over the ranks of a communicator with no rank holding all of
 * it (docs/mpi.md "Distributed meshes"). Every rank's handle holds one block
 * of the vertices, [vertex_begin, vertex_begin + vertex_count) of the whole
 * mesh's numbering, and one block of its faces, whose indices are global;
 * the blocks follow the rank order. Each handle keeps its own duplicate of
 * the communicator. Every call below is collective over it (the same options
 * on every rank) and returns the same status on every rank, the lowest
 * failing rank's message in every context.
 */
typedef struct limn_mpi_mesh limn_mpi_mesh;

/* Every rank reads its own slice of the file at path: binary PLY by byte
   offsets, OBJ / OFF / ASCII PLY by byte ranges cut at line ends (the format
   from the extension); STL is refused (its vertices are welded over the
   whole file); format LIMN_FORMAT_AUTO from the extension, or one of those.
   The blocks' concatenation is limn_mesh_read's mesh. */
LIMN_API limn_status limn_mpi_mesh_read(limn_context *ctx, MPI_Comm comm, const char *path,
                                        limn_format format, limn_mpi_mesh **out);

/* The same from a split input: rank p reads NAME.r<p>.ply (name given with
   or without ".ply"), made by limn_mpi_mesh_write_split or by the caller in
   the format of docs/mpi.md; the ranks must be as many as the files. */
LIMN_API limn_status limn_mpi_mesh_read_split(limn_context *ctx, MPI_Comm comm, const char *name,
                                              limn_mpi_mesh **out);
/* Writes the split input of mesh: rank p writes NAME.r<p>.ply, its blocks. */
LIMN_API limn_status limn_mpi_mesh_write_split(limn_context *ctx, const limn_mpi_mesh *mesh,
                                               const char *name);

/* A distributed mesh from every rank's own arrays (copied): this rank's
   vertex_count vertices follow the previous ranks' ones, its face_count
   faces (CSR, face_offsets[0] = 0) the previous ranks' faces; face indices
   are global. */
LIMN_API limn_status limn_mpi_mesh_create(limn_context *ctx, MPI_Comm comm, size_t vertex_count,
                                          const double *positions, size_t face_count,
                                          const uint32_t *face_offsets,
                                          const uint32_t *face_indices, limn_mpi_mesh **out);

LIMN_API void limn_mpi_mesh_destroy(limn_mpi_mesh *mesh);

/* This rank's blocks (pointers valid until the handle is destroyed) and the
   whole mesh's counts. */
LIMN_API size_t limn_mpi_mesh_vertex_begin(const limn_mpi_mesh *mesh);
LIMN_API size_t limn_mpi_mesh_vertex_count(const limn_mpi_mesh *mesh);
LIMN_API size_t limn_mpi_mesh_vertex_total(const limn_mpi_mesh *mesh);
LIMN_API size_t limn_mpi_mesh_face_begin(const limn_mpi_mesh *mesh);
LIMN_API size_t limn_mpi_mesh_face_count(const limn_mpi_mesh *mesh);
LIMN_API size_t limn_mpi_mesh_face_total(const limn_mpi_mesh *mesh);
LIMN_API const double *limn_mpi_mesh_positions(const limn_mpi_mesh *mesh);
LIMN_API const uint32_t *limn_mpi_mesh_face_offsets(const limn_mpi_mesh *mesh);
LIMN_API const uint32_t *limn_mpi_mesh_face_indices(const limn_mpi_mesh *mesh);

/* limn_mesh_repair over the ranks: faces that use a vertex twice are
   repaired as the single process repairs them (the face blocks renumbered),
   report (may be NULL) and warnings with global numbers. Duplicate faces are
   found (and removed with options->duplicate_faces) and what is kept is
   counted as the single process does (components and boundary_loops stay
   0). With options->sub_meshes (the default), unless duplicates are removed
   or PT-Scotch is chosen, the counts come from every rank's sub-mesh under
   the curve partition (the faces at its vertices), which stays on the mesh
   for the next call that builds rows (interpolate, the series): it skips
   its own partition and face exchange. That call, a call that builds no
   rows, limn_mpi_mesh_destroy or another repair frees it. */
LIMN_API limn_status limn_mpi_mesh_repair(limn_context *ctx, limn_mpi_mesh *mesh,
                                          const limn_repair_options *options,
                                          limn_repair_report *report);

/* limn_mesh_measure of the whole distributed mesh (closed, volume, area,
   centroid): the same bits as one process, the sums added in its order
   (each rank's terms, then the running sums passed from rank to rank). */
LIMN_API limn_status limn_mpi_mesh_measure(limn_context *ctx, const limn_mpi_mesh *mesh,
                                           limn_mesh_measures *out);
/* limn_mesh_volume_area of the whole distributed mesh, the same bits; volume
   and area (may be NULL) are NaN on failure. */
LIMN_API limn_status limn_mpi_mesh_volume_area(limn_context *ctx, const limn_mpi_mesh *mesh,
                                               double *volume, double *area);

/* Writes the whole mesh to path: every rank writes its blocks at their
   offsets (MPI-IO), the same bytes as limn_mesh_write_with of the whole
   mesh, the file whole or not at all. options (NULL: the defaults) and
   report (may be NULL; its mean error is summed over the ranks, so it may
   differ from the single process's in the last bits) as there. */
LIMN_API limn_status limn_mpi_mesh_write(limn_context *ctx, const limn_mpi_mesh *mesh,
                                         const char *path, limn_format format,
                                         const limn_write_options *options,
                                         limn_write_report *report);
/* limn_mpi_mesh_write staged in an output set (limn.h) instead of appearing:
   the file is complete and synced under its temporary name, held by rank
   0's set, and appears at that set's limn_output_set_commit on rank 0, with
   the set's other outputs (a report, say); limn_output_set_destroy without
   a commit removes it and leaves an existing target as it was. set: rank
   0's must not be NULL and must have room; the other ranks' is not used
   (may be NULL). Collective; refusals as limn_mpi_mesh_write's. */
LIMN_API limn_status limn_mpi_output_set_add_mesh(limn_context *ctx, limn_output_set *set,
                                                  const limn_mpi_mesh *mesh, const char *path,
                                                  limn_format format,
                                                  const limn_write_options *options,
                                                  limn_write_report *report);

/* limn_interpolate on a distributed mesh: the vertices partitioned over the
   ranks in parallel (PT-Scotch), each rank building its own rows from the
   faces around its vertices; *control gets a distributed mesh with the same
   blocks. The results of limn_interpolate_mpi (the single process's). */
LIMN_API limn_status limn_mpi_mesh_interpolate(limn_context *ctx, const limn_mpi_mesh *mesh,
                                               const limn_interpolate_options *options,
                                               limn_mpi_mesh **control, limn_report *report,
                                               const limn_mpi_options *mpi,
                                               limn_mpi_result *result);

/* limn_smooth, limn_denoise and limn_sharpen on a distributed mesh: rows
   built as limn_mpi_mesh_interpolate builds them (no rank holding the
   mesh), *out a distributed mesh with the same blocks and faces; the
   single process's bits. Options, checks and report as limn_smooth_mpi
   etc.; keep_piece is ignored. limn_mpi_mesh_denoise's keep_volume
   needs a closed mesh and scales as limn_denoise does (the same bits:
   limn_mpi_mesh_measure's sums). */
LIMN_API limn_status limn_mpi_mesh_smooth(limn_context *ctx, const limn_mpi_mesh *mesh,
                                          const limn_series_options *options, int terms,
                                          limn_mpi_mesh **out, limn_series_report *report,
                                          const limn_mpi_options *mpi, limn_mpi_result *result);
LIMN_API limn_status limn_mpi_mesh_denoise(limn_context *ctx, const limn_mpi_mesh *mesh,
                                           const limn_series_options *options, int m, int steps,
                                           int keep_volume, limn_mpi_mesh **out,
                                           limn_series_report *report,
                                           const limn_mpi_options *mpi, limn_mpi_result *result);
/* limn_denoise_sure on a distributed mesh: no rank gathers a vector; the
   noise estimate's and the fit's inner products are summed rank to rank in
   input order (the single process's additions), so the single process's
   bits on any rank count; *sigma (may be NULL) on every rank. */
LIMN_API limn_status limn_mpi_mesh_denoise_sure(limn_context *ctx, const limn_mpi_mesh *mesh,
                                                const limn_series_options *options, int products,
                                                int keep_volume, limn_mpi_mesh **out,
                                                double *sigma, limn_series_report *report,
                                                const limn_mpi_options *mpi,
                                                limn_mpi_result *result);
LIMN_API limn_status limn_mpi_mesh_sharpen(limn_context *ctx, const limn_mpi_mesh *mesh,
                                           const limn_series_options *options, int from, int to,
                                           int steps, limn_mpi_mesh **out,
                                           limn_series_report *report,
                                           const limn_mpi_options *mpi, limn_mpi_result *result);

/* limn_denoise_features on a distributed mesh, no rank holding the whole
   mesh: each rank filters the normals of its face block and fits its
   vertex block, the faces and vertices around them refreshed from their
   owners between the steps; *out has the same blocks and faces and the
   single process's bits (keep_volume as limn_mpi_mesh_denoise's). Options,
   checks and report as limn_denoise_features; keep_piece is ignored. */
LIMN_API limn_status limn_mpi_mesh_denoise_features(limn_context *ctx, const limn_mpi_mesh *mesh,
                                                    const limn_feature_options *options,
                                                    limn_mpi_mesh **out,
                                                    limn_series_report *report,
                                                    const limn_mpi_options *mpi,
                                                    limn_mpi_result *result);

/* limn_bands on a distributed mesh: bands[i] (count + 1 entries, the
   caller's array; the caller destroys each) gets band i as a distributed
   mesh with the input's blocks and faces and the band's vectors as its
   positions, bands[count] the remainder; energy (count + 1 doubles, may be
   NULL) the same on every rank. Bands and energies are the single
   process's bits (the energies summed in its device's order, the running
   sums passed from rank to rank). On failure every bands[i] is NULL. */
LIMN_API limn_status limn_mpi_mesh_bands(limn_context *ctx, const limn_mpi_mesh *mesh,
                                         const limn_series_options *options, int count,
                                         limn_mpi_mesh **bands, double *energy,
                                         limn_series_report *report,
                                         const limn_mpi_options *mpi, limn_mpi_result *result);

/* limn_morph on distributed meshes (FROM's operator rows built as
   limn_mpi_mesh_smooth builds them; TO may have other blocks): fn is called
   on every rank, once per frame in order, with the frame as a distributed
   mesh of FROM's blocks and faces (valid during the call; write it with
   limn_mpi_mesh_write, collective) and limn_morph's measures, the same on
   every rank (measures->positions: this rank's block). The frames and the
   measures are the single process's bits. A failure of fn on any rank
   stops every rank. options->linear blends the blocks. */
typedef limn_status (*limn_mpi_morph_frame_fn)(void *user, const limn_mpi_mesh *frame,
                                               const limn_morph_frame *measures);
LIMN_API limn_status limn_mpi_mesh_morph(limn_context *ctx, const limn_mpi_mesh *from,
                                         const limn_mpi_mesh *to,
                                         const limn_morph_options *options,
                                         limn_mpi_morph_frame_fn fn, void *user,
                                         limn_series_report *report,
                                         const limn_mpi_options *mpi, limn_mpi_result *result);

/* limn_texture on a distributed mesh: the levels refined as
   limn_mpi_mesh_subdivide refines them, each level's noise interpolated by
   a distributed solve, the controls carried down the levels and the limit
   taken rank by rank; *surface gets G_L on its limit with per-vertex
   colours (even vertex blocks), whose PLY file (limn_mpi_mesh_write) is the
   single process's bytes. options (never NULL: there are no default
   colours) as limn_texture's; max_memory is not checked (as
   limn_mpi_mesh_subdivide). mpi and result may be NULL. */
LIMN_API limn_status limn_mpi_mesh_texture(limn_context *ctx, const limn_mpi_mesh *mesh,
                                           const limn_texture_options *options,
                                           limn_mpi_mesh **surface, limn_series_report *report,
                                           const limn_mpi_options *mpi, limn_mpi_result *result);

/* limn_subdivide on a distributed mesh: every level refined rank by rank
   (each rank refines the faces around its vertex block and keeps its own
   points, numbered as one process numbers them), the limit (options->limit)
   a last product; *surface gets the refined distributed mesh (even vertex
   blocks, the children of each rank's face block), whose file
   (limn_mpi_mesh_write) is the single process's bytes. options->max_memory
   is not checked (no rank holds the whole estimate's arrays); report as
   limn_subdivide's with estimated_bytes 0. mpi and result may be NULL. */
LIMN_API limn_status limn_mpi_mesh_subdivide(limn_context *ctx, const limn_mpi_mesh *mesh,
                                             const limn_subdivide_options *options,
                                             limn_mpi_mesh **surface,
                                             limn_subdivide_report *report,
                                             const limn_mpi_options *mpi,
                                             limn_mpi_result *result);

#ifdef __cplusplus
}
#endif
#endif
