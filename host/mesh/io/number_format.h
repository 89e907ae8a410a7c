/* SPDX-License-Identifier: MIT */
/*
 * Numbers as the text writers print them, without printf (the text writers
 * format millions of them): the same characters as printf's "%.17g" (C
 * locale) and "%llu".
 */
#ifndef LIMN_MESH_IO_NUMBER_FORMAT_H
#define LIMN_MESH_IO_NUMBER_FORMAT_H

#include <stddef.h>
#include <stdint.h>

/* Longest "%.17g" of a double: "-1.2345678901234567e-308" and a NUL. */
#define NUMBER_G17_MAX 26

/* Writes "%.17g" of x at out (no NUL); returns the length. */
size_t number_g17(double x, char *out);

/* Writes "%llu" of v at out (no NUL, at most 20 characters); returns the length. */
size_t number_u64(uint64_t v, char *out);

#endif
