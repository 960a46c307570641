// qex <-> OpenMesh adapter (header-only; link OpenMeshCore). For users who hold their meshes in
// OpenMesh: the map is read from halfedge texture coordinates, the OpenMesh convention being that
// a halfedge's texcoord is its to-vertex's UV in the halfedge's face.
#pragma once

#include "qex/qex.h"

#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>

#include <array>

namespace qex {

/// Builds a qex::Input from a triangle mesh with halfedge_texcoords2D (throws nothing; faces that
/// are not triangles are skipped and counted in `skipped_faces`).
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
            if (k == 3) { k = 4; break; }
            tri[k] = mesh.to_vertex_handle(heh).idx();
            const auto t = mesh.texcoord2D(heh);
            uv[k] = {static_cast<double>(t[0]), static_cast<double>(t[1])};
            ++k;
        }
        if (k != 3) { ++skipped; continue; }
        in.triangles.push_back(tri);
        in.uvs.insert(in.uvs.end(), uv.begin(), uv.end());
    }
    if (skipped_faces) *skipped_faces = skipped;
    return in;
}

/// The quad mesh as an OpenMesh polygon mesh, local UVs as halfedge texcoords.
template <class PolyMesh = OpenMesh::PolyMesh_ArrayKernelT<>>
PolyMesh to_openmesh(const QuadMesh& q) {
    PolyMesh mesh;
    mesh.request_halfedge_texcoords2D();
    std::vector<typename PolyMesh::VertexHandle> vh;
    vh.reserve(q.positions.size());
    for (const auto& p : q.positions)
        vh.push_back(mesh.add_vertex(typename PolyMesh::Point(static_cast<float>(p[0]), static_cast<float>(p[1]),
                                                              static_cast<float>(p[2]))));
    for (std::size_t f = 0; f < q.faces.size(); ++f) {
        std::vector<typename PolyMesh::VertexHandle> face;
        for (int v : q.faces[f]) face.push_back(vh[v]);
        const auto fh = mesh.add_face(face);
        if (!fh.is_valid() || q.face_uvs.size() != q.faces.size()) continue;
        std::size_t k = 0;
        for (auto heh : mesh.fh_range(fh)) {
            // Corners in face order: the halfedge into corner k is the k-th of fh_range starting at
            // the halfedge into the first vertex.
            for (std::size_t i = 0; i < q.faces[f].size(); ++i)
                if (mesh.to_vertex_handle(heh) == vh[q.faces[f][i]]) k = i;
            const auto& t = q.face_uvs[f][k];
            mesh.set_texcoord2D(heh, typename PolyMesh::TexCoord2D(static_cast<float>(t[0]), static_cast<float>(t[1])));
        }
    }
    return mesh;
}

} // namespace qex
