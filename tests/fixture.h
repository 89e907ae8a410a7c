/* SPDX-License-Identifier: MIT */
/* cmocka per-test fixtures: *state is a new context, made before the test
   and destroyed after it, so a test body does neither. In a test table:
   CONTEXT_TEST(f) (the default device), REFERENCE_TEST(f), OPENCL_TEST(f),
   and KEEP_TEST(f) for a test without a context that keeps objects. */
#ifndef LIMN_TEST_FIXTURE_H
#define LIMN_TEST_FIXTURE_H

#include "limn.h"

int test_context_setup(void **state);
/* The context on the named device; the choice must succeed. */
int test_reference_setup(void **state);
int test_opencl_setup(void **state);
/* Releases what the test kept (below), then destroys the context. */
int test_context_teardown(void **state);

/* Objects a test hands to its fixture: the teardown releases them after the
   test, last kept first, whether the test passed or not. A failing cmocka
   assertion longjmps out of the body, so whatever the body would have freed
   at its end leaked (and those leaks hid real ones in the ASan run). Each
   returns what it is given, so a test keeps an object where it makes it. */
void *test_defer(void (*release)(void *), void *p);
limn_mesh *test_keep_mesh(limn_mesh *m);
limn_context *test_keep_context(limn_context *ctx);
void *test_keep(void *p); /* free()'d */
/* A shared real mesh (support.h's test_shared_path), read or the test fails
   with the file and the context's message; the caller destroys it. */
limn_mesh *test_read_shared(limn_context *ctx, const char *rel);
/* test_read_shared, then the mesh's info into *info; NULL where limn refuses
   the mesh (the refusal printed as "  REL refused: MESSAGE", REL padded to
   width, and the mesh destroyed) so a sweep over the shared set goes on. */
limn_mesh *test_read_shared_info(limn_context *ctx, const char *rel, int width,
                                 limn_mesh_info *info);
/* Releases the kept objects (the teardown of KEEP_TEST). */
int test_release_teardown(void **state);

#define CONTEXT_TEST(f) cmocka_unit_test_setup_teardown(f, test_context_setup, test_context_teardown)
#define REFERENCE_TEST(f)                                                                      \
    cmocka_unit_test_setup_teardown(f, test_reference_setup, test_context_teardown)
#define OPENCL_TEST(f) cmocka_unit_test_setup_teardown(f, test_opencl_setup, test_context_teardown)
#define KEEP_TEST(f) cmocka_unit_test_teardown(f, test_release_teardown)

/* A test file's main: its table of tests run as one group, with the group's
   setup and teardown (NULL for none). */
#define TEST_MAIN(group_setup, group_teardown, ...)                                            \
    int main(void)                                                                             \
    {                                                                                          \
        const struct CMUnitTest tests[] = {__VA_ARGS__};                                       \
        return cmocka_run_group_tests(tests, group_setup, group_teardown);                     \
    }

#endif
