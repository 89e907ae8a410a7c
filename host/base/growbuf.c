/* SPDX-License-Identifier: MIT */
/* Growable byte array (see growbuf.h). */
#include "base/growbuf.h"
#include "base/large_alloc.h"

#include <stdlib.h>

int growbuf_reserve(growbuf *g, size_t more)
{
    if (g->cap - g->len >= more)
        return 1;
    if (more > SIZE_MAX - g->len)
        return 0;
    size_t need = g->len + more;
    size_t cap = g->cap ? g->cap : 256;
    while (cap < need)
        cap = cap > SIZE_MAX / 2 ? need : cap * 2;
    if (!growbuf_budget_take(g->budget, cap - g->cap))
        return 0;
    unsigned char *p = realloc(g->data, cap);
    if (!p) {
        growbuf_budget_give(g->budget, cap - g->cap);
        return 0;
    }
    large_advise(p, cap); /* a reader's growing array: a mesh array to be */
    g->data = p;
    g->cap = cap;
    return 1;
}

void growbuf_free(growbuf *g)
{
    growbuf_budget_give(g->budget, g->cap);
    free(g->data);
    g->data = NULL;
    g->len = g->cap = 0;
}

void *growbuf_take(growbuf *g)
{
    void *p = g->data;
    if (!p)
        p = malloc(1);
    else if (g->len < g->cap) {
        void *q = realloc(p, g->len ? g->len : 1);
        if (q)
            p = q;
    }
    g->data = NULL;
    g->len = g->cap = 0;
    return p;
}
