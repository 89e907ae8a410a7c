/* SPDX-License-Identifier: MIT */
/* Thread-local switches to the C locale (see c_locale.h). */
#include "base/c_locale.h"

int c_locale_enter(c_locale_scope *s)
{
    /* glibc hands out its static C locale here: no allocation, cheap per call */
    s->c = newlocale(LC_ALL_MASK, "C", (locale_t)0);
    if (s->c == (locale_t)0) {
        s->prev = (locale_t)0;
        return 0;
    }
    s->prev = uselocale(s->c);
    return 1;
}

void c_locale_leave(c_locale_scope *s)
{
    if (s->c == (locale_t)0)
        return;
    uselocale(s->prev);
    freelocale(s->c);
    s->c = (locale_t)0;
}
