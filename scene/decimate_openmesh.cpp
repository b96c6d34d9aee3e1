// The one OpenMesh decimation shim (C++ behind extern "C"): Garland & Heckbert's quadric error
// metric (1997) through OpenMesh's DecimaterT + ModQuadricT, guarded by ModNormalFlippingT so no
// face turns over, with sharp edges kept as feature lines. Compiled -O2 -DNDEBUG even in Debug
// builds (PLATFORM.md §7b: the template code is several times slower with assertions on).
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <new>
#include <vector>

#include "scene/lodgen_internal.h"

namespace {

typedef OpenMesh::TriMesh_ArrayKernelT<> OmTriMesh;

// OpenMesh's modules log to omerr/omlog ("Mesh has no face normals…"); keep them off the terminal.
struct QuietLogs {
    QuietLogs() { ::omlog().disable(), ::omout().disable(), ::omerr().disable(); }
    ~QuietLogs() { ::omlog().enable(), ::omout().enable(), ::omerr().enable(); }
};

// Builds the half-edge mesh. A face OpenMesh refuses (it would make an edge non-manifold) gets
// its own copies of its three vertices, as OpenMesh's own importer does; the copies are welded
// back after decimation (scn_mesh_weld_exact) where they have not moved apart.
void build(const struct scn_mesh *in, OmTriMesh &mesh)
{
    mesh.reserve(in->vertex_count, in->index_count, in->index_count / 3);
    std::vector<OmTriMesh::VertexHandle> vh(in->vertex_count);
    for (uint32_t v = 0; v < in->vertex_count; ++v) {
        const float *p = in->positions + 3 * (size_t)v;
        vh[v] = mesh.add_vertex(OmTriMesh::Point(p[0], p[1], p[2]));
    }
    for (uint32_t t = 0; t + 2 < in->index_count; t += 3) {
        OmTriMesh::VertexHandle f[3] = {vh[in->indices[t]], vh[in->indices[t + 1]], vh[in->indices[t + 2]]};
        if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2])
            continue;
        if (mesh.add_face(f[0], f[1], f[2]).is_valid())
            continue;
        for (int k = 0; k < 3; ++k)
            f[k] = mesh.add_vertex(OmTriMesh::Point(mesh.point(f[k])));
        mesh.add_face(f[0], f[1], f[2]);
    }
}

// Feature lines: interior edges whose faces meet at a dihedral angle above the threshold (the
// angle between the face normals, atan2 form: exact near 0 and 180°). The Decimater then collapses
// a feature vertex only along a feature edge (BaseDecimaterT::is_collapse_legal), so lines slide
// along themselves but never off; their ends and corners (feature valence ≠ 2) are locked.
void mark_features(OmTriMesh &mesh, double angle_deg)
{
    double limit = angle_deg * M_PI / 180.0;
    for (OmTriMesh::EdgeHandle eh : mesh.edges()) {
        if (mesh.is_boundary(eh))
            continue;
        OmTriMesh::HalfedgeHandle h0 = mesh.halfedge_handle(eh, 0), h1 = mesh.halfedge_handle(eh, 1);
        OmTriMesh::Normal n0 = mesh.calc_face_normal(mesh.face_handle(h0));
        OmTriMesh::Normal n1 = mesh.calc_face_normal(mesh.face_handle(h1));
        double cr = (double)OpenMesh::cross(n0, n1).norm(), dt = (double)OpenMesh::dot(n0, n1);
        if (std::atan2(cr, dt) > limit) {
            mesh.status(eh).set_feature(true);
            mesh.status(mesh.to_vertex_handle(h0)).set_feature(true);
            mesh.status(mesh.to_vertex_handle(h1)).set_feature(true);
        }
    }
    for (OmTriMesh::VertexHandle v : mesh.vertices()) {
        if (!mesh.status(v).feature())
            continue;
        int valence = 0;
        for (OmTriMesh::EdgeHandle e : mesh.ve_range(v))
            valence += mesh.status(e).feature() ? 1 : 0;
        if (valence != 2)
            mesh.status(v).set_locked(true);
    }
}

