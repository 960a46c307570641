// Stage-level unit tests: sanitization (Section 3) and the transition table on the working mesh.
// The ladder's stages are in stages_holes_test.cpp (coarsening, closing and filling holes) and
// stages_mend_test.cpp (mending, separating sheets).
#include "stages_support.h"

#include "ladder/ladder.h"
#include "pipeline.h"
#include "test_support.h"
#include "transform_checks.h"
#include <climits>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <algorithm>
#include <random>

namespace qex::testing {
namespace {

TEST(Extraction, SanitizationIsIdempotent) {
    Input in = make_map(icosahedron_layout(), 2, 3);
    std::mt19937 rng(5);
    add_noise(in, 1e-8, rng);
    rechart(in, rng);
    detail::TriMesh m = sanitized(in);
    const auto once = m.uv;
    // Every transition maps both corners of its edge exactly.
    for (int h = 0; h < 3 * m.num_faces(); ++h) {
        const int o = m.opp[h];
        if (o < 0) continue;
        EXPECT_EQ(m.map.transition[h](m.uv[h]), m.uv[detail::TriMesh::next(o)]);
        EXPECT_EQ(m.map.transition[h](m.uv[detail::TriMesh::next(h)]), m.uv[o]);
    }
    detail::compute_transitions(m);
    detail::count_valences(m);
    Report rep2;
    ASSERT_EQ(detail::sanitize(m, {}, {}, rep2).code, ErrorCode::None);
    EXPECT_EQ(m.uv, once);
    EXPECT_EQ(rep2.max_sanitization_displacement, 0.0);
}

/// n unit right corners round vertex 0 (ring 1..n on the boundary), each triangle in its own
/// chart, so the transitions across the n inner edges turn by n quarters; mirrored: u and v
/// swapped in every triangle, the whole fan one flipped run. Vertex 0's winding valence and
/// Algorithm 8's valence.
std::array<int, 2> counted_fan(int n, bool mirrored) {
    Input in;
    in.positions.push_back({0, 0, 1});
    for (int i = 0; i < n; ++i) {
        const double a = 2.0 * M_PI * i / n;
        in.positions.push_back({std::cos(a), std::sin(a), 0});
    }
    for (int i = 0; i < n; ++i) {
        in.triangles.push_back({0, 1 + i, 1 + (i + 1) % n});
        for (const auto& uv : {std::array<double, 2>{0, 0}, {1, 0}, {0, 1}})
            in.uvs.push_back(mirrored ? std::array<double, 2>{uv[1], uv[0]} : uv);
    }
    detail::TriMesh m = detail::make_mesh(in);
    EXPECT_EQ(detail::build_topology(m, "test").code, ErrorCode::None);
    detail::compute_transitions(m);
    detail::count_valences(m);
    for (int v = 0; v < m.num_vertices; ++v)
        if (m.input_vertex[v] == 0) return {m.map.winding_valence[v], m.map.valence[v]};
    ADD_FAILURE() << "vertex 0 is not in the working mesh";
    return {0, 0};
}

/// A disk of n triangles round vertex 0 in one chart: vertex 0 at `centre`, ring vertex i at
/// angle angles[i] round it (one UV per vertex: every transition is the identity). Vertex 0
/// after sanitizing: whether it is singular, and how far it moved.
std::pair<bool, double> sanitized_centre(const std::array<double, 2>& centre, const std::vector<double>& angles,
                                         double noise_scale = 1.0) {
    Input in;
    const std::size_t n = angles.size();
    in.positions.push_back({0, 0, 1});
    for (std::size_t i = 0; i < n; ++i) {
        const double a = 2.0 * M_PI * static_cast<double>(i) / static_cast<double>(n);
        in.positions.push_back({std::cos(a), std::sin(a), 0});
    }
    const auto ring = [&](std::size_t i) {
        return std::array<double, 2>{centre[0] + 2 * std::cos(angles[i]), centre[1] + 2 * std::sin(angles[i])};
    };
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t j = (i + 1) % n;
        in.triangles.push_back({0, static_cast<int>(1 + i), static_cast<int>(1 + j)});
        for (const auto& uv : {centre, ring(i), ring(j)}) in.uvs.push_back(uv);
    }
    detail::TriMesh m = detail::make_mesh(in);
    EXPECT_EQ(detail::build_topology(m, "test").code, ErrorCode::None);
    m.noise_scale = noise_scale;
    Report rep;
    detail::compute_transitions(m);
    detail::count_valences(m);
    EXPECT_EQ(detail::sanitize(m, {}, {}, rep, true).code, ErrorCode::None);
    for (int v = 0; v < m.num_vertices; ++v)
        if (m.input_vertex[v] == 0) {
            const auto& u = m.uv[static_cast<std::size_t>(m.fan_start[v])];
            return {m.map.singular[v] != 0, std::max(std::abs(u[0] - centre[0]), std::abs(u[1] - centre[1]))};
        }
    ADD_FAILURE() << "vertex 0 is not in the working mesh";
    return {false, 0.0};
}

TEST(Sanitize, AFoldThatWindsAFanTwiceOffTheGridIsNotABranchPoint) {
    // Eight quarter turns round vertex 0 with transitions that do not turn: a branch point, or a
    // fold that winds the fan twice. Folded: ten steps, nine of 760/9 degrees and one of -40 (a
    // flipped triangle). Positive: eight right angles, no triangle flipped.
    std::vector<double> folded(10), positive(8);
    for (std::size_t i = 1; i < folded.size(); ++i)
        folded[i] = folded[i - 1] + (i == 5 ? -40.0 : 760.0 / 9.0) * M_PI / 180.0;
    for (std::size_t i = 0; i < positive.size(); ++i) positive[i] = 0.5 * M_PI * static_cast<double>(i) + 0.1;
    for (const auto& angles : {folded, positive}) {
        // Off every grid point: a fold, not snapped (snapping would move it 0.3).
        const auto [fold_singular, fold_moved] = sanitized_centre({0.3, 0.2}, angles);
        EXPECT_FALSE(fold_singular) << angles.size();
        EXPECT_LT(fold_moved, 1e-9) << angles.size();
        // On a grid point up to solver noise: a branch point, snapped to it.
        const auto [singular, moved] = sanitized_centre({3.0 + 1e-7, -2.0}, angles);
        EXPECT_TRUE(singular) << angles.size();
        EXPECT_NEAR(moved, 1e-7, 1e-12) << angles.size();
        // A map refined x4 multiplies its noise by 4: 3/4096 of a cell off at the map's own
        // scale is 3/1024 at x4, still noise there, and more than noise at the map's own scale.
        const double off = 3.0 / 1024;
        EXPECT_TRUE(sanitized_centre({12.0 + off, -8.0}, angles, 4.0).first) << angles.size();
        EXPECT_FALSE(sanitized_centre({12.0 + off, -8.0}, angles, 1.0).first) << angles.size();
    }
}

/// Stage merge_vertices on hand-made face walks (q-vertex, local UV): q-vertex i lies inside the
/// one triangle of a stand-in mesh, at position (i, 0, 0). The faces, as output vertices.
std::vector<std::vector<int>> merged_walks(const std::vector<std::vector<std::pair<int, detail::IPoint>>>& walks,
                                           int qvertices, Report& report) {
    Input in;
    in.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    in.triangles = {{0, 1, 2}};
    in.uvs = {{0, 0}, {8, 0}, {0, 8}};
    detail::TriMesh m = detail::make_mesh(in);
    EXPECT_EQ(detail::build_topology(m, "test").code, ErrorCode::None);
    detail::QState q;
    for (int i = 0; i < qvertices; ++i)
        q.qvertices.push_back({QVertexKind::Face, 0, 0, {i, 0}, {static_cast<double>(i), 0, 0}, {1, 0, 0}});
    detail::FaceWalks w;
    for (const auto& walk : walks) {
        for (const auto& [v, uv] : walk) w.qv.push_back(v), w.uv.push_back(uv);
        w.first.push_back(w.qv.size());
    }
    QuadMesh out;
    const detail::FaceWalks merged = detail::merge_vertices(m, q, w, Options{}, out, report);
    std::vector<std::vector<int>> faces;
    for (std::size_t f = 0; f < merged.size(); ++f)
        faces.emplace_back(merged.qv.begin() + static_cast<std::ptrdiff_t>(merged.first[f]),
                           merged.qv.begin() + static_cast<std::ptrdiff_t>(merged.first[f + 1]));
    return faces;
}

TEST(MergeVertices, AClockwiseFaceAndItsNearReverseCancelAndTheirOddCornersMerge) {
    // Cells [0,1]x[0,1] (F1), [1,2]x[0,1] (B) and [0,1]x[1,2] (F3); q-vertex 6 is a clone of
    // grid point (1, 1) (q-vertex 4) on another sheet, which F3 reaches. A walks B's cell
    // clockwise through the clone: A and B cover it once each way, like a ghost pair.
    using W = std::vector<std::pair<int, detail::IPoint>>;
    const W f1{{0, {0, 0}}, {1, {1, 0}}, {4, {1, 1}}, {3, {0, 1}}};
    const W b{{1, {1, 0}}, {2, {2, 0}}, {5, {2, 1}}, {4, {1, 1}}};
    const W a{{1, {1, 0}}, {6, {1, 1}}, {5, {2, 1}}, {2, {2, 0}}};
    const W f3{{3, {0, 1}}, {6, {1, 1}}, {7, {1, 2}}, {8, {0, 2}}};
    {
        Report report;
        const auto faces = merged_walks({f1, b, a, f3}, 9, report);
        ASSERT_EQ(faces.size(), 2u);
        EXPECT_EQ(report.ghost_faces_cancelled, 2);
        EXPECT_EQ(report.merged_qvertices, 1);
        // F1 and F3 now share the edge from grid point (0, 1) to the merged (1, 1): six vertices
        // (2 and 5 went with B).
        std::set<int> vertices;
        std::vector<int> shared;
        for (const int v : faces[0]) {
            vertices.insert(v);
            if (std::count(faces[1].begin(), faces[1].end(), v)) shared.push_back(v);
        }
        vertices.insert(faces[1].begin(), faces[1].end());
        EXPECT_EQ(vertices.size(), 6u);
        EXPECT_EQ(shared.size(), 2u);
    }
    {
        // The same corners with A's local UVs counter-clockwise: no face walked a reversed sheet.
        W ccw = a;
        ccw[1].second = {2, 0}, ccw[3].second = {1, 1};
        Report report;
        EXPECT_EQ(merged_walks({f1, b, ccw, f3}, 9, report).size(), 4u);
        EXPECT_EQ(report.ghost_faces_cancelled, 0);
    }
    {
        // B clockwise too: two clockwise faces with three corners in common are mirror images
        // across an edge, their fourth corners two grid points.
        W mirrored = b;
        mirrored[1].second = {1, 1}, mirrored[3].second = {2, 0};
        Report report;
        EXPECT_EQ(merged_walks({f1, mirrored, a, f3}, 9, report).size(), 4u);
        EXPECT_EQ(report.ghost_faces_cancelled, 0);
    }
    {
        // The clones already share a face: merging them would put a corner twice in it.
        const W joint{{4, {1, 1}}, {9, {2, 1}}, {6, {2, 2}}, {10, {1, 2}}};
        Report report;
        EXPECT_EQ(merged_walks({f1, b, a, f3, joint}, 11, report).size(), 5u);
        EXPECT_EQ(report.ghost_faces_cancelled, 0);
    }
}

TEST(Valences, WhollyFlippedFanCountsAsItsTransitionsTurn) {
    // A cone of three quarter turns, given as is or mirrored: mirrored, the signed sum is -3
    // quarter turns and the transitions turn by +1, so an unfolded fan must span 1 (or 5, ...)
    // quarter turns, never |sum| = 3. Algorithm 8's valence must agree with the turn modulo 4
    // in both.
    for (const bool mirrored : {false, true}) {
        const auto [winding, valence] = counted_fan(3, mirrored);
        EXPECT_EQ(winding, mirrored ? -3 : 3);
        EXPECT_EQ(valence, mirrored ? 1 : 3);
        EXPECT_EQ(((valence - winding) % 4 + 4) % 4, 0);
    }
}

TEST(Valences, WhollyFlippedFanWhoseTransitionsDoNotTurnKeepsItsWholeTurns) {
    // n = 4, 8, 12: the transitions turn by whole turns. Mirrored, the whole fan is one flipped
    // run with signed sum -n quarter turns and transitions that do not turn: the turns are the
    // winding's to decide, so a mirrored branch point of 8 stays 8 (the fewest positive quarter
    // turns congruent to 0 would make it 4, regular), and a mirrored regular vertex stays 4.
    for (const int n : {4, 8, 12})
        for (const bool mirrored : {false, true}) {
            const auto [winding, valence] = counted_fan(n, mirrored);
            EXPECT_EQ(winding, mirrored ? -n : n) << n << (mirrored ? " mirrored" : "");
            EXPECT_EQ(valence, n) << n << (mirrored ? " mirrored" : "");
        }
}

TEST(Transitions, EveryHalfEdgeIsWrittenEvenOverStaleEntries) {
    // The table is allocated without clearing (and reused when the size is unchanged), so
    // compute_transitions must write every entry: boundary half-edges and edges of a triangle
    // without UVs (collapsed away) get the identity, every interior pair two inverses.
    Input in = make_map(annulus_layout(), 2, 3);
    std::mt19937 rng(9);
    rechart(in, rng);
    detail::TriMesh m = detail::make_mesh(in);
    ASSERT_EQ(detail::build_topology(m, "test").code, ErrorCode::None);
    const int nh = 3 * m.num_faces();
    int interior_face = -1;
    for (int f = 0; f < m.num_faces() && interior_face < 0; ++f)
        if (m.opp[3 * f] >= 0 && m.opp[3 * f + 1] >= 0 && m.opp[3 * f + 2] >= 0) interior_face = f;
    ASSERT_GE(interior_face, 0);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (int k = 0; k < 3; ++k) m.uv[3 * interior_face + k] = {nan, nan};
    m.map.transition.allocate(static_cast<std::size_t>(nh));
    const detail::GridAutomorphism junk{3, 12345, -678};
    for (int h = 0; h < nh; ++h) m.map.transition.set(static_cast<std::size_t>(h), junk);
    detail::compute_transitions(m);
    int boundary = 0, missing = 0;
    for (int h = 0; h < nh; ++h) {
        const int o = m.opp[h];
        const bool no_uv =
            detail::TriMesh::face(h) == interior_face || (o >= 0 && detail::TriMesh::face(o) == interior_face);
        if (o < 0 || no_uv) {
            EXPECT_TRUE(m.map.transition[h] == detail::GridAutomorphism{}) << h;
            boundary += o < 0;
            missing += no_uv;
        } else {
            EXPECT_TRUE(m.map.transition[h].after(m.map.transition[o]) == detail::GridAutomorphism{}) << h;
        }
    }
    EXPECT_GT(boundary, 0);
    EXPECT_EQ(missing, 6); // the triangle's three half-edges and their three opposites
}

TEST(Transitions, ATieBetweenTwoRotationsIsBrokenTheSameInAnyOrder) {
    // Two triangles on edge 0-1, whose copies run (1, 0) and (-1, 1): rotations by 1 and by 2
    // quarters fit them equally well (by 3 and 2 seen from the other side, so "the first of the
    // best" depends on the side), and no fan closes round the edge (both ends are on the
    // boundary), so the nearest rotation stands. With the triangles in either order, the edge
    // must turn the same way from the first triangle's chart to the second's.
    std::array<int, 2> turns{};
    for (const bool swapped : {false, true}) {
        Input in;
        in.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, -1, 0}};
        const std::array<int, 3> first{0, 1, 2}, second{1, 0, 3};
        const std::vector<std::array<double, 2>> first_uv{{0, 0}, {1, 0}, {0, 1}}, second_uv{{-1, 1}, {0, 0}, {0, 2}};
        in.triangles =
            swapped ? std::vector<std::array<int, 3>>{second, first} : std::vector<std::array<int, 3>>{first, second};
        for (const auto* uvs : swapped ? std::array{&second_uv, &first_uv} : std::array{&first_uv, &second_uv})
            in.uvs.insert(in.uvs.end(), uvs->begin(), uvs->end());
        detail::TriMesh m = detail::make_mesh(in);
        ASSERT_EQ(detail::build_topology(m, "test").code, ErrorCode::None);
        detail::compute_transitions(m);
        // The first triangle's half-edge 0 -> 1, and the rotation from its chart to the other's.
        int h = -1;
        for (int c = 0; c < 3 * m.num_faces(); ++c)
            if (m.input_vertex[m.origin(c)] == 0 && m.input_vertex[m.target(c)] == 1) h = c;
        ASSERT_GE(h, 0);
        turns[swapped] = m.map.transition[h].r;
    }
    EXPECT_EQ(turns[0], turns[1]);
}

