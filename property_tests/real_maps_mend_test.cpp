// Real maps from ../shared (skipped with a message where absent): a later rung's mesh, holes
// closed, sheets separated, near reverses cancelled, cone fans opened, and broken meshes rejected.

#include "real_maps_support.h"

#include "ladder/ladder.h"
#include "map_transforms.h"
#include "pipeline.h"
#include "result_checks.h"
#include "test_support.h"
#include "transform_checks.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <optional>
#include <random>
#include <set>
#include <tuple>

namespace qex::testing {
namespace {

/// cheburashka_miq_20's mesh comes from a relaxed rung; the repaired rung before it proved a region
/// has no fold-free map. Those proofs hold of the map, so the relaxed mesh's report carries them,
/// the same as the repaired rung named them, first among its explanations.
TEST(RealMaps, ALaterRungsMeshCarriesTheRepairsProofs) {
    Input in;
    if (const std::string why = read_real_map("miq", "cheburashka_miq_20", in); !why.empty()) GTEST_SKIP() << why;
    const Result r = extract(in);
    ASSERT_TRUE(r.ok()) << r.error.message;
    ASSERT_TRUE(r.check.valid);
    ASSERT_TRUE(detail::relaxed_rung(r.report.rung)) << r.report.rung << ": pick another case";
    const auto proofs_of = [](const Result& x) {
        std::vector<std::string> out;
        for (const Defect& d : x.report.explanations)
            if (detail::is_proof(d.kind)) out.push_back(std::string(to_string(d.kind)) + ": " + d.message);
        return out;
    };
    const std::vector<std::string> carried = proofs_of(r), named = proofs_of(first_rung(in));
    ASSERT_FALSE(named.empty()) << "the repaired rung proves nothing: pick another case";
    EXPECT_EQ(carried, named);
    const std::array<int, 4> count = expect_proofs_placed(in, r);
    EXPECT_EQ(static_cast<std::size_t>(count[0] + count[1] + count[2] + count[3]), named.size());
    ASSERT_FALSE(r.report.explanations.empty());
    EXPECT_TRUE(detail::is_proof(r.report.explanations.front().kind));
}

/// cheburashka_miq_40: next to a fold-over the repair leaves, two traces claim one q-port and the
/// face walks round the lost edge run open, leaving one cell of a closed surface out (a boundary
/// loop, Euler characteristic 1). Stage close_holes lays the hole's rim out in the grid and
/// closes it with that cell: the mesh is valid at the map's own scale (refinement was needed
/// before), passes the oracle without provenance, and names the hole.
TEST(RealMaps, AHoleThatFaceWalksLeftIsClosedAtTheMapsOwnScale) {
    const fs::path path = fs::path(QEX_SHARED_DIR) / "meshes" / "miq" / "cheburashka_miq_40_param.obj";
    Input in;
    if (!read_obj(path.string(), in).ok()) GTEST_SKIP() << "no " << path;
    const Result r = extract(in);
    ASSERT_TRUE(r.ok()) << r.error.message;
    ASSERT_TRUE(r.check.valid) << (r.check.violations.empty() ? "" : r.check.violations[0].message);
    EXPECT_EQ(r.mesh.grid_scale, 1);
    const auto closed = std::count_if(r.report.explanations.begin(), r.report.explanations.end(),
                                      [](const Defect& d) { return d.kind == DefectKind::HoleClosed; });
    EXPECT_GE(closed, 1);
    // Quads within the area the fold-overs left as given may take.
    const auto quads = static_cast<double>(r.mesh.faces.size());
    EXPECT_LE(quads, std::round(r.report.signed_uv_area));
    EXPECT_GE(quads, 0.99 * r.report.signed_uv_area);
    expect_bare_valid(in, r.mesh, path);
}

/// cow_miq_40: next to a fold-over, merging clones joins faces of two sheets at one edge (four
/// face sides, two fans round each end). Stage separate_sheets splits an end into a vertex per
/// fan, each on its own sheet: cow_miq_40 is valid at its own scale, the cut named, every edge
/// of two face sides (welded by position too), and valid without provenance too. (cow_miq_20
/// needed the cut too while sanitizing snapped a vertex a fold winds twice; it no longer does.)
/// duck_qc_8 with its UVs x4 too (valid at its own scale): there the
/// grid point of one end has a single preimage, so splitting it left two vertices at one point,
/// joined in space; that candidate is dropped, and the other end is split instead.
TEST(RealMaps, SheetsJoinedAtAnEdgeAreSeparated) {
    for (const auto& [folder, name, uv_scale, scale] :
         {std::tuple<const char*, const char*, int, int>{"miq-more", "cow_miq_40", 1, 1},
          {"paper", "duck_qc_8", 4, 1}}) {
        const fs::path path = fs::path(QEX_SHARED_DIR) / "meshes" / folder / (std::string(name) + "_param.obj");
        Input in;
        if (!read_obj(path.string(), in).ok()) GTEST_SKIP() << "no " << path;
        ASSERT_EQ(transforms::scale_uvs(in, uv_scale), 0);
        const Result r = extract(in);
        ASSERT_TRUE(r.ok()) << r.error.message;
        ASSERT_TRUE(r.check.valid) << name << ": " << (r.check.violations.empty() ? "" : r.check.violations[0].message);
        EXPECT_EQ(r.mesh.grid_scale, scale) << name;
        EXPECT_EQ(result_inconsistency(in, r), "") << name;
        const auto cut = std::count_if(r.report.explanations.begin(), r.report.explanations.end(),
                                       [](const Defect& d) { return d.kind == DefectKind::SheetsSeparated; });
        EXPECT_GE(cut, 1) << name;
        // Every edge has two face sides, also with the vertices welded by position: no two
        // vertices coincide (a vertex split lies on its own sheet's preimage).
        std::map<std::array<double, 3>, int> welded;
        for (const auto& p : r.mesh.positions) welded.emplace(p, static_cast<int>(welded.size()));
        EXPECT_EQ(welded.size(), r.mesh.positions.size()) << name;
        std::map<std::pair<int, int>, int> sides;
        for (const auto& f : r.mesh.faces)
            for (std::size_t k = 0; k < f.size(); ++k)
                ++sides[std::minmax(welded.at(r.mesh.positions[static_cast<std::size_t>(f[k])]),
                                    welded.at(r.mesh.positions[static_cast<std::size_t>(f[(k + 1) % f.size()])]))];
        for (const auto& [edge, n] : sides) EXPECT_EQ(n, 2) << name << ": edge " << edge.first << " " << edge.second;
        expect_bare_valid(in, r.mesh, path);
    }
}

/// duck_miq_28 with its UVs x4 (655 flipped triangles): a face walk runs clockwise over a fold's
/// reversed sheet beside a counter-clockwise face with its other three corners in reverse
/// order, the fourth a clone of the same grid point on another sheet. Stage merge_vertices
/// merges the clones and cancels the pair, as it does a ghost pair: the mesh is valid at the
/// map's own scale with exactly the signed area's quads (320; 308 came from the map at x2 split
/// before), also without provenance, and the same whatever the input's order. Clockwise pairs
/// are not cancelled: two clockwise faces with three corners in common are mirror images, and
/// merging their fourth corners joined two grid points (duck_miq_16 x8 then had 3 quads more
/// than its area).
TEST(RealMaps, ClockwiseFacesOverAFoldCancelWithTheirNearReverses) {
    const fs::path path = fs::path(QEX_SHARED_DIR) / "meshes" / "paper" / "duck_miq_28_param.obj";
    Input in;
    if (!read_obj(path.string(), in).ok()) GTEST_SKIP() << "no " << path;
    ASSERT_EQ(transforms::scale_uvs(in, 4), 0);
    const Result r = extract(in);
    ASSERT_TRUE(r.ok()) << r.error.message;
    ASSERT_TRUE(r.check.valid) << (r.check.violations.empty() ? "" : r.check.violations[0].message);
    EXPECT_GT(r.report.near_ghost_faces_cancelled, 0);
    EXPECT_EQ(r.mesh.grid_scale, 1);
    EXPECT_EQ(r.report.coarsening, 1);
    EXPECT_EQ(static_cast<std::int64_t>(r.mesh.faces.size()), std::llround(r.report.signed_uv_area));
    const auto near = std::count_if(r.report.explanations.begin(), r.report.explanations.end(), [](const Defect& d) {
        return d.kind == DefectKind::GhostFacesCancelled && d.message.find("fourth corners") != std::string::npos;
    });
    EXPECT_EQ(2 * near, r.report.near_ghost_faces_cancelled);
    EXPECT_EQ(result_inconsistency(in, r), "");
    expect_bare_valid(in, r.mesh, path);
    Input shuffled = in;
    transforms::shuffle(shuffled, 1);
    const Result s = extract(shuffled);
    ASSERT_TRUE(s.check.valid) << "shuffled";
    EXPECT_EQ(mesh_difference(s.mesh, r.mesh, 0.0), "") << "shuffled";
}

/// duck_miq_8 with its UVs x 16: folds close the fans of valence-5 singularities (a run of
/// flipped triangles in each, Algorithm 8 counting the turn the signed angles lack). Untangled as
/// given, such a region keeps the cone a turn short and winds a neighbour twice, which the
/// certificate refuses; the repair opens the cone's fan first and keeps it open. Every fold is
/// repaired, no singularity is lost but in named merges of co-located dipoles (four on this map),
/// and the mesh has exactly the signed area's quads.
TEST(RealMaps, FoldsClosingConesFansAreOpened) {
    if (!expect_scaled_map_repaired("duck_miq_8", 16)) GTEST_SKIP() << "no duck_miq_8 in " << QEX_SHARED_DIR;
}

/// Local breaks of the good mesh at face f round vertex x (inside a repaired triangle): a quad
/// dropped, x pinched to the opposite corner, the face reversed; each rejected.
void expect_local_breaks_rejected(const Input& in, const QuadMesh& good, std::size_t f, int x) {
    { // Dropped: a hole.
        QuadMesh m = good;
        m.faces.erase(m.faces.begin() + static_cast<std::ptrdiff_t>(f));
        const VerifyResult v = verify(in, m, with_fold_regions());
        EXPECT_FALSE(v.valid);
        bool hole = false;
        for (const Violation& y : v.violations) hole = hole || y.kind == ViolationKind::BoundaryMismatch;
        EXPECT_TRUE(hole);
    }
    { // Pinched: x glued to the corner opposite it in its face (whose other faces it keeps).
        QuadMesh m = good;
        const auto& q = good.faces[f];
        const std::size_t i = static_cast<std::size_t>(std::find(q.begin(), q.end(), x) - q.begin());
        const int y = q[(i + 2) % 4];
        m.faces.erase(m.faces.begin() + static_cast<std::ptrdiff_t>(f));
        for (auto& face : m.faces)
            for (int& c : face)
                if (c == y) c = x;
        const VerifyResult v = verify(in, m, with_fold_regions());
        EXPECT_FALSE(v.valid);
    }
    { // Flipped: the face reversed (inconsistent orientation with its neighbours).
        QuadMesh m = good;
        std::reverse(m.faces[f].begin(), m.faces[f].end());
        const VerifyResult v = verify(in, m, with_fold_regions());
        EXPECT_FALSE(v.valid);
        bool flipped = false;
        for (const Violation& y : v.violations)
            flipped =
                flipped || y.kind == ViolationKind::InconsistentOrientation || y.kind == ViolationKind::NonManifoldEdge;
        EXPECT_TRUE(flipped) << (v.violations.empty() ? "" : v.violations[0].message);
    }
}

/// Outside the fold-over regions a vertex off its grid point is still named: the vertex farthest
/// (in 3D) from every flipped triangle, slid half way to a neighbour.
void expect_off_grid_vertex_named(const Input& in, const QuadMesh& good) {
    std::vector<std::array<double, 3>> folds;
    for (std::size_t t = 0; t < in.triangles.size(); ++t) {
        const auto &a = in.uvs[3 * t], &b = in.uvs[3 * t + 1], &c = in.uvs[3 * t + 2];
        if ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) >= 0) continue;
        folds.push_back(in.positions[static_cast<std::size_t>(in.triangles[t][0])]);
    }
    ASSERT_FALSE(folds.empty());
    int far = -1;
    double best = -1;
    for (std::size_t v = 0; v < good.positions.size(); ++v) {
        double d = HUGE_VAL;
        for (const auto& p : folds) {
            const auto& x = good.positions[v];
            d = std::min(d,
                         (x[0] - p[0]) * (x[0] - p[0]) + (x[1] - p[1]) * (x[1] - p[1]) + (x[2] - p[2]) * (x[2] - p[2]));
        }
        if (d > best) best = d, far = static_cast<int>(v);
    }
    std::size_t g = 0;
    while (std::find(good.faces[g].begin(), good.faces[g].end(), far) == good.faces[g].end()) ++g;
    const auto& q = good.faces[g];
    const int next = q[(static_cast<std::size_t>(std::find(q.begin(), q.end(), far) - q.begin()) + 1) % 4];
    QuadMesh m = good;
    for (int k = 0; k < 3; ++k)
        m.positions[static_cast<std::size_t>(far)][k] = 0.5 * (good.positions[static_cast<std::size_t>(far)][k] +
                                                               good.positions[static_cast<std::size_t>(next)][k]);
    const VerifyResult v = verify(in, m, with_fold_regions());
    EXPECT_FALSE(v.valid);
    bool named = false;
    for (const Violation& y : v.violations)
        named = named ||
                ((y.kind == ViolationKind::NotOnGridPoint || y.kind == ViolationKind::OffSurface) && y.element == far);
    EXPECT_TRUE(named) << "vertex " << far << ": " << (v.violations.empty() ? "" : v.violations[0].message);
}

