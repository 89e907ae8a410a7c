/* SPDX-License-Identifier: MIT */
/*
 * The limit operator A of one mesh: topology, host CSR table and its copy on
 * the device. Built once per (mesh topology, scheme, alpha) and reused by
 * every iteration and every application (interpolation, series, ...).
 */
#ifndef LIMN_OPERATOR_H
#define LIMN_OPERATOR_H

#include "device/device.h"
#include "stencil/stencil.h"
#include "topology/topology.h"

typedef struct stencil_operator {
    limn_scheme scheme;     /* resolved: LOOP or CATMARK */
    double alpha;
    size_t vertex_count;
    topology topo;
    stencil_csr host;
    device_csr device;
    struct device *dev;
    double bbox_diagonal;
    double seconds_topology, seconds_stencil, seconds_reorder;
    /* Locality order (OPERATOR_REORDER): device row k is input vertex
       order[k]; rank is the inverse. NULL when rows are in input order. */
    uint32_t *order, *rank;
} stencil_operator;

enum {
    OPERATOR_REORDER = 1,
    OPERATOR_HOST_ONLY = 2    /* no device copy (MPI: the root sends rows to ranks) */
};

/* operator_build with flags (OPERATOR_REORDER: renumber rows for locality;
   then use operator_pack / operator_unpack for every vector). */
limn_status operator_build_ex(limn_context *ctx, const limn_mesh *mesh, limn_scheme scheme,
                              double alpha, int flags, stencil_operator *out);
/* 3 doubles per input vertex -> 4 per row in the operator's order, and back. */
void operator_pack(const stencil_operator *op, const double *xyz, double *rows4);
void operator_unpack(const stencil_operator *op, const double *rows4, double *xyz);

/* Chooses the scheme (AUTO: Loop for all-triangle meshes, else Catmull-Clark)
   and refuses a mesh the scheme cannot take, naming the face. */
limn_status operator_resolve_scheme(limn_context *ctx, const limn_mesh *mesh, limn_scheme want,
                                    limn_scheme *out);
limn_status operator_build(limn_context *ctx, const limn_mesh *mesh, limn_scheme scheme,
                           double alpha, stencil_operator *out);
void operator_free(stencil_operator *op);
/* limn_limit_positions of checked arguments, inside another entry point (the
   context's warnings so far are kept: limn_subdivide --limit's fallback). */
limn_status operator_limit_positions(limn_context *ctx, const limn_mesh *mesh, limn_scheme scheme,
                                     double alpha, double *out);

#endif
