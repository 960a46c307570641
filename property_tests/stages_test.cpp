// Stage-level unit tests: sanitization (Section 3) and the transition table on the working mesh.
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

/// The map sanitized (stages transitions, valences, sanitize), its transitions computed again.
detail::TriMesh sanitized(const Input& in) {
    detail::TriMesh m = detail::make_mesh(in);
    EXPECT_EQ(detail::build_topology(m, "test").code, ErrorCode::None);
    Report rep;
    detail::compute_transitions(m);
    detail::count_valences(m);
    EXPECT_EQ(detail::sanitize(m, {}, {}, rep).code, ErrorCode::None);
    detail::compute_transitions(m);
    return m;
}

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

// ---------------------------------------------------------------------------- coarsening

Input times(Input in, std::int64_t k) {
    for (auto& uv : in.uvs) uv = {uv[0] * static_cast<double>(k), uv[1] * static_cast<double>(k)};
    return in;
}

TEST(Coarsening, AMapTwiceAnIntegerGridMapHalvesFromItsOrigin) {
    // A map times 2 halves back to an integer-grid map laid from (0, 0); moved by a cell, from
    // (1, 0) (fixed by its singularities, its boundary's iso-lines or its turning transitions);
    // times 2 it halves twice
    // only if the map itself halves. The cube with one quad per face has singularities on both
    // parities: it halves from no origin.
    for (const QuadLayout& layout : {icosahedron_layout(), cube_layout(), torus_layout(), disk_layout(3)}) {
        std::mt19937 rng(3);
        Input base = make_map(layout, 1, 2);
        rechart(base, rng, 8);
        detail::IPoint origin{-1, -1};
        const bool base_halves = detail::map_divisible_by(sanitized(base), {}, 2, origin);
        const Input twice = times(base, 2);
        ASSERT_TRUE(detail::map_divisible_by(sanitized(twice), {}, 2, origin)) << layout.name;
        EXPECT_EQ(origin, (detail::IPoint{0, 0})) << layout.name;
        EXPECT_EQ(detail::map_divisible_by(sanitized(twice), {}, 4, origin), base_halves) << layout.name;
        Input moved = twice;
        translate(moved, 1, 0);
        ASSERT_TRUE(detail::map_divisible_by(sanitized(moved), {}, 2, origin)) << layout.name;
        // (On the torus only turning transitions fix it, and (0, 1) suits them as well as (1, 0).)
        const bool either = layout.name == "torus" && origin == detail::IPoint{0, 1};
        if (!either) { EXPECT_EQ(origin, (detail::IPoint{1, 0})) << layout.name; }
    }
    detail::IPoint origin;
    EXPECT_FALSE(detail::map_divisible_by(sanitized(make_map(cube_layout(), 1, 2)), {}, 2, origin));
}

TEST(Coarsening, ASplitMeshIsTheFineMeshOfAFoldFreeMap) {
    // The mesh of a map split k x k onto the map times k: valid there, k^2 times the quads, and
    // the vertices of the fine map's own mesh, where each is found on its grid point.
    for (const QuadLayout& layout : {icosahedron_layout(), cube_layout(), torus_layout(), disk_layout(3)}) {
        std::mt19937 rng(7);
        Input in = make_map(layout, 2, 3);
        rechart(in, rng, 8);
        const Result coarse = extract_valid(in);
        for (const int k : {2, 4}) {
            const Input fine = times(in, k);
            std::vector<std::array<double, 2>> map = coarse.mesh.map_uvs;
            for (auto& uv : map) uv = {uv[0] * k, uv[1] * k};
            QuadMesh split;
            ASSERT_TRUE(detail::split_onto_map(fine, map, coarse.mesh, k, {0, 0}, split)) << layout.name << " x" << k;
            const VerifyResult v = verify(fine, split);
            EXPECT_TRUE(v.valid) << layout.name << " x" << k << ": "
                                 << (v.violations.empty() ? std::string() : v.violations[0].message);
            EXPECT_EQ(split.faces.size(), static_cast<std::size_t>(k * k) * coarse.mesh.faces.size());
            const Result direct = extract_valid(fine);
            ASSERT_EQ(direct.mesh.positions.size(), split.positions.size()) << layout.name << " x" << k;
            // Every vertex of the one mesh has a vertex of the other where it is (up to rounding).
            double worst = 0.0;
            for (const auto& p : direct.mesh.positions) {
                double nearest = INFINITY;
                for (const auto& q : split.positions)
                    nearest = std::min(nearest, std::hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]));
                worst = std::max(worst, nearest);
            }
            EXPECT_LT(worst, 1e-9) << layout.name << " x" << k;
        }
    }
}