int extract(const OmTriMesh &mesh, struct scn_mesh *out)
{
    memset(out, 0, sizeof *out);
    size_t nv = mesh.n_vertices(), nf = mesh.n_faces();
    out->positions = (float *)malloc((nv * 3 + 1) * sizeof(float));
    out->normals = (float *)calloc(nv * 3 + 1, sizeof(float));
    out->indices = (uint32_t *)malloc((nf * 3 + 1) * sizeof(uint32_t));
    if (!out->positions || !out->normals || !out->indices) {
        scn_mesh_free(out);
        return -1;
    }
    for (OmTriMesh::VertexHandle v : mesh.vertices()) {
        OmTriMesh::Point p = mesh.point(v);
        float *d = out->positions + 3 * (size_t)v.idx();
        d[0] = p[0], d[1] = p[1], d[2] = p[2];
    }
    out->vertex_count = out->vertex_cap = (uint32_t)nv;
    uint32_t n = 0;
    for (OmTriMesh::FaceHandle f : mesh.faces()) {
        if (mesh.status(f).deleted())
            continue;
        for (OmTriMesh::VertexHandle v : mesh.fv_range(f))
            out->indices[n++] = (uint32_t)v.idx();
    }
    out->index_count = n, out->index_cap = (uint32_t)(nf * 3 + 1);
    return scn_mesh_weld_exact(out) < 0 ? -1 : 0;
}

} // namespace

extern "C" int scn_om_decimate_chain(const struct scn_mesh *in, const uint32_t *target_tris, int count,
                                     double feature_angle_deg, struct scn_mesh *outs, struct scn_om_timing *timing,
                                     const struct scn_chain_observer *obs, struct hl_error *err)
{
    struct scn_om_timing tm = {0, 0, 0, 0, 0, 0};
    for (int k = 0; k < count; ++k)
        memset(&outs[k], 0, sizeof outs[k]);
    try {
        QuietLogs quiet;
        double t0 = hl_clock_now_s();
        OmTriMesh mesh;
        mesh.request_vertex_status();
        mesh.request_edge_status();
        mesh.request_face_status();
        mesh.request_face_normals();
        build(in, mesh);
        mesh.update_face_normals();
        double t1 = hl_clock_now_s();
        tm.build_s = t1 - t0;
        if (feature_angle_deg >= 0)
            mark_features(mesh, feature_angle_deg);
        double t2 = hl_clock_now_s();
        tm.feature_s = t2 - t1;

        typedef OpenMesh::Decimater::DecimaterT<OmTriMesh> Decimater;
        Decimater dec(mesh);
        OpenMesh::Decimater::ModQuadricT<OmTriMesh>::Handle quadric;
        OpenMesh::Decimater::ModNormalFlippingT<OmTriMesh>::Handle flip;
        dec.add(quadric);
        dec.module(quadric).unset_max_err(); // quadric as priority only: the target count decides
        dec.add(flip);
        if (!dec.initialize())
            return hl_fail(err, "OpenMesh decimater: cannot initialise its modules");
        double t3 = hl_clock_now_s();
        tm.init_s = t3 - t2;
        for (int k = 0; k < count; ++k) {
            double a = hl_clock_now_s();
            // One decimater through all levels (PLATFORM.md §7b): each level starts where the last
            // one stopped. Where no legal collapse is left it returns early; we take what it reached.
            dec.decimate_to_faces(0, target_tris[k]);
            double b = hl_clock_now_s();
            mesh.garbage_collection();
            double c = hl_clock_now_s();
            if (extract(mesh, &outs[k]) != 0) {
                for (int j = 0; j <= k; ++j)
                    scn_mesh_free(&outs[j]);
                return hl_fail(err, "OpenMesh decimater: out of memory");
            }
            double d = hl_clock_now_s();
            tm.decimate_s += b - a, tm.gc_s += c - b, tm.extract_s += d - c;
            if (obs && obs->level_done)
                obs->level_done(obs->user, k);
        }
    } catch (const std::bad_alloc &) {
        for (int j = 0; j < count; ++j)
            scn_mesh_free(&outs[j]);
        return hl_fail(err, "OpenMesh decimater: out of memory");
    } catch (const std::exception &e) {
        for (int j = 0; j < count; ++j)
            scn_mesh_free(&outs[j]);
        return hl_fail(err, "OpenMesh decimater failed: %s", e.what());
    }
    if (timing)
        *timing = tm;
    return 0;
}
