/* SPDX-License-Identifier: MIT */
/*
 * limn — interpolating subdivision surfaces and mesh series on OpenCL.
 *
 * Conventions of this API:
 *  - every object is an opaque handle created and destroyed by the caller;
 *  - every call that can fail returns a limn_status and leaves a readable
 *    message in its limn_context (limn_context_message);
 *  - there is no global state: two contexts never share anything;
 *  - a context may be used by one thread at a time; contexts share nothing
 *    but the process-wide thread-count decision (limn_context_set_threads).
 *
 * Ownership (README "Embedding limn"):
 *  - arrays passed in (positions, faces, colours, options) are read during
 *    the call only and copied where kept: free or reuse them on return;
 *  - arrays passed out (double *out, bands, energy, rgb, limn_mesh_copy_*)
 *    belong to the caller, are written during the call only (sizes given per
 *    call) and never kept; a refused call writes nothing into them;
 *  - handles returned through **out belong to the caller (*_destroy); a mesh
 *    does not refer to the context that made it: destroy them in any order;
 *  - pointers from accessors (limn_mesh_positions, _face_offsets, ...) point
 *    into the mesh: valid until it is destroyed, repaired (faces) or given
 *    new colours (colours); limn_mesh_set_positions keeps them valid;
 *  - strings from a context (message, warnings, device name) are valid until
 *    its next call or its destruction.
 *
 * The ABI rule (README "Embedding limn"): every options and report struct
 * the caller allocates begins with `size_t size`, its sizeof as the caller
 * was compiled, so fields can be added at the end without breaking programs
 * built against an older limn.h:
 *  - options: fill them with their limn_*_options_default(), which sets
 *    size, then change fields. The library refuses (LIMN_ERR_ARGUMENT,
 *    naming the struct and the defaults function) a size of 0, one smaller
 *    than the first released layout (this one) and one larger than its own
 *    whose extra bytes are not all zero (an option it does not have); a
 *    smaller older size gets the defaults for the fields it lacks. A struct
 *    embedded in another (`series` in morph and texture options) has its
 *    own size, set by the outer defaults function.
 *  - reports and results (limn_report, limn_*_report, limn_mesh_info,
 *    limn_mesh_measures, limn_mesh_comparison, limn_mpi_result): zero them
 *    and set size before the call, e.g. `limn_report r = {.size = sizeof r};`
 *    (limn_mpi_result: also stats.size). The library writes no byte past
 *    size and zeroes the bytes beyond its own layout; a size of 0 or one
 *    smaller than sizeof(size_t) is refused before any work.
 *  - limn_morph_frame (made by the library for the callback) and limn_noise
 *    carry no size: the first is read-only to the caller, the second fixed.
 */
#ifndef LIMN_H
#define LIMN_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

/* Marks the public API: the only symbols liblimn.so exports (the library is
   built with -fvisibility=hidden). Every function declared here carries it
   (test_exports checks). */
#if defined(__GNUC__) && __GNUC__ >= 4
#define LIMN_API __attribute__((visibility("default")))
#else
#define LIMN_API
#endif

