/* SPDX-License-Identifier: MIT */
#include "slurp.h"

#include <stdlib.h>

char *test_read_stream(FILE *f, size_t *n)
{
    size_t cap = 1 << 16, len = 0, got;
    char *b = malloc(cap + 1);
    while (b && (got = fread(b + len, 1, cap - len, f)) > 0) {
        len += got;
        if (len == cap) {
            char *g = realloc(b, 2 * cap + 1);
            if (!g) {
                free(b);
                b = NULL;
                break;
            }
            b = g;
            cap *= 2;
        }
    }
    if (b)
        b[len] = '\0';
    *n = len;
    return b;
}
