// A prepared input (qex::PreparedInput, VerifyOptions::prepared) changes how often the checker
// analyses the input, never its verdict: the same violations, in the same order, with or without
// it; and one made from another input is not taken.
#include "test_support.h"

#include <string>

namespace qex::testing {
namespace {

/// The verdict's figures and violations, to compare two verdicts whole.
std::string summary(const VerifyResult& v) {
    std::string s = std::string(v.valid ? "valid" : "invalid") + " euler " + std::to_string(v.euler) + "/" +
                    std::to_string(v.input_euler) + " loops " + std::to_string(v.boundary_loops) + "/" +
                    std::to_string(v.input_boundary_loops) + " components " + std::to_string(v.components) + "/" +
                    std::to_string(v.input_components) + " area " + std::to_string(v.input_signed_uv_area_rounded) +
                    " undecided " + std::to_string(v.undecided.size()) + "\n";
    for (const Violation& x : v.violations)
        s += std::string(to_string(x.kind)) + " " + std::to_string(x.element) + " " + x.message + "\n";
    return s;
}

/// Judges `mesh` against `in` without a prepared input and with `prepared`, and requires the
/// same verdict; returns it.
VerifyResult judged_both_ways(const Input& in, const QuadMesh& mesh, const PreparedInput& prepared) {
    VerifyOptions with;
    with.prepared = &prepared;
    const VerifyResult a = verify(in, mesh), b = verify(in, mesh, with);
    EXPECT_EQ(summary(a), summary(b));
    return a;
}

TEST(PreparedInput, GivesTheVerdictOfTheInputAnalysedAgain) {
    const Input in = make_map(cube_layout(), 2, 3);
    const QuadMesh mesh = extract(in).mesh;
    const PreparedInput prepared(in);
    EXPECT_TRUE(prepared.describes(in));
    EXPECT_TRUE(judged_both_ways(in, mesh, prepared).valid);
    // Wrong meshes: a hole, a reversed face, a map moved off its grid, and one judged located.
    QuadMesh hole = mesh;
    hole.faces.pop_back();
    EXPECT_FALSE(judged_both_ways(in, hole, prepared).valid);
    QuadMesh reversed = mesh;
    std::reverse(reversed.faces[0].begin(), reversed.faces[0].end());
    EXPECT_FALSE(judged_both_ways(in, reversed, prepared).valid);
    QuadMesh moved = mesh;
    for (auto& uv : moved.map_uvs) uv[0] += 0.5;
    EXPECT_FALSE(judged_both_ways(in, moved, prepared).valid);
    QuadMesh located;
    located.positions = mesh.positions;
    located.faces = mesh.faces;
    located.faces.pop_back();
    EXPECT_FALSE(judged_both_ways(in, located, prepared).valid);
}

TEST(PreparedInput, HoldsForTheSameTrianglesAtAnotherScale) {
    // A refined map keeps the triangles: the analysis is the same, and so is the verdict on a
    // mesh refined with it (a copy of the input, as an extractor's refinement makes).
    const Input in = make_map(cube_layout(), 2, 3);
    const PreparedInput prepared(in);
    Input scaled = in;
    for (auto& uv : scaled.uvs) uv = {2 * uv[0], 2 * uv[1]};
    EXPECT_TRUE(prepared.describes(scaled));
    const QuadMesh mesh = extract(scaled).mesh;
    EXPECT_TRUE(judged_both_ways(scaled, mesh, prepared).valid);
    QuadMesh at_scale = mesh; // the same mesh said to be refined x2 from `in`
    at_scale.grid_scale = 2;
    EXPECT_EQ(summary(verify(scaled, mesh)), summary(verify(in, at_scale)));
    judged_both_ways(in, at_scale, prepared);
}

TEST(PreparedInput, IsNotTakenForAnotherInput) {
    const Input cube = make_map(cube_layout(), 2, 3);
    const PreparedInput of_cube(cube);
    // Another surface with as many vertices, then the cube with one triangle's corners turned
    // (the same vertices, other edges), then one index out of range.
    Input other = make_map(cube_layout(), 2, 3);
    std::swap(other.triangles[0][0], other.triangles[0][1]);
    std::swap(other.uvs[0], other.uvs[1]);
    EXPECT_FALSE(of_cube.describes(other));
    const QuadMesh mesh = extract(cube).mesh;
    const VerifyResult v = judged_both_ways(other, mesh, of_cube);
    EXPECT_FALSE(v.valid);
    Input bad = cube;
    bad.triangles[3][2] = static_cast<int>(bad.positions.size());
    EXPECT_FALSE(of_cube.describes(bad));
    judged_both_ways(bad, mesh, of_cube);
    Input fewer = cube;
    fewer.positions.pop_back();
    EXPECT_FALSE(of_cube.describes(fewer));
    // Prepared from a bad input, it is still judged against as the input itself would be.
    const PreparedInput of_bad(bad);
    EXPECT_TRUE(of_bad.describes(bad));
    judged_both_ways(bad, mesh, of_bad);
}

} // namespace
} // namespace qex::testing
