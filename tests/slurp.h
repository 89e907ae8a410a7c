/* SPDX-License-Identifier: MIT */
/* A whole stream read into memory, for the tests and the fuzz replay (no
   cmocka here: replay is a plain program). */
#ifndef LIMN_TEST_SLURP_H
#define LIMN_TEST_SLURP_H

#include <stddef.h>
#include <stdio.h>

/* The rest of f in a malloc'ed buffer with a '\0' after the *n bytes read;
   NULL when memory runs out. */
char *test_read_stream(FILE *f, size_t *n);

#endif