/// `mesh` without the faces listed (face_uvs kept in step).
QuadMesh without_faces(const QuadMesh& mesh, std::vector<std::size_t> drop) {
    QuadMesh out = mesh;
    std::sort(drop.rbegin(), drop.rend());
    for (const std::size_t f : drop) {
        out.faces.erase(out.faces.begin() + static_cast<std::ptrdiff_t>(f));
        out.face_uvs.erase(out.face_uvs.begin() + static_cast<std::ptrdiff_t>(f));
    }
    return out;
}

/// The faces of `mesh`, each turned to start at its smallest vertex, sorted.
std::vector<std::vector<int>> face_set(const QuadMesh& mesh) {
    std::vector<std::vector<int>> faces = mesh.faces;
    for (auto& f : faces) std::rotate(f.begin(), std::min_element(f.begin(), f.end()), f.end());
    std::sort(faces.begin(), faces.end());
    return faces;
}

/// Per vertex of `mesh`, the faces round it, in face order.
std::vector<std::vector<std::size_t>> faces_around(const QuadMesh& mesh) {
    std::vector<std::vector<std::size_t>> around(mesh.positions.size());
    for (std::size_t f = 0; f < mesh.faces.size(); ++f)
        for (const int v : mesh.faces[f]) around[static_cast<std::size_t>(v)].push_back(f);
    return around;
}

/// A torus, an icosahedron (valence-5 singularities) and a disk (a boundary), each with its map
/// (3 quads per layout edge, on the grid) and its valid mesh.
struct LayoutMesh {
    QuadLayout layout;
    Input in;
    QuadMesh mesh;
};
std::vector<LayoutMesh> layout_meshes() {
    std::vector<LayoutMesh> out;
    for (const QuadLayout& layout : {torus_layout(), icosahedron_layout(), disk_layout(3)}) {
        Input in = make_map(layout, 3, 3);
        QuadMesh mesh = extract_valid(in).mesh;
        out.push_back({layout, std::move(in), std::move(mesh)});
    }
    return out;
}

/// The first vertex with four faces whose faces' corners all have four faces too (away from
/// singularities and the boundary), given the faces round each vertex; SIZE_MAX if none.
std::size_t inner_vertex(const QuadMesh& mesh, const std::vector<std::vector<std::size_t>>& around) {
    for (std::size_t v = 0; v < around.size(); ++v) {
        bool inner = around[v].size() == 4;
        for (const std::size_t f : around[v])
            for (const int u : mesh.faces[f]) inner = inner && around[static_cast<std::size_t>(u)].size() == 4;
        if (inner) return v;
    }
    return SIZE_MAX;
}

