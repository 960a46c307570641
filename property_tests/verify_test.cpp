// The checker must reject what is wrong: a triangle, a hole, a flipped face, a moved vertex,
// a missing or extra quad, a broken local UV square.
#include "test_support.h"

#include <algorithm>
#include <cmath>
#include <map>

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

std::size_t count(const VerifyResult& v, ViolationKind k) {
    std::size_t n = 0;
    for (const auto& x : v.violations) n += x.kind == k;
    return n;
}

TEST(Checker, AcceptsExtraction) {
    Fixture f;
    const VerifyResult v = verify(f.in, f.mesh);
    EXPECT_TRUE(v.valid);
    EXPECT_EQ(v.euler, 2);
    EXPECT_EQ(v.input_signed_uv_area_rounded, static_cast<std::int64_t>(f.mesh.faces.size()));
}

TEST(Checker, AUvToleranceAboveOneIsOneAndNanIsZero) {
    // Every point lies within 0.5 of a grid point: verify() takes a larger tolerance as 1 (the
    // coverage search would otherwise grow with it: 1e308 hung `qex check`), NaN or negative as 0.
    Fixture f;
    QuadMesh bare;
    bare.positions = f.mesh.positions;
    bare.faces = f.mesh.faces;
    bare.faces.pop_back(); // a hole, so that the verdicts have violations to compare
    const auto judged = [&](double tolerance) {
        VerifyOptions o;
        o.uv_tolerance = tolerance;
        return verify(f.in, bare, o);
    };
    const VerifyResult one = judged(1.0), huge = judged(1e308), zero = judged(0.0);
    EXPECT_FALSE(one.valid);
    EXPECT_EQ(huge.valid, one.valid);
    EXPECT_EQ(huge.violations.size(), one.violations.size());
    for (const double bad : {std::nan(""), -1.0}) {
        const VerifyResult r = judged(bad);
        EXPECT_EQ(r.valid, zero.valid);
        EXPECT_EQ(r.violations.size(), zero.violations.size());
    }
}

