// Stage-level unit tests of the ladder: coarsening, and the holes a rejected mesh's face walks
// left closed by their cells or filled from their rims.
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
    const Input odd = make_map(cube_layout(), 1, 2);
    EXPECT_FALSE(detail::map_divisible_by(sanitized(odd), {}, 2, origin));
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

/// The patch fill_holes laid (faces from holed.faces.size() on): every corner on the rim of eight
/// vertices `done` names, the hole's centre not among them, and two new diagonals.
void expect_patch_on_rim(const Input& in, const QuadMesh& holed, const QuadMesh& filled, const Defect& done,
                         std::size_t centre, const std::string& name) {
    std::set<int> rim;
    const std::size_t at = done.message.find("output vertices ");
    ASSERT_NE(at, std::string::npos) << done.message;
    std::istringstream named(done.message.substr(at + 16));
    for (int v = 0; named >> v;) rim.insert(v);
    EXPECT_EQ(rim.size(), 8u) << done.message;
    EXPECT_EQ(rim.count(static_cast<int>(centre)), 0u) << done.message;
    for (std::size_t f = holed.faces.size(); f < filled.faces.size(); ++f)
        for (const int v : filled.faces[f])
            EXPECT_EQ(rim.count(v), 1u) << name << ": vertex " << v << " is not on " << done.message;
    EXPECT_TRUE(topology_kept(in, filled)) << name;
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
    EXPECT_EQ(new_edges, 2 * 2) << name << ": two diagonals, each a side of two quads";
}

/// On the torus (flat, no singularity), the 4 x 4 faces round the centre out: a rim of 16,
/// whose 7,752 quadrangulations the test judges all; and the 6 x 6 faces: a rim of 24
/// vertices, past what close_holes closes (8.4 million quadrangulations), filled.
void expect_torus_holes_filled(const Input& in, const QuadMesh& mesh,
                               const std::vector<std::vector<std::size_t>>& around, std::size_t centre,
                               const std::string& name) {
    std::set<std::size_t> block(around[centre].begin(), around[centre].end());
    for (int ring = 1; ring < 3; ++ring) {
        if (ring == 2) {
            QuadMesh sixteen = without_faces(mesh, {block.begin(), block.end()});
            const QuadMesh before = sixteen;
            const std::vector<Defect> d = detail::fill_holes(in, sixteen);
            ASSERT_EQ(d.size(), 1u) << name;
            EXPECT_EQ(patch_difference(before, sixteen), least_difference(before, d[0])) << name;
        }
        std::set<std::size_t> grown = block;
        for (const std::size_t f : block)
            for (const int u : mesh.faces[f])
                grown.insert(around[static_cast<std::size_t>(u)].begin(), around[static_cast<std::size_t>(u)].end());
        block = std::move(grown);
    }
    ASSERT_EQ(block.size(), 36u) << name;
    QuadMesh big = without_faces(mesh, {block.begin(), block.end()});
    const std::size_t before = big.faces.size();
    const std::vector<Defect> big_done = detail::fill_holes(in, big);
    ASSERT_EQ(big_done.size(), 1u) << name;
    EXPECT_EQ(big_done[0].kind, DefectKind::HoleFilled) << name;
    EXPECT_EQ(big.faces.size(), before + 11) << name << ": (24 - 2) / 2 quads";
    EXPECT_TRUE(topology_kept(in, big)) << name;
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
        expect_patch_on_rim(in, holed, filled, done[0], centre, layout.name);
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
        if (layout.name.find("torus") != std::string::npos)
            expect_torus_holes_filled(in, mesh, around, centre, layout.name);
        // One face out: its cell closes the hole, and nothing is filled.
        QuadMesh one = without_faces(mesh, {around[centre][0]});
        const std::vector<Defect> closed = detail::fill_holes(in, one);
        ASSERT_EQ(closed.size(), 1u) << layout.name;
        EXPECT_EQ(closed[0].kind, DefectKind::HoleClosed) << layout.name;
        EXPECT_EQ(face_set(one), face_set(mesh)) << layout.name;
    }
}

} // namespace
} // namespace qex::testing