TEST(CloseHoles, TheCellsAHoleLostComeBackAndNothingElse) {
    // A valid mesh with one face, or two faces side by side, taken out: the hole is closed by
    // exactly those faces (the checker passes the mesh again). A hole round a vertex (its four
    // faces taken out) is left open: the grid point inside has no vertex on the rim.
    for (const LayoutMesh& made : layout_meshes()) {
        const QuadLayout& layout = made.layout;
        const Input& in = made.in;
        const QuadMesh& mesh = made.mesh;
        // An interior vertex with four faces, none on the input's boundary, and two faces sharing an edge.
        const std::vector<std::vector<std::size_t>> around = faces_around(mesh);
        const std::size_t centre = inner_vertex(mesh, around);
        ASSERT_NE(centre, SIZE_MAX) << layout.name;
        const std::size_t a = around[centre][0];
        std::size_t b = SIZE_MAX; // a neighbour of a across an edge at the centre
        for (const std::size_t f : around[centre]) {
            int shared = 0;
            for (const int u : mesh.faces[f]) shared += std::count(mesh.faces[a].begin(), mesh.faces[a].end(), u) > 0;
            if (f != a && shared == 2) b = f;
        }
        ASSERT_NE(b, SIZE_MAX) << layout.name;
        for (const std::vector<std::size_t>& drop : {std::vector<std::size_t>{a}, std::vector<std::size_t>{a, b}}) {
            QuadMesh holed = without_faces(mesh, drop);
            EXPECT_FALSE(verify(in, holed).valid) << layout.name;
            const std::vector<Defect> closed = detail::close_holes(in, holed);
            ASSERT_EQ(closed.size(), 1u) << layout.name;
            EXPECT_EQ(closed[0].kind, DefectKind::HoleClosed);
            EXPECT_EQ(face_set(holed), face_set(mesh)) << layout.name << ", " << drop.size() << " faces";
            const VerifyResult v = verify(in, holed);
            EXPECT_TRUE(v.valid) << layout.name << ": " << (v.violations.empty() ? "" : v.violations[0].message);
        }
        QuadMesh round_vertex = without_faces(mesh, around[centre]);
        EXPECT_TRUE(detail::close_holes(in, round_vertex).empty()) << layout.name;
        EXPECT_EQ(round_vertex.faces.size(), mesh.faces.size() - 4) << layout.name;
        // A face at a singularity (not four faces round it): its rim closes only as the
        // singularity's fan winds, whichever reading is tried first.
        bool at_singularity = false;
        for (std::size_t v = 0; v < around.size() && !at_singularity; ++v) {
            if (around[v].size() == 4 || around[v].empty()) continue;
            if (mesh.provenance[v].kind != QVertexKind::Vertex) continue;
            bool inner = true; // every corner of the face's neighbourhood away from the boundary
            for (const std::size_t f : around[v])
                for (const int u : mesh.faces[f]) inner = inner && around[static_cast<std::size_t>(u)].size() >= 3;
            if (!inner || layout.name == "disk") continue;
            at_singularity = true;
            for (const bool wound_first : {false, true}) {
                QuadMesh holed = without_faces(mesh, {around[v][0]});
                ASSERT_EQ(detail::close_holes(in, holed, wound_first).size(), 1u) << layout.name << " vertex " << v;
                EXPECT_EQ(face_set(holed), face_set(mesh)) << layout.name << " vertex " << v;
            }
        }
        // The icosahedron's valence-5 singularities carry vertices of the mesh.
        EXPECT_EQ(at_singularity, layout.name.find("icosahedron") != std::string::npos) << layout.name;
        // A face on the input's boundary: taken out, it leaves a notch in the boundary, not a hole.
        for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
            bool on_boundary = false;
            for (const int u : mesh.faces[f])
                on_boundary = on_boundary || around[static_cast<std::size_t>(u)].size() < 3;
            if (!on_boundary) continue;
            QuadMesh notched = without_faces(mesh, {f});
            EXPECT_TRUE(detail::close_holes(in, notched).empty()) << layout.name << " face " << f;
            break;
        }
    }
}

/// `mesh`'s positions and faces alone (no provenance), its vertices no face uses left out.
QuadMesh compacted(const QuadMesh& mesh) {
    QuadMesh bare;
    std::vector<int> index(mesh.positions.size(), -1);
    for (const auto& f : mesh.faces) {
        bare.faces.push_back(f);
        for (int& v : bare.faces.back()) {
            int& i = index[static_cast<std::size_t>(v)];
            if (i < 0) {
                i = static_cast<int>(bare.positions.size());
                bare.positions.push_back(mesh.positions[static_cast<std::size_t>(v)]);
            }
            v = i;
        }
    }
    return bare;
}

/// Whether `mesh`'s faces, without its provenance, make an all-quad, manifold, consistently
/// oriented surface of the input's topology (the checker's first part, locating nothing), its
/// vertices no face uses left out.
bool topology_kept(const Input& in, const QuadMesh& mesh) {
    VerifyOptions topology_only;
    topology_only.locate = false;
    return verify(in, compacted(mesh), topology_only).valid;
}

/// The rim a HoleFilled explanation names (its output vertices, in order).
std::vector<int> named_rim(const Defect& d) {
    std::vector<int> rim;
    std::istringstream named(d.message.substr(d.message.find("output vertices ") + 16));
    for (int v = 0; named >> v;) rim.push_back(v);
    return rim;
}

