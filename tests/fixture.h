/* SPDX-License-Identifier: MIT */
/* cmocka per-test fixtures: *state is a new context, made before the test
   and destroyed after it, so a test body does neither. In a test table:
   CONTEXT_TEST(f) (the default device), REFERENCE_TEST(f), OPENCL_TEST(f). */
#ifndef LIMN_TEST_FIXTURE_H
#define LIMN_TEST_FIXTURE_H

int test_context_setup(void **state);
/* The context on the named device; the choice must succeed. */
int test_reference_setup(void **state);
int test_opencl_setup(void **state);
int test_context_teardown(void **state);

#define CONTEXT_TEST(f) cmocka_unit_test_setup_teardown(f, test_context_setup, test_context_teardown)
#define REFERENCE_TEST(f)                                                                      \
    cmocka_unit_test_setup_teardown(f, test_reference_setup, test_context_teardown)
#define OPENCL_TEST(f) cmocka_unit_test_setup_teardown(f, test_opencl_setup, test_context_teardown)

#endif
