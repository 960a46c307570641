// The checker must reject what is wrong: a triangle, a hole, a flipped face, a moved vertex,
// a missing or extra quad, a broken local UV square.
#include "test_support.h"

namespace qex::testing {
namespace {

struct Fixture {
    Input in = make_map(cube_layout(), 2, 3);
    QuadMesh mesh = extract(in).mesh;
};

bool has(const VerifyResult& v, ViolationKind k) {
    for (const auto& x : v.violations)
        if (x.kind == k) return true;
    return false;
}

TEST(Checker, AcceptsExtraction) {
    Fixture f;
    const VerifyResult v = verify(f.in, f.mesh);
    EXPECT_TRUE(v.valid);
    EXPECT_EQ(v.euler, 2);
    EXPECT_EQ(v.input_signed_uv_area_rounded, static_cast<std::int64_t>(f.mesh.faces.size()));
}

TEST(Checker, RejectsTriangle) {
    Fixture f;
    f.mesh.faces[0].pop_back();
    f.mesh.face_uvs[0].pop_back();
    EXPECT_TRUE(has(verify(f.in, f.mesh), ViolationKind::NotQuad));
}

TEST(Checker, RejectsHoleAndMissingQuad) {
    Fixture f;
    f.mesh.faces.erase(f.mesh.faces.begin() + 3);
    f.mesh.face_uvs.erase(f.mesh.face_uvs.begin() + 3);
    const VerifyResult v = verify(f.in, f.mesh);
    EXPECT_FALSE(v.valid);
    EXPECT_TRUE(has(v, ViolationKind::BoundaryMismatch));
}

TEST(Checker, RejectsFlippedFace) {
    Fixture f;
    std::reverse(f.mesh.faces[5].begin(), f.mesh.faces[5].end());
    EXPECT_TRUE(has(verify(f.in, f.mesh), ViolationKind::InconsistentOrientation));
}

TEST(Checker, RejectsExtraQuad) {
    Fixture f;
    f.mesh.faces.push_back(f.mesh.faces[0]);
    f.mesh.face_uvs.push_back(f.mesh.face_uvs[0]);
    EXPECT_FALSE(verify(f.in, f.mesh).valid);
}

TEST(Checker, RejectsBrokenLocalUvs) {
    Fixture f;
    f.mesh.face_uvs[2][1][0] += 1;
    EXPECT_TRUE(has(verify(f.in, f.mesh), ViolationKind::LocalUvNotUnitSquare));
}

TEST(Checker, RejectsUnreferencedAndNonFinite) {
    Fixture f;
    f.mesh.positions.push_back({0, 0, 0});
    EXPECT_TRUE(has(verify(f.in, f.mesh), ViolationKind::UnreferencedVertex));
    Fixture g;
    g.mesh.positions[0][1] = std::numeric_limits<double>::quiet_NaN();
    EXPECT_TRUE(has(verify(g.in, g.mesh), ViolationKind::NonFinitePosition));
}

TEST(Checker, RejectsWrongTopology) {
    // The cube's quads judged against a torus map: Euler characteristic differs.
    Fixture f;
    const Input torus = make_map(torus_layout(), 1, 2);
    EXPECT_TRUE(has(verify(torus, f.mesh), ViolationKind::EulerMismatch));
}

TEST(Checker, VerifiesTheSanitizedMapAndProvenance) {
    Fixture f;
    ASSERT_EQ(f.mesh.map_uvs.size(), f.in.uvs.size());
    EXPECT_TRUE(verify(f.in, f.mesh).valid);
    // A map that is not an integer-grid map: one corner moved by a tiny amount.
    QuadMesh broken = f.mesh;
    broken.map_uvs[7][0] += 1e-9;
    EXPECT_TRUE(has(verify(f.in, broken), ViolationKind::MapNotIntegerGrid));
    // A vertex claiming a grid point that is not on its element.
    QuadMesh moved = f.mesh;
    moved.provenance[3].grid[0] += 1;
    EXPECT_TRUE(has(verify(f.in, moved), ViolationKind::NotOnGridPoint));
    // Noise in the input: the map is sanitized, and the displacement is reported.
    Input noisy = f.in;
    std::mt19937 rng(6);
    add_noise(noisy, 1e-9, rng);
    const Result r = extract(noisy);
    const VerifyResult v = verify(noisy, r.mesh);
    EXPECT_TRUE(v.valid);
    EXPECT_GT(v.max_map_displacement, 0.0);
    EXPECT_LE(v.max_map_displacement, 1e-8);
    EXPECT_GE(v.sum_map_displacement, v.max_map_displacement);
    EXPECT_LE(v.sum_map_displacement, 1e-8 * static_cast<double>(noisy.uvs.size()));
}

TEST(Checker, SingularitiesSitOnIntegerGridPoints) {
    Fixture f;
    const VerifyResult v = verify(f.in, f.mesh);
    EXPECT_EQ(v.map_singularities, 8); // the cube's corners, valence 3
    EXPECT_FALSE(has(v, ViolationKind::SingularityOffGrid));
    // Shifting every chart by (1/2, 1/2) keeps each edge transition an exact grid automorphism
    // (h - R h is integer for every quarter turn R) but moves the singularities to cell centres.
    QuadMesh shifted = f.mesh;
    for (auto& uv : shifted.map_uvs) {
        uv[0] += 0.5;
        uv[1] += 0.5;
    }
    const VerifyResult s = verify(f.in, shifted);
    EXPECT_FALSE(has(s, ViolationKind::MapNotIntegerGrid));
    EXPECT_EQ(s.map_singularities, 8);
    std::size_t off = 0;
    for (const auto& x : s.violations) off += x.kind == ViolationKind::SingularityOffGrid;
    EXPECT_EQ(off, 8u);
    // A torus has none.
    const Input torus = make_map(torus_layout(), 2, 3);
    EXPECT_EQ(verify(torus, extract(torus).mesh).map_singularities, 0);
}

TEST(Checker, RejectsBadIndicesWithoutCrashing) {
    Fixture f;
    f.mesh.faces[0][0] = -7;
    f.mesh.faces[1][2] = 1 << 28;
    EXPECT_TRUE(has(verify(f.in, f.mesh), ViolationKind::BadIndex));
    EXPECT_TRUE(has(verify(f.in, QuadMesh{}), ViolationKind::EmptyMesh));
}

} // namespace
} // namespace qex::testing
