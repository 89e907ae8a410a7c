/* SPDX-License-Identifier: MIT */
/*
 * The text readers' fast path (OBJ, OFF, ASCII PLY; text_fast.c): the file
 * mapped, split at line ends into one byte range per host thread
 * (base/parallel.h), each range parsed into its own buffers, then the
 * counts prefix-summed and the buffers copied into the mesh arrays in file
 * order, so the mesh is the same for any thread count. A format gives a
 * line function for the lines it knows; anything else (a line it does not
 * know, a number strtod refuses, a NUL byte, a lone '\r', a long line, an
 * OBJ continuation, too few records, the memory limit) makes the whole
 * path give up with nothing changed, and the general reader reads the file
 * and gives its messages and warnings. The test-only LIMN_TEST_TEXT_GENERAL=1
 * turns the path off.
 */
#ifndef LIMN_MESH_IO_TEXT_FAST_H
#define LIMN_MESH_IO_TEXT_FAST_H

#include "base/growbuf.h"
#include "base/parallel.h"
#include "mesh/io/toolkit.h"

#include <stddef.h>
#include <stdint.h>

/* One range's results. */
typedef struct tf_chunk {
    growbuf pos, col, off, idx; /* off: each face's end in idx, local to the range */
    growbuf_budget budget;      /* this range's share of the memory limit */
    uint64_t lines;             /* '\n' in the range (up to the stop, when it is here) */
    uint64_t records;           /* content lines (not blank, not a '#' comment) */
    uint64_t max_ref;           /* OBJ: the largest vertex number used (from 1) */
    size_t stop;                /* positional: file offset after the last record, or 0 */
} tf_chunk;

typedef struct tf_text tf_text;

/* Parses the content line [s, e) (s at its first non-space byte; e at the
   '\n' or the end of the file; a '\r' may end it), number `record` of the
   body's content lines, into c; 0 gives up. */
typedef int (*tf_line_fn)(const tf_text *t, tf_chunk *c, const char *s, const char *e,
                          uint64_t record);

struct tf_text {
    /* set by the format */
    tf_line_fn line;
    const void *format;         /* the format's own state, for line */
    int obj;                    /* every line read, to the end: a final '\n' and no '\' ends */
    int hash_comments;          /* a line starting with '#' is a comment */
    uint64_t records;           /* positional formats: content lines to read */
    uint32_t nv;                /* positional formats: the vertex count (indices below it) */
    int colors;                 /* line pushes 3 colour bytes per vertex */
    /* the engine's */
    limn_context *ctx;
    const char *map;
    size_t size, begin;
    unsigned parts;
    size_t cut[PARALLEL_MAX + 1];
    uint64_t first[PARALLEL_MAX + 1]; /* content lines before each range */
    tf_chunk chunk[PARALLEL_MAX];
    int pass;
};

/* Whether the fast path may run (LIMN_TEST_TEXT_GENERAL unset or "0"). */
int tf_enabled(void);
/* Runs t over r's file from the reader's offset. 1: a holds the mesh arrays
   (charged to r's budget) and r has moved past what was read (its line
   count too); 0: a and r untouched. */
int tf_read(tf_text *t, mio_reader *r, mio_arrays *a);

/* ------------------------------------------------- for the line functions */
static inline int tf_space(char c)
{
    return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}
static inline const char *tf_skip(const char *s, const char *e)
{
    while (s < e && tf_space(*s))
        s++;
    return s;
}
static inline const char *tf_token_end(const char *s, const char *e)
{
    while (s < e && !tf_space(*s))
        s++;
    return s;
}
/* The number at *s (after spaces; it must end at a space or e), as
   mio_parse_double gives it; advances *s. 0 when missing or refused. */
int tf_double(const char **s, const char *e, double *out);
/* The integer at *s as mio_parse_ll(stop) gives it, up to 18 digits; it
   must end at a space, e or stop (0: none). 0 when missing or refused. */
int tf_int(const char **s, const char *e, long long *out, char stop);
int tf_push_vertex(tf_chunk *c, const double xyz[3]);
int tf_push_index(tf_chunk *c, uint32_t v);
int tf_end_face(tf_chunk *c);

#endif