TEST(Transitions, AnUndeterminedEdgeAtASingularityClosesTheSameFanInAnyOrder) {
    // A cube corner s (valence 3) and a vertex w inserted into one of its triangles a little off
    // s in that triangle's chart: the edge s-w is about as long as the difference of its two
    // copies, so its rotation is undetermined, and closing s's fan (s regular, the singularity
    // moves to w) and closing w's fan (s stays singular) disagree. Which end decides must not
    // depend on the input's order.
    Input base = make_map(cube_layout(), 2, 2);
    std::size_t f = 0, corner = 0;
    for (std::size_t c = 0; c < 3 * base.triangles.size(); ++c) {
        const auto& p = base.positions[static_cast<std::size_t>(base.triangles[c / 3][c % 3])];
        if ((p[0] == 0 || p[0] == 1) && (p[1] == 0 || p[1] == 1) && (p[2] == 0 || p[2] == 1)) {
            f = c / 3, corner = c % 3;
            break;
        }
    }
    const int sv = base.triangles[f][corner];
    const auto s = base.positions[static_cast<std::size_t>(sv)];
    const auto s_uv = base.uvs[3 * f + corner]; // the three new triangles keep f's chart
    insert_collapsed_edge(base, static_cast<int>(f), static_cast<int>(corner));
    const int w = static_cast<int>(base.positions.size()) - 1;
    const auto w_position = base.positions.back();
    // w's corners: s + (d, 0), but s + (d, d) in the triangle where the edge runs from w to s.
    const double d = std::ldexp(1.0, -20);
    for (std::size_t g = 0; g < base.triangles.size(); ++g)
        for (std::size_t k = 0; k < 3; ++k)
            if (base.triangles[g][k] == w)
                base.uvs[3 * g + k] = {s_uv[0] + d, s_uv[1] + (base.triangles[g][(k + 1) % 3] == sv ? d : 0.0)};
    // The turns round s and w, found by their 3D positions.
    const auto turns = [&](const Input& in) {
        detail::TriMesh m = detail::make_mesh(in);
        EXPECT_EQ(detail::build_topology(m, "test").code, ErrorCode::None);
        detail::compute_transitions(m);
        std::array<int, 2> out{-9, -9};
        for (int v = 0; v < m.num_vertices; ++v) {
            const auto& p = in.positions[static_cast<std::size_t>(m.input_vertex[v])];
            if (p == s) out[0] = detail::fan_turn(m, v);
            if (p == w_position) out[1] = detail::fan_turn(m, v);
        }
        return out;
    };
    const std::array<int, 2> expected = turns(base);
    EXPECT_TRUE((expected[0] == 0) != (expected[1] == 0)) << expected[0] << " " << expected[1];
    for (std::uint32_t seed = 1; seed <= 8; ++seed) {
        std::mt19937 rng(seed);
        Input shuffled = base;
        shuffle(shuffled, rng);
        const std::array<int, 2> got = turns(shuffled);
        EXPECT_EQ(got[0], expected[0]) << "seed " << seed;
        EXPECT_EQ(got[1], expected[1]) << "seed " << seed;
    }
}

