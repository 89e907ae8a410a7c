/* SPDX-License-Identifier: MIT */
/*
 * An experiment, not part of limn: an LD_PRELOAD interposer that serves
 * blocks of 4 MiB or more from mmap and keeps freed ones for reuse while the
 * live and kept bytes together stay under the high-water mark of live bytes
 * so far (so the mapped bytes never pass what they would have reached
 * without it). It answers docs/mpi.md "Set-up, 2026-12-07 (session 28)":
 * would a rank's set-up fall if its freed arrays were reused instead of
 * given back (the MPI CLI fixes glibc's mmap threshold at 128 KiB)?
 * perf/freed_block_cache.sh builds it and runs 2 ranks with and without.
 * calloc'd blocks are always fresh (zero, and resident only where written);
 * FREED_BLOCK_GROW=1 also grows the largest kept block with mremap when no
 * kept block is large enough; FREED_BLOCK_REPORT=1 prints the bytes mapped
 * fresh and reused at exit. glibc only (__libc_malloc and friends).
 */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <malloc.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>

#define BIG ((size_t)4 << 20)
#define ALIGN ((size_t)2 << 20) /* large_malloc's huge-page alignment */
#define MAX_BLOCKS 8192

extern void *__libc_malloc(size_t);
extern void __libc_free(void *);
extern void *__libc_calloc(size_t, size_t);
extern void *__libc_realloc(void *, size_t);
extern void *__libc_memalign(size_t, size_t);

typedef struct block {
    char *p;
    size_t bytes;
    int kept;
} block;

/* One process, one cache: an interposer cannot take a handle. */
static block blocks[MAX_BLOCKS];
static int nblocks;
static size_t live, kept, high, fresh_bytes, reused_bytes;
static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;

static size_t round_up(size_t n)
{
    return (n + ALIGN - 1) & ~(ALIGN - 1);
}

static char *map_aligned(size_t bytes)
{
    char *q = mmap(NULL, bytes + ALIGN, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS,
                   -1, 0);
    if (q == MAP_FAILED)
        return NULL;
    char *p = (char *)(((uintptr_t)q + ALIGN - 1) & ~(uintptr_t)(ALIGN - 1));
    if (p > q)
        munmap(q, (size_t)(p - q));
    size_t tail = (size_t)((q + bytes + ALIGN) - (p + bytes));
    if (tail)
        munmap(p + bytes, tail);
    return p;
}

/* Unmaps the smallest kept blocks until live + kept <= high. */
static void evict(void)
{
    while (live + kept > high) {
        int m = -1;
        for (int i = 0; i < nblocks; i++)
            if (blocks[i].kept && (m < 0 || blocks[i].bytes < blocks[m].bytes))
                m = i;
        if (m < 0)
            return;
        munmap(blocks[m].p, blocks[m].bytes);
        kept -= blocks[m].bytes;
        blocks[m] = blocks[--nblocks];
    }
}

static char *map_fresh(size_t bytes)
{
    char *p = nblocks < MAX_BLOCKS ? map_aligned(bytes) : NULL;
    if (p) {
        blocks[nblocks++] = (block){p, bytes, 0};
        live += bytes;
        fresh_bytes += bytes;
    }
    return p;
}

/* A kept block of at least `bytes` (its tail unmapped), else the largest
   grown by mremap when asked; NULL when neither. */
static char *reuse(size_t bytes)
{
    int best = -1, largest = -1;
    for (int i = 0; i < nblocks; i++) {
        if (!blocks[i].kept)
            continue;
        if (blocks[i].bytes >= bytes && (best < 0 || blocks[i].bytes < blocks[best].bytes))
            best = i;
        if (largest < 0 || blocks[i].bytes > blocks[largest].bytes)
            largest = i;
    }
    if (best >= 0) {
        block *b = &blocks[best];
        if (b->bytes > bytes) {
            munmap(b->p + bytes, b->bytes - bytes);
            kept -= b->bytes - bytes;
            b->bytes = bytes;
        }
        b->kept = 0;
        kept -= bytes;
        live += bytes;
        reused_bytes += bytes;
        return b->p;
    }
    if (largest < 0 || !getenv("FREED_BLOCK_GROW"))
        return NULL;
    block *b = &blocks[largest];
    char *q = mremap(b->p, b->bytes, bytes, MREMAP_MAYMOVE);
    if (q == MAP_FAILED)
        return NULL;
    kept -= b->bytes;
    reused_bytes += b->bytes;
    fresh_bytes += bytes - b->bytes;
    *b = (block){q, bytes, 0};
    live += bytes;
    return q; /* mremap keeps page alignment only: huge-page advice may split */
}

