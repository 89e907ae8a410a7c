/* SPDX-License-Identifier: MIT */
// Test-only oracle: OpenSubdiv 3.5 Far API in double precision behind a C API.
// See osd_oracle.h. Independent of limn's code.

#include "osd_oracle.h"

#include <opensubdiv/far/error.h>
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefiner.h>
#include <opensubdiv/far/topologyRefinerFactory.h>
#include <opensubdiv/sdc/options.h>
#include <opensubdiv/sdc/types.h>

#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <new>
#include <string>
#include <vector>

using namespace OpenSubdiv;

namespace {

// ---------------------------------------------------------------- messages --
std::string g_messages;  // OSD errors/warnings of the current call

void on_osd_error(Far::ErrorType type, const char *message) {
    g_messages += "OSD error ";
    g_messages += std::to_string(static_cast<int>(type));
    g_messages += ": ";
    g_messages += message ? message : "(null)";
    g_messages += "\n";
}

void on_osd_warning(const char *message) {
    g_messages += "OSD warning: ";
    g_messages += message ? message : "(null)";
    g_messages += "\n";
}

void begin_call() {
    Far::SetErrorCallback(on_osd_error);
    Far::SetWarningCallback(on_osd_warning);
    g_messages.clear();
}

int fail(char *err, size_t errlen, const char *fmt, ...) {
    if (err && errlen > 0) {
        va_list ap;
        va_start(ap, fmt);
        std::vsnprintf(err, errlen, fmt, ap);
        va_end(ap);
        if (!g_messages.empty()) {
            size_t used = std::strlen(err);
            if (used + 3 < errlen)
                std::snprintf(err + used, errlen - used, " [%s]", g_messages.c_str());
        }
    }
    return 1;
}

// ------------------------------------------------------- primvar buffers --
struct Vtx {
    double p[3];
    void Clear(void * = nullptr) { p[0] = p[1] = p[2] = 0.0; }
    void AddWithWeight(Vtx const &src, double w) {
        p[0] += w * src.p[0];
        p[1] += w * src.p[1];
        p[2] += w * src.p[2];
    }
};

// --------------------------------------------------------------- refiner --
int check_input(int scheme, int nverts, const double *pos, int nfaces, const int *face_sizes,
                const int *face_indices, bool need_pos, char *err, size_t errlen) {
    if (scheme != 0 && scheme != 1)
        return fail(err, errlen, "osd_oracle: scheme must be 0 (Loop) or 1 (Catmull-Clark), got %d",
                    scheme);
    if (nverts < 0 || nfaces < 0)
        return fail(err, errlen, "osd_oracle: negative counts");
    if ((need_pos && nverts > 0 && !pos) || (nfaces > 0 && (!face_sizes || !face_indices)))
        return fail(err, errlen, "osd_oracle: NULL array");
    long total = 0;
    for (int f = 0; f < nfaces; ++f) {
        if (face_sizes[f] < 3)
            return fail(err, errlen, "osd_oracle: face %d has %d vertices (< 3)", f,
                        face_sizes[f]);
        for (int k = 0; k < face_sizes[f]; ++k) {
            int v = face_indices[total + k];
            if (v < 0 || v >= nverts)
                return fail(err, errlen, "osd_oracle: face %d references vertex %d (nverts %d)",
                            f, v, nverts);
        }
        total += face_sizes[f];
    }
    return 0;
}

Far::TopologyRefiner *make_refiner(int scheme, int nverts, int nfaces, const int *face_sizes,
                                   const int *face_indices) {
    Sdc::SchemeType type = scheme == 0 ? Sdc::SCHEME_LOOP : Sdc::SCHEME_CATMARK;
    Sdc::Options opts;
    opts.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER);
    opts.SetFVarLinearInterpolation(Sdc::Options::FVAR_LINEAR_ALL);
    opts.SetCreasingMethod(Sdc::Options::CREASE_UNIFORM);
    opts.SetTriangleSubdivision(Sdc::Options::TRI_SUB_CATMARK);

    Far::TopologyDescriptor desc;
    desc.numVertices = nverts;
    desc.numFaces = nfaces;
    desc.numVertsPerFace = face_sizes;
    desc.vertIndicesPerFace = face_indices;

    Far::TopologyRefinerFactory<Far::TopologyDescriptor>::Options fopts(type, opts);
    return Far::TopologyRefinerFactory<Far::TopologyDescriptor>::Create(desc, fopts);
}