#ifdef __cplusplus
extern "C" {
#endif

#define LIMN_VERSION_MAJOR 0
#define LIMN_VERSION_MINOR 1
#define LIMN_VERSION_PATCH 0

/* The library's version as "MAJOR.MINOR.PATCH" (static storage): that of the
   liblimn actually loaded, which may differ from the header's macros. */
LIMN_API const char *limn_version(void);

typedef enum limn_status {
    LIMN_OK = 0,
    LIMN_ERR_ARGUMENT = 1,     /* a bad argument or option */
    LIMN_ERR_IO = 2,           /* a file could not be opened, read or written */
    LIMN_ERR_FORMAT = 3,       /* a file is malformed */
    LIMN_ERR_TOPOLOGY = 4,     /* the mesh is not usable by the scheme */
    LIMN_ERR_MEMORY = 5,       /* an allocation failed or would exceed a limit */
    LIMN_ERR_DEVICE = 6,       /* an OpenCL failure */
    LIMN_ERR_NO_CONVERGENCE = 7, /* an iteration hit its cap */
    LIMN_ERR_SINGULAR = 8      /* the limit operator is singular (e.g. alpha=0 cube) */
} limn_status;

/* A short constant name for a status ("LIMN_ERR_FORMAT"). */
LIMN_API const char *limn_status_name(limn_status status);

/* ------------------------------------------------------------------ context */

typedef struct limn_context limn_context;

/* Creates a context. Returns NULL only when memory is exhausted. */
LIMN_API limn_context *limn_context_create(void);
LIMN_API void limn_context_destroy(limn_context *ctx);

/* The message of the last failed call on this context ("" after success). */
LIMN_API const char *limn_context_message(const limn_context *ctx);

/* Warnings accumulated by the last call (repairs made, etc.); "" if none. */
LIMN_API const char *limn_context_warnings(const limn_context *ctx);

/* Progress callback for long work: fraction in [0,1], a stage name. */
typedef void (*limn_progress_fn)(void *user, const char *stage, double fraction);
LIMN_API void limn_context_set_progress(limn_context *ctx, limn_progress_fn fn, void *user);

/*
 * The memory limit of the mesh readers, in bytes (0, the default: three
 * quarters of physical memory): limn_mesh_read stops with LIMN_ERR_MEMORY and
 * a message naming the file, line and limit as soon as what it holds (line
 * buffer, positions, faces, colours) would exceed it, so a huge or endless
 * input (a pipe, /dev/zero) cannot take the machine. A line of a text file is
 * also refused beyond 64 MiB whatever the limit. The CLI sets --max-memory.
 */
LIMN_API void limn_context_set_max_memory(limn_context *ctx, size_t bytes);

/* ------------------------------------------------------------------ devices */

typedef enum limn_backend {
    LIMN_BACKEND_OPENCL = 0,    /* default */
    LIMN_BACKEND_REFERENCE = 1  /* plain C, the oracle for the OpenCL path */
} limn_backend;

/*
 * Chooses the compute device. spec may be NULL (then the environment:
 * LIMN_PLATFORM, LIMN_DEVICE, LIMN_DEVICE_TYPE, then the first OpenCL device).
 * Forms of spec:
 *   "reference"             the C reference backend
 *   "opencl"                OpenCL, device from the environment or the first
 *   "opencl:P.D"            OpenCL platform index P, device index D
 *   "opencl:TEXT"           first OpenCL device whose name contains TEXT
 * The device is opened lazily by the first operation that needs it.
 */
LIMN_API limn_status limn_context_set_device(limn_context *ctx, const char *spec);

/* Fills buf with one line per OpenCL device ("P.D  name  (platform)  type").
   A NULL buf, a buf_size of 0 or a list that does not fit is refused. */
LIMN_API limn_status limn_list_devices(limn_context *ctx, char *buf, size_t buf_size);

/* The device that ran the last operation, in words ("" before any). */
LIMN_API const char *limn_context_device_name(const limn_context *ctx);

/*
 * Threads of the OpenCL runtime (PoCL sizes its pool from the whole machine
 * and ignores the process's CPU binding, e.g. an MPI rank's cores). Before
 * the first OpenCL platform query in the process, limn sets
 * POCL_MAX_PTHREAD_COUNT (PoCL 3.x) and POCL_CPU_MAX_CU_COUNT (PoCL 4.x) to:
 *   - nothing, when the user set either variable (the other one is set to
 *     the same value, so both PoCL generations see it);
 *   - else `threads` as given here, when > 0;
 *   - else (LIMN_THREADS_FROM_BINDING, the default) the number of cores
 *     (hwloc) with at least one CPU inside the process's binding;
 *   - LIMN_THREADS_RUNTIME_DEFAULT sets nothing: the runtime decides.
 * setenv is process wide and PoCL reads these once: the first context to
 * query a platform decides for the whole process (later requests only get a
 * warning), and the application should not call getenv/setenv from other
 * threads meanwhile. An application that initialises OpenCL itself before
 * limn must set the variables itself.
 */
#define LIMN_THREADS_FROM_BINDING 0
#define LIMN_THREADS_RUNTIME_DEFAULT (-1)
LIMN_API limn_status limn_context_set_threads(limn_context *ctx, int threads);

/*
 * The thread count in effect and where it came from: "binding via hwloc",
 * "API", "POCL_MAX_PTHREAD_COUNT", "POCL_CPU_MAX_CU_COUNT", "OpenCL runtime
 * default ..." (threads 0: the runtime chose), or "reference backend" (1)
 * when ctx's device is the C backend. Before any platform query: 0 and a
 * source saying so. *source is static storage, valid for the process.
 */
LIMN_API limn_status limn_context_threads(const limn_context *ctx, int *threads,
                                          const char **source);

/*
 * Threads limn's own host code uses (reading, topology, stencil rows,
 * writing): `threads` > 0 as given; 0 (the default) the count
 * limn_context_set_threads gave, else the cores (hwloc) inside the process's
 * CPU binding, the count PoCL gets. Results are the same bytes for any count.
 */
LIMN_API limn_status limn_context_set_host_threads(limn_context *ctx, int threads);
/* The host thread count in effect and where it came from ("API (host
   threads)", "API", "binding via hwloc", "affinity mask"); *source is static. */
LIMN_API limn_status limn_context_host_threads(limn_context *ctx, int *threads,
                                               const char **source);

/*
 * Whether the C reference backend may stand in when the OpenCL device cannot
 * be used: backend "reference" allows it, "none" (or NULL) forbids it.
 * Default: the environment LIMN_FALLBACK=reference, else none. When allowed,
 * an OpenCL device that cannot be opened (no platform, no matching device, a
 * kernel build failure) gives way to the reference backend with a warning.
 */
LIMN_API limn_status limn_context_set_fallback(limn_context *ctx, const char *backend);

/*
 * After an operation failed with `status`: when the failure came from the
 * OpenCL device (LIMN_ERR_DEVICE, or device memory exhausted) and the
 * fallback is allowed, switches the context to the reference backend, adds a
 * warning saying so and returns LIMN_OK: run the operation again. Otherwise
 * returns status unchanged.
 */
LIMN_API limn_status limn_context_fall_back(limn_context *ctx, limn_status status);

/*
 * A STREAM-like triad on the context's device (OpenCL or the reference
 * backend), the memory-bandwidth yardstick of `limn bench`: three arrays of
 * `bytes` bytes each (rounded down to whole 4-double records; at least 32
 * bytes), a[i] = b[i] + s c[i] in double, run `repeats` times (1..1000).
 * gb_per_s is STREAM's count, 3 x 8 bytes per element over the best run's
 * seconds. Each run is one kernel launch and a 32-byte blocking read of a
 * (the wait); the device's one-time set-up and each kernel's first launch
 * are done before the first timed run. After the runs a is read back and
 * every element compared with b[i] + s c[i] computed on the host:
 * `mismatches` counts the elements that differ (0 on a working device).
 * Buffers above the device's largest allocation or memory are refused
 * (LIMN_ERR_MEMORY, LIMN_ERR_DEVICE), naming the size. report is required.
 */
typedef struct limn_triad_report {
    size_t size;              /* sizeof, set by the caller (see the top) */
    size_t elements;          /* doubles per array */
    size_t array_bytes;       /* 8 x elements */
    int repeats;
    double seconds_best, seconds_mean; /* per run */
    double gb_per_s;          /* 24 x elements / seconds_best / 1e9 */
    size_t mismatches;        /* elements of a that differ from b + s c */
    char device[256];
} limn_triad_report;

LIMN_API limn_status limn_device_triad(limn_context *ctx, size_t bytes, int repeats,
                                       limn_triad_report *report);

/* --------------------------------------------------------------------- mesh */

typedef struct limn_mesh limn_mesh;

/*
 * Makes a mesh from caller arrays (copied). positions: 3 doubles per vertex,
 * all finite (else refused naming the first vertex, its axis and value).
 * face_offsets: face_count + 1 entries, face_offsets[0] = 0; face f uses
 * face_indices[face_offsets[f] .. face_offsets[f+1]). Indices are 0-based.
 */
LIMN_API limn_status limn_mesh_create(limn_context *ctx, size_t vertex_count,
                                      const double *positions, size_t face_count,
                                      const uint32_t *face_offsets,
                                      const uint32_t *face_indices, limn_mesh **out);
LIMN_API limn_status limn_mesh_copy(limn_context *ctx, const limn_mesh *mesh, limn_mesh **out);
LIMN_API void limn_mesh_destroy(limn_mesh *mesh);

LIMN_API size_t limn_mesh_vertex_count(const limn_mesh *mesh);
LIMN_API size_t limn_mesh_face_count(const limn_mesh *mesh);
LIMN_API const double *limn_mesh_positions(const limn_mesh *mesh);     /* 3 per vertex */
/* Positions written here are checked by the next call that uses them. */
LIMN_API double *limn_mesh_positions_mutable(limn_mesh *mesh);
LIMN_API const uint32_t *limn_mesh_face_offsets(const limn_mesh *mesh);
LIMN_API const uint32_t *limn_mesh_face_indices(const limn_mesh *mesh);
/* Per-vertex RGB colours (3 bytes per vertex), or NULL when the mesh has none. */
LIMN_API const uint8_t *limn_mesh_colors(const limn_mesh *mesh);
/* Copies 3 * vertex_count bytes from rgb (NULL removes the colours). */
LIMN_API limn_status limn_mesh_set_colors(limn_context *ctx, limn_mesh *mesh, const uint8_t *rgb);
/* Entries of face_indices: face_offsets[face_count]. */
LIMN_API size_t limn_mesh_index_count(const limn_mesh *mesh);

/*
 * Results into the caller's own arrays. Each copies the whole of the mesh's
 * data; capacities count what the caller's buffer holds (vertices for
 * positions, 3 doubles each, and colours, 3 bytes each; uint32 entries for
 * faces: limn_mesh_face_count + 1 offsets, limn_mesh_index_count indices).
 * A buffer too small, a NULL or (colours) a mesh without colours is refused
 * with LIMN_ERR_ARGUMENT and a message, and nothing is written.
 */
LIMN_API limn_status limn_mesh_copy_positions(limn_context *ctx, const limn_mesh *mesh,
                                              double *dst, size_t capacity_vertices);
LIMN_API limn_status limn_mesh_copy_faces(limn_context *ctx, const limn_mesh *mesh,
                                          uint32_t *offsets, size_t offsets_capacity,
                                          uint32_t *indices, size_t indices_capacity);
LIMN_API limn_status limn_mesh_copy_colors(limn_context *ctx, const limn_mesh *mesh,
                                           uint8_t *dst, size_t capacity_vertices);
/*
 * New positions for the same vertices (vertex_count must be the mesh's; all
 * finite), copied in place: run an operation again on moved vertices without
 * making a new mesh. Refused, with the mesh unchanged, otherwise.
 */
LIMN_API limn_status limn_mesh_set_positions(limn_context *ctx, limn_mesh *mesh,
                                             const double *positions, size_t vertex_count);

typedef enum limn_format {
    LIMN_FORMAT_AUTO = 0,        /* from the file name's extension */
    LIMN_FORMAT_OBJ,
    LIMN_FORMAT_PLY,             /* reading: any PLY; writing: binary little endian */
    LIMN_FORMAT_PLY_ASCII,
    LIMN_FORMAT_PLY_BINARY_BE,
    LIMN_FORMAT_OFF,
    LIMN_FORMAT_STL              /* reading: ascii or binary; writing: binary */
} limn_format;

/* "obj", "ply", "ply-ascii", "ply-be", "off", "stl" -> format; 0 if unknown. */
LIMN_API int limn_format_from_name(const char *name, limn_format *out);

/* Format from a file name's extension (.obj .ply .off .stl, any case); 0 if none. */
LIMN_API int limn_format_from_path(const char *path, limn_format *out);

/*
 * Reads OBJ, PLY (ascii, binary LE/BE, faces or tristrips), OFF or STL
 * (ascii or binary, told apart by content; corners with exactly equal
 * coordinates are welded into one vertex, with a warning giving the counts).
 * Malformed files are refused with a message "PATH:LINE: ..." (text) or
 * "PATH: byte N: ..." (binary); counts in a header are checked against the
 * file size before anything is allocated. Text is read the same whatever the
 * process locale (numbers always with a '.'), with or without a UTF-8 byte
 * order mark, with LF, CRLF or CR-only line ends. A path that is not a regular
 * file (a pipe, a device: its size is unknown) is read only when format is
 * given (not LIMN_FORMAT_AUTO); the limit of limn_context_set_max_memory
 * bounds what it may cost.
 */
LIMN_API limn_status limn_mesh_read(limn_context *ctx, const char *path, limn_format format,
                                    limn_mesh **out);
/*
 * Reads a mesh from an already open stream (standard input, a pipe, a
 * socket), from its current position to its end. format must be given (a
 * stream has no extension: LIMN_FORMAT_AUTO is refused); name (may be NULL)
 * stands for the file in messages. The stream stays the caller's: it is
 * neither closed nor rewound.
 */
LIMN_API limn_status limn_mesh_read_stream(limn_context *ctx, FILE *stream, const char *name,
                                           limn_format format, limn_mesh **out);
/*
 * Writes the mesh. A regular file appears whole or not at all: data goes to
 * a temporary file (.NAME.limn-tmp.PID.XXXXXX) beside it which is then
 * renamed over it, keeping the replaced file's mode (and owner and group
 * where the process may set them); stale temporaries of dead processes are
 * removed. A symlink is followed and the file it names replaced (the link
 * stays). "-" (or /dev/stdout) is standard output; a FIFO or a character
 * device is written straight through (not atomic). A directory is refused.
 * Numbers are written in the C locale whatever the process locale.
 * Refused, with nothing written, what limn_mesh_read would not read back: a
 * non-finite coordinate (naming the vertex), a mesh without vertices, and
 * STL for a mesh without faces (STL holds nothing but triangles).
 */
LIMN_API limn_status limn_mesh_write(limn_context *ctx, const limn_mesh *mesh,
                                     const char *path, limn_format format);

/* How positions are written: doubles (lossless, the default) or float32. */
typedef enum limn_output_precision {
    LIMN_OUTPUT_DOUBLE = 0, /* every format; lossless */
    LIMN_OUTPUT_FLOAT = 1   /* PLY only ("property float x"; ascii: "%.17g" of the float) */
} limn_output_precision;

typedef struct limn_write_options {
    size_t size;                     /* sizeof, set by limn_write_options_default() */
    limn_output_precision precision; /* LIMN_OUTPUT_DOUBLE (default) or _FLOAT */
} limn_write_options;

LIMN_API void limn_write_options_default(limn_write_options *options);

/* The error of the file as written: per vertex, the distance between its
   position and the one written (float32 rounding; 0 for doubles). */
typedef struct limn_write_report {
    size_t size;          /* sizeof, set by the caller */
    double max_error;     /* the largest distance */
    double mean_error;    /* the mean distance over the vertices */
    double bbox_diagonal; /* the mesh's, to make them relative */
} limn_write_report;

/*
 * limn_mesh_write with options (NULL: the defaults, as limn_mesh_write) and
 * a report (may be NULL). LIMN_OUTPUT_FLOAT for a format other than PLY is
 * refused (LIMN_ERR_ARGUMENT), nothing written.
 */
LIMN_API limn_status limn_mesh_write_with(limn_context *ctx, const limn_mesh *mesh,
                                          const char *path, limn_format format,
                                          const limn_write_options *options,
                                          limn_write_report *report);

/* ------------------------------------------------------------------- repair */
/*
 * The repair step for meshes from scans and unknown tools, run by the CLI
 * after reading (README "Meshes limn accepts"). Every change is reported as
 * a warning (limn_context_warnings) saying what was changed; the defaults
 * let real scans through.
 */
typedef struct limn_repair_options {
    size_t size;              /* sizeof, set by limn_repair_options_default() */
    int repeated_vertices;    /* faces using a vertex twice: 1 repair (default), 0 refuse */
    int duplicate_faces;      /* faces with an earlier face's vertices: 0 keep (default), 1 remove */
    int sub_meshes;           /* limn_mpi_mesh_repair only (limn_mesh_repair ignores it; added
                                 after duplicate_faces): 1 (default) counts from every rank's
                                 sub-mesh under the curve partition and leaves them on the mesh
                                 for the next call that builds rows (interpolate, the series),
                                 which skips its own partition and face exchange; 0 counts by
                                 exchanges and leaves nothing: for calls that build no rows
                                 (subdivide, texture, denoise_features), which would pay for
                                 sub-meshes they drop */
    int keep_topology;        /* limn_mesh_repair only (added after sub_meshes): 1 (default)
                                 counts from the mesh's topology and leaves it on the mesh for
                                 the next call that reads it (an operator, the series,
                                 limn_mesh_info_compute, measure, refinement): one topology
                                 a run; 0 counts by a census (the same counts, about a third
                                 of the memory, no edge arrays) and leaves only the counts:
                                 for a run that reads nothing else (`limn info`) */
} limn_repair_options;

LIMN_API void limn_repair_options_default(limn_repair_options *options);

typedef struct limn_repair_report {
    size_t size;              /* sizeof, set by the caller (see the top) */
    size_t faces_before, faces_after;
    size_t repeat_faces;      /* faces that used a vertex more than once, of which: */
    size_t repeats_removed;   /*   lost a repeated corner (a a -> a) */
    size_t faces_split;       /*   were split where a vertex came back */
    size_t degenerate_removed;/*   had fewer than 3 distinct vertices: removed */
    size_t first_repeat_face; /* input numbering; valid when repeat_faces > 0 */
    uint32_t first_repeat_vertex;
    size_t duplicate_faces;   /* faces with the vertex set of an earlier face */
    size_t duplicates_removed;
    size_t first_duplicate_face, first_duplicate_of; /* valid when duplicate_faces > 0 */
    /* found and kept (processed by OpenSubdiv's rules) */
    size_t nonmanifold_edges; /* with more than two faces */
    size_t nonmanifold_vertices, inconsistent_edges, unreferenced_vertices;
    size_t components, boundary_loops;
} limn_repair_report;

/*
 * Repairs mesh in place: faces that use a vertex more than once lose their
 * consecutive repeats, are split where a vertex comes back, and are removed
 * when fewer than 3 distinct vertices are left (orientation is kept); with
 * options->duplicate_faces, later copies of a face are removed. Non-manifold
 * edges and vertices, inconsistent orientation and unreferenced vertices are
 * kept and reported. With repeated_vertices = 0 a face using a vertex twice
 * is refused (LIMN_ERR_TOPOLOGY, naming it). options and report may be NULL.
 */
LIMN_API limn_status limn_mesh_repair(limn_context *ctx, limn_mesh *mesh,
                                      const limn_repair_options *options,
                                      limn_repair_report *report);

/* ----------------------------------------------------------------- topology */

typedef struct limn_mesh_info {
    size_t size;              /* sizeof, set by the caller (see the top) */
    size_t vertices, faces, edges;
    size_t referenced_vertices;   /* used by at least one face */
    size_t boundary_edges, boundary_loops;
    size_t nonmanifold_edges, nonmanifold_vertices;
    size_t inconsistent_edges;    /* two faces disagree on orientation */
    size_t components;            /* of the faces (sharing a vertex) */
    size_t triangles, quads, other_faces;
    size_t max_face_size, max_valence;
    long euler_characteristic;    /* referenced V - E + F */
    double bbox_min[3], bbox_max[3];
    double bbox_diagonal;
} limn_mesh_info;

/* The mesh's counts: from the topology limn_mesh_repair left on it, else
   from its census (the counts alone, kept on the mesh until its faces
   change; no topology is built). */
LIMN_API limn_status limn_mesh_info_compute(limn_context *ctx, const limn_mesh *mesh,
                                            limn_mesh_info *info);

/* -------------------------------------------------------------- interpolate */

typedef enum limn_scheme {
    LIMN_SCHEME_AUTO = 0,      /* Loop for all-triangle meshes, else Catmull-Clark */
    LIMN_SCHEME_LOOP = 1,
    LIMN_SCHEME_CATMARK = 2
} limn_scheme;

LIMN_API const char *limn_scheme_name(limn_scheme scheme);  /* "loop", "catmark", "auto" */

typedef enum limn_method {
    LIMN_METHOD_AUTO = 0,      /* the default: the fastest as measured (README "Solvers") */
    LIMN_METHOD_PAPER = 1,     /* the seeds' iteration P += M - A P, the reference */
    LIMN_METHOD_WEIGHTED = 2,  /* P += w (M - A P), w = 2 / (lambda_min + 1) estimated */
    LIMN_METHOD_CG = 3,        /* tiered, D-preconditioned conjugate gradients */
    LIMN_METHOD_CHEBYSHEV = 4, /* Chebyshev iteration on [a, 1], one fused step a product */
    LIMN_METHOD_SGS = 5        /* tiered CG preconditioned by symmetric Gauss-Seidel
                                  (multicolour sweeps, Eisenstat's form): fewest products */
} limn_method;

/* "paper", "weighted", "cg", "chebyshev", "sgs", "auto" */
LIMN_API const char *limn_method_name(limn_method method);

typedef enum limn_precision {
    LIMN_PRECISION_AUTO = 0,   /* the default: float where it measured faster (README "Precision") */
    LIMN_PRECISION_DOUBLE = 1, /* every product in double */
    LIMN_PRECISION_FLOAT = 2   /* mixed: residuals of P in double, corrections iterated in
                                  float; the tolerance still holds, measured in double */
} limn_precision;

/* "double", "float", "auto" */
LIMN_API const char *limn_precision_name(limn_precision precision);

typedef struct limn_interpolate_options {
    size_t size;              /* sizeof, set by limn_interpolate_options_default() */
    limn_scheme scheme;       /* default LIMN_SCHEME_AUTO */
    double alpha;             /* Catmull-Clark alpha in [0, 1]; default 0 */
    double tolerance;         /* max |M - A P| / bbox diagonal; default 1e-6 */
    int max_iterations;       /* default 1000; at most LIMN_MAX_ITERATIONS */
    int reorder;              /* renumber vertices for locality (RCM) inside the
                                 solve; results stay in input order; default 1 */
    limn_method method;       /* default LIMN_METHOD_AUTO */
    limn_precision precision; /* default LIMN_PRECISION_AUTO; float runs with every
                                 method but cg */
} limn_interpolate_options;

LIMN_API void limn_interpolate_options_default(limn_interpolate_options *options);

/* The cap on max_iterations: a larger value is refused (LIMN_ERR_ARGUMENT,
   naming it), as every count below is beyond its cap; no solve needs more. */
#define LIMN_MAX_ITERATIONS 10000000

typedef struct limn_report {
    size_t size;              /* sizeof, set by the caller (see the top) */
    size_t vertices, faces;
    limn_scheme scheme;       /* the scheme that ran (never AUTO) */
    double alpha;
    const char *method;       /* the method that ran: "paper", "weighted", "cg" */
    const char *method_reason; /* why that one, in words */
    double products;          /* stencil products, in units of one full A P */
    double omega;             /* the weight of the weighted iteration (1 for paper) */
    double spectrum_lower;    /* chebyshev: the lower bound a of [a, 1] it ended with */
    int restarts;             /* chebyshev: restarts after lowering a */
    int iterations;           /* updates applied to P */
    double max_abs_error, mean_abs_error;   /* of the returned P: |M - A P| */
    double max_rel_error, mean_rel_error;   /* the same over the bbox diagonal */
    double bbox_diagonal;
    char device[256];
    size_t stencil_nonzeros;
    int reordered;            /* 1 when the solve ran in RCM order */
    double seconds_topology, seconds_stencil, seconds_solve;
    double seconds_iterations; /* of seconds_solve, the iteration loop alone: products and
                                  their reductions, no buffer set-up, packing or output (cg,
                                  sgs: their steps and the final check; not their blocks',
                                  tables' and vectors' set-up) */
    const char *precision;    /* the precision that ran: "double" or "float" */
    const char *precision_reason; /* why that one, in words */
    double products_float;    /* of `products`, those run in float */
    /* OpenCL set-up during this call (zero on the reference backend, or when
       the context's device was open and its kernels compiled already):
       platform query and device choice, context and queue, program build
       (from PoCL's kernel cache when warm), and the compiles on each
       kernel's first launch. seconds_solve leaves the last out. */
    double seconds_opencl_platform, seconds_opencl_context, seconds_opencl_build,
        seconds_opencl_kernels;
    /* Of seconds_solve, what follows the last loop: the read-back of P and
       the control mesh made from it (0 on several ranks). What precedes the
       loops, packing M and the buffers, is seconds_solve minus
       seconds_iterations minus this. */
    double seconds_solve_finish;
} limn_report;

/*
 * Solves A P = M for the control mesh P whose limit surface passes through
 * every vertex of M (same topology as M). On success *control is a new mesh.
 * Like every operation that computes with positions (subdivide, limit
 * positions, the series, texture, render), it refuses with LIMN_ERR_ARGUMENT,
 * naming the first vertex, a non-finite coordinate (e.g. written through
 * limn_mesh_positions_mutable), and coordinates so large that their sum of
 * squares or squared bbox diagonal exceeds DBL_MAX / 2^20 (overflow: one
 * coordinate of 1.3e151, or a million of 1.3e148).
 * Fails with LIMN_ERR_SINGULAR or LIMN_ERR_NO_CONVERGENCE (and no mesh) when
 * the tolerance cannot be reached; the message says what to do.
 * report may be NULL.
 */
LIMN_API limn_status limn_interpolate(limn_context *ctx, const limn_mesh *mesh,
                                      const limn_interpolate_options *options,
                                      limn_mesh **control, limn_report *report);

/*
 * Predicts the peak memory of limn_interpolate on mesh (bytes, host and
 * device together: measured per vertex and per stencil entry, the entries
 * counted from the faces, plus the OpenCL runtime; docs/robustness.md
 * "Memory") and refuses with LIMN_ERR_MEMORY, naming the sizes, when it exceeds
 * max_memory (0 = three quarters of physical memory). peak_bytes may be NULL.
 */
LIMN_API limn_status limn_interpolate_estimate(limn_context *ctx, const limn_mesh *mesh,
                                               const limn_interpolate_options *options,
                                               size_t max_memory, size_t *peak_bytes);

/* -------------------------------------------------------------- subdivide */

typedef struct limn_subdivide_options {
    size_t size;              /* sizeof, set by limn_subdivide_options_default() */
    limn_scheme scheme;       /* default LIMN_SCHEME_AUTO */
    double alpha;             /* Catmull-Clark alpha of the first step; default 0 */
    int levels;               /* uniform refinement levels, 0..LIMN_MAX_SUBDIVIDE_LEVELS
                                 (16); default 1 */
    int limit;                /* move the finest vertices to their limit points */
    size_t max_memory;        /* bytes; 0 = three quarters of physical memory */
} limn_subdivide_options;

LIMN_API void limn_subdivide_options_default(limn_subdivide_options *options);

/* levels above this are refused; max_memory refuses most meshes well before */
#define LIMN_MAX_SUBDIVIDE_LEVELS 16

typedef struct limn_subdivide_report {
    size_t size;              /* sizeof, set by the caller (see the top) */
    size_t input_vertices, input_faces;
    size_t vertices, faces;   /* of the surface written */
    limn_scheme scheme;
    double alpha;
    int levels, limit;
    size_t estimated_bytes;   /* predicted peak, checked against max_memory */
    size_t stencil_nonzeros;  /* of all step tables */
    char device[256];
    double seconds_plan, seconds_apply, seconds_limit;
} limn_subdivide_report;

/*
 * Refines mesh uniformly `levels` times (Catmull-Clark: quads after the first
 * step; Loop: triangles). Vertex i of the input is vertex i of the result;
 * then (Catmull-Clark) one vertex per face of each level, then one per edge.
 * With alpha > 0 the alpha vertex rule is used on the first step only, so the
 * surface is the one whose limit points limn_interpolate matched. Refuses with
 * LIMN_ERR_MEMORY, before allocating, when the predicted peak exceeds
 * max_memory. report may be NULL.
 */
/* Vertex colours are not carried to the refined vertices: a warning says so. */
LIMN_API limn_status limn_subdivide(limn_context *ctx, const limn_mesh *mesh,
                                    const limn_subdivide_options *options, limn_mesh **surface,
                                    limn_subdivide_report *report);

/*
 * Predicts what limn_subdivide would make: vertex and face counts and the
 * peak memory in bytes. Returns LIMN_ERR_MEMORY (with the message) when the
 * peak exceeds options->max_memory, so callers can refuse before any work.
 */
LIMN_API limn_status limn_subdivide_estimate(limn_context *ctx, const limn_mesh *mesh,
                                             const limn_subdivide_options *options,
                                             size_t *vertices, size_t *faces,
                                             size_t *peak_bytes);

/* Limit positions A P of every vertex of P (written to out, 3 per vertex). */
LIMN_API limn_status limn_limit_positions(limn_context *ctx, const limn_mesh *mesh,
                                          limn_scheme scheme, double alpha, double *out);

/* ------------------------------------------------------------------- series */
/*
 * A mesh as a series (seed 000 §3, DESIGN.md §1): M = sum_i (E - A)^i A M,
 * A the limit operator of the scheme on M's topology, E the identity.
 * Band i = (E - A)^i A M: band 0 (the limit points) carries the overall
 * shape, higher bands finer detail. Each function below builds A once and
 * applies it on the context's device; "products" counts applications of A.
 */
typedef struct limn_series_options {
    size_t size;              /* sizeof, set by limn_series_options_default() */
    limn_scheme scheme;       /* default LIMN_SCHEME_AUTO */
    double alpha;             /* Catmull-Clark alpha in [0, 1]; default 0 */
} limn_series_options;

LIMN_API void limn_series_options_default(limn_series_options *options);

/*
 * Caps on the counts below, refused beyond with LIMN_ERR_ARGUMENT and a
 * message naming the argument, its value and the cap (the terms shrink
 * geometrically: far fewer than these already reach rounding):
 * LIMN_MAX_TERMS for bands' count, smooth's terms, denoise's and morph's m
 * and sharpen's `to`; LIMN_MAX_STEPS for denoise's and sharpen's steps;
 * LIMN_MAX_PRODUCTS for a call's stencil products ((m + 1) * steps, to *
 * steps, (m + 1) * (frames - 1)); LIMN_MAX_FRAMES for morph's frames;
 * LIMN_MAX_SURE_PRODUCTS for limn_denoise_sure's products (each a copy of
 * the positions held; past ~30 the Krylov vectors are parallel to rounding).
 */
#define LIMN_MAX_TERMS 10000
#define LIMN_MAX_SURE_PRODUCTS 64
#define LIMN_MAX_STEPS 10000
#define LIMN_MAX_PRODUCTS 10000000
#define LIMN_MAX_FRAMES 100000

typedef struct limn_series_report {
    size_t size;              /* sizeof, set by the caller (see the top) */
    size_t vertices, faces;
    limn_scheme scheme;       /* the scheme that ran (never AUTO) */
    double alpha;
    char device[256];
    size_t stencil_nonzeros;
    double bbox_diagonal;
    long long products;       /* stencil products A x applied */
    double seconds_topology, seconds_stencil, seconds_compute;
} limn_series_report;

/*
 * Bands 0..count-1 and the remainder (E - A)^count M; they sum to M.
 * bands (may be NULL): (count + 1) * 3 * vertices doubles, band i at
 * i * 3 * vertices, the remainder last. energy (may be NULL): count + 1
 * values, sum over vertices of |band_i|^2 (the remainder's last).
 * report may be NULL (here and below).
 */
LIMN_API limn_status limn_bands(limn_context *ctx, const limn_mesh *mesh,
                                const limn_series_options *options, int count, double *bands,
                                double *energy, limn_series_report *report);

/* Partial sum of the first `terms` bands, = (E - (E - A)^terms) M: a new mesh. */
LIMN_API limn_status limn_smooth(limn_context *ctx, const limn_mesh *mesh,
                                 const limn_series_options *options, int terms, limn_mesh **out,
                                 limn_series_report *report);

/*
 * Seed 000 eq. 8: T_0 = M, T_{k+1} = sum_{i=0..m} (E - A)^i A T_k, `steps`
 * times ((m + 1) * steps products). With keep_volume the result is scaled
 * about the mean of its vertices to the input's volume (closed meshes only:
 * LIMN_ERR_TOPOLOGY otherwise).
 */
LIMN_API limn_status limn_denoise(limn_context *ctx, const limn_mesh *mesh,
                                  const limn_series_options *options, int m, int steps,
                                  int keep_volume, limn_mesh **out,
                                  limn_series_report *report);

/*
 * limn denoise's default: F = E + sum_{i=1..products} d_i (E - A)^i, a
 * polynomial of degree `products` in A (that many stencil products), whose
 * coefficients minimise Stein's unbiased estimate of the squared distance to
 * the unknown clean mesh for Gaussian noise of deviation sigma on every
 * coordinate; sigma is estimated from the mesh (the smallest over k of
 * |(E - A)^k M|^2 / (3 tr (E - A)^{2k}), the energy noise alone would leave)
 * and returned in *sigma (may be NULL). Then, from the same vectors (no
 * further products), the split: each vector's part along the vertex normals
 * of F M and its part across them get their own polynomial, fitted the same
 * way with their own noise estimates, so noise along the normals (a range
 * scanner's) leaves the vertices where they are along the surface
 * (docs/series.md). Both keep constants (p(1) = 1). keep_volume as for
 * limn_denoise. Holds `products` copies of the positions on the host, and
 * one more third of that while the split is fitted.
 */
LIMN_API limn_status limn_denoise_sure(limn_context *ctx, const limn_mesh *mesh,
                                       const limn_series_options *options, int products,
                                       int keep_volume, limn_mesh **out, double *sigma,
                                       limn_series_report *report);

/*
 * Feature-preserving denoising (docs/series.md "Keeping sharp features"):
 * outer_steps times, the face normals are filtered normal_steps times by a
 * face operator W (row f: the faces sharing a vertex with f) rebuilt from
 * the current normals before every product (bilateral in normals, as Zheng
 * et al. 2011: w_fj = a_j exp(-|c_f - c_j|^2 / 2 sigma_s^2)
 * exp(-|n_f - n_j|^2 / 2 sigma_r^2), rows divided by their sums, so the
 * weights are >= 0, rows sum to 1 and W's eigenvalues lie in [-1, 1]), then
 * the vertices are moved vertex_steps times to fit the filtered normals
 * (Sun et al. 2007) plus `tangential` times a pull to their faces'
 * centroids within the vertex's plane (it undoes faces the noise folded
 * over). With `adaptive` (the default) the rounds after the first take
 * their range width from the noise left: sigma_r = 1.5 x the median of
 * |n_f - n_j| over the ring (at least 0.05), with normal_steps / 2 (rounded
 * up) products each, so a smooth second pass does not erode the creases the
 * first kept. With crease_angle > 0 a crease pass follows: the edges of the
 * result whose faces' normals differ by more than crease_angle are creases,
 * W's pair (f, j) is cut unless f and j meet around a shared vertex without
 * crossing one, and the rounds run again from the input on the cut W, the
 * first with 3 products (at most normal_steps) at sigma_r 1.0: no product
 * averages across a crease. W's products run on the context's device;
 * "products" in the report counts them (both passes). Same input and options: the same bytes on either
 * backend.
 */
typedef struct limn_feature_options {
    size_t size;              /* sizeof, set by limn_feature_options_default() */
    int outer_steps;          /* filter-then-fit rounds, 1..LIMN_MAX_STEPS; default 3 */
    int normal_steps;         /* products of W a round (the first with adaptive),
                                 1..LIMN_MAX_STEPS; default 10 */
    int vertex_steps;         /* vertex-fit sweeps a round, 1..LIMN_MAX_STEPS; default 10 */
    double sigma_r;           /* range kernel width on |n_f - n_j| (the first round's with
                                 adaptive), > 0; default 0.35 */
    double sigma_s;           /* spatial kernel width; 0 (default): the mean distance
                                 between the centroids of neighbouring faces */
    double tangential;        /* the tangential pull, in [0, 1]; default 0.1 */
    int keep_volume;          /* 1: the result scaled about the mean of its vertices back to
                                 the input's volume, as limn_denoise's (closed meshes only:
                                 LIMN_ERR_TOPOLOGY otherwise); default 0 */
    int adaptive;             /* 1 (default): later rounds' sigma_r from the noise left and
                                 half the products (above); 0: sigma_r and normal_steps in
                                 every round */
    double crease_angle;      /* degrees in [0, 180); > 0 (default 30): the crease pass
                                 (above); 0: none */
} limn_feature_options;

LIMN_API void limn_feature_options_default(limn_feature_options *options);

/* A new mesh: mesh denoised with its sharp edges kept (above); report: the
   series report (scheme and stencil fields unused, products: W's). */
LIMN_API limn_status limn_denoise_features(limn_context *ctx, const limn_mesh *mesh,
                                           const limn_feature_options *options, limn_mesh **out,
                                           limn_series_report *report);

/* Seed 000: T_{k+1} = T_k + sum_{i=from..to} (E - A)^i T_k, `steps` times
   (to * steps products); 0 <= from <= to. */
LIMN_API limn_status limn_sharpen(limn_context *ctx, const limn_mesh *mesh,
                                  const limn_series_options *options, int from, int to, int steps,
                                  limn_mesh **out, limn_series_report *report);

typedef struct limn_morph_options {
    size_t size;              /* sizeof, set by limn_morph_options_default() */
    limn_series_options series;
    int frames;               /* frames written, FROM first; 2..LIMN_MAX_FRAMES; default 30 */
    int m;                    /* terms of eq. 9 minus one; default 2 */
    double p;                 /* speed, 0 < p < 1 (smaller is faster); default 0.8 */
    int linear;               /* 1: the linear blend (1 - t) FROM + t TO, t = k / (frames - 1) */
} limn_morph_options;

LIMN_API void limn_morph_options_default(limn_morph_options *options);

typedef struct limn_morph_frame {
    int index;                /* 0 .. frames - 1 */
    const double *positions;  /* 3 per vertex; valid during the callback only */
    double volume;            /* signed volume; NaN when the mesh is not closed */
    double area;
    size_t flipped_faces;     /* face normals turned more than 90 degrees from FROM's */
    double mean_distance_to_target; /* mean |Q_k - TO| over vertices / bbox diagonal of TO */
} limn_morph_frame;

/* Called once per frame, in order; a status other than LIMN_OK stops the morph
   and is returned (the callback sets the context's message). */
typedef limn_status (*limn_morph_frame_fn)(void *user, const limn_morph_frame *frame);

/*
 * Morphs FROM into TO (same topology: LIMN_ERR_TOPOLOGY naming the first
 * differing face otherwise) by seed 000 eq. 9: Q_0 = FROM,
 * Q_{k+1} = TO + p sum_{i=0..m} (E - A)^i A (Q_k - TO), computed with stencil
 * products only ((m + 1) per frame), A the operator of the shared topology.
 * Frame 0 is FROM exactly; frames approach TO geometrically (not exactly).
 */
LIMN_API limn_status limn_morph(limn_context *ctx, const limn_mesh *from, const limn_mesh *to,
                                const limn_morph_options *options, limn_morph_frame_fn fn,
                                void *user, limn_series_report *report);

/* ----------------------------------------------------------------- measures */

typedef struct limn_mesh_measures {
    size_t size;              /* sizeof, set by the caller (see the top) */
    int closed;               /* every edge has two faces of agreeing orientation */
    double volume;            /* signed volume (divergence theorem); NaN when not closed */
    double area;              /* faces fan-triangulated from their first vertex */
    double centroid[3];       /* mean of the vertices */
} limn_mesh_measures;

LIMN_API limn_status limn_mesh_measure(limn_context *ctx, const limn_mesh *mesh,
                                       limn_mesh_measures *out);

/* Signed volume and area from the faces alone, without building the topology
   (cheaper; the volume means something only where limn_mesh_measure says the
   mesh is closed). */
LIMN_API void limn_mesh_volume_area(const limn_mesh *mesh, double *volume, double *area);

/* LIMN_OK when a and b have the same vertex count and faces; otherwise
   LIMN_ERR_TOPOLOGY with a message naming the first difference. */
LIMN_API limn_status limn_mesh_same_topology(limn_context *ctx, const limn_mesh *a,
                                             const limn_mesh *b);

typedef struct limn_mesh_comparison {
    size_t size;              /* sizeof, set by the caller (see the top) */
    double mean_distance, max_distance;   /* |a_i - b_i| over vertices */
    double mean_normal_angle;             /* degrees, between face normals (Newell) */
    size_t flipped_faces;                 /* faces whose normals differ by > 90 degrees */
} limn_mesh_comparison;

/* Compares two meshes of one topology vertex by vertex and face by face. */
LIMN_API limn_status limn_mesh_compare(limn_context *ctx, const limn_mesh *a, const limn_mesh *b,
                                       limn_mesh_comparison *out);

/* ------------------------------------------------------------------ texture */

typedef struct limn_texture_options {
    size_t size;              /* sizeof, set by limn_texture_options_default() */
    limn_series_options series;
    int levels;               /* refinement levels G_1..G_levels, 0..LIMN_MAX_TEXTURE_LEVELS;
                                 default 3 */
    const uint8_t *colors;    /* RGB triples, interpolated in order; required */
    size_t color_count;       /* 1..LIMN_MAX_COLORS */
    uint64_t seed;            /* shuffles the noise's permutation; default 1 */
    double frequency;         /* noise cells across the bbox diagonal on G_0; default 4 */
    double tolerance;         /* of each level's scalar interpolation; default 1e-6 */
    size_t max_memory;        /* refuse above this predicted peak, bytes; 0 = three
                                 quarters of physical memory (as limn_subdivide) */
} limn_texture_options;

LIMN_API void limn_texture_options_default(limn_texture_options *options);

#define LIMN_MAX_TEXTURE_LEVELS 8
#define LIMN_MAX_COLORS 65536

/*
 * Procedural texture (seed 000 §5): improved Perlin noise f(2^i p)/2^i on the
 * vertices of each level G_i of the refinement, interpolated per level (the
 * scalar interpolation), carried to the finest level and summed there, taken
 * at the limit points, normalised to [0, 1] and mapped through the uniform
 * cubic B-spline that interpolates the colours (clamped to their per-channel
 * range). *out: level `levels`, positions on the limit surface, with colours.
 */
LIMN_API limn_status limn_texture(limn_context *ctx, const limn_mesh *mesh,
                                  const limn_texture_options *options, limn_mesh **out,
                                  limn_series_report *report);

/* Improved Perlin noise (Perlin 2002) with a permutation shuffled from seed. */
typedef struct limn_noise {
    uint8_t perm[512];
} limn_noise;
LIMN_API void limn_noise_init(limn_noise *noise, uint64_t seed);
LIMN_API double limn_noise_eval(const limn_noise *noise, double x, double y, double z);

/* ------------------------------------------------------------------- render */

typedef struct limn_render_options {
    size_t size;              /* sizeof, set by limn_render_options_default() */
    int width, height;        /* pixels; default 400 x 300 */
    double azimuth, elevation;/* view direction in degrees; default 30, 20 */
    int up_axis;              /* 0 = x, 1 = y, 2 = z up; default 1 */
    int flat;                 /* 1: flat shading with face normals; default 0 (smooth) */
    int supersample;          /* samples per pixel side (anti-aliasing); default 2 */
    uint8_t background[3];    /* default white */
    uint8_t color[3];         /* surface colour when the mesh has none */
} limn_render_options;

LIMN_API void limn_render_options_default(limn_render_options *options);

/* Headless z-buffer rendering, orthographic, Lambert shading with vertex
   colours when present; rgb: width * height * 3 bytes, rows top first. */
LIMN_API limn_status limn_render(limn_context *ctx, const limn_mesh *mesh,
                                 const limn_render_options *options, uint8_t *rgb);

/* Writes an 8-bit RGB PNG (own deflate encoder, no dependency), as
   limn_mesh_write writes a mesh (atomically, links followed, "-" stdout). */
LIMN_API limn_status limn_png_write(limn_context *ctx, const char *path, int width, int height,
                                    const uint8_t *rgb);

/* ------------------------------------------------------------------ outputs
 * Every file limn writes appears whole or not at all (README "Command line",
 * output rules): written under a temporary name beside its target, synced,
 * then renamed over it; "-" (standard output), FIFOs and character devices
 * are written straight through, last. A symlink's target is replaced.
 */

/* Is path standard output ("-", /dev/stdout, /dev/fd/1, /proc/self/fd/1)? */
LIMN_API int limn_output_is_stdout(const char *path);

/*
 * Checks an output before any work, so that a long run does not fail at its
 * end: refuses (LIMN_ERR_IO or LIMN_ERR_ARGUMENT, the message naming path) a
 * directory, a missing or unwritable directory, a name over the directory's
 * NAME_MAX, a link loop, another kind of special file, a replacement that a
 * sticky directory would not allow, a closed standard output. With input
 * non-NULL, also refuses (LIMN_ERR_ARGUMENT) an output that is the same
 * existing file as input, so that an input is never overwritten. Creates
 * nothing (a probe temporary file is made and removed).
 */
LIMN_API limn_status limn_output_check(limn_context *ctx, const char *path, const char *input);

/*
 * A set of outputs staged together and made to appear together: each add
 * writes one output completely (synced, under its temporary name) without
 * making it appear; limn_output_set_commit then renames them all in the
 * order added (under a flock of their directories, so that concurrent runs
 * never interleave their sets) and writes the straight-through ones. After
 * a failure nothing more appears and the staged files are removed; a
 * destroyed set that was not committed leaves every target as it was.
 *
 * Ownership: the set belongs to the caller (limn_output_set_destroy, also
 * after a commit); the data of an add is read during the call only. A set
 * holds up to 2^24 outputs (a few hundred bytes of memory each while
 * staged; a straight-through one also holds an open file); the lock is
 * taken on their first 16 distinct directories. A set is used with one
 * context at a time.
 */
typedef struct limn_output_set limn_output_set;

LIMN_API limn_status limn_output_set_create(limn_context *ctx, limn_output_set **out);
/* Stages mesh as limn_mesh_write would write it (format AUTO: from path). */
LIMN_API limn_status limn_output_set_add_mesh(limn_context *ctx, limn_output_set *set,
                                              const limn_mesh *mesh, const char *path,
                                              limn_format format);
/* limn_output_set_add_mesh with limn_mesh_write_with's options and report. */
LIMN_API limn_status limn_output_set_add_mesh_with(limn_context *ctx, limn_output_set *set,
                                                   const limn_mesh *mesh, const char *path,
                                                   limn_format format,
                                                   const limn_write_options *options,
                                                   limn_write_report *report);
/* Stages size bytes (a report, a document of the caller's own) as path. */
LIMN_API limn_status limn_output_set_add_bytes(limn_context *ctx, limn_output_set *set,
                                               const char *path, const void *data,
                                               size_t size);
/* Stages the picture as limn_png_write would write it (limn_render's rgb). */
LIMN_API limn_status limn_output_set_add_png(limn_context *ctx, limn_output_set *set,
                                             const char *path, int width, int height,
                                             const uint8_t *rgb);
/* Number of outputs staged and not yet committed. */
LIMN_API int limn_output_set_count(const limn_output_set *set);
/* Makes every staged output appear; returns the first failure (the outputs
   after it are dropped). The set is left empty and may be reused. */
LIMN_API limn_status limn_output_set_commit(limn_context *ctx, limn_output_set *set);
/* Drops whatever is staged (targets untouched) and frees the set; NULL is fine. */
LIMN_API void limn_output_set_destroy(limn_output_set *set);

#ifdef __cplusplus
}
#endif
#endif