/// A vertex moved off the surface in a fold-over region is still named.
void expect_off_surface_named(const Input& in, const QuadMesh& good, std::size_t f, int x) {
    // Off the surface: moved by 0.1% of the diagonal along the face's normal direction.
    QuadMesh m = good;
    std::array<double, 3> lo = good.positions[0], hi = lo;
    for (const auto& p : good.positions)
        for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
    const double diag = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                                  (hi[2] - lo[2]) * (hi[2] - lo[2]));
    const auto& q = good.faces[f];
    const auto& a = good.positions[static_cast<std::size_t>(q[0])];
    const auto& b = good.positions[static_cast<std::size_t>(q[1])];
    const auto& c = good.positions[static_cast<std::size_t>(q[2])];
    const std::array<double, 3> e1{b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2{c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    std::array<double, 3> n{e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                            e1[0] * e2[1] - e1[1] * e2[0]};
    const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    ASSERT_GT(len, 0);
    for (int k = 0; k < 3; ++k) m.positions[static_cast<std::size_t>(x)][k] += 1e-3 * diag * n[k] / len;
    const VerifyResult v = verify(in, m, with_fold_regions());
    EXPECT_FALSE(v.valid);
    bool off = false;
    for (const Violation& y : v.violations) off = off || (y.kind == ViolationKind::OffSurface && y.element == x);
    EXPECT_TRUE(off) << (v.violations.empty() ? "" : v.violations[0].message);
}

/// fandisk's repaired output without provenance: a quad dropped, a vertex pinched or a face
/// flipped where the repair moved the map (in a fold-over region, where vertices are judged on
/// the surface only) is still rejected, and a vertex moved off the surface there too; outside
/// the regions a vertex off its grid point still is.
TEST(RealMaps, BrokenMeshInAFoldRegionIsRejected) {
    const fs::path path = fs::path(QEX_SHARED_DIR) / "meshes" / "paper" / "fandisk_param.obj";
    Input in;
    if (!read_obj(path.string(), in).ok()) GTEST_SKIP() << "no " << path;
    const Result r = extract(in);
    ASSERT_TRUE(r.check.valid);
    ASSERT_FALSE(r.mesh.map_repaired.empty()) << "fandisk's map is no longer repaired: pick another map";
    QuadMesh good;
    good.positions = r.mesh.positions;
    good.faces = r.mesh.faces;
    const VerifyResult ok = verify(in, good, with_fold_regions());
    ASSERT_TRUE(ok.valid) << (ok.violations.empty() ? "" : ok.violations[0].message);
    ASSERT_GT(ok.surface_only_vertices, 0);
    // Without the fold-over regions the raw map judges the repaired vertices: off its grid points.
    VerifyOptions raw;
    raw.fold_regions = false;
    EXPECT_FALSE(verify(in, good, raw).valid);
    // A vertex inside a triangle the repair changed (its provenance), and a face at it.
    int x = -1;
    for (std::size_t v = 0; v < r.mesh.provenance.size() && x < 0; ++v) {
        const Provenance& p = r.mesh.provenance[v];
        if (p.kind == QVertexKind::Face &&
            std::binary_search(r.mesh.map_repaired.begin(), r.mesh.map_repaired.end(), p.element))
            x = static_cast<int>(v);
    }
    ASSERT_GE(x, 0);
    std::size_t f = 0;
    while (f < good.faces.size() && std::find(good.faces[f].begin(), good.faces[f].end(), x) == good.faces[f].end())
        ++f;
    ASSERT_LT(f, good.faces.size());
    expect_local_breaks_rejected(in, good, f, x);
    expect_off_grid_vertex_named(in, good);
    expect_off_surface_named(in, good, f, x);
}

} // namespace
} // namespace qex::testing