// Checks that vertex i of level l+1 is the child of vertex i of level l, for all l.
int check_vertex_order(Far::TopologyRefiner const &r, char *err, size_t errlen) {
    for (int l = 0; l < r.GetMaxLevel(); ++l) {
        Far::TopologyLevel const &lev = r.GetLevel(l);
        Far::TopologyLevel const &child = r.GetLevel(l + 1);
        int nv = lev.GetNumVertices();
        if (child.GetNumVertices() != nv + lev.GetNumFaces() * (r.GetSchemeType() ==
                                                                   Sdc::SCHEME_LOOP ? 0 : 1) +
                                          lev.GetNumEdges())
            return fail(err, errlen,
                        "osd_oracle: level %d has %d vertices, expected V+F+E (Catmark) or V+E "
                        "(Loop) of level %d",
                        l + 1, child.GetNumVertices(), l);
        for (int v = 0; v < nv; ++v) {
            if (lev.GetVertexChildVertex(v) != v)
                return fail(err, errlen,
                            "osd_oracle: child of level-%d vertex %d is level-%d vertex %d "
                            "(expected vertex-vertices first, same index)",
                            l, v, l + 1, lev.GetVertexChildVertex(v));
        }
    }
    return 0;
}

}  // namespace

// ============================================================ C interface ==
extern "C" const char *osd_oracle_last_messages(void) { return g_messages.c_str(); }

extern "C" int osd_oracle_limit(int scheme, int nverts, const double *pos, int nfaces,
                                const int *face_sizes, const int *face_indices,
                                double *limit_out, char *err, size_t errlen) {
    try {
        begin_call();
        if (err && errlen) err[0] = '\0';
        if (check_input(scheme, nverts, pos, nfaces, face_sizes, face_indices, true, err, errlen))
            return 1;
        if (!limit_out) return fail(err, errlen, "osd_oracle_limit: NULL limit_out");
        if (nverts == 0) return 0;

        std::unique_ptr<Far::TopologyRefiner> r(
            make_refiner(scheme, nverts, nfaces, face_sizes, face_indices));
        if (!r) return fail(err, errlen, "osd_oracle_limit: TopologyRefinerFactory::Create failed");

        Far::TopologyRefiner::UniformOptions uo(1);
        uo.orderVerticesFromFacesFirst = false;
        uo.fullTopologyInLastLevel = true;
        r->RefineUniform(uo);
        if (r->GetMaxLevel() != 1)
            return fail(err, errlen, "osd_oracle_limit: RefineUniform(1) gave %d levels",
                        r->GetMaxLevel());
        if (check_vertex_order(*r, err, errlen)) return 1;

        std::vector<Vtx> v0(nverts), v1(r->GetLevel(1).GetNumVertices()), lim(v1.size());
        for (int i = 0; i < nverts; ++i)
            for (int c = 0; c < 3; ++c) v0[i].p[c] = pos[3 * i + c];

        Far::PrimvarRefinerReal<double> pr(*r);
        Vtx *src = v0.data();
        Vtx *dst = v1.data();
        pr.Interpolate(1, src, dst);
        Vtx *lsrc = v1.data();
        Vtx *ldst = lim.data();
        pr.Limit(lsrc, ldst);

        // Unreferenced vertices need no special case: OSD tags a face-less vertex
        // non-manifold and infinitely sharp, refines it to a copy of itself and its
        // limit is its own position (oracle_selfcheck asserts this).
        Far::TopologyLevel const &base = r->GetLevel(0);
        for (int i = 0; i < nverts; ++i) {
            int ci = base.GetVertexChildVertex(i);
            for (int c = 0; c < 3; ++c) limit_out[3 * i + c] = lim[ci].p[c];
        }
        return 0;
    } catch (std::bad_alloc const &) {
        return fail(err, errlen, "osd_oracle_limit: out of memory");
    } catch (...) {
        return fail(err, errlen, "osd_oracle_limit: C++ exception");
    }
}

