/* SPDX-License-Identifier: MIT */
/* The start the kernel benchmarks share (float_floor, step_bench): a mesh
   file and its reordered operator. */
#ifndef LIMN_PERF_BENCH_OPERATOR_H
#define LIMN_PERF_BENCH_OPERATOR_H

#include "limn.h"
#include "solve/operator.h"

/* A new context (default device), the mesh at path and its operator for
   scheme ("loop", else Catmull-Clark), reordered; on failure prints
   "prog: message" and returns 1, else 0. */
int bench_operator(const char *prog, const char *path, const char *scheme, limn_context **ctx,
                   limn_mesh **mesh, stencil_operator *op);

#endif
