/* SPDX-License-Identifier: MIT */
/*
 * The reader toolkit shared by the mesh file formats (mesh_obj.c, mesh_ply.c,
 * mesh_off.c, mesh_stl.c; their entry points are in formats.h, the public
 * ones in dispatch.c): the buffered reader, number parsing, the mesh built
 * from reader buffers, the text writers' vertex and face lines, the
 * write-failure message.
 */
#ifndef LIMN_MESH_IO_TOOLKIT_H
#define LIMN_MESH_IO_TOOLKIT_H

#include "limn.h"
#include "base/growbuf.h"

#include <stdint.h>
#include <stdio.h>

/* ------------------------------------------------------------ buffered reader
 * One buffer serves both text lines and binary bytes, so a PLY header can be
 * read as lines and the data after it as bytes. */
typedef struct mio_reader {
    limn_context *ctx;
    const char *path;
    FILE *f;
    char *buf;
    size_t cap, start, end;   /* unread data is buf[start, end); buf[end] is writable */
    uint64_t buf_offset;      /* file offset of buf[0] */
    uint64_t file_size;       /* 0 when unknown (not a regular file) */
    int eof;                  /* fread reached the end of the file */
    int error;                /* errno of a failed read, or -1 for an unknown error */
    int continuation;         /* join lines ending in '\' (OBJ) */
    unsigned long line;       /* number of the line last returned by mio_line */
    unsigned long next_line;  /* number of the next line */
    int unterminated;         /* the last line returned ended the file without '\n' */
    unsigned long error_line; /* the line a MIO_ERR_* refusal was found on */
    growbuf_budget budget;    /* what the reader and its arrays may hold (max_memory) */
} mio_reader;

/* r->error values beside errno ones: the file is not text as expected. */
#define MIO_ERR_UNKNOWN (-1)
#define MIO_ERR_LONG_LINE (-2) /* a line longer than MIO_MAX_LINE */
#define MIO_ERR_NUL (-3)       /* a NUL byte in a line: binary data */
#define MIO_MAX_LINE ((size_t)64 << 20)

/* Returns 0 (with a message) when memory is exhausted. The budget's limit
   is the context's max_memory; readers point their growbufs at r->budget. */
int mio_init(mio_reader *r, limn_context *ctx, const char *path, FILE *f);
void mio_free(mio_reader *r);
/* The next line without its end ('\n', "\r\n" or a lone '\r'), NUL-terminated
   and writable; NULL at the end of the file or on a read error (check
   r->error), when out of memory or over the budget (r->error = ENOMEM), on a
   NUL byte (MIO_ERR_NUL) or a line over MIO_MAX_LINE (MIO_ERR_LONG_LINE).
   *len gets its length. */
char *mio_line(mio_reader *r, size_t *len);
/* Pointer to the next n bytes (consumed), or NULL when fewer remain (or a read
   error, see r->error). */
const unsigned char *mio_bytes(mio_reader *r, size_t n);
/* Up to n bytes ahead without consuming them (*avail gets how many: fewer only
   at the end of the file, on an error, or when n exceeds the buffer). */
const unsigned char *mio_peek(mio_reader *r, size_t n, size_t *avail);
/* Consumes n bytes without keeping them; 0 when fewer remain (or an error). */
int mio_skip(mio_reader *r, uint64_t n);
/* File offset of the next unread byte. */
static inline uint64_t mio_offset(const mio_reader *r) { return r->buf_offset + r->start; }
/* Bytes left in the file after the current position (UINT64_MAX if unknown). */
uint64_t mio_remaining(const mio_reader *r);
/* Moves the reader to file offset `offset` (a reader that took the data by
   other means, e.g. mapped); 0 when the file cannot seek there. */
int mio_jump(mio_reader *r, uint64_t offset);
/* Consumes a UTF-8 byte order mark (EF BB BF) at the start of the file. */
void mio_skip_bom(mio_reader *r);
/* Sets the message for a read error (r->error) and returns LIMN_ERR_IO
   (LIMN_ERR_FORMAT for a file that is not text, LIMN_ERR_MEMORY). */
limn_status mio_read_failed(mio_reader *r);
/* A reader's final status: a LIMN_ERR_MEMORY that came from the budget gets
   the message naming the limit (at the current line, or byte offset when
   binary). Returns st. */
limn_status mio_finish(mio_reader *r, limn_status st, int binary);

/* ----------------------------------------------------------------- tokens */
static inline int mio_space(char c)
{
    return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}
static inline char *mio_skip_space(char *s)
{
    while (mio_space(*s))
        s++;
    return s;
}
/* Parses a finite double ending at whitespace or the end of the string.
   Returns 1 and advances *s; 0 when not a number, 2 when NaN/Inf/overflow. */
int mio_parse_double(char **s, double *out);
/* Parses a decimal integer ending at whitespace, end of string or `stop`
   (0 for none). Returns 1 and advances *s; 0 when not an integer or out of
   range of long long. */
int mio_parse_ll(char **s, long long *out, char stop);
/* Copies a token for a message: at most 40 characters, quoted. */
const char *mio_token(const char *s, char buf[64]);

/* ------------------------------------------------------------- mesh arrays
 * What every reader fills and builds its mesh from. */
typedef struct mio_arrays {
    growbuf pos;     /* 3 doubles per vertex */
    growbuf col;     /* 3 bytes per vertex, or empty (no colours) */
    growbuf offsets; /* face_count + 1 uint32 starting with 0 */
    growbuf indices; /* uint32 */
} mio_arrays;

/* Charges the (zeroed) arrays to the reader's budget (max_memory). */
void mio_arrays_init(mio_arrays *a, mio_reader *r);
void mio_arrays_free(mio_arrays *a);
/* Gives the empty g exactly n bytes (len n, contents unset), charged to its
   budget; 0 when over the budget (budget->exceeded set) or out of memory. */
int mio_array_exact(growbuf *g, size_t n);
/* Builds a mesh from the arrays, taking their memory (they are left empty). */
limn_status mio_make_mesh(limn_context *ctx, mio_arrays *a, limn_mesh **out);

/* The frame every reader runs in: r and a (members of state, zeroed) set up
   for path and f, then parse(state, &binary), the mesh made from a when that
   succeeded, mio_finish (binary: what parse left in it), a and r freed.
   Returns the reader's status. */
typedef limn_status (*mio_parse_fn)(void *state, int *binary);
limn_status mio_read(mio_reader *r, mio_arrays *a, limn_context *ctx, const char *path, FILE *f,
                     mio_parse_fn parse, void *state, limn_mesh **out);

/* Message for a failed write (errno) to the target path; returns LIMN_ERR_IO. */
limn_status mio_write_failed(limn_context *ctx, const char *path);

#endif
