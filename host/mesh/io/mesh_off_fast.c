/* SPDX-License-Identifier: MIT */
/*
 * OFF's fast path (text_formats.h) for the body after the header the
 * general reader (mesh_off.c) has read: files without vertex colours, one
 * record per content line as OFF has it, "x y z ..." for the first nv and
 * "n i1 ... in ..." for the next nf (what follows ignored, as the general
 * reader ignores it; '#' comments cut off by the general reader can only
 * follow the values used, so they are ignored too). The rest of the file
 * is left to the general reader, which warns of data after the last face.
 */
#include "mesh/io/text_formats.h"
#include "mesh/io/text_fast.h"

#include <stdlib.h>

static int off_fast_line(const tf_text *t, tf_chunk *c, const char *s, const char *e,
                         uint64_t record)
{
    if (record < t->nv) {
        double xyz[3];
        for (int k = 0; k < 3; k++)
            if (!tf_double(&s, e, &xyz[k]))
                return 0;
        return tf_push_vertex(c, xyz);
    }
    long long k, v;
    if (!tf_int(&s, e, &k, 0) || k < 3)
        return 0;
    for (long long i = 0; i < k; i++)
        if (!tf_int(&s, e, &v, 0) || v < 0 || v >= (long long)t->nv ||
            !tf_push_index(c, (uint32_t)v))
            return 0;
    return tf_end_face(c);
}

int off_fast_setup(tf_text *t, long long nv, long long nf)
{
    if (nv <= 0 || nf < 0 || nv >= (long long)UINT32_MAX)
        return 0;
    t->line = off_fast_line;
    t->hash_comments = 1;
    t->nv = (uint32_t)nv;
    t->records = (uint64_t)nv + (uint64_t)nf;
    return 1;
}

int off_fast_body(mio_reader *r, mio_arrays *a, long long nv, long long nf)
{
    tf_text *t = calloc(1, sizeof *t);
    if (!t)
        return 0;
    if (!off_fast_setup(t, nv, nf)) {
        free(t);
        return 0;
    }
    int ok = tf_read(t, r, a);
    free(t);
    return ok;
}