/// Over the vertices of `filled`'s patch (the faces past those of `holed`), the sum of the
/// differences between their face counts and four.
int patch_difference(const QuadMesh& holed, const QuadMesh& filled) {
    std::map<int, int> faces;
    for (std::size_t f = holed.faces.size(); f < filled.faces.size(); ++f)
        for (const int v : filled.faces[f]) faces[v] = 0;
    for (const auto& f : filled.faces)
        for (const int v : f)
            if (faces.count(v)) ++faces[v];
    int sum = 0;
    for (const auto& [v, n] : faces) sum += std::abs(n - 4);
    return sum;
}

/// By brute force, the least sum of differences from four of the face counts of the rim `filled`
/// names, over every quadrangulation of it (every quad (i, a, b, j) on a side (i, j), recursively).
int least_difference(const QuadMesh& holed, const Defect& filled) {
    const std::vector<int> rim = named_rim(filled);
    const int n = static_cast<int>(rim.size());
    std::vector<int> corners(static_cast<std::size_t>(n), 0);
    for (const auto& f : holed.faces)
        for (const int v : f)
            for (int i = 0; i < n; ++i) corners[static_cast<std::size_t>(i)] += v == rim[static_cast<std::size_t>(i)];
    int best = INT_MAX;
    std::vector<int> added(static_cast<std::size_t>(n), 0);
    std::vector<std::pair<int, int>> pending{{0, n - 1}};
    std::function<void()> search = [&] {
        if (pending.empty()) {
            int sum = 0;
            for (int i = 0; i < n; ++i)
                sum += std::abs(corners[static_cast<std::size_t>(i)] + added[static_cast<std::size_t>(i)] - 4);
            best = std::min(best, sum);
            return;
        }
        const auto [i, j] = pending.back();
        pending.pop_back();
        if (j - i == 1) {
            search();
        } else {
            for (int a = i + 1; a < j; a += 2)
                for (int b = a + 1; b < j; b += 2) {
                    for (const int v : {i, a, b, j}) ++added[static_cast<std::size_t>(v)];
                    pending.insert(pending.end(), {{i, a}, {a, b}, {b, j}});
                    search();
                    pending.resize(pending.size() - 3);
                    for (const int v : {i, a, b, j}) --added[static_cast<std::size_t>(v)];
                }
        }
        pending.emplace_back(i, j);
    };
    search();
    return best;
}

