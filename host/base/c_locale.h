/* SPDX-License-Identifier: MIT */
/*
 * Numbers in mesh files and reports are read and written in the C locale,
 * whatever locale the host program set: under de_DE "%g" writes "0,5" and
 * strtod stops at "0.5"'s point. Each entry point that reads or writes
 * numbers switches the calling thread alone (uselocale) and switches back on
 * every path, so other threads and the host's own output are untouched.
 */
#ifndef LIMN_C_LOCALE_H
#define LIMN_C_LOCALE_H

#ifndef _POSIX_C_SOURCE
#define _POSIX_C_SOURCE 200809L /* locale_t, newlocale, uselocale */
#endif
#include <locale.h>

typedef struct c_locale_scope {
    locale_t c;     /* the C locale object, (locale_t)0 when none could be made */
    locale_t prev;  /* the thread's locale before, restored by c_locale_leave */
} c_locale_scope;

/* Makes the calling thread use the C locale; returns 0 (nothing changed)
   when the locale object cannot be made (out of memory). */
int c_locale_enter(c_locale_scope *s);
/* Restores the thread's previous locale; harmless after a failed enter. */
void c_locale_leave(c_locale_scope *s);

#endif
