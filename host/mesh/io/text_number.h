/* SPDX-License-Identifier: MIT */
/*
 * Locale-free decimal numbers for the text readers' fast paths
 * (text_fast.c): the same double as strtod in the C locale, bit for bit,
 * for the forms mesh files use; anything else is left to strtod.
 */
#ifndef LIMN_MESH_IO_TEXT_NUMBER_H
#define LIMN_MESH_IO_TEXT_NUMBER_H

/* Converts the number [+-]digits[.digits][(e|E)[+-]digits] (at least one
   mantissa digit) at the start of [s, e), reading no further than e.
   Returns where it ends and *out when the value is computed exactly here
   (up to 19 significant digits and a power of ten from 1e-22 to 1e22);
   NULL otherwise. The caller checks what follows the number and asks
   strtod when NULL (which also gives hex floats, inf, nan and errors). */
const char *tn_double(const char *s, const char *e, double *out);

#endif