static void *big_alloc(size_t n, int zero)
{
    size_t bytes = round_up(n);
    pthread_mutex_lock(&lock);
    char *p = zero ? NULL : reuse(bytes);
    if (!p)
        p = map_fresh(bytes);
    if (live > high)
        high = live;
    evict();
    pthread_mutex_unlock(&lock);
    return p;
}

static int find_live(const void *p)
{
    for (int i = 0; i < nblocks; i++)
        if (blocks[i].p == p && !blocks[i].kept)
            return i;
    return -1;
}

void *malloc(size_t n)
{
    return n >= BIG ? big_alloc(n, 0) : __libc_malloc(n);
}

void *calloc(size_t count, size_t size)
{
    if (size && count > SIZE_MAX / size) {
        errno = ENOMEM;
        return NULL;
    }
    return count * size >= BIG ? big_alloc(count * size, 1) : __libc_calloc(count, size);
}

void free(void *p)
{
    if (!p)
        return;
    pthread_mutex_lock(&lock);
    int i = find_live(p);
    if (i >= 0) {
        blocks[i].kept = 1;
        live -= blocks[i].bytes;
        kept += blocks[i].bytes;
        evict();
    }
    pthread_mutex_unlock(&lock);
    if (i < 0)
        __libc_free(p);
}

void *realloc(void *p, size_t n)
{
    if (!p)
        return malloc(n);
    pthread_mutex_lock(&lock);
    int i = find_live(p);
    size_t old = i >= 0 ? blocks[i].bytes : 0;
    size_t bytes = round_up(n ? n : 1);
    if (i >= 0 && bytes <= old) { /* shrinking: the tail goes back */
        if (bytes < old) {
            munmap(blocks[i].p + bytes, old - bytes);
            blocks[i].bytes = bytes;
            live -= old - bytes;
        }
        pthread_mutex_unlock(&lock);
        return p;
    }
    pthread_mutex_unlock(&lock);
    if (i < 0 && n < BIG)
        return __libc_realloc(p, n);
    size_t have = i >= 0 ? old : malloc_usable_size(p);
    void *q = big_alloc(n, 0);
    if (q) {
        memcpy(q, p, have < n ? have : n);
        free(p);
    }
    return q;
}

void *aligned_alloc(size_t alignment, size_t n)
{
    return n >= BIG && alignment <= ALIGN ? big_alloc(n, 0) : __libc_memalign(alignment, n);
}

void *memalign(size_t alignment, size_t n)
{
    return aligned_alloc(alignment, n);
}

int posix_memalign(void **out, size_t alignment, size_t n)
{
    void *p = aligned_alloc(alignment, n);
    if (!p)
        return ENOMEM;
    *out = p;
    return 0;
}

size_t malloc_usable_size(void *p)
{
    pthread_mutex_lock(&lock);
    int i = find_live(p);
    size_t bytes = i >= 0 ? blocks[i].bytes : 0;
    pthread_mutex_unlock(&lock);
    if (i >= 0)
        return bytes;
    size_t (*next)(void *);
    *(void **)&next = dlsym(RTLD_NEXT, "malloc_usable_size"); /* POSIX's way round ISO C */
    return next ? next(p) : 0;
}

__attribute__((destructor)) static void report(void)
{
    if (getenv("FREED_BLOCK_REPORT"))
        fprintf(stderr, "freed_block_cache: %zu MiB mapped fresh, %zu MiB reused, high %zu MiB\n",
                fresh_bytes >> 20, reused_bytes >> 20, high >> 20);
}
