// The OpenMesh adapter: a generated map through OpenMesh and back extracts the same quad mesh, and
// faces OpenMesh rejects on the way out are reported.
#include "qex/openmesh.h"
#include "test_support.h"

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

namespace qex::testing {
namespace {

TEST(OpenMesh, RoundTripThroughHalfedgeTexcoords) {
    const Input in = make_map(cube_layout(), 2, 3);
    OpenMesh::TriMesh_ArrayKernelT<> tm;
    tm.request_halfedge_texcoords2D();
    std::vector<OpenMesh::VertexHandle> vh;
    for (const auto& p : in.positions) vh.push_back(tm.add_vertex({float(p[0]), float(p[1]), float(p[2])}));
    for (std::size_t f = 0; f < in.triangles.size(); ++f) {
        const auto fh = tm.add_face(vh[in.triangles[f][0]], vh[in.triangles[f][1]], vh[in.triangles[f][2]]);
        ASSERT_TRUE(fh.is_valid());
        for (auto heh : tm.fh_range(fh))
            for (int k = 0; k < 3; ++k)
                if (tm.to_vertex_handle(heh) == vh[in.triangles[f][k]])
                    tm.set_texcoord2D(heh, {float(in.uvs[3 * f + k][0]), float(in.uvs[3 * f + k][1])});
    }
    int skipped = -1;
    const Input back = from_openmesh(tm, &skipped);
    EXPECT_EQ(skipped, 0);
    ASSERT_EQ(back.triangles.size(), in.triangles.size());
    const Result r = extract_valid(back);
    EXPECT_EQ(static_cast<std::int64_t>(r.mesh.faces.size()), expected_quads(cube_layout(), 2));
    std::vector<std::size_t> rejected{99}; // cleared by to_openmesh
    const auto pm = to_openmesh(r.mesh, &rejected);
    EXPECT_TRUE(rejected.empty()); // a valid quad mesh is manifold: nothing rejected
    EXPECT_EQ(pm.n_faces(), r.mesh.faces.size());
    EXPECT_EQ(pm.n_vertices(), r.mesh.positions.size());
}

TEST(OpenMesh, FacesOpenMeshRejectsAreReported) {
    // A 2x2 grid of quads around vertex 4, then: a face at 4, whose faces already close around
    // it; a second face on the boundary edge 0-1 (accepted); a third face on that edge; and a
    // face apart from the others (accepted).
    QuadMesh q;
    for (int i = 0; i < 20; ++i) q.positions.push_back({double(i % 3), double(i / 3), double(i / 9)});
    q.faces = {{0, 1, 4, 3},   {1, 2, 5, 4},   {3, 4, 7, 6},   {4, 5, 8, 7},
               {4, 9, 10, 11}, {1, 0, 12, 13}, {0, 1, 14, 15}, {16, 17, 18, 19}};
    for (std::size_t f = 0; f < q.faces.size(); ++f) {
        q.face_uvs.emplace_back();
        for (std::int64_t k = 0; k < 4; ++k) q.face_uvs.back().push_back({10 * std::int64_t(f) + k, -k});
    }
    std::vector<std::size_t> rejected;
    const auto pm = to_openmesh(q, &rejected);
    EXPECT_EQ(rejected, (std::vector<std::size_t>{4, 6}));
    ASSERT_EQ(pm.n_faces(), q.faces.size() - rejected.size());
    // The accepted faces keep their order and their corners' UVs.
    const std::vector<std::size_t> accepted = {0, 1, 2, 3, 5, 7};
    for (auto fh : pm.faces()) {
        const std::size_t f = accepted[static_cast<std::size_t>(fh.idx())];
        for (auto heh : pm.fh_range(fh)) {
            const int v = pm.to_vertex_handle(heh).idx();
            const auto corner = std::find(q.faces[f].begin(), q.faces[f].end(), v);
            const auto k = static_cast<std::size_t>(corner - q.faces[f].begin());
            ASSERT_LT(k, q.faces[f].size());
            EXPECT_EQ(pm.texcoord2D(heh)[0], float(q.face_uvs[f][k][0]));
            EXPECT_EQ(pm.texcoord2D(heh)[1], float(q.face_uvs[f][k][1]));
        }
    }
    // Without the out-parameter the same faces are left out.
    EXPECT_EQ(to_openmesh(q).n_faces(), pm.n_faces());
}

TEST(OpenMesh, NothingRejectedFromAManifoldMesh) {
    QuadMesh q;
    q.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {1, 1, 0}, {2, 1, 0}};
    q.faces = {{0, 1, 4, 3}, {1, 2, 5, 4}};
    std::vector<std::size_t> rejected{7};
    const auto pm = to_openmesh(q, &rejected);
    EXPECT_TRUE(rejected.empty());
    EXPECT_EQ(pm.n_faces(), 2u);
}

} // namespace
} // namespace qex::testing