extern "C" int osd_oracle_refine(int scheme, int nverts, const double *pos, int nfaces,
                                 const int *face_sizes, const int *face_indices, int levels,
                                 int *out_nverts, double **out_pos, int *out_nfaces,
                                 int **out_face_sizes, int **out_face_indices, char *err,
                                 size_t errlen) {
    if (out_nverts) *out_nverts = 0;
    if (out_nfaces) *out_nfaces = 0;
    if (out_pos) *out_pos = nullptr;
    if (out_face_sizes) *out_face_sizes = nullptr;
    if (out_face_indices) *out_face_indices = nullptr;
    double *opos = nullptr;
    int *osizes = nullptr, *oidx = nullptr;
    try {
        begin_call();
        if (err && errlen) err[0] = '\0';
        if (!out_nverts || !out_pos || !out_nfaces || !out_face_sizes || !out_face_indices)
            return fail(err, errlen, "osd_oracle_refine: NULL output pointer");
        if (check_input(scheme, nverts, pos, nfaces, face_sizes, face_indices, true, err, errlen))
            return 1;
        if (levels < 0 || levels > 15)
            return fail(err, errlen, "osd_oracle_refine: levels must be in [0, 15], got %d",
                        levels);

        std::unique_ptr<Far::TopologyRefiner> r(
            make_refiner(scheme, nverts, nfaces, face_sizes, face_indices));
        if (!r)
            return fail(err, errlen, "osd_oracle_refine: TopologyRefinerFactory::Create failed");
        if (levels > 0) {
            Far::TopologyRefiner::UniformOptions uo(levels);
            uo.orderVerticesFromFacesFirst = false;
            uo.fullTopologyInLastLevel = true;
            r->RefineUniform(uo);
            if (r->GetMaxLevel() != levels)
                return fail(err, errlen, "osd_oracle_refine: RefineUniform(%d) gave %d levels",
                            levels, r->GetMaxLevel());
            if (check_vertex_order(*r, err, errlen)) return 1;
        }

        std::vector<Vtx> cur(nverts), next;
        for (int i = 0; i < nverts; ++i)
            for (int c = 0; c < 3; ++c) cur[i].p[c] = pos[3 * i + c];
        Far::PrimvarRefinerReal<double> pr(*r);
        for (int l = 1; l <= levels; ++l) {
            next.assign(r->GetLevel(l).GetNumVertices(), Vtx());
            Vtx *src = cur.data();
            Vtx *dst = next.data();
            pr.Interpolate(l, src, dst);
            cur.swap(next);
        }

        Far::TopologyLevel const &fin = r->GetLevel(levels);
        int nv = fin.GetNumVertices(), nf = fin.GetNumFaces();
        if ((int)cur.size() != nv)
            return fail(err, errlen, "osd_oracle_refine: vertex count mismatch");
        long nidx = 0;
        for (int f = 0; f < nf; ++f) nidx += fin.GetFaceVertices(f).size();

        opos = (double *)std::malloc(sizeof(double) * 3 * (size_t)(nv > 0 ? nv : 1));
        osizes = (int *)std::malloc(sizeof(int) * (size_t)(nf > 0 ? nf : 1));
        oidx = (int *)std::malloc(sizeof(int) * (size_t)(nidx > 0 ? nidx : 1));
        if (!opos || !osizes || !oidx) throw std::bad_alloc();
        for (int i = 0; i < nv; ++i)
            for (int c = 0; c < 3; ++c) opos[3 * i + c] = cur[i].p[c];
        long k = 0;
        for (int f = 0; f < nf; ++f) {
            Far::ConstIndexArray fv = fin.GetFaceVertices(f);
            osizes[f] = fv.size();
            for (int j = 0; j < fv.size(); ++j) oidx[k++] = fv[j];
        }
        *out_nverts = nv;
        *out_pos = opos;
        *out_nfaces = nf;
        *out_face_sizes = osizes;
        *out_face_indices = oidx;
        return 0;
    } catch (std::bad_alloc const &) {
        std::free(opos);
        std::free(osizes);
        std::free(oidx);
        return fail(err, errlen, "osd_oracle_refine: out of memory");
    } catch (...) {
        std::free(opos);
        std::free(osizes);
        std::free(oidx);
        return fail(err, errlen, "osd_oracle_refine: C++ exception");
    }
}

extern "C" int osd_oracle_classify(int scheme, int nverts, int nfaces, const int *face_sizes,
                                   const int *face_indices, int *is_boundary,
                                   int *is_nonmanifold, int *is_corner, char *err,
                                   size_t errlen) {
    try {
        begin_call();
        if (err && errlen) err[0] = '\0';
        if (check_input(scheme, nverts, nullptr, nfaces, face_sizes, face_indices, false, err,
                        errlen))
            return 1;
        std::unique_ptr<Far::TopologyRefiner> r(
            make_refiner(scheme, nverts, nfaces, face_sizes, face_indices));
        if (!r)
            return fail(err, errlen, "osd_oracle_classify: TopologyRefinerFactory::Create failed");
        Far::TopologyLevel const &base = r->GetLevel(0);
        for (int i = 0; i < nverts; ++i) {
            if (is_boundary) is_boundary[i] = base.IsVertexBoundary(i) ? 1 : 0;
            if (is_nonmanifold) is_nonmanifold[i] = base.IsVertexNonManifold(i) ? 1 : 0;
            if (is_corner) is_corner[i] = base.IsVertexCorner(i) ? 1 : 0;
        }
        return 0;
    } catch (...) {
        return fail(err, errlen, "osd_oracle_classify: C++ exception");
    }
}
