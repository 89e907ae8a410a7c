/* SPDX-License-Identifier: MIT */
/*
 * Allocation failures on demand, for the tests that sweep them (test_oom,
 * test_mpi_oom). A test linked with limn_alloc_fail() in tests/CMakeLists.txt
 * (-Wl,--wrap=malloc,calloc,realloc,aligned_alloc,pthread_create) sends
 * every call of those from its own objects and from limn's static library through
 * alloc_fail.c; the shared libraries (PoCL, MPI, libc's own) keep theirs.
 */
#ifndef LIMN_TEST_ALLOC_FAIL_H
#define LIMN_TEST_ALLOC_FAIL_H

/* From now on count allocations; the k-th fails (k <= 0: none does). */
void alloc_fail_arm(long k);
/* Stop counting and failing; the allocations seen since the arm. */
long alloc_fail_disarm(void);
/* While on (nonzero), every pthread_create of limn's fails with EAGAIN
   (link with --wrap=pthread_create, as limn_alloc_fail does). */
void alloc_fail_threads(int on);

#endif
