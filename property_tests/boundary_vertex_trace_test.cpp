// An iso-line that passes through a boundary vertex has not left the surface: a hole (a dropped
// triangle) with a corner on a seam's iso-line must not stop the trace there (09_trace_ports.cpp,
// past_boundary_vertex). Before, the trace ended "into the boundary" on the side of the hole, the
// face beside it was left out and the oracle rejected the mesh (GridCellNotCovered,
// ValenceMismatch) while qex extract exited 0.
#include "qex/check.h"
#include "qex/conform.h"
#include "qex/io.h"
#include "qex/qex.h"

#include <gtest/gtest.h>

#include <string>

namespace {

/// The map of a `qex conform` hostile case, from its recipe.
qex::Input hostile_map(const std::string& recipe) {
    const qex::ConformCase c = qex::conform_case_from_json(
        R"({"expected_quads":-1,"family":"hostile/dropped_triangle","generated":true,"kind":"hostile",)"
        R"("map_path":"","name":"hostile/dropped_triangle/test","recipe":)" +
        recipe + "}");
    const std::string text = qex::conform_map_text(c);
    qex::Input in;
    EXPECT_TRUE(qex::parse_obj(text.data(), text.size(), in, 1).ok());
    return in;
}

/// qex's mesh of the map is valid, and the oracle agrees without the extractor's provenance, as
/// `qex check` judges the written mesh.
void expect_valid_beside_the_hole(const qex::Input& in) {
    qex::Options options;
    options.threads = 1;
    const qex::Result r = qex::extract(in, options);
    ASSERT_TRUE(r.ok()) << r.error.message;
    EXPECT_TRUE(r.check.valid);
    qex::VerifyOptions vo;
    vo.threads = 1;
    qex::QuadMesh written;
    written.positions = r.mesh.positions;
    written.faces = r.mesh.faces;
    const qex::MeshCheck check = qex::check_mesh(in, written, 1, vo);
    ASSERT_TRUE(check.map_ok());
    EXPECT_TRUE(check.verdict.valid) << (check.verdict.violations.empty() ? std::string()
                                                                          : check.verdict.violations[0].message);
}

TEST(BoundaryVertexTrace, IcosahedronWithATriangleDropped) {
    // conform seed 1, hostile/dropped_triangle/0004.
    expect_valid_beside_the_hole(hostile_map(R"({"diagonals":2,"k":3,"layout":"icosahedron","n":2,"seed":990878,)"
                                             R"("steps":[{"a":0.5359251416526986,"b":0.0,"op":"dropped_triangle"}]})"));
}

TEST(BoundaryVertexTrace, CubeWithATriangleDropped) {
    // conform seed 1, hostile/dropped_triangle/0031.
    expect_valid_beside_the_hole(
        hostile_map(R"({"diagonals":1,"k":4,"layout":"cube","n":3,"seed":1038381,)"
                    R"("steps":[{"a":0.07628720324747085,"b":0.0,"op":"dropped_triangle"}]})"));
}

} // namespace
