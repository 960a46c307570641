// The quad layout (qex/layout.h, issue 33): generated maps with a known layout (a cube's 6
// patches, a torus without separatrix, disks and an annulus with boundary corners), the check
// rejecting broken layouts, invariance under input order, and the shared real maps (the check
// accepts each layout, patch sizes sum to the face count). Its time against extraction's is a
// benchmark's (BM_Layout, bench/RESULTS.md), not a test's.
#include "quad_grids.h"
#include "test_support.h"

#include "qex/layout.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <map>
#include <numeric>
#include <random>

namespace qex::testing {
namespace {

using Point = std::array<double, 3>;

QuadMesh mesh_of(const QuadLayout& layout, int n) {
    const Result r = extract_valid(make_map(layout, n, n));
    return r.mesh;
}

/// A valid layout whose patch sizes add up to the face count; returns it.
Layout expect_layout(const QuadMesh& mesh, const LayoutOptions& options = {}) {
    Layout l = extract_layout(mesh, options);
    EXPECT_TRUE(l.valid) << l.error;
    EXPECT_EQ(check_layout(mesh, l, options), "");
    long long area = 0;
    for (const Patch& p : l.patches) area += static_cast<long long>(p.u) * p.v;
    EXPECT_EQ(area, static_cast<long long>(mesh.faces.size()));
    return l;
}

/// The layout by positions: separatrices as position lists, patches as (u, v, their faces' sorted corners).
struct Picture {
    std::vector<std::vector<Point>> separatrices;
    std::vector<std::tuple<int, int, std::vector<std::array<Point, 4>>>> patches;
    bool operator==(const Picture& o) const { return separatrices == o.separatrices && patches == o.patches; }
};

Picture picture(const QuadMesh& m, const Layout& l) {
    Picture pic;
    for (const Separatrix& s : l.separatrices) {
        pic.separatrices.emplace_back();
        for (const int v : s.vertices) pic.separatrices.back().push_back(m.positions[v]);
    }
    for (const Patch& p : l.patches) {
        std::vector<std::array<Point, 4>> centres;
        for (const int f : p.faces) {
            std::array<Point, 4> c;
            for (int k = 0; k < 4; ++k) c[k] = m.positions[m.faces[f][k]];
            std::sort(c.begin(), c.end());
            centres.push_back(c);
        }
        std::sort(centres.begin(), centres.end());
        pic.patches.emplace_back(p.u, p.v, centres);
    }
    return pic;
}

/// The mesh with its vertices renumbered, faces reordered and each face's corners rotated.
QuadMesh shuffled(const QuadMesh& m, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::vector<int> perm(m.positions.size());
    std::iota(perm.begin(), perm.end(), 0);
    std::shuffle(perm.begin(), perm.end(), rng);
    QuadMesh out;
    out.positions.resize(m.positions.size());
    for (std::size_t v = 0; v < perm.size(); ++v) out.positions[perm[v]] = m.positions[v];
    for (const auto& f : m.faces) {
        std::vector<int> g;
        for (const int v : f) g.push_back(perm[v]);
        std::rotate(g.begin(), g.begin() + rng() % 4, g.end());
        out.faces.push_back(g);
    }
    std::shuffle(out.faces.begin(), out.faces.end(), rng);
    return out;
}

TEST(Layout, ACubeHasSixSquarePatches) {
    const QuadMesh mesh = mesh_of(cube_layout(), 3);
    const Layout l = expect_layout(mesh);
    ASSERT_EQ(l.patches.size(), 6u);
    for (const Patch& p : l.patches) {
        EXPECT_EQ(p.kind, PatchKind::Rectangle);
        EXPECT_EQ(p.u, 3);
        EXPECT_EQ(p.v, 3);
    }
    EXPECT_EQ(l.special_vertices.size(), 8u);
    ASSERT_EQ(l.separatrices.size(), 12u); // the cube's edges, each traced from both ends
    for (const Separatrix& s : l.separatrices) {
        EXPECT_EQ(s.vertices.size(), 4u);
        EXPECT_EQ(s.end, SeparatrixEnd::HeadOn);
    }
    EXPECT_EQ(l.adjacency.size(), 12u);
}

TEST(Layout, TheJsonSaysWhatTheStructSays) {
    const QuadMesh mesh = mesh_of(cube_layout(), 2);
    const Layout l = expect_layout(mesh);
    const nlohmann::json j = nlohmann::json::parse(layout_json(l));
    EXPECT_EQ(j["valid"], true);
    EXPECT_EQ(j["error"], "");
    EXPECT_EQ(j["separatrices"].size(), l.separatrices.size());
    EXPECT_EQ(j["separatrices"][0]["end"], "HeadOn");
    EXPECT_EQ(j["separatrices"][0]["vertices"].get<std::vector<int>>(), l.separatrices[0].vertices);
    ASSERT_EQ(j["patches"].size(), 6u);
    EXPECT_EQ(j["patches"][0]["u"], 2);
    EXPECT_EQ(j["patches"][0]["kind"], "Rectangle");
    EXPECT_EQ(j["patches"][0]["faces"].get<std::vector<int>>(), l.patches[0].faces);
    EXPECT_EQ(j["face_patch"].get<std::vector<int>>(), l.face_patch);
    EXPECT_EQ(j["adjacency"].size(), 12u);
    EXPECT_EQ(j["special_vertices"].size(), 8u);
}

TEST(Layout, ATorusHasNoSeparatrixAndOnePatch) {
    const QuadMesh mesh = mesh_of(torus_layout(4, 3), 2);
    const Layout l = expect_layout(mesh);
    EXPECT_TRUE(l.separatrices.empty());
    EXPECT_TRUE(l.special_vertices.empty());
    ASSERT_EQ(l.patches.size(), 1u);
    EXPECT_EQ(l.patches[0].kind, PatchKind::Torus);
    EXPECT_EQ(l.patches[0].u * l.patches[0].v, 48);
    EXPECT_FALSE(l.notes.empty());
}

/// A torus whose grid lines in one direction close only after several turns (the v-wrap shifted
/// by s), beside a cube: the torus one patch whatever its twist, the cube six.
TEST(Layout, ATwistedTorusBesideACube) {
    const double pi = std::acos(-1.0);
    for (int s = 0; s < 5; ++s) {
        const int w = 5, h = 3;
        QuadMesh m;
        for (int j = 0; j < h; ++j)
            for (int i = 0; i < w; ++i) {
                const double t = 2 * pi * (i + double(s) * j / h) / w, p = 2 * pi * j / h;
                m.positions.push_back({(3 + std::cos(p)) * std::cos(t), (3 + std::cos(p)) * std::sin(t), std::sin(p)});
            }
        const auto id = [&](int i, int j) { return j == h ? (i + s) % w : j * w + i % w; };
        for (int j = 0; j < h; ++j)
            for (int i = 0; i < w; ++i) m.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
        const QuadMesh cube = mesh_of(cube_layout(), 2);
        const int base = static_cast<int>(m.positions.size());
        for (const auto& p : cube.positions) m.positions.push_back({p[0] + 10, p[1], p[2]});
        for (auto f : cube.faces) {
            for (int& v : f) v += base;
            m.faces.push_back(f);
        }
        SCOPED_TRACE("twist " + std::to_string(s));
        const Layout l = expect_layout(m);
        ASSERT_EQ(l.patches.size(), 7u);
        EXPECT_EQ(std::count_if(l.patches.begin(), l.patches.end(),
                                [](const Patch& p) { return p.kind == PatchKind::Torus; }),
                  1);
        EXPECT_EQ(l.separatrices.size(), 12u);
    }
}

TEST(Layout, ADiskIsOneRectangleBetweenItsBoundaryCorners) {
    const QuadMesh mesh = mesh_of(disk_layout(3), 2);
    const Layout l = expect_layout(mesh);
    EXPECT_TRUE(l.separatrices.empty());
    EXPECT_EQ(l.special_vertices.size(), 4u);
    ASSERT_EQ(l.patches.size(), 1u);
    EXPECT_EQ(l.patches[0].u, 6);
    EXPECT_EQ(l.patches[0].v, 6);
}

TEST(Layout, AnAnnulusIsCutAcross) {
    const QuadMesh mesh = mesh_of(annulus_layout(6, 2), 2);
    const Layout l = expect_layout(mesh);
    ASSERT_EQ(l.separatrices.size(), 2u); // two cuts: each piece a rectangle embedded in the mesh
    for (const Separatrix& s : l.separatrices) {
        EXPECT_EQ(s.start, SeparatrixStart::Cut);
        EXPECT_EQ(s.end, SeparatrixEnd::Boundary);
    }
    ASSERT_EQ(l.patches.size(), 2u);
}

TEST(Layout, ADiskWithAConcaveCornerAndAFeature) {
    // An L of three squares, 2 x 2 faces each: the concave boundary corner sends two separatrices.
    QuadMesh m;
    for (int y = 0; y <= 4; ++y)
        for (int x = 0; x <= 4; ++x) m.positions.push_back({double(x), double(y), 0.0});
    const auto id = [](int x, int y) { return 5 * y + x; };
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x)
            if (x < 2 || y < 2) m.faces.push_back({id(x, y), id(x + 1, y), id(x + 1, y + 1), id(x, y + 1)});
    const Layout l = expect_layout(m);
    EXPECT_EQ(l.patches.size(), 3u);
    for (const Patch& p : l.patches) EXPECT_EQ(p.u * p.v, 4);
    LayoutOptions features;
    features.feature_edges = {{id(0, 1), id(1, 1)}}; // a dangling feature: 3 more separatrices at its end
    const Layout lf = expect_layout(m, features);
    EXPECT_GT(lf.patches.size(), l.patches.size());
}

/// Feature edges of the map along the iso-line u = 2 of every face of a 4 x 4 cube: the mesh's edges
/// on them (through the provenance) cut the layout, each face's line ending on the cube's edges.
TEST(Layout, TheMapsFeatureEdgesCutTheLayout) {
    Input in = make_map(cube_layout(), 4, 4);
    for (std::size_t t = 0; t < in.triangles.size(); ++t)
        for (int k = 0; k < 3; ++k) {
            const auto &a = in.uvs[3 * t + k], &b = in.uvs[3 * t + (k + 1) % 3];
            if (a[0] == 2 && b[0] == 2) in.feature_edges.push_back({in.triangles[t][k], in.triangles[t][(k + 1) % 3]});
        }
    ASSERT_FALSE(in.feature_edges.empty());
    const Result r = extract_valid(in);
    LayoutOptions options;
    options.feature_edges = quad_feature_edges(in, r.mesh);
    EXPECT_EQ(options.feature_edges.size(), 24u); // 4 edges across each face
    const Layout plain = expect_layout(r.mesh), cut = expect_layout(r.mesh, options);
    EXPECT_EQ(plain.patches.size(), 6u);
    EXPECT_GT(cut.patches.size(), 6u);
    // A feature line ending on a cube edge makes its end a feature corner (a sector of 4 faces).
    EXPECT_TRUE(std::any_of(cut.separatrices.begin(), cut.separatrices.end(),
                            [](const Separatrix& s) { return s.start == SeparatrixStart::FeatureVertex; }));
    std::printf("[ layout   ] the cube with feature lines: %zu patches, %zu separatrices\n", cut.patches.size(),
                cut.separatrices.size());
}

TEST(Layout, MoreSingularities) {
    for (const QuadLayout& q : {icosahedron_layout(), prism_layout(5), prism_layout(3)}) {
        SCOPED_TRACE(q.name);
        const Layout l = expect_layout(mesh_of(q, 2));
        EXPECT_FALSE(l.separatrices.empty());
    }
}

TEST(Layout, TheSameForAnyOrderOfFacesCornersAndVertices) {
    for (const QuadLayout& q : {cube_layout(), icosahedron_layout(), annulus_layout(), prism_layout(5)}) {
        SCOPED_TRACE(q.name);
        const QuadMesh mesh = mesh_of(q, 3);
        const Picture want = picture(mesh, expect_layout(mesh));
        for (std::uint32_t seed = 1; seed <= 3; ++seed) {
            const QuadMesh other = shuffled(mesh, seed);
            EXPECT_TRUE(picture(other, expect_layout(other)) == want) << "seed " << seed;
        }
    }
}

TEST(Layout, EveryGeneratedMapAtEveryScale) {
    for (const QuadLayout& q : {cube_layout(), torus_layout(), icosahedron_layout(), prism_layout(3), prism_layout(6),
                                disk_layout(2), annulus_layout(5, 1), annulus_layout(3, 3), torus_layout(3, 5)})
        for (int n = 1; n <= 4; ++n) {
            SCOPED_TRACE(q.name + " n=" + std::to_string(n));
            const QuadMesh mesh = mesh_of(q, n);
            const Layout l = expect_layout(mesh);
            const QuadMesh other = shuffled(mesh, 11u + n);
            EXPECT_TRUE(picture(other, expect_layout(other)) == picture(mesh, l));
        }
}

/// Grids on the plane, a cylinder and a torus with random faces left out: every mesh the layout
/// takes (an oriented manifold) gets a layout the check accepts, the same when shuffled.
/// A planar polygon split into quads round its centre: an irregular vertex (valence = sides) with
/// separatrices to the boundary, and a corner of one face at each of the polygon's corners.
TEST(Layout, PolygonsSplitRoundTheirCentre) {
    const double pi = std::acos(-1.0);
    for (int sides = 3; sides <= 6; ++sides) {
        std::vector<std::array<double, 3>> corners;
        std::vector<int> polygon;
        for (int i = 0; i < sides; ++i) {
            corners.push_back({std::cos(2 * pi * i / sides), std::sin(2 * pi * i / sides), 0.0});
            polygon.push_back(i);
        }
        for (int n = 1; n <= 3; ++n) {
            SCOPED_TRACE(std::to_string(sides) + " sides, n=" + std::to_string(n));
            const QuadMesh mesh = mesh_of(split_polygons("polygon", corners, {polygon}), n);
            const Layout l = expect_layout(mesh);
            // A square's centre is regular: one patch of 2n x 2n.
            EXPECT_EQ(l.patches.size(), sides == 4 ? 1u : static_cast<std::size_t>(sides));
            for (const Patch& p : l.patches) EXPECT_EQ(p.u * p.v, sides == 4 ? 4 * n * n : n * n);
            EXPECT_EQ(l.special_vertices.size(), static_cast<std::size_t>(sides == 4 ? 4 : sides + 1));
        }
    }
}

TEST(Layout, GridsWithHoles) {
    std::mt19937 rng(33);
    int valid = 0, refused = 0, cut = 0;
    for (int round = 0; round < 600; ++round) {
        const int w = 3 + static_cast<int>(rng() % 8), h = 3 + static_cast<int>(rng() % 8), kind = round % 4;
        std::vector<char> keep(w * h, 1);
        const int holes = static_cast<int>(rng() % (w * h / 3 + 1));
        for (int k = 0; k < holes; ++k) keep[rng() % keep.size()] = 0;
        const QuadMesh mesh = quad_grid(w, h, kind & 1, kind & 2, keep);
        if (mesh.faces.empty()) continue;
        const Layout l = extract_layout(mesh);
        if (!l.valid) {
            // Only a mesh that is no oriented manifold is refused, before any tracing.
            EXPECT_EQ(l.error.rfind("no layout: vertex", 0), 0u) << "round " << round << ": " << l.error;
            ++refused;
            continue;
        }
        ++valid;
        cut += !l.notes.empty();
        long long area = 0;
        for (const Patch& p : l.patches) area += static_cast<long long>(p.u) * p.v;
        EXPECT_EQ(area, static_cast<long long>(mesh.faces.size())) << "round " << round;
        const QuadMesh other = shuffled(mesh, static_cast<std::uint32_t>(round));
        EXPECT_TRUE(picture(other, extract_layout(other)) == picture(mesh, l)) << "round " << round;
    }
    std::printf(
        "[ layout   ] grids with holes: %d valid layouts (%d with a cut or a torus), %d refused as non-manifold\n",
        valid, cut, refused);
    EXPECT_GT(valid, 300);
}

TEST(Layout, TheCheckRejectsABrokenLayout) {
    const QuadMesh mesh = mesh_of(cube_layout(), 3);
    const Layout good = expect_layout(mesh);
    Layout l = good;
    l.separatrices.pop_back(); // two patches now meet across an edge on no separatrix
    EXPECT_NE(check_layout(mesh, l), "");
    l = good;
    std::swap(l.patches[0].u, l.patches[1].v);
    l.patches[0].u = 1;
    EXPECT_NE(check_layout(mesh, l), "");
    l = good;
    l.face_patch[0] = (l.face_patch[0] + 1) % 6;
    EXPECT_NE(check_layout(mesh, l), "");
    l = good;
    l.separatrices[0].end = SeparatrixEnd::Boundary;
    EXPECT_NE(check_layout(mesh, l), "");
    l = good;
    l.adjacency.pop_back();
    EXPECT_NE(check_layout(mesh, l), "");
    QuadMesh tri = mesh;
    tri.faces[0].pop_back();
    EXPECT_FALSE(extract_layout(tri).valid);
}

// ---------------------------------------------------------------------------- the shared real maps

class RealMapLayout : public ::testing::TestWithParam<const char*> {};

/// The check accepts the layout, the sizes add up, the layout is the same for a shuffled mesh and
/// for the mesh extracted serially.
TEST_P(RealMapLayout, IsCheckedAndCanonicalAndCheap) {
    const std::filesystem::path path = std::filesystem::path(QEX_SHARED_DIR) / "meshes" / GetParam();
    if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " not found (the shared maps are absent)";
    Input in;
    ASSERT_TRUE(read_obj(path.string(), in).ok());
    const Result r = extract(in);
    ASSERT_TRUE(r.ok() && r.check.valid) << path;
    const Layout l = extract_layout(r.mesh);
    EXPECT_TRUE(l.valid) << l.error;
    long long area = 0;
    for (const Patch& p : l.patches) area += static_cast<long long>(p.u) * p.v;
    EXPECT_EQ(area, static_cast<long long>(r.mesh.faces.size()));
    const Picture want = picture(r.mesh, l);
    const QuadMesh other = shuffled(r.mesh, 7);
    EXPECT_TRUE(picture(other, extract_layout(other)) == want);
    Options serial;
    serial.threads = 1;
    const Result r1 = extract(in, serial);
    EXPECT_TRUE(picture(r1.mesh, extract_layout(r1.mesh)) == want);
    std::printf("[ layout   ] %s: %zu faces, %zu patches, %zu separatrices, %zu special vertices\n", GetParam(),
                r.mesh.faces.size(), l.patches.size(), l.separatrices.size(), l.special_vertices.size());
}

INSTANTIATE_TEST_SUITE_P(LayoutMaps, RealMapLayout,
                         ::testing::Values("paper/fandisk_param.obj", "paper/duck_miq_28_param.obj",
                                           "paper/duck_miq_8_param.obj", "miq/fandisk_miq_40_param.obj",
                                           "miq/bunny_miq_40_param.obj", "miq/camelhead_miq_40_param.obj"));

} // namespace
} // namespace qex::testing
