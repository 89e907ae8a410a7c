/* SPDX-License-Identifier: MIT */
#include "bench_operator.h"

#include <stdio.h>
#include <string.h>

int bench_operator(const char *prog, const char *path, const char *scheme, limn_context **ctx,
                   limn_mesh **mesh, stencil_operator *op)
{
    limn_scheme s = strcmp(scheme, "loop") == 0 ? LIMN_SCHEME_LOOP : LIMN_SCHEME_CATMARK;
    *ctx = limn_context_create();
    *mesh = NULL;
    if (limn_mesh_read(*ctx, path, LIMN_FORMAT_AUTO, mesh) ||
        operator_build_ex(*ctx, *mesh, s, 0.0, OPERATOR_REORDER, op)) {
        fprintf(stderr, "%s: %s\n", prog, limn_context_message(*ctx));
        return 1;
    }
    return 0;
}
