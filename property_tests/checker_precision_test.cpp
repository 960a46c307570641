// The checker as an oracle for meshes written with ordinary precision: each of qex's valid
// outputs of the real maps (../shared, skipped where absent; a map whose extraction is not valid
// is skipped), judged as `qex check --grid-scale K` judges it (no provenance, the raw map scaled
// by the output's grid scale, fold-over regions on the surface only), passes in double precision
// (--strict), with positions as %.6g and as float32 values. Its mutations (mutations.h) are
// rejected with the right kind and place, and the coverage check names every cell it requires
// when that cell's face is dropped, and nothing else.
// One ctest test per map (SharedMaps/*, label precision: `ctest -L precision`); all 45 take about
// 65 s of CPU (the rotated edges of a test are judged together, a face apart).
#include "mutations.h"
#include "test_support.h"

#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <map>
#include <set>

namespace qex::testing {
namespace {

namespace fs = std::filesystem;
using Index = std::int64_t;

/// The shared real maps, relative to QEX_SHARED_DIR/meshes ("paper/fandisk_param.obj").
std::vector<std::string> real_maps() {
    std::vector<std::string> out;
    for (const char* sub : {"paper", "miq", "miq-more"}) {
        std::error_code ec;
        for (const auto& e : fs::directory_iterator(fs::path(QEX_SHARED_DIR) / "meshes" / sub, ec))
            if (e.path().extension() == ".obj") out.push_back(std::string(sub) + "/" + e.path().filename().string());
    }
    std::sort(out.begin(), out.end());
    return out;
}

/// The mesh with every coordinate as printf("%.6g") writes it.
QuadMesh printed_6g(QuadMesh m) {
    char buf[32];
    for (auto& p : m.positions)
        for (double& x : p) {
            std::snprintf(buf, sizeof buf, "%.6g", x);
            x = std::strtod(buf, nullptr);
        }
    return m;
}

/// The mesh with every coordinate rounded to a float32 (through a volatile float: with
/// -frounding-math GCC 12 drops the double -> float -> double round trip).
QuadMesh as_float32(QuadMesh m) {
    for (auto& p : m.positions)
        for (double& x : p) {
            volatile float narrow = static_cast<float>(x);
            x = narrow;
        }
    return m;
}

/// Face f of `m` has the corners `cell` in the same cyclic order.
bool is_face(const QuadMesh& m, std::size_t f, const std::vector<Index>& cell) {
    const auto& q = m.faces[f];
    if (q.size() != 4 || cell.size() != 4) return false;
    for (std::size_t s = 0; s < 4; ++s) {
        bool all = true;
        for (std::size_t i = 0; i < 4; ++i) all = all && q[(s + i) % 4] == cell[i];
        if (all) return true;
    }
    return false;
}

/// The corner vertices a GridCellNotCovered violation names.
std::vector<Index> cell_corners(const Violation& x) {
    for (const Place& p : x.places)
        if (p.kind == PlaceKind::Vertex) return p.indices;
    return {};
}

/// Coverage on a correct mesh: the faces are dropped in seven classes (by index mod 7); each
/// GridCellNotCovered then names a dropped face by its corners, no grid point is named (the
/// vertices stay), and the classes together name every cell the check requires once. Returns
/// the faces whose cells are required.
std::vector<std::size_t> drops_are_named(const Input& in, const QuadMesh& good, const VerifyOptions& opt,
                                         Index required) {
    constexpr std::size_t kClasses = 7;
    std::vector<std::size_t> named;
    Index uncovered = 0;
    for (std::size_t j = 0; j < kClasses; ++j) {
        QuadMesh m = good;
        std::vector<std::size_t> dropped;
        m.faces.clear();
        for (std::size_t f = 0; f < good.faces.size(); ++f)
            if (f % kClasses == j)
                dropped.push_back(f);
            else
                m.faces.push_back(good.faces[f]);
        const VerifyResult v = verify(in, m, opt);
        uncovered += v.uncovered_cells;
        // (Undecided where a corner's vertex lies in a fold-over region, on the surface only.)
        for (const Violation& x : v.undecided) uncovered += x.kind == ViolationKind::GridCellNotCovered;
        EXPECT_EQ(v.uncovered_grid_points, 0) << "class " << j;
        for (const Violation& x : v.violations) {
            if (x.kind != ViolationKind::GridCellNotCovered) continue;
            const std::vector<Index> corners = cell_corners(x);
            const auto hit =
                std::find_if(dropped.begin(), dropped.end(), [&](std::size_t f) { return is_face(good, f, corners); });
            EXPECT_NE(hit, dropped.end()) << "class " << j << ": not a dropped face: " << x.message;
            if (hit != dropped.end()) named.push_back(*hit);
        }
    }
    EXPECT_EQ(uncovered, required) << "the required cells, each named once when its face is dropped";
    std::sort(named.begin(), named.end());
    return named;
}

/// What the coverage check caught on one map.
struct Tally {
    Index faces = 0, required = 0, rotations = 0, rotations_located = 0, rotations_rejected = 0;
    Index rotations_face_rejected = 0; ///< of the rejected, by the face check (the others by coverage)
};

/// A quad dropped (a hole, named by its loop), and two neighbouring quads dropped with two
/// opposite corners of their hexagonal hole pinched: each named at its place.
void expect_holes_named(const Input& in, const QuadMesh& good, const VerifyOptions& opt, std::size_t f,
                        const std::vector<int>& q, bool interior) {
    { // Drop a quad: a hole, named by its loop.
        QuadMesh m = good;
        m.faces.erase(m.faces.begin() + static_cast<std::ptrdiff_t>(f));
        const VerifyResult v = verify(in, m, opt);
        EXPECT_FALSE(v.valid);
        std::string said;
        for (const Violation& x : v.violations) said += "\n  " + x.message;
        // (Where the hole touches itself at a vertex, that vertex is named instead.)
        bool pinched = false;
        for (const Violation& x : v.violations) pinched = pinched || x.kind == ViolationKind::NonManifoldVertex;
        if (interior && !pinched) {
            EXPECT_TRUE(names(v, ViolationKind::BoundaryMismatch, PlaceKind::Loop, {q[0], q[1], q[2], q[3]}))
                << "face " << f << said;
        }
        EXPECT_EQ(unplaced(v), "");
    }
    { // Drop two neighbouring quads and pinch two opposite corners of their hexagonal hole: a
        // vertex with two boundary fans.
        const SharedEdge e = shared_edge(good, f);
        ASSERT_GE(e.a, 0);
        QuadMesh hex = good;
        rotate_edge(hex, e); // the same hexagon: face e.f is now (z, w, b, x)
        const int z = hex.faces[e.f][0], x = hex.faces[e.f][3];
        QuadMesh m = good;
        m.faces.erase(m.faces.begin() + static_cast<std::ptrdiff_t>(std::max(e.f, e.g)));
        m.faces.erase(m.faces.begin() + static_cast<std::ptrdiff_t>(std::min(e.f, e.g)));
        merge_into(m, x, z);
        const VerifyResult p = verify(in, m, opt);
        EXPECT_TRUE(names(p, ViolationKind::NonManifoldVertex, PlaceKind::Vertex, {z}));
        EXPECT_TRUE(names(p, ViolationKind::UnreferencedVertex, PlaceKind::Vertex, {x}));
        EXPECT_EQ(unplaced(p), "");
    }
}

/// A quad split into triangles, a quad glued to its reverse, the ends of an edge merged: each
/// named at its place.
void expect_broken_faces_named(const Input& in, const QuadMesh& good, const VerifyOptions& opt, std::size_t f,
                               const std::vector<int>& q) {
    { // Split a quad into two triangles.
        QuadMesh m = good;
        m.faces[f] = {q[0], q[1], q[2]};
        m.faces.push_back({q[0], q[2], q[3]});
        const VerifyResult v = verify(in, m, opt);
        EXPECT_TRUE(names(v, ViolationKind::NotQuad, PlaceKind::Face, {static_cast<Index>(f)}));
        EXPECT_TRUE(names(v, ViolationKind::NotQuad, PlaceKind::Face, {static_cast<Index>(m.faces.size() - 1)}));
        EXPECT_EQ(unplaced(v), "");
    }
    { // Glue a quad to its reverse: an extra component of two faces.
        QuadMesh m = good;
        const auto n = static_cast<int>(m.positions.size());
        for (int x : q) m.positions.push_back(m.positions[static_cast<std::size_t>(x)]);
        const auto f0 = static_cast<Index>(m.faces.size());
        m.faces.push_back({n, n + 1, n + 2, n + 3});
        m.faces.push_back({n + 3, n + 2, n + 1, n});
        const VerifyResult v = verify(in, m, opt);
        EXPECT_TRUE(names(v, ViolationKind::ComponentMismatch, PlaceKind::Face, {f0, f0 + 1}));
        EXPECT_EQ(unplaced(v), "");
    }
    { // Merge the ends of an edge at their average.
        const SharedEdge e = shared_edge(good, f);
        ASSERT_GE(e.a, 0);
        QuadMesh m = good;
        auto& x = m.positions[static_cast<std::size_t>(e.a)];
        const auto& y = good.positions[static_cast<std::size_t>(e.b)];
        for (int k = 0; k < 3; ++k) x[k] = 0.5 * (x[k] + y[k]);
        merge_into(m, e.b, e.a);
        const VerifyResult v = verify(in, m, opt);
        EXPECT_TRUE(names(v, ViolationKind::RepeatedVertex, PlaceKind::Face, {static_cast<Index>(e.f)}));
        EXPECT_TRUE(names(v, ViolationKind::RepeatedVertex, PlaceKind::Face, {static_cast<Index>(e.g)}));
        EXPECT_TRUE(names(v, ViolationKind::UnreferencedVertex, PlaceKind::Vertex, {e.b}));
        EXPECT_EQ(unplaced(v), "");
    }
}

/// Edges rotated between two quads, spread over the mesh and judged at once, counted in `tally`.
void rotate_edges_and_tally(const Input& in, const QuadMesh& good, const VerifyOptions& opt, Tally& tally) {
    // Rotate edges between two quads, spread over the mesh, a face apart and judged at once: each
    // named, rejected where a corridor certifies it.
    Sites sites(good);
    QuadMesh m = good;
    std::vector<SharedEdge> rotated;
    for (std::size_t start = 0; start < good.faces.size(); start += good.faces.size() / 8 + 1) {
        const SharedEdge e = shared_edge(good, start);
        if (e.a >= 0 && rotate_apart(sites, good, m, e)) rotated.push_back(e);
    }
    if (rotated.empty()) return;
    const VerifyResult v = verify(in, m, opt);
    EXPECT_EQ(unplaced(v), "");
    for (const SharedEdge& e : rotated) {
        const std::set<Index> faces{static_cast<Index>(e.f), static_cast<Index>(e.g)};
        const std::vector<int> site = edge_site(good, e);
        const std::set<Index> vertices(site.begin(), site.end());
        ++tally.rotations;
        tally.rotations_rejected += named(v.violations, vertices, faces);
        tally.rotations_face_rejected +=
            names_face(v, static_cast<Index>(e.f), false) || names_face(v, static_cast<Index>(e.g), false);
        const bool face_named =
            names_face(v, static_cast<Index>(e.f), true) || names_face(v, static_cast<Index>(e.g), true);
        EXPECT_TRUE(face_named) << "faces " << e.f << " and " << e.g;
    }
}

/// The mutations of mutations.h on a correct real-map mesh (positions as %.6g, as other tools
/// write them): each rejected with its kind and place; a rotated edge named at least as undecided
/// by the face check, and located by the coverage check where both its cells are required.
void mutate(const Input& in, const QuadMesh& good, const VerifyOptions& opt, Tally& tally) {
    // A face away from the boundary, so that dropping it leaves a hole of its own (a tiny mesh
    // may have none).
    const std::size_t inner = interior_face(good, good.faces.size() / 2);
    const bool interior = inner < good.faces.size();
    const std::size_t f = interior ? inner : good.faces.size() / 2;
    const std::vector<int> q = good.faces[f];
    expect_holes_named(in, good, opt, f, q, interior);
    expect_broken_faces_named(in, good, opt, f, q);
    rotate_edges_and_tally(in, good, opt, tally);
}

/// Rotated edges between two faces whose cells the coverage check requires: both cells named,
/// with their corners and the two faces in their place (up to eight edges, a face apart, judged
/// together).
void rotations_are_located(const Input& in, const QuadMesh& good, const VerifyOptions& opt,
                           const std::vector<std::size_t>& required, Tally& tally) {
    std::vector<char> is_required(good.faces.size(), 0);
    for (const std::size_t f : required) is_required[f] = 1;
    const std::size_t step = required.size() / 8 + 1;
    Sites sites(good);
    QuadMesh m = good;
    std::vector<SharedEdge> rotated;
    for (std::size_t i = 0; i < required.size(); i += step) {
        const SharedEdge e = shared_edge(good, required[i]);
        if (e.a >= 0 && e.f == required[i] && is_required[e.g] && rotate_apart(sites, good, m, e)) rotated.push_back(e);
    }
    if (rotated.empty()) return;
    // Judged at once, a face apart: each rotation's two cells named, with their corners and the
    // two faces in their place.
    const VerifyResult v = verify(in, m, opt);
    EXPECT_FALSE(v.valid);
    EXPECT_EQ(unplaced(v), "");
    for (const SharedEdge& e : rotated) {
        ++tally.rotations_located;
        for (const std::size_t g : {e.f, e.g}) {
            const std::vector<Index> cell(good.faces[g].begin(), good.faces[g].end());
            EXPECT_TRUE(names(v, ViolationKind::GridCellNotCovered, PlaceKind::Vertex, cell)) << "face " << g;
        }
        EXPECT_TRUE(names(v, ViolationKind::GridCellNotCovered, PlaceKind::Face,
                          {static_cast<Index>(e.f), static_cast<Index>(e.g)}));
    }
}

class RealMapPrecision : public ::testing::TestWithParam<std::string> {};

TEST_P(RealMapPrecision, RoundedOutputPassesAndMutationsAreLocated) {
    const fs::path path = fs::path(QEX_SHARED_DIR) / "meshes" / GetParam();
    if (!fs::exists(path)) GTEST_SKIP() << path << " is absent";
    Input in;
    ASSERT_TRUE(read_obj(path.string(), in).ok()) << path;
    const Result r = extract(in);
    if (!r.ok() || !r.check.valid) GTEST_SKIP() << path.filename() << ": extraction gives no valid mesh to judge";
    // As `qex check --param RAW --grid-scale K OUT` judges it: vertices in the raw map's fold-over
    // regions, where the repair moved the map, on the surface only.
    QuadMesh exact = bare(r.mesh);
    exact.grid_scale = r.mesh.grid_scale;
    VerifyOptions opt;
    opt.fold_regions = true;
    VerifyOptions strict = opt;
    strict.position_digits = 0;
    const VerifyResult d = verify(in, exact, strict);
    EXPECT_TRUE(d.valid) << "(double, --strict): " << first_message(d);
    EXPECT_TRUE(verify(in, exact, opt).valid);
    const QuadMesh rounded = printed_6g(exact);
    const VerifyResult p = verify(in, rounded, opt);
    EXPECT_TRUE(p.valid) << "(%.6g): " << first_message(p);
    EXPECT_LE(p.position_digits, 6);
    const VerifyResult f = verify(in, as_float32(exact), opt);
    EXPECT_TRUE(f.valid) << "(float32): " << first_message(f);
    EXPECT_TRUE(f.positions_float32);
    // The coverage check requires the same cells at every precision.
    EXPECT_EQ(p.coverage_cells, d.coverage_cells);
    EXPECT_EQ(f.coverage_cells, d.coverage_cells);
    Tally tally;
    tally.faces = static_cast<Index>(exact.faces.size());
    tally.required = p.coverage_cells;
    mutate(in, rounded, opt, tally);
    const std::vector<std::size_t> required = drops_are_named(in, rounded, opt, p.coverage_cells);
    rotations_are_located(in, rounded, opt, required, tally);
    std::cout << path.filename().string() << " (grid scale " << exact.grid_scale << "): " << tally.required << " of "
              << tally.faces << " cells required by the coverage check; rotated edges: " << tally.rotations_rejected
              << " of " << tally.rotations << " rejected (" << tally.rotations_face_rejected << " by the face check), "
              << tally.rotations_located << " between required cells located\n";
}

std::string test_name(const ::testing::TestParamInfo<std::string>& info) {
    std::string s = fs::path(info.param).stem().string();
    for (char& c : s)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return s;
}

// Every real map, one ctest test each (label precision); none where ../shared is absent.
INSTANTIATE_TEST_SUITE_P(SharedMaps, RealMapPrecision, ::testing::ValuesIn(real_maps()), test_name);
GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(RealMapPrecision);

TEST(CheckerPrecision, StrictModeTakesPositionsAsExact) {
    // A vertex moved off the surface by 3e-6 of its coordinates' magnitude: within the rounding
    // of 6 significant digits (5e-6), beyond the strict tolerance (1e-6 of the diagonal).
    const Input in = make_map(torus_layout(), 3, 2);
    QuadMesh m = bare(extract(in).mesh);
    VerifyOptions strict;
    strict.position_digits = 0;
    ASSERT_TRUE(verify(in, m, strict).valid);
    auto& x = m.positions[3];
    const double norm = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
    // Along the direction away from the torus' core circle's axis (z): off the surface.
    const double rxy = std::sqrt(x[0] * x[0] + x[1] * x[1]);
    const double shift = 3e-6 * norm;
    if (rxy > 0) x[0] += shift * x[0] / rxy, x[1] += shift * x[1] / rxy;
    const VerifyResult s = verify(in, m, strict);
    const VerifyResult d = verify(in, m);
    EXPECT_EQ(d.position_digits, 17);
    // The default tolerance takes it as rounding; strict mode does not, where the shift left the
    // surface by more than its tolerance (1e-6 of the diagonal: max_surface_distance's unit).
    EXPECT_TRUE(d.valid) << first_message(d);
    EXPECT_GT(d.max_rounding_tolerance, shift);
    if (s.max_surface_distance > 1e-6) {
        ASSERT_FALSE(s.valid);
        EXPECT_EQ(s.violations.front().kind, ViolationKind::OffSurface);
    }
}

} // namespace
} // namespace qex::testing
