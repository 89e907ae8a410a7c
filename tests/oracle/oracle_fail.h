/* SPDX-License-Identifier: MIT */
/* The oracles' error report: a formatted message into the caller's buffer. */
#ifndef LIMN_ORACLE_FAIL_H
#define LIMN_ORACLE_FAIL_H

#include <stddef.h>

/* Writes the message into err (when err is given) and returns 1. */
#if defined(__GNUC__)
__attribute__((format(printf, 3, 4)))
#endif
int oracle_fail(char *err, size_t errlen, const char *fmt, ...);

#endif
