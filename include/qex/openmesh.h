// qex <-> OpenMesh adapter (header-only; link OpenMeshCore). For users who hold their meshes in
// OpenMesh: the map is read from halfedge texture coordinates, the OpenMesh convention being that
// a halfedge's texcoord is its to-vertex's UV in the halfedge's face.
#pragma once

#include "qex/qex.h"

// OpenMesh's property arrays grow by copying a default-constructed VectorT, whose elements are
// left uninitialized by design; GCC 12 flags that copy (-Wmaybe-uninitialized) in every
// translation unit that adds a vertex, so the warning is silenced for OpenMesh's headers only.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

#include <array>
#include <cstddef>
#include <vector>

namespace qex {

/// Builds a qex::Input from a triangle mesh with halfedge_texcoords2D. Faces that are not
/// triangles are skipped and counted in `*skipped_faces` when it is given.
template <class Mesh>
Input from_openmesh(const Mesh& mesh, int* skipped_faces = nullptr) {
    Input in;
    in.positions.reserve(mesh.n_vertices());
    for (auto vh : mesh.vertices()) {
        const auto p = mesh.point(vh);
        in.positions.push_back({static_cast<double>(p[0]), static_cast<double>(p[1]), static_cast<double>(p[2])});
    }
    int skipped = 0;
    for (auto fh : mesh.faces()) {
        std::array<int, 3> tri{};
        std::array<std::array<double, 2>, 3> uv{};
        int k = 0;
        for (auto heh : mesh.fh_range(fh)) {
            if (k == 3) {
                k = 4;
                break;
            }
            tri[k] = mesh.to_vertex_handle(heh).idx();
            const auto t = mesh.texcoord2D(heh);
            uv[k] = {static_cast<double>(t[0]), static_cast<double>(t[1])};
            ++k;
        }
        if (k != 3) {
            ++skipped;
            continue;
        }
        in.triangles.push_back(tri);
        in.uvs.insert(in.uvs.end(), uv.begin(), uv.end());
    }
    if (skipped_faces) *skipped_faces = skipped;
    return in;
}

/// The quad mesh as an OpenMesh polygon mesh (positions and UVs through float), local UVs as
/// halfedge texcoords if every face has them.
///
/// OpenMesh's add_face rejects a face its halfedge structure cannot hold: one that would take the
/// side of an edge another face already has (a third face on an edge, or a second one running
/// along it in the same direction), one at a vertex whose faces already close around it, or one
/// whose fans at a vertex cannot be relinked; and here a face with a vertex index out of range.
/// Such faces are left out of the result. Their
/// indices into `q.faces`, ascending, are stored in `*rejected_faces` (cleared first) when it is
/// given: the result has `q.faces.size() - rejected_faces->size()` faces, the accepted ones in
/// their order in `q`. Pass it unless the mesh is known to be manifold (qex's valid meshes are).
template <class PolyMesh = OpenMesh::PolyMesh_ArrayKernelT<>>
PolyMesh to_openmesh(const QuadMesh& q, std::vector<std::size_t>* rejected_faces = nullptr) {
    PolyMesh mesh;
    mesh.request_halfedge_texcoords2D();
    if (rejected_faces) rejected_faces->clear();
    std::vector<typename PolyMesh::VertexHandle> vh;
    vh.reserve(q.positions.size());
    for (const auto& p : q.positions)
        vh.push_back(mesh.add_vertex(
            typename PolyMesh::Point(static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2]))));
    for (std::size_t f = 0; f < q.faces.size(); ++f) {
        std::vector<typename PolyMesh::VertexHandle> face;
        for (int v : q.faces[f])
            if (v >= 0 && static_cast<std::size_t>(v) < vh.size()) face.push_back(vh[static_cast<std::size_t>(v)]);
        const auto fh = face.size() == q.faces[f].size() ? mesh.add_face(face) : typename PolyMesh::FaceHandle();
        if (!fh.is_valid()) {
            if (rejected_faces) rejected_faces->push_back(f);
            continue;
        }
        if (q.face_uvs.size() != q.faces.size()) continue;
        std::size_t k = 0;
        for (auto heh : mesh.fh_range(fh)) {
            // The halfedge's texcoord is the UV of the corner it points to.
            for (std::size_t i = 0; i < q.faces[f].size(); ++i)
                if (mesh.to_vertex_handle(heh) == vh[q.faces[f][i]]) k = i;
            const auto& t = q.face_uvs[f][k];
            mesh.set_texcoord2D(heh, typename PolyMesh::TexCoord2D(static_cast<float>(t[0]), static_cast<float>(t[1])));
        }
    }
    return mesh;
}

} // namespace qex