/// A cube corner s (valence 3) and a seam s-a leaving it. Both triangles on the seam get a vertex
/// joined to s by a collapsed edge, and the map is subdivided 1-to-4: the midpoint of s-a then
/// has a collapsed edge on each side of the seam. Every corner is then perturbed by independent
/// noise far below the seam check's bound, so the short edges' copies point any way and the
/// midpoint's fan crosses two of them: only the copies' positions tell their rotations. Every
/// seed must pass the seam check and give the noiseless map's quads (refined, if it must be),
/// the same in any input order.
void expect_short_edges_take_their_positions_rotations(int n, int k) {
    Input base = make_map(cube_layout(), n, k);
    const auto is_corner = [&](int v) {
        const auto& p = base.positions[static_cast<std::size_t>(v)];
        return (p[0] == 0 || p[0] == 1) && (p[1] == 0 || p[1] == 1) && (p[2] == 0 || p[2] == 1);
    };
    // Two triangles at s sharing the edge s-a with different UV copies of a.
    std::array<std::size_t, 2> on_seam{};
    std::array<int, 2> at_s{};
    bool found = false;
    for (std::size_t f = 0; f < base.triangles.size() && !found; ++f)
        for (int k = 0; k < 3 && !found; ++k) {
            const int s_vertex = base.triangles[f][k], a = base.triangles[f][(k + 1) % 3];
            if (!is_corner(s_vertex)) continue;
            for (std::size_t g = 0; g < base.triangles.size() && !found; ++g)
                for (int j = 0; j < 3 && !found; ++j)
                    if (base.triangles[g][j] == a && base.triangles[g][(j + 1) % 3] == s_vertex &&
                        base.uvs[3 * g + j] != base.uvs[3 * f + (k + 1) % 3]) {
                        on_seam = {f, g}, at_s = {k, (j + 1) % 3};
                        found = true;
                    }
        }
    ASSERT_TRUE(found);
    insert_collapsed_edge(base, static_cast<int>(on_seam[0]), at_s[0]);
    insert_collapsed_edge(base, static_cast<int>(on_seam[1]), at_s[1]);
    const Input fine = subdivide(base);
    const auto quads = static_cast<std::int64_t>(extract_valid(fine).mesh.faces.size());
    for (std::uint32_t seed = 1; seed <= 16; ++seed) {
        Input in = fine;
        std::mt19937 rng(seed);
        add_noise(in, 1e-6, rng);
        detail::TriMesh m = detail::make_mesh(in);
        ASSERT_EQ(detail::build_topology(m, "test").code, ErrorCode::None);
        detail::compute_transitions(m);
        Report rep;
        const Error seams = detail::check_seams(m, detail::SeamPolicy::Checked, rep);
        EXPECT_EQ(seams.code, ErrorCode::None) << "seed " << seed << ": " << seams.message;
        const Result r = extract(in);
        ASSERT_TRUE(r.ok()) << "seed " << seed << ": " << r.error.message;
        EXPECT_TRUE(r.check.valid) << "seed " << seed;
        // At the map's own scale, or refined (each quad split into grid_scale x grid_scale).
        EXPECT_EQ(static_cast<std::int64_t>(r.mesh.faces.size()), quads * r.mesh.grid_scale * r.mesh.grid_scale)
            << "seed " << seed;
        std::mt19937 order(seed);
        shuffle(in, order);
        const Result shuffled = extract(in);
        ASSERT_TRUE(shuffled.ok()) << "seed " << seed << ", shuffled: " << shuffled.error.message;
        EXPECT_EQ(mesh_difference(r.mesh, shuffled.mesh, 0.0), "") << "seed " << seed;
    }
}

TEST(Transitions, EdgesShorterThanTheirNoiseTakeTheRotationTheirCopiesPositionsAdmit) {
    // Layout vertices on grid points, the others at multiples of 3/4: the midpoint's collapsed
    // edges lie where no quarter or half turn about a grid point, cell centre or edge midpoint
    // fixes them, so their positions single one rotation out.
    expect_short_edges_take_their_positions_rotations(3, 4);
}

TEST(Transitions, EdgesShorterThanTheirNoiseAtAnEdgeMidpointTakeARotationItsPositionsAllow) {
    // Every vertex on a grid point: the midpoint's collapsed edges lie on edge midpoints, which a
    // half turn fixes, so their positions allow two rotations, and the choice is made among those.
    expect_short_edges_take_their_positions_rotations(2, 2);
}

} // namespace
} // namespace qex::testing
