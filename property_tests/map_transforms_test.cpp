// The map transforms themselves (map_transforms.h), and their metamorphic relations on generated
// fold-free maps, where they hold exactly: subdivision keeps the mesh, scaling by K multiplies
// the quads by K^2, translation and re-charting keep the mesh, shuffling keeps it bit for bit.
#include "map_transforms.h"
#include "test_support.h"
#include "transform_checks.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace qex::testing {
namespace {

std::vector<QuadLayout> layouts() {
    return {torus_layout(), cube_layout(), icosahedron_layout(), prism_layout(6), disk_layout(2), annulus_layout()};
}

/// The cube map with its cross-field valences (3 at the cube's corners) and its 12 cube edges as
/// feature edges (they lie on integer iso-lines already, so they do not change the mesh).
Input cube_with_valences_and_features() {
    Input in = make_map(cube_layout(), 2, 2, 2, 7);
    auto on_cube_edge = [&](int a, int b) {
        int shared = 0;
        for (int k = 0; k < 3; ++k) {
            const double x = in.positions[a][k];
            shared += x == in.positions[b][k] && (x == 0.0 || x == 1.0);
        }
        return shared >= 2;
    };
    for (const auto& p : in.positions) {
        bool corner = true;
        for (double x : p) corner = corner && (x == 0.0 || x == 1.0);
        in.valences.push_back(corner ? 3 : 4);
    }
    for (const auto& t : in.triangles)
        for (int c = 0; c < 3; ++c) {
            const int a = t[c], b = t[(c + 1) % 3];
            if (a < b && on_cube_edge(a, b)) in.feature_edges.push_back({a, b});
        }
    return in;
}

// ============================================================================ the transforms

TEST(MapTransforms, CountRoundedCoordinates) {
    Input in = make_map(disk_layout(1), 1, 1);
    for (auto& uv : in.uvs) uv = {uv[0] + 0.1, uv[1] + 0.5};
    Input scaled = in;
    EXPECT_EQ(transforms::scale_uvs(scaled, 4), 0); // powers of two: exact
    EXPECT_EQ(scaled.uvs[0][0], 4 * in.uvs[0][0]);
    scaled = in;
    EXPECT_GT(transforms::scale_uvs(scaled, 3), 0); // 0.1 * 3 rounds
    Input moved = in;
    EXPECT_GT(transforms::translate_uvs(moved, 1000, 0), 0); // 0.1 + 1000 loses low bits of 0.1
    moved = in;
    EXPECT_EQ(transforms::translate_uvs(moved, 0, 1000), 0); // every v is a multiple of 0.5
}

TEST(MapTransforms, ShuffleCarriesValencesAndFeatureEdges) {
    const Input base = cube_with_valences_and_features();
    ASSERT_EQ(base.feature_edges.size(), 24u); // 12 cube edges, two mesh edges each
    const Result expected = extract_valid(base);
    for (std::uint64_t seed : {1u, 2u, 3u}) {
        Input in = base;
        transforms::shuffle(in, seed);
        ASSERT_EQ(validate(in).code, ErrorCode::None) << validate(in).message;
        ASSERT_EQ(in.valences.size(), in.positions.size());
        int corners = 0;
        for (int v : in.valences) corners += v == 3;
        EXPECT_EQ(corners, 8);
        const Result r = extract_valid(in);
        EXPECT_EQ(position_difference(r.mesh.positions, expected.mesh.positions), "") << "seed " << seed;
        EXPECT_TRUE(r.mesh.faces == expected.mesh.faces) << "seed " << seed;
    }
}

TEST(MapTransforms, SubdivisionCarriesValencesAndFeatureEdges) {
    const Input base = cube_with_valences_and_features();
    const Input in = transforms::subdivide(base);
    EXPECT_EQ(in.triangles.size(), 4 * base.triangles.size());
    EXPECT_EQ(in.feature_edges.size(), 2 * base.feature_edges.size());
    ASSERT_EQ(in.valences.size(), in.positions.size());
    ASSERT_EQ(validate(in).code, ErrorCode::None) << validate(in).message;
    const Result a = extract_valid(base), b = extract_valid(in);
    EXPECT_EQ(mesh_difference(b.mesh, a.mesh, 1e-9 * bbox_diagonal(base.positions)), "");
}

TEST(MapTransforms, ApplyRunsTheNamedTransformsInOrder) {
    const Input base = make_map(torus_layout(), 3, 4); // UVs multiples of 3/4: every step exact
    Input in = base;
    std::int64_t rounded = 0;
    ASSERT_EQ(transforms::apply(in, "scale 2 translate 3 -5 rechart 9 shuffle 4 subdivide", &rounded), "");
    EXPECT_EQ(rounded, 0);
    EXPECT_EQ(in.triangles.size(), 4 * base.triangles.size());
    Input by_hand = base;
    transforms::scale_uvs(by_hand, 2);
    transforms::translate_uvs(by_hand, 3, -5);
    transforms::rechart(by_hand, 9);
    transforms::shuffle(by_hand, 4);
    by_hand = transforms::subdivide(by_hand);
    EXPECT_EQ(in.uvs, by_hand.uvs);
    EXPECT_EQ(in.triangles, by_hand.triangles);
    in = base;
    ASSERT_EQ(transforms::apply(in, "rechart 9 100 shuffle 1"), ""); // the optional largest translation
    for (const char* bad : {"scale 0", "scale", "translate 1", "rechart -", "shuffle x", "twist 3"}) {
        in = base;
        EXPECT_NE(transforms::apply(in, bad), "") << bad;
    }
}

// ============================================================================ generated maps

TEST(GeneratedMapTransforms, SubdivisionKeepsTheMesh) {
    for (const QuadLayout& layout : layouts()) {
        const Input base = make_map(layout, 2, 3, 2, 5);
        const Input in = transforms::subdivide(base);
        const Result a = extract_valid(base), b = extract_valid(in);
        EXPECT_EQ(static_cast<std::int64_t>(b.mesh.faces.size()), expected_quads(layout, 2)) << layout.name;
        const VerifyResult va = verify(base, a.mesh), vb = verify(in, b.mesh);
        EXPECT_EQ(vb.euler, va.euler) << layout.name;
        EXPECT_EQ(vb.boundary_loops, va.boundary_loops) << layout.name;
        EXPECT_EQ(vb.components, va.components) << layout.name;
        EXPECT_EQ(mesh_difference(b.mesh, a.mesh, 1e-9 * bbox_diagonal(base.positions)), "") << layout.name;
    }
}

TEST(GeneratedMapTransforms, ScalingByKMultipliesTheQuadsByKSquared) {
    for (const QuadLayout& layout : layouts())
        for (std::int64_t k : {2, 3, 5}) {
            Input in = make_map(layout, 3, 4, 1, 3); // UVs multiples of 3/4: exact in any scale
            ASSERT_EQ(transforms::scale_uvs(in, k), 0) << layout.name << " x " << k;
            const Result r = extract_valid(in);
            EXPECT_EQ(static_cast<std::int64_t>(r.mesh.faces.size()), k * k * expected_quads(layout, 3))
                << layout.name << " x " << k;
            EXPECT_EQ(static_cast<std::int64_t>(r.mesh.faces.size()), verify(in, r.mesh).input_signed_uv_area_rounded)
                << layout.name << " x " << k;
        }
}

TEST(GeneratedMapTransforms, TranslationRechartingAndShufflingKeepTheMesh) {
    for (const QuadLayout& layout : layouts()) {
        const Input base = make_map(layout, 3, 4, 2, 11); // exact under integer translations
        const Result a = extract_valid(base);
        const double tol = 1e-9 * bbox_diagonal(base.positions);
        for (std::uint64_t seed : {1u, 2u}) {
            const std::string about = layout.name + ", seed " + std::to_string(seed);
            Input moved = base;
            ASSERT_EQ(transforms::translate_uvs(moved, 5 * static_cast<std::int64_t>(seed), -17), 0);
            EXPECT_EQ(mesh_difference(extract_valid(moved).mesh, a.mesh, tol), "") << about << ": translated";
            Input recharted = base;
            ASSERT_EQ(transforms::rechart(recharted, seed), 0);
            EXPECT_EQ(mesh_difference(extract_valid(recharted).mesh, a.mesh, tol), "") << about << ": recharted";
            Input shuffled = base;
            transforms::shuffle(shuffled, seed);
            const Result s = extract_valid(shuffled);
            EXPECT_EQ(position_difference(s.mesh.positions, a.mesh.positions), "") << about << ": shuffled";
            EXPECT_TRUE(s.mesh.faces == a.mesh.faces) << about << ": shuffled";
        }
    }
}

/// A vertex whose corners all carry one UV in several charts: each triangle round it is turned
/// about the grid point p it lies on, by 0, 1, 2, 3, 0, ... quarter turns (exact), and then
/// every corner of the vertex is put at one UV a little off p. The charts agree on that UV only
/// up to the offset, as solver noise leaves a vertex next to a singularity on cow_miq_40 (at four
/// times its scale): sanitizing truncates the vertex's UV in the chart of its fan's first corner,
/// and the smallest UV does not decide which corner that is.
Input one_uv_in_several_charts() {
    std::vector<char> single_chart;
    Input in = make_map(torus_layout(), 2, 2, 1, 1, &single_chart);
    const auto v = static_cast<int>(std::find(single_chart.begin(), single_chart.end(), 1) - single_chart.begin());
    std::array<double, 2> p{};
    std::vector<std::size_t> fan;
    for (std::size_t f = 0; f < in.triangles.size(); ++f)
        for (std::size_t k = 0; k < 3; ++k)
            if (in.triangles[f][k] == v) {
                fan.push_back(f);
                p = in.uvs[3 * f + k];
            }
    // The generator's contract: the torus has a vertex inside one layout quad, with a fan.
    EXPECT_LT(static_cast<std::size_t>(v), single_chart.size());
    EXPECT_GE(fan.size(), 3u);
    const double offset = std::ldexp(1.0, -20);
    for (std::size_t i = 0; i < fan.size(); ++i)
        for (std::size_t k = 0; k < 3; ++k) {
            auto& uv = in.uvs[3 * fan[i] + k];
            for (std::size_t r = 0; r < i % 4; ++r) uv = {p[0] - (uv[1] - p[1]), p[1] + (uv[0] - p[0])};
            if (in.triangles[fan[i]][k] == v) uv = {p[0] + offset, p[1]};
        }
    return in;
}

TEST(GeneratedMapTransforms, ShufflingKeepsTheMeshOfAVertexWithOneUvInSeveralCharts) {
    const Input base = one_uv_in_several_charts();
    const Result a = extract_valid(base);
    for (std::uint64_t seed = 1; seed <= 8; ++seed) {
        Input shuffled = base;
        transforms::shuffle(shuffled, seed);
        const Result s = extract_valid(shuffled);
        EXPECT_EQ(position_difference(s.mesh.positions, a.mesh.positions), "") << "seed " << seed;
        EXPECT_TRUE(s.mesh.faces == a.mesh.faces) << "seed " << seed;
    }
}

} // namespace
} // namespace qex::testing
