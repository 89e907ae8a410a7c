/*
 * The limit operator A of one mesh: topology, host CSR table and its copy on
 * the device. Built once per (mesh topology, scheme, alpha) and reused by
 * every iteration and every application (interpolation, series, ...).
 */
#ifndef LIMN_OPERATOR_H
#define LIMN_OPERATOR_H

#include "device.h"
#include "stencil.h"
#include "topology.h"

typedef struct limn_operator {
    limn_scheme scheme;     /* resolved: LOOP or CATMARK */
    double alpha;
    size_t vertex_count;
    topology topo;
    stencil_csr host;
    device_csr device;
    struct limn_device *dev;
    double bbox_diagonal;
    double seconds_topology, seconds_stencil;
} limn_operator;

/* Chooses the scheme (AUTO: Loop for all-triangle meshes, else Catmull-Clark)
   and refuses a mesh the scheme cannot take, naming the face. */
limn_status operator_resolve_scheme(limn_context *ctx, const limn_mesh *mesh, limn_scheme want,
                                    limn_scheme *out);
limn_status operator_build(limn_context *ctx, const limn_mesh *mesh, limn_scheme scheme,
                           double alpha, limn_operator *out);
void operator_free(limn_operator *op);

double limn_seconds(void);
double mesh_bbox_diagonal(const limn_mesh *mesh, double lo[3], double hi[3]);

#endif