TEST(FillHoles, AHoleNoCellsCloseIsFilledFromItsRimAndTheCheckerStillJudgesIt) {
    // The four faces round an interior vertex taken out: the rim of eight vertices encloses a grid
    // point with no vertex, so no cells close it; fill_holes joins rim vertices with three quads
    // (no new vertex). The surface is whole again, but the map requires the cells round that grid
    // point (no fold there): the checker rejects the mesh, and the last resort keeps nothing. A
    // hole that cells close is closed by them alone.
    for (const LayoutMesh& made : layout_meshes()) {
        const QuadLayout& layout = made.layout;
        const Input& in = made.in;
        const QuadMesh& mesh = made.mesh;
        const std::vector<std::vector<std::size_t>> around = faces_around(mesh);
        const std::size_t centre = inner_vertex(mesh, around);
        ASSERT_NE(centre, SIZE_MAX) << layout.name;
        const QuadMesh holed = without_faces(mesh, around[centre]);
        ASSERT_FALSE(topology_kept(in, holed)) << layout.name;
        QuadMesh filled = holed;
        const std::vector<Defect> done = detail::fill_holes(in, filled);
        ASSERT_EQ(done.size(), 1u) << layout.name;
        EXPECT_EQ(done[0].kind, DefectKind::HoleFilled) << layout.name;
        EXPECT_EQ(filled.positions.size(), mesh.positions.size()) << layout.name;
        ASSERT_EQ(filled.faces.size(), holed.faces.size() + 3) << layout.name;
        EXPECT_EQ(filled.face_uvs.size(), filled.faces.size()) << layout.name;
        // Every corner of the patch is a vertex of the rim the explanation names (eight of them).
        std::set<int> rim;
        const std::size_t at = done[0].message.find("output vertices ");
        ASSERT_NE(at, std::string::npos) << done[0].message;
        std::istringstream named(done[0].message.substr(at + 16));
        for (int v = 0; named >> v;) rim.insert(v);
        EXPECT_EQ(rim.size(), 8u) << done[0].message;
        EXPECT_EQ(rim.count(static_cast<int>(centre)), 0u) << done[0].message;
        for (std::size_t f = holed.faces.size(); f < filled.faces.size(); ++f)
            for (const int v : filled.faces[f])
                EXPECT_EQ(rim.count(v), 1u) << layout.name << ": vertex " << v << " is not on " << done[0].message;
        EXPECT_TRUE(topology_kept(in, filled)) << layout.name;
        // No diagonal of the patch is an edge of the mesh already.
        std::set<std::pair<int, int>> edges;
        for (std::size_t f = 0; f < holed.faces.size(); ++f)
            for (std::size_t k = 0; k < 4; ++k) {
                const int a = holed.faces[f][k], b = holed.faces[f][(k + 1) % 4];
                edges.insert({std::min(a, b), std::max(a, b)});
            }
        int new_edges = 0;
        for (std::size_t f = holed.faces.size(); f < filled.faces.size(); ++f)
            for (std::size_t k = 0; k < 4; ++k) {
                const int a = filled.faces[f][k], b = filled.faces[f][(k + 1) % 4];
                new_edges += edges.count({std::min(a, b), std::max(a, b)}) == 0;
            }
        EXPECT_EQ(new_edges, 2 * 2) << layout.name << ": two diagonals, each a side of two quads";
        // The map requires the cells the patch does not follow: the grid point inside has no
        // vertex (the mesh judged without its provenance, the vertex no face uses left out).
        const std::vector<Violation> judged = verify(in, compacted(filled)).violations;
        EXPECT_TRUE(std::any_of(judged.begin(), judged.end(),
                                [](const Violation& v) { return v.kind == ViolationKind::GridPointNotCovered; }))
            << layout.name << ": " << judged.size() << " violations";
        Result attempt;
        attempt.mesh = holed;
        attempt.check = verify(in, holed);
        ASSERT_FALSE(attempt.check.valid) << layout.name;
        EXPECT_FALSE(detail::fill_holes_if_accepted(in, Options{}, attempt)) << layout.name;
        EXPECT_EQ(face_set(attempt.mesh), face_set(holed)) << layout.name;
        EXPECT_FALSE(attempt.check.valid) << layout.name;
        // The patch leaves the rim's face counts as near their four as any quadrangulation can.
        EXPECT_EQ(patch_difference(holed, filled), least_difference(holed, done[0])) << layout.name;
        // On the torus (flat, no singularity), the 4 x 4 faces round the centre out: a rim of 16,
        // whose 7,752 quadrangulations the test judges all; and the 6 x 6 faces: a rim of 24
        // vertices, past what close_holes closes (8.4 million quadrangulations), filled.
        if (layout.name.find("torus") != std::string::npos) {
            std::set<std::size_t> block(around[centre].begin(), around[centre].end());
            for (int ring = 1; ring < 3; ++ring) {
                if (ring == 2) {
                    QuadMesh sixteen = without_faces(mesh, {block.begin(), block.end()});
                    const QuadMesh before = sixteen;
                    const std::vector<Defect> d = detail::fill_holes(in, sixteen);
                    ASSERT_EQ(d.size(), 1u) << layout.name;
                    EXPECT_EQ(patch_difference(before, sixteen), least_difference(before, d[0])) << layout.name;
                }
                std::set<std::size_t> grown = block;
                for (const std::size_t f : block)
                    for (const int u : mesh.faces[f])
                        grown.insert(around[static_cast<std::size_t>(u)].begin(),
                                     around[static_cast<std::size_t>(u)].end());
                block = std::move(grown);
            }
            ASSERT_EQ(block.size(), 36u) << layout.name;
            QuadMesh big = without_faces(mesh, {block.begin(), block.end()});
            const std::size_t before = big.faces.size();
            const std::vector<Defect> big_done = detail::fill_holes(in, big);
            ASSERT_EQ(big_done.size(), 1u) << layout.name;
            EXPECT_EQ(big_done[0].kind, DefectKind::HoleFilled) << layout.name;
            EXPECT_EQ(big.faces.size(), before + 11) << layout.name << ": (24 - 2) / 2 quads";
            EXPECT_TRUE(topology_kept(in, big)) << layout.name;
        }
        // One face out: its cell closes the hole, and nothing is filled.
        QuadMesh one = without_faces(mesh, {around[centre][0]});
        const std::vector<Defect> closed = detail::fill_holes(in, one);
        ASSERT_EQ(closed.size(), 1u) << layout.name;
        EXPECT_EQ(closed[0].kind, DefectKind::HoleClosed) << layout.name;
        EXPECT_EQ(face_set(one), face_set(mesh)) << layout.name;
    }
}

