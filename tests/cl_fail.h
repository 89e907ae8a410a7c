/* SPDX-License-Identifier: MIT */
/*
 * OpenCL calls failing on demand, for the tests that sweep them (test_oom,
 * test_mpi_oom): linked with limn_alloc_fail() in tests/CMakeLists.txt,
 * limn's calls of the OpenCL functions that can fail while it runs
 * (clCreateBuffer, clEnqueueNDRangeKernel, clEnqueueReadBuffer,
 * clEnqueueWriteBuffer, clEnqueueMapBuffer, clEnqueueUnmapMemObject,
 * clEnqueueFillBuffer, clFinish) go through cl_fail.c, which counts them
 * and fails the k-th as a device out of resources would
 * (CL_MEM_OBJECT_ALLOCATION_FAILURE for a buffer, CL_OUT_OF_RESOURCES for
 * the others). Opening a device has its own faults (LIMN_TEST_FAULT).
 */
#ifndef LIMN_TEST_CL_FAIL_H
#define LIMN_TEST_CL_FAIL_H

/* From now on count those calls; the k-th fails (k <= 0: none does). */
void cl_fail_arm(long k);
/* Stop counting and failing; the calls seen since the arm. */
long cl_fail_disarm(void);

#endif
