/* SPDX-License-Identifier: MIT */
/*
 * The PLY reader's header model, shared by the general reader (mesh_ply.c)
 * and its binary fast path (mesh_ply_fast.c).
 */
#ifndef LIMN_MESH_IO_MESH_PLY_H
#define LIMN_MESH_IO_MESH_PLY_H

#include "mesh/io/toolkit.h"

#include <stddef.h>
#include <stdint.h>
#include <string.h>

enum { T_NONE, T_I8, T_U8, T_I16, T_U16, T_I32, T_U32, T_F32, T_F64, T_COUNT };
extern const unsigned char ply_type_size[T_COUNT];
extern const long long ply_type_max[T_COUNT]; /* of the integer types */
#define IS_INT(t) ((t) >= T_I8 && (t) <= T_U32)

enum { R_OTHER, R_X, R_Y, R_Z, R_RED, R_GREEN, R_BLUE, R_INDICES, R_COUNT };
enum { E_OTHER, E_VERTEX, E_FACE, E_TRISTRIPS };
enum { F_NONE, F_ASCII, F_LE, F_BE };

#define PLY_MAX_ELEMENTS 256
#define PLY_MAX_PROPERTIES 1024

typedef struct ply_prop {
    unsigned char type;        /* scalar type, or the item type of a list */
    unsigned char count_type;  /* T_NONE for a scalar */
    unsigned char role;
} ply_prop;

typedef struct ply_elem {
    int kind;
    char name[40];
    uint64_t count;
    ply_prop *props;
    size_t nprops;
    int has_list;
    uint64_t min_size;         /* least bytes one record takes in this format */
    int roles[R_COUNT];        /* how many properties have each role */
} ply_elem;

typedef struct ply {
    mio_reader r;
    limn_context *ctx;
    const char *path;
    int format;
    int in_header;             /* messages give the line, not a byte offset */
    ply_elem elems[PLY_MAX_ELEMENTS];
    size_t nelems;
    const ply_elem *elem;      /* being read, for messages */
    uint64_t index;            /* record being read */
    uint64_t at;               /* binary: offset of the value being read */
    char *tok;                 /* ascii: rest of the current line */
    uint64_t nv;
    int colors;
    mio_arrays a;
    char dropped[256];         /* vertex properties limn does not keep, for one warning */
    size_t ndropped;
    char slice_comment[256];   /* after "comment limn-slice " (mesh_slice_split.c), or "" */
} ply;

/* The header of f read and checked as ply_read does (warnings included)
   into p (zeroed here): for readers of parts of the body (mesh_slice_ply.c).
   p->r is then at the body's first byte. ply_close frees p's contents, also
   after a failure. */
limn_status ply_open(ply *p, limn_context *ctx, const char *path, FILE *f);
void ply_close(ply *p);

/* A binary scalar of type t at b (big: big endian), as the general reader
   converts it. */
long long ply_bin_int(const unsigned char *b, int t, int big);
double ply_bin_double(const unsigned char *b, int t, int big);

/* The same values, the types scanners write converted in line (a call and
   a switch per value cost more than the conversion): uchar, 4-byte little
   endian integers and little-endian float; others through ply_bin_*. */
static inline uint32_t ply_rd32le(const unsigned char *b)
{
    return (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
}
static inline long long ply_bin_int_inline(const unsigned char *b, int t, int big)
{
    if (t == T_U8)
        return *b;
    if (!big && t == T_I32)
        return (long long)(int32_t)ply_rd32le(b);
    if (!big && t == T_U32)
        return (long long)ply_rd32le(b);
    return ply_bin_int(b, t, big);
}
static inline double ply_bin_double_inline(const unsigned char *b, int t, int big)
{
    if (!big && t == T_F32) {
        uint32_t u = ply_rd32le(b);
        float f;
        memcpy(&f, &u, 4);
        return f;
    }
    return ply_bin_double(b, t, big);
}

/* The binary record layouts the fast path and the slice reader
   (mesh_slice_ply.c) take (mesh_ply_fast.c). A vertex record: fixed-size
   scalars, x y z (and red green blue) at off[] within stride bytes; 0 when a
   property is a list. A face record: scalars and the count (before bytes
   before it, the indices from lead), the indices, scalars (fixed bytes in all
   beside the indices); 0 unless its one list is the indices. */
typedef struct ply_vertex_layout {
    size_t stride, off[6];
    unsigned char type[3];
} ply_vertex_layout;
typedef struct ply_face_layout {
    size_t before, lead, fixed, isize;
    unsigned char ctype, itype;
} ply_face_layout;
int ply_vertex_records(const ply_elem *e, ply_vertex_layout *v);
int ply_face_records(const ply_elem *e, ply_face_layout *f);

/* The fast path for a binary file of the common layout (fixed-size vertex
   records, one face list, no tristrips; mesh_ply_fast.c), run after the
   header is checked: 1 when it read the whole body into p->a and left the
   reader after it; 0, with p->a and the reader untouched, when the layout,
   the data or the memory limit is anything it does not handle (the general
   reader then reads the body and gives its messages). The test-only
   LIMN_TEST_PLY_GENERAL=1 makes it always 0. */
int ply_fast_body(ply *p);

/* The same for an ascii file (mesh_ply_text_fast.c, text_fast.h): vertex
   and face elements only, one record a line; LIMN_TEST_TEXT_GENERAL=1 makes
   it always 0. */
int ply_text_fast_body(ply *p);

/* The ascii body's line parser as the fast path sets it up, for a reader of
   parts of the file (mesh_slice_text.c): the elements with records in file
   order (order[1] == order[0] when there is one), records of order[0]. */
struct tf_text;
typedef struct ply_text {
    const ply_elem *order[2];
    uint64_t first;
} ply_text;
/* Sets t's line function, format (pt, which must outlive t), nv, colours
   and record count for p's ascii body; 0 when the layout is one the line
   parser does not take (other elements with records, tristrips, lists
   beside the face indices). */
int ply_text_setup(const ply *p, ply_text *pt, struct tf_text *t);

#endif