/// Whether stage `name` ran (has a time) in the report.
bool stage_ran(const Report& report, const std::string& name) {
    return std::any_of(report.stage_seconds.begin(), report.stage_seconds.end(),
                       [&](const auto& entry) { return entry.first == name; });
}

TEST(Mend, AHoleIsClosedUnlessAFaceNoStepChangesIsWrong) {
    // A valid mesh with one face taken out: mending closes the hole and the checker accepts it.
    // With another face's local UVs spoiled too (no unit square: neither step changes an existing
    // face's local UVs), no mended mesh could pass: nothing is tried, the mesh stays as it is.
    for (const LayoutMesh& made : layout_meshes()) {
        const QuadLayout& layout = made.layout;
        const Input& in = made.in;
        const std::vector<std::vector<std::size_t>> around = faces_around(made.mesh);
        std::size_t inner = SIZE_MAX; // a face none of whose corners is on a boundary
        for (std::size_t f = 0; f < made.mesh.faces.size() && inner == SIZE_MAX; ++f) {
            bool ok = true;
            for (const int u : made.mesh.faces[f]) ok = ok && around[static_cast<std::size_t>(u)].size() == 4;
            if (ok) inner = f;
        }
        ASSERT_NE(inner, SIZE_MAX) << layout.name;
        const QuadMesh holed = without_faces(made.mesh, {inner});
        for (const bool spoiled : {false, true}) {
            const std::string about = layout.name + (spoiled ? ", a face's local UVs spoiled" : "");
            Result attempt;
            attempt.mesh = holed;
            if (spoiled) attempt.mesh.face_uvs[inner == 0 ? 1 : 0] = {{0, 0}, {2, 0}, {2, 1}, {0, 1}};
            attempt.check = verify(in, attempt.mesh);
            ASSERT_FALSE(attempt.check.valid) << about;
            detail::StageTimer timer(attempt.report);
            detail::mend_if_accepted(in, false, VerifyOptions{}, timer, attempt);
            EXPECT_EQ(attempt.check.valid, !spoiled) << about;
            EXPECT_EQ(stage_ran(attempt.report, "close_holes"), !spoiled) << about;
            EXPECT_EQ(face_set(attempt.mesh), face_set(spoiled ? holed : made.mesh)) << about;
        }
    }
}

/// Whether `got` is `want` with its vertices renamed: the same number of faces, and one
/// one-to-one renaming taking each face of `got`, corner by corner, to the face of `want` at the
/// same index.
bool same_up_to_renaming(const QuadMesh& got, const QuadMesh& want) {
    if (got.faces.size() != want.faces.size()) return false;
    std::map<int, int> to, from;
    for (std::size_t f = 0; f < got.faces.size(); ++f) {
        if (got.faces[f].size() != want.faces[f].size()) return false;
        for (std::size_t k = 0; k < got.faces[f].size(); ++k) {
            const int g = got.faces[f][k], w = want.faces[f][k];
            if (to.emplace(g, w).first->second != w || from.emplace(w, g).first->second != g) return false;
        }
    }
    return true;
}

