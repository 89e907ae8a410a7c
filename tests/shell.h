/* SPDX-License-Identifier: MIT */
/* Shared helpers of the tests that drive the limn command line or the file
   system: scratch directories, paths in them, files in and out, shell
   commands with their output captured. Failures to run at all (popen, a
   short write) fail the calling cmocka test. */
#ifndef LIMN_TEST_SHELL_H
#define LIMN_TEST_SHELL_H

#include "limn.h"

#include <stdarg.h>
#include <stddef.h>

/* Makes /tmp/limn_NAME_XXXXXX into dir (cap bytes); 0, or -1 on failure. */
int test_make_dir(char *dir, size_t cap, const char *name);
/* rm -rf DIR; 0, or -1 on failure. */
int test_remove_dir(const char *dir);
/* DIR/NAME in one of eight rotating static buffers. */
const char *test_join(const char *dir, const char *name);
/* $LIMN_TEST_DATA/NAME (the repository's data/), rotating like test_join. */
const char *test_data_path(const char *name);

/* A test group's scratch: one directory for all its tests and the captured
   output of the last command run. test_scratch_make (called by the group
   setup) makes /tmp/limn_NAME_XXXXXX into test_dir and, when ctx is not
   NULL, a context into *ctx; 0, or -1 on failure. test_scratch_teardown is
   a group teardown: it removes test_dir. */
extern char test_dir[64];
extern char test_text[1 << 17];
int test_scratch_make(const char *name, limn_context **ctx);
int test_scratch_teardown(void **state);

/* Writes n bytes to path (failing the test when it cannot); returns path. */
const char *test_write_bytes(const char *path, const void *data, size_t n);
/* The whole file, NUL-terminated, its length in *n (caller frees); NULL
   when it cannot be opened. */
char *test_slurp(const char *path, size_t *n);
/* Both files readable, with the same bytes (what `cmp -s A B` says). */
int test_same_bytes(const char *a, const char *b);

/* Runs a shell command, its output (what the command sends to the pipe) in
   out; returns the exit status, -1 when it did not exit. */
int test_run(char *out, size_t cap, const char *cmd);
/* The same for a printf-style command. */
int test_runf(char *out, size_t cap, const char *fmt, ...);
int test_vrunf(char *out, size_t cap, const char *fmt, va_list ap);
/* Runs `[env ENV] $LIMN_BIN ARGS 2>&1` (ARGS printf-style; env NULL: none). */
int test_limn(char *out, size_t cap, const char *env, const char *fmt, ...);
/* Runs `cd DIR && { LINE; } 2>&1` (LINE printf-style). */
int test_in_dir(char *out, size_t cap, const char *dir, const char *fmt, ...);

#endif
