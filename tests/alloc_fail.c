/* SPDX-License-Identifier: MIT */
/* Allocation failures on demand (alloc_fail.h): the link-time wrappers. */
#include "alloc_fail.h"

#include <errno.h>
#include <pthread.h>
#include <stddef.h>

/* atomic: limn's host threads allocate too (which one the k-th is then
   varies from run to run, never whether every k is tried) */
static _Atomic int armed;
static _Atomic long count, fail_at;

void *__real_malloc(size_t n);
void *__real_calloc(size_t k, size_t n);
void *__real_realloc(void *p, size_t n);
void *__real_aligned_alloc(size_t a, size_t n);
void *__wrap_malloc(size_t n);
void *__wrap_calloc(size_t k, size_t n);
void *__wrap_realloc(void *p, size_t n);
void *__wrap_aligned_alloc(size_t a, size_t n);
int __real_pthread_create(pthread_t *t, const pthread_attr_t *a, void *(*fn)(void *), void *arg);
int __wrap_pthread_create(pthread_t *t, const pthread_attr_t *a, void *(*fn)(void *), void *arg);

static _Atomic int threads_fail;

void alloc_fail_threads(int on)
{
    threads_fail = on;
}

int __wrap_pthread_create(pthread_t *t, const pthread_attr_t *a, void *(*fn)(void *), void *arg)
{
    return threads_fail ? EAGAIN : __real_pthread_create(t, a, fn, arg);
}

void alloc_fail_arm(long k)
{
    count = 0;
    fail_at = k;
    armed = 1;
}

long alloc_fail_disarm(void)
{
    armed = 0;
    return count;
}

/* 1 when this allocation is the one to fail. */
static int fails_now(void)
{
    return armed && ++count == fail_at; /* ++ on an _Atomic: one atomic add */
}

void *__wrap_malloc(size_t n)
{
    return fails_now() ? NULL : __real_malloc(n);
}

void *__wrap_calloc(size_t k, size_t n)
{
    return fails_now() ? NULL : __real_calloc(k, n);
}

void *__wrap_realloc(void *p, size_t n)
{
    return fails_now() ? NULL : __real_realloc(p, n);
}

void *__wrap_aligned_alloc(size_t a, size_t n)
{
    return fails_now() ? NULL : __real_aligned_alloc(a, n);
}