TEST(SeparateSheets, TwoSheetsJoinedAtAnEdgeComeApartAndNothingElse) {
    // A valid mesh whose edge (c, d) is glued onto a far edge (a, b) that runs the same way (c
    // renamed a, d renamed b): the edge has four face sides (three on the disk, whose edge (a, b)
    // is on its boundary) and each end two fans. Cutting it (each end split into its fans) gives
    // the mesh back, up to the names of its vertices, whichever end goes first; so does a path of
    // two edges glued onto another. A valid mesh is left as it is.
    for (const LayoutMesh& made : layout_meshes()) {
        const QuadLayout& layout = made.layout;
        const Input& in = made.in;
        const QuadMesh& mesh = made.mesh;
        for (const bool larger_end_first : {false, true}) {
            QuadMesh same = mesh;
            EXPECT_TRUE(detail::separate_sheets(in, same, larger_end_first).empty()) << layout.name;
            EXPECT_EQ(same.faces, mesh.faces) << layout.name;
            EXPECT_EQ(same.positions.size(), mesh.positions.size()) << layout.name;
        }
        const std::vector<std::vector<std::size_t>> around = faces_around(mesh);
        // Vertices of faces round a vertex: its ring.
        const auto ring = [&](int v) {
            std::set<int> out;
            for (const std::size_t f : around[static_cast<std::size_t>(v)])
                out.insert(mesh.faces[f].begin(), mesh.faces[f].end());
            return out;
        };
        // A path of one or two edges glued onto another: the first corners of face 0 (a, b, and
        // g) and those of a face whose corners' rings miss theirs, each corner with three faces or
        // more. Two edges meet at b: a vertex that ends two such edges is split last, once its
        // edges have been cut at their other ends (its own sheet is not torn).
        for (const std::size_t length : {1u, 2u}) {
            const std::vector<int> path(mesh.faces[0].begin(), mesh.faces[0].begin() + length + 1);
            std::set<int> near;
            for (const int v : path)
                for (const int u : ring(v)) near.insert(u);
            std::vector<int> other;
            for (std::size_t f = 1; f < mesh.faces.size() && other.empty(); ++f) {
                bool apart = true; // no vertex of their rings in those of the path
                for (std::size_t i = 0; i <= length; ++i) {
                    const int x = mesh.faces[f][i];
                    apart = apart && around[static_cast<std::size_t>(x)].size() >= 3;
                    for (const int u : ring(x)) apart = apart && !near.count(u);
                }
                if (apart) other.assign(mesh.faces[f].begin(), mesh.faces[f].begin() + length + 1);
            }
            ASSERT_FALSE(other.empty()) << layout.name;
            const bool disk = layout.name == "disk"; // face 0 on its boundary: one face side there
            QuadMesh glued = mesh;
            for (auto& f : glued.faces)
                for (int& v : f)
                    for (std::size_t i = 0; i <= length; ++i)
                        if (v == other[i]) {
                            v = path[i];
                            break;
                        }
            EXPECT_FALSE(verify(in, glued).valid) << layout.name;
            for (const bool larger_end_first : {false, true}) {
                const std::string about = layout.name + ", " + std::to_string(length) + " edges, larger end first " +
                                          std::to_string(larger_end_first);
                QuadMesh cut = glued;
                std::vector<std::vector<int>> groups;
                const std::vector<Defect> separated = detail::cut_joined_edges(cut, larger_end_first, groups);
                ASSERT_EQ(separated.size(), length) << about;
                EXPECT_EQ(separated[0].kind, DefectKind::SheetsSeparated);
                if (length == 1) {
                    const int a = path[0], b = path[1];
                    EXPECT_NE(separated[0].message.find("(" + std::to_string(std::min(a, b)) + ", " +
                                                        std::to_string(std::max(a, b)) + ") had " +
                                                        std::to_string(disk ? 3 : 4) + " face sides"),
                              std::string::npos)
                        << separated[0].message;
                }
                EXPECT_EQ(cut.positions.size(), mesh.positions.size() + length + 1) << about;
                EXPECT_EQ(cut.provenance.size(), cut.positions.size()) << about;
                EXPECT_TRUE(same_up_to_renaming(cut, mesh)) << about;
                // Every vertex of the path split, each into two: it, then its copy.
                ASSERT_EQ(groups.size(), length + 1) << about;
                for (const auto& group : groups) EXPECT_EQ(group.size(), 2u) << about;
                // No preimage of a path vertex's grid point lies near the other path's fans: each
                // copy would stay on its vertex, where the sheets stay joined in space, and
                // separate_sheets refuses.
                QuadMesh refused = glued;
                EXPECT_TRUE(detail::separate_sheets(in, refused, larger_end_first).empty()) << about;
            }
        }
    }
}
} // namespace
} // namespace qex::testing