TEST(Checker, LocatedModeAcceptsAMeshOfAMapFarFromTheOrigin) {
    // UVs near 2^43, where one unit in the last place is 2^-9: a vertex located on the surface
    // gets its UV interpolated in doubles that far out, a rounding step off its grid point,
    // which is not a distance from it (fuzz_extract regression 94335006bc8d4aee).
    for (const std::int64_t far : {std::int64_t{1} << 40, std::int64_t{1} << 43, std::int64_t{1} << 45}) {
        Input in = make_map(torus_layout(), 2, 3);
        translate(in, far + 12345, 3 * far + 7);
        const Result r = extract_valid(in);
        ASSERT_TRUE(r.check.valid) << far;
        QuadMesh bare;
        bare.positions = r.mesh.positions;
        bare.faces = r.mesh.faces;
        const VerifyResult v = verify(in, bare);
        EXPECT_TRUE(v.valid) << far << ": " << (v.violations.empty() ? "" : v.violations[0].message);
        // And a vertex moved a third of the way to a neighbour is still rejected there.
        const std::vector<int>& face = bare.faces[0];
        auto& p = bare.positions[static_cast<std::size_t>(face[0])];
        const auto& q = bare.positions[static_cast<std::size_t>(face[1])];
        for (int d = 0; d < 3; ++d)
            p[static_cast<std::size_t>(d)] += (q[static_cast<std::size_t>(d)] - p[static_cast<std::size_t>(d)]) / 3;
        EXPECT_FALSE(verify(in, bare).valid) << far;
    }
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

/// A torus map's carried copy in which the 8 neighbours of a vertex `v` (every corner of them in
/// one chart) go round it `turns` times, evenly from the first one's direction, at 0.9 of their
/// distances; v's fan is listed as repaired. Returns v, or -1 when the map has no such vertex.
int wind_fan(const Input& in, QuadMesh& mesh, const std::vector<char>& single_chart, int turns) {
    for (int v = 0; v < static_cast<int>(single_chart.size()); ++v) {
        if (!single_chart[v]) continue;
        // v's fan, counter-clockwise: each triangle (v, a, b) is followed by the one starting at b.
        std::map<int, std::pair<int, int>> next; // a -> (b, triangle)
        bool all_single = true;
        for (int t = 0; t < static_cast<int>(in.triangles.size()); ++t)
            for (int k = 0; k < 3; ++k)
                if (in.triangles[t][k] == v) {
                    const int a = in.triangles[t][(k + 1) % 3], b = in.triangles[t][(k + 2) % 3];
                    next[a] = {b, t};
                    all_single = all_single && single_chart[a] && single_chart[b];
                }
        if (!all_single || next.size() != 8) continue;
        std::map<int, std::array<double, 2>> uv; // the single-chart vertices' UVs
        for (std::size_t c = 0; c < in.uvs.size(); ++c) uv[in.triangles[c / 3][c % 3]] = mesh.map_uvs[c];
        const int first = next.begin()->first;
        const std::array<double, 2> o = uv[v];
        const double start = std::atan2(uv[first][1] - o[1], uv[first][0] - o[0]);
        int i = 0;
        for (int a = first; i == 0 || a != first; a = next[a].first, ++i) {
            mesh.map_repaired.push_back(next[a].second);
            const double angle = start + 2.0 * M_PI * turns * i / 8.0;
            const double r = 0.9 * std::hypot(uv[a][0] - o[0], uv[a][1] - o[1]);
            for (std::size_t c = 0; c < in.uvs.size(); ++c)
                if (in.triangles[c / 3][c % 3] == a)
                    mesh.map_uvs[c] = {o[0] + r * std::cos(angle), o[1] + r * std::sin(angle)};
        }
        std::sort(mesh.map_repaired.begin(), mesh.map_repaired.end());
        return v;
    }
    return -1;
}

TEST(Checker, RepairMayNotAddABranchPoint) {
    std::vector<char> single_chart;
    const Input in = make_map(torus_layout(), 4, 5, 1, 1, &single_chart);
    const QuadMesh mesh = extract(in).mesh;
    ASSERT_FALSE(mesh.map_uvs.empty());
    // Once round, a little closer: the repaired triangles are positive and every vertex still
    // winds once, so the certificate holds.
    QuadMesh once = mesh;
    const int v = wind_fan(in, once, single_chart, 1);
    ASSERT_GE(v, 0);
    const VerifyResult v1 = verify(in, once);
    EXPECT_FALSE(has(v1, ViolationKind::RepairNotCertified));
    EXPECT_FALSE(has(v1, ViolationKind::MapNotIntegerGrid));
    // Twice round: v's triangles are still positive, but v is a branch point.
    QuadMesh twice = mesh;
    ASSERT_EQ(wind_fan(in, twice, single_chart, 2), v);
    // Named at a repaired triangle round v (the kind's place is an input triangle), v in words.
    bool named = false;
    for (const auto& x : verify(in, twice).violations) {
        if (x.kind != ViolationKind::RepairNotCertified || x.message.find("winds 720 degrees") == std::string::npos)
            continue;
        const auto t = static_cast<std::size_t>(x.element);
        const bool listed = std::binary_search(twice.map_repaired.begin(), twice.map_repaired.end(),
                                               static_cast<std::int32_t>(x.element));
        const bool round_v = x.element >= 0 && t < in.triangles.size() &&
                             std::find(in.triangles[t].begin(), in.triangles[t].end(), v) != in.triangles[t].end();
        named = named || (listed && round_v &&
                          x.message.find("input vertex " + std::to_string(v) + " ") != std::string::npos);
    }
    EXPECT_TRUE(named);
}

TEST(Checker, MixedPolygonsAreWalkedFaceByFace) {
    // A quad and a 2-gon have 6 corners, as two triangles would: the edges must still come
    // from the faces as given ({0,1}, {1,2}, {2,3}, {3,0}), not from corners taken in threes.
    const Input in = make_map(cube_layout(), 2, 3);
    QuadMesh mesh;
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    mesh.faces = {{0, 1, 2, 3}, {3, 2}};
    const VerifyResult v = verify(in, mesh);
    EXPECT_EQ(v.edges, 4);
    EXPECT_EQ(count(v, ViolationKind::NotQuad), 1u);
    EXPECT_FALSE(v.valid);
}

TEST(Checker, ParallelLoopsGiveTheSerialVerdict) {
    // VerifyOptions::threads changes who computes, not what: the same violations in the same
    // order. The checker's loops run in parallel from 2^16 corners on (input or mesh).
    VerifyOptions serial, parallel;
    serial.threads = 1;
    parallel.threads = 2;
    auto same = [&](const Input& in, const QuadMesh& mesh) -> VerifyResult {
        const VerifyResult a = verify(in, mesh, serial), b = verify(in, mesh, parallel);
        EXPECT_EQ(a.valid, b.valid);
        EXPECT_EQ(a.map_singularities, b.map_singularities);
        EXPECT_EQ(a.edges, b.edges);
        EXPECT_EQ(a.euler, b.euler);
        EXPECT_EQ(a.violations.size(), b.violations.size());
        for (std::size_t i = 0; i < std::min(a.violations.size(), b.violations.size()); ++i) {
            EXPECT_EQ(a.violations[i].kind, b.violations[i].kind);
            EXPECT_EQ(a.violations[i].message, b.violations[i].message);
            EXPECT_EQ(a.violations[i].element, b.violations[i].element);
        }
        return a;
    };
    // A large input: the subdivided cube, its map shifted off the grid and one corner moved.
    const Input cube = subdivide(subdivide(subdivide(subdivide(make_map(cube_layout(), 3, 3, 2, 5)))));
    ASSERT_GE(3 * cube.triangles.size(), std::size_t{1} << 16);
    const QuadMesh cube_mesh = extract(cube).mesh;
    EXPECT_TRUE(same(cube, cube_mesh).valid);
    QuadMesh shifted = cube_mesh;
    for (auto& uv : shifted.map_uvs) uv[0] += 0.5, uv[1] += 0.5;
    shifted.map_uvs[1000][1] += 1e-7;
    const VerifyResult s = same(cube, shifted);
    EXPECT_EQ(count(s, ViolationKind::SingularityOffGrid), 8u);
    EXPECT_GE(count(s, ViolationKind::MapNotIntegerGrid), 1u);
    // Located mode (no provenance) on a finer triangulation of the same cube (the coverage check
    // enumerates its 110K triangles in parallel): a quad dropped, a vertex moved off its grid point.
    const Input finer = subdivide(cube);
    QuadMesh located;
    located.positions = cube_mesh.positions;
    located.faces = cube_mesh.faces;
    const VerifyResult l = same(finer, located);
    EXPECT_TRUE(l.valid);
    EXPECT_EQ(l.coverage_cells, static_cast<std::int64_t>(located.faces.size()));
    located.faces.erase(located.faces.begin() + 7);
    const int moved = located.faces[20][0];
    for (int k = 0; k < 3; ++k)
        located.positions[static_cast<std::size_t>(moved)][k] =
            0.5 * (located.positions[static_cast<std::size_t>(moved)][k] +
                   located.positions[static_cast<std::size_t>(located.faces[20][1])][k]);
    const VerifyResult m = same(finer, located);
    EXPECT_EQ(count(m, ViolationKind::GridCellNotCovered), 1u);
    EXPECT_EQ(count(m, ViolationKind::GridPointNotCovered), 1u);
    EXPECT_EQ(m.coverage_cells, l.coverage_cells);
    // A large mesh: a torus with many quads, one face reversed and one doubled.
    const Input torus = make_map(torus_layout(32, 16), 8, 2);
    QuadMesh quads = extract(torus).mesh;
    ASSERT_GE(4 * quads.faces.size(), std::size_t{1} << 16);
    EXPECT_TRUE(same(torus, quads).valid);
    std::reverse(quads.faces[5].begin(), quads.faces[5].end());
    quads.faces.push_back(quads.faces[900]);
    quads.face_uvs.push_back(quads.face_uvs[900]);
    const VerifyResult q = same(torus, quads);
    EXPECT_GE(count(q, ViolationKind::InconsistentOrientation), 1u);
    EXPECT_GE(count(q, ViolationKind::NonManifoldEdge), 1u);
}

/// The mesh as another extractor (or an OBJ read back) would give it: no provenance, no map.
QuadMesh without_provenance(QuadMesh m) {
    m.provenance.clear();
    m.map_uvs.clear();
    m.face_uvs.clear();
    return m;
}

TEST(CheckerLocated, AcceptsCorrectMeshesOfOtherExtractors) {
    for (const Input& in : {make_map(cube_layout(), 2, 3), make_map(torus_layout(), 3, 2),
                            make_map(annulus_layout(), 2, 3), make_map(prism_layout(5), 2, 3)}) {
        const QuadMesh m = without_provenance(extract(in).mesh);
        const VerifyResult v = verify(in, m);
        EXPECT_TRUE(v.located);
        EXPECT_TRUE(v.valid) << (v.violations.empty() ? "" : v.violations[0].message);
        EXPECT_LT(v.max_grid_distance, 1e-9);
        EXPECT_EQ(v.coverage_difference, 0);
        EXPECT_TRUE(v.undecided.empty());
        // Rounded positions, as a tool writing 7 significant digits would leave them.
        QuadMesh rounded = m;
        for (auto& p : rounded.positions)
            for (double& x : p) x = std::round(x * 1e6) / 1e6;
        VerifyOptions loose;
        loose.distance_tolerance = 1e-5;
        EXPECT_TRUE(verify(in, rounded, loose).valid);
    }
}

TEST(CheckerLocated, GridPointsNearAnOffGridVertexKeepTheirOwnUv) {
    // A fine grid puts grid points closer to an input vertex than the distance tolerance (as
    // duck_miq_4 with UVs x 32 does); where the vertex's UV is off the grid, such a point keeps
    // the UV it has in its triangle, not the vertex's. Here the tolerance is made large instead.
    const Input in = make_map(torus_layout(), 4, 5); // k coprime to n: vertices off the grid
    const QuadMesh m = without_provenance(extract(in).mesh);
    VerifyOptions wide;
    wide.distance_tolerance = 0.02;
    const VerifyResult v = verify(in, m, wide);
    EXPECT_TRUE(v.valid) << (v.violations.empty() ? "" : v.violations[0].message);
    EXPECT_LT(v.max_grid_distance, 1e-9);
    // A vertex moved off its grid point is still rejected at that tolerance.
    QuadMesh moved = m;
    for (double& x : moved.positions[7]) x += 1e-3;
    const VerifyResult w = verify(in, moved, wide);
    EXPECT_FALSE(w.valid);
}

TEST(CheckerLocated, RejectsVerticesOffTheirGridPoints) {
    const Input in = make_map(cube_layout(), 2, 3);
    const QuadMesh good = without_provenance(extract(in).mesh);
    // Slide a vertex along its (flat) cube face to the middle of one of its edges.
    QuadMesh slid = good;
    const auto& f0 = slid.faces[0];
    for (int k = 0; k < 3; ++k)
        slid.positions[static_cast<std::size_t>(f0[0])][k] = 0.5 * (good.positions[static_cast<std::size_t>(f0[0])][k] +
                                                                    good.positions[static_cast<std::size_t>(f0[1])][k]);
    const VerifyResult a = verify(in, slid);
    EXPECT_EQ(count(a, ViolationKind::NotOnGridPoint), 1u);
    EXPECT_GT(a.max_grid_distance, 0.4);
    // Lift a vertex off the surface (away from the cube's centre).
    QuadMesh lifted = good;
    for (double& x : lifted.positions[5]) x = 0.5 + (x - 0.5) * 1.05;
    EXPECT_EQ(count(verify(in, lifted), ViolationKind::OffSurface), 1u);
}

TEST(CheckerLocated, RejectsFacesThatAreNotGridCells) {
    const Input in = make_map(torus_layout(), 3, 2); // no singularities: every failure is decided
    const QuadMesh good = without_provenance(extract(in).mesh);
    // A face whose corners are listed in bow-tie order.
    QuadMesh bowtie = good;
    std::swap(bowtie.faces[4][1], bowtie.faces[4][2]);
    EXPECT_GE(count(verify(in, bowtie), ViolationKind::FaceNotGridCell), 1u);
    // A face reversed (clockwise in the map) and everything else as it was.
    QuadMesh reversed = good;
    std::reverse(reversed.faces[7].begin(), reversed.faces[7].end());
    const VerifyResult r = verify(in, reversed);
    EXPECT_GE(count(r, ViolationKind::FaceNotGridCell), 1u);
    // A whole mesh reversed is consistently oriented, closed and of the right size: only the
    // map can tell that every face is clockwise.
    QuadMesh all_reversed = good;
    for (auto& f : all_reversed.faces) std::reverse(f.begin(), f.end());
    // Each face is named: a violation where its edges' corridors certify the failure, undecided
    // where a corridor wraps round the thin torus (the transitions around it are a period).
    const VerifyResult rev = verify(in, all_reversed);
    std::size_t undecided = 0;
    for (const auto& x : rev.undecided) undecided += x.kind == ViolationKind::FaceNotGridCell;
    EXPECT_EQ(count(rev, ViolationKind::FaceNotGridCell) + undecided, all_reversed.faces.size());
    EXPECT_GE(2 * count(rev, ViolationKind::FaceNotGridCell), all_reversed.faces.size());
    EXPECT_TRUE(verify(in, all_reversed, VerifyOptions{false}).valid); // topology alone accepts it
}

TEST(CheckerLocated, RejectsMissingAndExtraQuads) {
    const Input in = make_map(torus_layout(), 3, 2);
    const QuadMesh good = without_provenance(extract(in).mesh);
    QuadMesh missing = good;
    missing.faces.pop_back();
    const VerifyResult a = verify(in, missing);
    EXPECT_EQ(count(a, ViolationKind::CoverageMismatch), 1u);
    EXPECT_EQ(a.coverage_difference, -1);
    QuadMesh extra = good;
    extra.faces.push_back(extra.faces[0]);
    EXPECT_EQ(verify(in, extra).coverage_difference, 1);
    EXPECT_TRUE(has(verify(in, extra), ViolationKind::CoverageMismatch));
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
