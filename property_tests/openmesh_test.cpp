// The OpenMesh adapter: a generated map through OpenMesh and back extracts the same quad mesh.
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
    const auto pm = to_openmesh(r.mesh);
    EXPECT_EQ(pm.n_faces(), r.mesh.faces.size());
    EXPECT_EQ(pm.n_vertices(), r.mesh.positions.size());
}

} // namespace
} // namespace qex::testing
