/* SPDX-License-Identifier: MIT */
// Benchmark anchor: the seeds' iteration P <- P + (M - A P) run on
// OpenSubdiv 3.5's limit stencil table (double), what a user would build from
// OpenSubdiv: adaptive refinement, a LimitStencilTable with one location per
// base vertex (a corner of one of its ptex faces), then a plain double loop.
// Prints one JSON line: stencil build seconds, entries, iterations to the
// tolerance, seconds per product, and the largest difference between
// OpenSubdiv's A M and limn's (a check that both iterate the same operator).
//   osd_iteration MESH loop|catmark [TOL=1e-6] [MAXITER=2000]
#include <opensubdiv/far/patchTableFactory.h>
#include <opensubdiv/far/ptexIndices.h>
#include <opensubdiv/far/stencilTableFactory.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>
#include <sys/resource.h>

#include "osd_base.h"

using namespace OpenSubdiv;

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: osd_iteration MESH loop|catmark [TOL] [MAXITER]\n");
        return 2;
    }
    bool loop = strcmp(argv[2], "loop") == 0;
    double tol = argc > 3 ? atof(argv[3]) : 1e-6;
    int max_iter = argc > 4 ? atoi(argv[4]) : 2000;
    osd_base base;
    if (!osd_base_read(argv[1], base))
        return 1;
    limn_context *ctx = base.ctx;
    limn_mesh *m = base.m;
    int nv = base.nv, nf = base.nf;
    const uint32_t *off = base.off;
    const std::vector<int> &sizes = base.sizes, &indices = base.indices;

    double t0 = now();
    Far::TopologyRefiner *r = osd_base_refiner(base, loop);
    r->RefineAdaptive(Far::TopologyRefiner::AdaptiveOptions(3));

    // one location per base vertex: a corner of the first ptex face touching it
    Far::PtexIndices ptex(*r);
    std::vector<int> loc_ptex(nv, -1);
    std::vector<double> loc_s(nv, 0), loc_t(nv, 0);
    for (int f = 0; f < nf; f++) {
        int d = sizes[f], base = ptex.GetFaceId(f);
        for (int k = 0; k < d; k++) {
            int v = indices[off[f] + k];
            if (loc_ptex[v] >= 0)
                continue;
            if (loop) {
                static const double s[3] = {0, 1, 0}, t[3] = {0, 0, 1};
                loc_ptex[v] = base, loc_s[v] = s[k], loc_t[v] = t[k];
            } else if (d == 4) {
                static const double s[4] = {0, 1, 1, 0}, t[4] = {0, 0, 1, 1};
                loc_ptex[v] = base, loc_s[v] = s[k], loc_t[v] = t[k];
            } else {
                loc_ptex[v] = base + k; // sub-face k has face vertex k at its (0,0)
            }
        }
    }
    Far::LimitStencilTableFactoryReal<double>::LocationArrayVec locs;
    std::vector<int> located; // base vertex of each location
    for (int v = 0; v < nv; v++) {
        if (loc_ptex[v] < 0)
            continue;
        Far::LimitStencilTableFactoryReal<double>::LocationArray a;
        a.ptexIdx = loc_ptex[v];
        a.numLocations = 1;
        a.s = &loc_s[v];
        a.t = &loc_t[v];
        locs.push_back(a);
        located.push_back(v);
    }
    Far::LimitStencilTableFactoryReal<double>::Options lo;
    lo.generate1stDerivatives = false;
    const Far::LimitStencilTableReal<double> *st =
        Far::LimitStencilTableFactoryReal<double>::Create(*r, locs, nullptr, nullptr, lo);
    double t1 = now();

    // The table as plain arrays, rows in base-vertex order.
    const std::vector<int> &sz = st->GetSizes();
    const std::vector<Far::Index> &ci = st->GetControlIndices();
    const std::vector<double> &w = st->GetWeights();
    const std::vector<Far::Index> &so = st->GetOffsets();
    std::vector<int> row_of(nv, -1);
    for (size_t k = 0; k < located.size(); k++)
        row_of[located[k]] = (int)k;

    const double *mp = limn_mesh_positions(m);
    double lo3[3] = {1e300, 1e300, 1e300}, hi3[3] = {-1e300, -1e300, -1e300};
    for (int i = 0; i < nv; i++)
        for (int c = 0; c < 3; c++) {
            lo3[c] = std::min(lo3[c], mp[3 * i + c]);
            hi3[c] = std::max(hi3[c], mp[3 * i + c]);
        }
    double diag = std::sqrt((hi3[0] - lo3[0]) * (hi3[0] - lo3[0]) + (hi3[1] - lo3[1]) * (hi3[1] - lo3[1]) +
                            (hi3[2] - lo3[2]) * (hi3[2] - lo3[2]));
    std::vector<double> P(mp, mp + 3 * (size_t)nv), AP(3 * (size_t)nv);
    auto apply = [&](const std::vector<double> &x, std::vector<double> &y) {
        for (int v = 0; v < nv; v++) {
            int rrow = row_of[v];
            double s0 = 0, s1 = 0, s2 = 0;
            if (rrow < 0) {
                s0 = x[3 * v], s1 = x[3 * v + 1], s2 = x[3 * v + 2];
            } else {
                for (int k = so[rrow]; k < so[rrow] + sz[rrow]; k++) {
                    const double *p = &x[3 * (size_t)ci[k]];
                    s0 += w[k] * p[0];
                    s1 += w[k] * p[1];
                    s2 += w[k] * p[2];
                }
            }
            y[3 * v] = s0, y[3 * v + 1] = s1, y[3 * v + 2] = s2;
        }
    };
    // check against limn's A M
    std::vector<double> ours(3 * (size_t)nv);
    limn_limit_positions(ctx, m, loop ? LIMN_SCHEME_LOOP : LIMN_SCHEME_CATMARK, 0.0, ours.data());
    apply(P, AP);
    double check = 0;
    for (size_t i = 0; i < 3 * (size_t)nv; i++)
        check = std::max(check, std::fabs(AP[i] - ours[i]));

    int it = 0;
    double err = 0, t2 = now();
    for (;; it++) {
        apply(P, AP);
        err = 0;
        for (size_t i = 0; i < (size_t)nv; i++) {
            double r0 = mp[3 * i] - AP[3 * i], r1 = mp[3 * i + 1] - AP[3 * i + 1],
                   r2 = mp[3 * i + 2] - AP[3 * i + 2];
            err = std::max(err, std::sqrt(r0 * r0 + r1 * r1 + r2 * r2));
            P[3 * i] += r0, P[3 * i + 1] += r1, P[3 * i + 2] += r2;
        }
        if (err <= tol * diag || it >= max_iter)
            break;
    }
    double t3 = now();
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    printf("{\"impl\": \"opensubdiv_stencils\", \"vertices\": %d, \"scheme\": \"%s\", "
           "\"stencil_entries\": %zu, \"seconds_stencils\": %.6f, \"iterations\": %d, "
           "\"products\": %d, \"max_rel_error\": %.3g, \"seconds_iterate\": %.6f, "
           "\"seconds_per_product\": %.6g, \"max_diff_vs_limn\": %.3g, \"peak_rss_bytes\": %lld}\n",
           nv, loop ? "loop" : "catmark", w.size(), t1 - t0, it, it + 1, err / diag, t3 - t2,
           (t3 - t2) / (it + 1), check, (long long)ru.ru_maxrss * 1024);
    delete st;
    delete r;
    limn_mesh_destroy(m);
    limn_context_destroy(ctx);
    return 0;
}
