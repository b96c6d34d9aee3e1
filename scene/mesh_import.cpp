// OBJ/PLY/OFF/STL through OpenMesh's IO (C++ behind extern "C"; the rest of scene/ is C11).
//
// OpenMesh's readers hand each vertex and face to an importer. Its stock ImporterT builds a half-edge
// mesh and, where a face would make an edge non-manifold, silently duplicates the face's vertices
// (beetle.obj: 105 of them) or drops faces with repeated vertices. We want the file as written, so
// this importer derives from ImporterT (the readers still get a valid mesh to attach attributes to)
// and also records every vertex and every face exactly as read into a scn_soup; validation
// (mesh_validate.c) then welds, counts and refuses with the file's own numbering.
#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/IO/importer/ImporterT.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <new>
#include <sstream>
#include <string>
#include <vector>

#include "scene/lodgen_internal.h"

namespace {

typedef OpenMesh::PolyMesh_ArrayKernelT<> OmPolyMesh;

class SoupImporter : public OpenMesh::IO::ImporterT<OmPolyMesh> {
  public:
    typedef OpenMesh::VertexHandle VertexHandle;
    typedef OpenMesh::FaceHandle FaceHandle;
    typedef std::vector<VertexHandle> VHandles;
    SoupImporter(OmPolyMesh &mesh) : OpenMesh::IO::ImporterT<OmPolyMesh>(mesh) {}

    // The PLY reader adds a vertex first and sets its point after (the others pass the point).
    VertexHandle add_vertex() override
    {
        pos.push_back(NAN), pos.push_back(NAN), pos.push_back(NAN);
        return ImporterT::add_vertex();
    }
    // The readers reserve the counts a header announces before reading a record; our checks bound
    // those counts by the file's size (mesh_off_check.c, mesh_ply_check.c), and not reserving at all
    // keeps any reader we did not check from allocating for content that is not there.
    void reserve(unsigned int, unsigned int, unsigned int) override {}
    VertexHandle add_vertex(const OpenMesh::Vec3f &p) override
    {
        pos.push_back(p[0]), pos.push_back(p[1]), pos.push_back(p[2]);
        return ImporterT::add_vertex(p);
    }
    VertexHandle add_vertex(const OpenMesh::Vec3d &p) override
    {
        pos.push_back(p[0]), pos.push_back(p[1]), pos.push_back(p[2]);
        return ImporterT::add_vertex(p);
    }
    void set_point(VertexHandle vh, const OpenMesh::Vec3f &p) override
    {
        size_t i = 3 * (size_t)vh.idx();
        if (vh.is_valid() && i + 2 < pos.size())
            pos[i] = p[0], pos[i + 1] = p[1], pos[i + 2] = p[2];
        ImporterT::set_point(vh, p);
    }
    void set_normal(VertexHandle vh, const OpenMesh::Vec3f &n) override { record_normal(vh, n[0], n[1], n[2]); }
    void set_normal(VertexHandle vh, const OpenMesh::Vec3d &n) override { record_normal(vh, n[0], n[1], n[2]); }
    FaceHandle add_face(const VHandles &idx) override
    {
        std::vector<int> f(idx.size());
        for (size_t i = 0; i < idx.size(); ++i)
            f[i] = idx[i].idx();
        faces.push_back(f);
        return ImporterT::add_face(idx);
    }

    std::vector<double> pos;
    std::vector<float> nrm; // 3 per vertex once any normal is given; NaN where none
    std::vector<std::vector<int>> faces;

  private:
    void record_normal(VertexHandle vh, double x, double y, double z)
    {
        size_t i = 3 * (size_t)vh.idx();
        // The OBJ reader sets normals through a face's vertex handles, and a face may name a vertex
        // that does not exist (index 2^31 − 1: a 24 GB resize; found by fuzz_mesh_import).
        // Validation refuses such faces; their normals are not recorded.
        if (!vh.is_valid() || i + 3 > pos.size())
            return;
        if (nrm.size() < i + 3)
            nrm.resize(pos.size() > i + 3 ? pos.size() : i + 3, NAN);
        nrm[i] = (float)x, nrm[i + 1] = (float)y, nrm[i + 2] = (float)z;
    }
};

// OpenMesh logs to std::cout/std::cerr through its own multiplexing streams ("[OBJReader] : ...").
// While a read runs, omlog/omout are off and std::cerr's buffer is swapped for a string, so `hmdlod`
// prints only its own messages and the reader's complaint can go into ours. (Not omerr().connect /
// disconnect: OpenMesh 9's disconnect leaks its target.)
class QuietOpenMesh {
  public:
    QuietOpenMesh()
    {
        ::omlog().disable();
        ::omout().disable();
        saved = std::cerr.rdbuf(text.rdbuf());
    }
    ~QuietOpenMesh()
    {
        ::omerr().flush();
        std::cerr.rdbuf(saved);
        ::omout().enable();
        ::omlog().enable();
    }
    std::ostringstream text;

