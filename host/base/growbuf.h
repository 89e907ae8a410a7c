/* SPDX-License-Identifier: MIT */
/* A growable byte array for readers: amortised appends, checked sizes. */
#ifndef LIMN_GROWBUF_H
#define LIMN_GROWBUF_H

#include <stddef.h>
#include <stdint.h>
#include <string.h>

/* What a reader's buffers may hold together (limn_context_set_max_memory):
   a growth past limit fails like an exhausted memory, with exceeded set so
   the reader can say which it was. */
typedef struct growbuf_budget {
    size_t limit, used;
    int exceeded;
} growbuf_budget;

typedef struct growbuf {
    unsigned char *data;
    size_t len;   /* bytes in use */
    size_t cap;   /* bytes allocated */
    growbuf_budget *budget; /* NULL: no cap */
} growbuf;

/* Books n more bytes against b (NULL: no cap); 0 (and b->exceeded) past it. */
static inline int growbuf_budget_take(growbuf_budget *b, size_t n)
{
    if (!b)
        return 1;
    if (n > b->limit - b->used) {
        b->exceeded = 1;
        return 0;
    }
    b->used += n;
    return 1;
}
static inline void growbuf_budget_give(growbuf_budget *b, size_t n)
{
    if (b)
        b->used = n < b->used ? b->used - n : 0;
}

/* Makes room for at least `more` further bytes. Returns 0 when the size
   would overflow or memory is exhausted (the buffer is then unchanged). */
int growbuf_reserve(growbuf *g, size_t more);
void growbuf_free(growbuf *g);
/* Hands the data over to the caller (shrunk to len, never NULL unless out of
   memory) and empties the buffer. */
void *growbuf_take(growbuf *g);

static inline int growbuf_append(growbuf *g, const void *p, size_t n)
{
    if (g->cap - g->len < n && !growbuf_reserve(g, n))
        return 0;
    memcpy(g->data + g->len, p, n);
    g->len += n;
    return 1;
}

static inline int growbuf_push_u32(growbuf *g, uint32_t v)
{
    return growbuf_append(g, &v, sizeof v);
}

static inline int growbuf_push_3d(growbuf *g, double x, double y, double z)
{
    double v[3] = {x, y, z};
    return growbuf_append(g, v, sizeof v);
}

#endif
