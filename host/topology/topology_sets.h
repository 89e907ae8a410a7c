/* SPDX-License-Identifier: MIT */
/*
 * Sets of vertices joined by edges (components, boundary loops), a union-find
 * that ranges of vertices or edges update at once: the topology's counts
 * (topology.c) and the census's (topology_census.c).
 */
#ifndef LIMN_TOPOLOGY_SETS_H
#define LIMN_TOPOLOGY_SETS_H

#include <stdatomic.h>
#include <stdint.h>

/* A union-find that ranges of edges update at once, lock-free. Every link
   points to a smaller index: a union links the larger root under the smaller
   by compare-and-swap (retried when another thread linked either first), and
   path halving stores a grandparent, an ancestor in the same set, with a
   plain store (a concurrent halving may store a nearer ancestor over it:
   still the same set, still a smaller index). So no cycle can form and the
   sets are those of the sequential union-find (which root stands for a set
   may differ; only the counts are used). */
static inline uint32_t topo_find(_Atomic uint32_t *parent, uint32_t x)
{
    for (;;) {
        uint32_t p = atomic_load_explicit(&parent[x], memory_order_relaxed);
        if (p == x)
            return x;
        uint32_t g = atomic_load_explicit(&parent[p], memory_order_relaxed);
        if (g != p)
            atomic_store_explicit(&parent[x], g, memory_order_relaxed);
        x = g;
    }
}

static inline void topo_unite(_Atomic uint32_t *parent, uint32_t a, uint32_t b)
{
    for (;;) {
        a = topo_find(parent, a);
        b = topo_find(parent, b);
        if (a == b)
            return;
        if (a > b) {
            uint32_t t = a;
            a = b;
            b = t;
        }
        uint32_t expected = b; /* b still a root: it now points at a */
        if (atomic_compare_exchange_strong_explicit(&parent[b], &expected, a,
                                                    memory_order_relaxed, memory_order_relaxed))
            return;
    }
}

#endif
