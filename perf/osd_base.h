/* SPDX-License-Identifier: MIT */
// The OpenSubdiv anchors' common start: the mesh read with limn's reader
// (only for I/O) and OpenSubdiv's TopologyRefiner over its faces, with the
// boundary rule limn uses (edges and corners sharp). Header-only: each
// anchor is one C++ file.
#ifndef LIMN_PERF_OSD_BASE_H
#define LIMN_PERF_OSD_BASE_H

#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include <chrono>
#include <cstdio>
#include <vector>

extern "C" {
#include "limn.h"
}

struct osd_base {
    limn_context *ctx;
    limn_mesh *m;
    int nv, nf;
    const uint32_t *off;
    std::vector<int> sizes, indices;
};

static inline double now()
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// Reads path into b; false (the reader's message printed) when it cannot.
static inline bool osd_base_read(const char *path, osd_base &b)
{
    b.ctx = limn_context_create();
    b.m = nullptr;
    if (limn_mesh_read(b.ctx, path, LIMN_FORMAT_AUTO, &b.m) != LIMN_OK) {
        fprintf(stderr, "%s\n", limn_context_message(b.ctx));
        return false;
    }
    b.nv = (int)limn_mesh_vertex_count(b.m);
    b.nf = (int)limn_mesh_face_count(b.m);
    b.off = limn_mesh_face_offsets(b.m);
    const uint32_t *idx = limn_mesh_face_indices(b.m);
    b.sizes.resize(b.nf);
    b.indices.assign(idx, idx + b.off[b.nf]);
    for (int f = 0; f < b.nf; f++)
        b.sizes[f] = (int)(b.off[f + 1] - b.off[f]);
    return true;
}

// The base level of the refiner, not yet refined.
static inline OpenSubdiv::Far::TopologyRefiner *osd_base_refiner(osd_base &b, bool loop)
{
    using namespace OpenSubdiv;
    Sdc::Options opt;
    opt.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER);
    Far::TopologyDescriptor desc;
    desc.numVertices = b.nv;
    desc.numFaces = b.nf;
    desc.numVertsPerFace = b.sizes.data();
    desc.vertIndicesPerFace = b.indices.data();
    typedef Far::TopologyRefinerFactory<Far::TopologyDescriptor> Factory;
    return Factory::Create(desc,
                           Factory::Options(loop ? Sdc::SCHEME_LOOP : Sdc::SCHEME_CATMARK, opt));
}

#endif