  private:
    std::streambuf *saved;
};

// The first line of what OpenMesh complained about, for the message ("" if nothing).
std::string first_line(const std::string &s)
{
    size_t b = s.find_first_not_of(" \t\r\n0123456789"); // OpenMesh prefixes some with a count
    if (b == std::string::npos)
        return "";
    size_t e = s.find_first_of("\r\n", b);
    return s.substr(b, e == std::string::npos ? std::string::npos : e - b);
}

int fill_soup(const SoupImporter &imp, struct scn_soup *soup)
{
    size_t nv = imp.pos.size() / 3;
    if (nv >= UINT32_MAX)
        return -1;
    soup->vertex_count = (uint32_t)nv;
    soup->positions = (double *)malloc((imp.pos.size() + 1) * sizeof(double));
    if (!soup->positions)
        return -1;
    if (nv)
        memcpy(soup->positions, imp.pos.data(), imp.pos.size() * sizeof(double));
    if (!imp.nrm.empty()) {
        soup->normals = (float *)malloc((nv * 3 + 1) * sizeof(float));
        if (!soup->normals)
            return -1;
        for (size_t i = 0; i < nv * 3; ++i)
            soup->normals[i] = i < imp.nrm.size() ? imp.nrm[i] : NAN;
    }
    std::vector<uint32_t> idx;
    for (const std::vector<int> &f : imp.faces) {
        idx.resize(f.size());
        for (size_t i = 0; i < f.size(); ++i)
            idx[i] = f[i] < 0 ? UINT32_MAX : (uint32_t)f[i];
        scn_soup_add_face(soup, idx.data(), (uint32_t)idx.size());
    }
    return soup->failed ? -1 : 0;
}

} // namespace

extern "C" int scn_om_read(const char *path, struct scn_soup *soup, int faces_follow, struct hl_error *err)
{
    memset(soup, 0, sizeof *soup);
    try {
        OmPolyMesh mesh;
        mesh.request_vertex_normals();
        SoupImporter imp(mesh);
        OpenMesh::IO::Options opt = OpenMesh::IO::Options::VertexNormal;
        bool ok;
        std::string complaint;
        {
            QuietOpenMesh quiet;
            ok = OpenMesh::IO::IOManager().read(path, imp, opt);
            complaint = first_line(quiet.text.str());
        }
        // With strips to come, OpenMesh may stop after the vertices: its reader skips an element it
        // does not know by its scalars' sizes and can run into the end of the file there.
        if (!ok && imp.faces.empty() && !(faces_follow && !imp.pos.empty()))
            return hl_fail(err, "%s: OpenMesh cannot read it%s%s", path, complaint.empty() ? "" : ": ",
                           complaint.c_str());
        // A reader that stopped part-way (ok == false) still hands over what it read; validation
        // decides whether that is a mesh (a truncated OBJ is usually a smaller valid one).
        snprintf(soup->reader_note, sizeof soup->reader_note, "%s", complaint.c_str());
        if (fill_soup(imp, soup) != 0) {
            scn_soup_free(soup);
            return hl_fail(err, "%s: out of memory while reading", path);
        }
        return 0;
    } catch (const std::bad_alloc &) {
        scn_soup_free(soup);
        return hl_fail(err, "%s: out of memory while reading", path);
    } catch (const std::exception &e) {
        scn_soup_free(soup);
        return hl_fail(err, "%s: OpenMesh reader failed: %s", path, e.what());
    } catch (...) {
        scn_soup_free(soup);
        return hl_fail(err, "%s: OpenMesh reader failed", path);
    }
}
