/* SPDX-License-Identifier: MIT */
// Benchmark anchor: OpenSubdiv 3.5 Far uniform refinement of a mesh in double
// precision (TopologyRefiner + PrimvarRefinerReal<double>::Interpolate), the
// route a user would otherwise take. Reads the mesh with limn's reader (only
// for I/O), prints one JSON line: counts, seconds, peak RSS.
//   osd_refine MESH LEVELS SCHEME(loop|catmark) [--factorized]
// --factorized also builds OpenSubdiv's stencil table from the base mesh to
// the finest level (factorizeIntermediateLevels) and reports its entries.
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/stencilTableFactory.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <vector>
#include <sys/resource.h>

#include "osd_base.h"

using namespace OpenSubdiv;

struct Point {
    double p[3];
    void Clear(void * = nullptr) { p[0] = p[1] = p[2] = 0; }
    void AddWithWeight(const Point &s, double w)
    {
        p[0] += w * s.p[0];
        p[1] += w * s.p[1];
        p[2] += w * s.p[2];
    }
};

int main(int argc, char **argv)
{
    if (argc < 4) {
        fprintf(stderr, "usage: osd_refine MESH LEVELS loop|catmark [--factorized]\n");
        return 2;
    }
    int levels = atoi(argv[2]);
    bool loop = strcmp(argv[3], "loop") == 0;
    bool factorized = argc > 4 && strcmp(argv[4], "--factorized") == 0;
    osd_base base;
    if (!osd_base_read(argv[1], base))
        return 1;

    double t0 = now();
    Far::TopologyRefiner *r = osd_base_refiner(base, loop);
    Far::TopologyRefiner::UniformOptions uo(levels);
    uo.fullTopologyInLastLevel = true;
    r->RefineUniform(uo);
    double t1 = now();

    std::vector<Point> verts(r->GetNumVerticesTotal());
    const double *pos = limn_mesh_positions(base.m);
    for (int i = 0; i < base.nv; i++)
        memcpy(verts[i].p, pos + 3 * i, sizeof verts[i].p);
    Far::PrimvarRefinerReal<double> pr(*r);
    Point *src = verts.data();
    for (int level = 1; level <= levels; level++) {
        Point *dst = src + r->GetLevel(level - 1).GetNumVertices();
        pr.Interpolate(level, src, dst);
        src = dst;
    }
    double t2 = now();
    const Far::TopologyLevel &last = r->GetLevel(levels);
    long long stencil_entries = -1;
    double t_stencil = 0;
    if (factorized) {
        double t3 = now();
        Far::StencilTableFactoryReal<double>::Options so;
        so.generateIntermediateLevels = false;
        so.factorizeIntermediateLevels = true;
        const Far::StencilTableReal<double> *st = Far::StencilTableFactoryReal<double>::Create(*r, so);
        stencil_entries = (long long)st->GetControlIndices().size();
        t_stencil = now() - t3;
        delete st;
    }
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    printf("{\"impl\": \"opensubdiv\", \"vertices\": %d, \"faces\": %d, \"levels\": %d, "
           "\"output_vertices\": %d, \"output_faces\": %d, \"seconds_topology\": %.6f, "
           "\"seconds_interpolate\": %.6f, \"seconds_total\": %.6f, \"peak_rss_bytes\": %lld, "
           "\"factorized_stencil_entries\": %lld, \"seconds_factorized_stencils\": %.6f}\n",
           base.nv, base.nf, levels, last.GetNumVertices(), last.GetNumFaces(), t1 - t0, t2 - t1,
           t2 - t0,
           (long long)ru.ru_maxrss * 1024, stencil_entries, t_stencil);
    delete r;
    limn_mesh_destroy(base.m);
    limn_context_destroy(base.ctx);
    return 0;
}
