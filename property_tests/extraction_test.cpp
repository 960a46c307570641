// Unit tests of the extraction, one hand-built map per special case the paper names.
#include "pipeline.h"
#include "result_checks.h"
#include "test_support.h"

#include <algorithm>
#include <cstdint>
#include <cmath>
#include <random>
#include <set>
#include <string>
#include <vector>

namespace qex::testing {
namespace {

// --- iso-lines in general position and in special position -----------------------------------

/// The torus map with n quads per layout edge and a k-step lattice: valid, with the map's area.
Result torus_case(int n, int k) {
    const auto layout = torus_layout();
    const Result r = extract_valid(make_map(layout, n, k));
    EXPECT_EQ(static_cast<std::int64_t>(r.mesh.faces.size()), expected_quads(layout, n)) << n << "/" << k;
    return r;
}

TEST(Extraction, TorusGeneralPosition) {
    const auto layout = torus_layout();
    const Result r = torus_case(3, 7);
    // A 3/7 lattice puts no mesh vertex on a grid point except the layout's own vertices.
    EXPECT_EQ(r.report.qvertices_on_vertices, static_cast<std::int64_t>(layout.positions.size()));
    EXPECT_GT(r.report.qvertices_in_faces, 0);
    EXPECT_GT(r.report.qvertices_on_edges, 0);
}

TEST(Extraction, IsoLinesThroughVerticesAndAlongEdges) {
    // k = n: every lattice vertex is a grid point and every axis-aligned edge lies on an iso-line.
    const Result r = torus_case(4, 4);
    EXPECT_EQ(r.report.qvertices_in_faces, 0);
    EXPECT_EQ(r.report.qvertices_on_edges, 0);
    EXPECT_GT(r.report.qvertices_on_vertices, 0);
}

TEST(Extraction, GridPointsOnEdges) {
    // Lattice spacing 2: every grid point off the lattice is the midpoint of an edge.
    const Result r = torus_case(4, 2);
    EXPECT_GT(r.report.qvertices_on_edges, 0);
    EXPECT_EQ(r.report.qvertices_in_faces, 0);
    // Spacing 3: grid points on the diagonals and strictly inside triangles.
    const Result r3 = torus_case(3, 1);
    EXPECT_GT(r3.report.qvertices_on_edges, 0);
    EXPECT_GT(r3.report.qvertices_in_faces, 0);
}

// --- singularities ------------------------------------------------------------------------------

class Singularities : public ::testing::TestWithParam<std::pair<QuadLayout, int>> {};

TEST_P(Singularities, ValidAndAreaPreserving) {
    const auto& [layout, valence] = GetParam();
    for (int k : {2, 3, 5}) {
        const Input in = make_map(layout, 2, k);
        const Result r = extract_valid(in);
        EXPECT_EQ(static_cast<std::int64_t>(r.mesh.faces.size()), expected_quads(layout, 2))
            << layout.name << " k=" << k;
        // The singular layout vertices are output vertices of the expected valence.
        std::vector<int> degree(r.mesh.positions.size(), 0);
        for (const auto& f : r.mesh.faces)
            for (int v : f) ++degree[v];
        EXPECT_NE(std::find(degree.begin(), degree.end(), valence), degree.end()) << layout.name;
    }
}

INSTANTIATE_TEST_SUITE_P(Extraction, Singularities,
                         ::testing::Values(std::make_pair(cube_layout(), 3), std::make_pair(icosahedron_layout(), 5),
                                           std::make_pair(prism_layout(6), 6), std::make_pair(prism_layout(8), 8)),
                         [](const auto& info) { return info.param.first.name; });

TEST(Extraction, Valence8IsSnappedAsSingularity) {
    // r = 0 around a valence 8 vertex: only the valence count tells it is singular.
    auto in = make_map(prism_layout(8), 2, 3);
    std::mt19937 rng(7);
    add_noise(in, 1e-7, rng);
    const Result r = extract_valid(in);
    EXPECT_EQ(static_cast<std::int64_t>(r.mesh.faces.size()), expected_quads(prism_layout(8), 2));
    EXPECT_GE(r.report.singularities, 2);
}

// --- boundaries ---------------------------------------------------------------------------------

TEST(Extraction, NoisyBoundarySnapped) {
    const auto layout = annulus_layout();
    Input in = make_map(layout, 2, 3);
    std::mt19937 rng(2);
    add_noise(in, 1e-7, rng);
    Options opt;
    opt.snap_boundary = true;
    const Result r = extract_valid(in, opt);
    EXPECT_EQ(static_cast<std::int64_t>(r.mesh.faces.size()), expected_quads(layout, 2));
    // Unsnapped, the boundary still follows its iso-lines up to solver noise (1e-7 of a cell,
    // the bound is 1/1024): it is snapped all the same, and no trace runs into it. (Before,
    // traces along it left the surface and the faces there were dropped.)
    const Result loose = extract_valid(in);
    EXPECT_EQ(loose.mesh.faces.size(), r.mesh.faces.size());
    EXPECT_EQ(loose.report.traces_into_boundary, 0);
    EXPECT_EQ(loose.report.boundary_faces_discarded, r.report.boundary_faces_discarded);
}

TEST(Extraction, DiskAndAnnulus) {
    for (const auto& layout : {disk_layout(3), annulus_layout()}) {
        for (int k : {2, 3}) {
            const Result r = extract_valid(make_map(layout, 2, k));
            EXPECT_EQ(static_cast<std::int64_t>(r.mesh.faces.size()), expected_quads(layout, 2)) << layout.name;
        }
    }
}

// --- charts, order and precision ------------------------------------------------------------------

/// The fan below: whether the integer point (x, y) lies inside its rim. The rim is a 60,000-gon
/// inscribed in the circle of radius 6.5 (x^2 + y^2 = 42.25); no integer point has x^2 + y^2 of
/// 42, 43 or 44 (none is a sum of two squares), so each is at least 0.09 inside or outside the
/// circle, while the rim's chords stay within 1e-8 of it.
bool inside_rim(std::int64_t x, std::int64_t y) { return x * x + y * y <= 41; }

/// Grid cells [i, i+1] x [j, j+1] of the fan's disk by their lower left corner: those with all
/// four corners inside the rim (inside, as the disk is convex), and those cut by the rim that
/// have an edge inside (a face walk runs along that edge into the boundary).
struct DiskCells {
    std::set<std::array<std::int64_t, 2>> full, cut;
};

/// The cells of the fan's disk, by whether their corners are inside the rim.
DiskCells disk_cells() {
    DiskCells c;
    for (std::int64_t i = -7; i <= 6; ++i)
        for (std::int64_t j = -7; j <= 6; ++j) {
            const bool a = inside_rim(i, j), b = inside_rim(i + 1, j);
            const bool d = inside_rim(i + 1, j + 1), e = inside_rim(i, j + 1);
            if (a && b && d && e)
                c.full.insert({i, j});
            else if ((a && b) || (b && d) || (d && e) || (e && a))
                c.cut.insert({i, j});
        }
    return c;
}

/// The fan's output is exactly the grid cells inside the rim, below the disk's area (the map is
/// one chart: UV = position); each cell cut by the rim is discarded and explained at one of its
/// corners (the walk's start), and every explanation is at such a corner.
void expect_the_cells_inside_the_rim(const Result& r) {
    const DiskCells cells = disk_cells();
    std::set<std::array<std::int64_t, 2>> faces;
    for (const auto& f : r.mesh.faces) {
        std::array<std::int64_t, 2> low{INT64_MAX, INT64_MAX};
        for (int v : f) {
            const auto& grid = r.mesh.provenance[static_cast<std::size_t>(v)].grid;
            for (int d = 0; d < 2; ++d) low[d] = std::min(low[d], grid[d]);
        }
        faces.insert(low);
    }
    EXPECT_EQ(r.mesh.faces.size(), cells.full.size());
    EXPECT_EQ(faces, cells.full);
    EXPECT_LT(static_cast<double>(r.mesh.faces.size()), r.report.signed_uv_area);
    EXPECT_EQ(r.report.boundary_faces_discarded, static_cast<std::int64_t>(r.report.explanations.size()));
    auto corner_of = [](const std::array<std::int64_t, 2>& cell, const std::array<std::int64_t, 2>& p) {
        return (p[0] == cell[0] || p[0] == cell[0] + 1) && (p[1] == cell[1] || p[1] == cell[1] + 1);
    };
    for (const auto& cell : cells.cut)
        EXPECT_TRUE(std::any_of(r.report.explanations.begin(), r.report.explanations.end(),
                                [&](const Defect& d) { return corner_of(cell, d.grid); }))
            << "cell " << cell[0] << " " << cell[1];
    for (const Defect& d : r.report.explanations) {
        EXPECT_EQ(d.kind, DefectKind::BoundaryFaceDiscarded);
        EXPECT_TRUE(std::any_of(cells.cut.begin(), cells.cut.end(), [&](const auto& cell) {
            return corner_of(cell, d.grid);
        })) << d.message;
    }
}

/// The fan's apex is the one output vertex at grid point (0, 0), generated on the input vertex itself.
void expect_the_apex_at_the_origin(const Input& in, const Result& r) {
    const std::array<double, 3> origin{0, 0, 0};
    const auto apex = std::find(in.positions.begin(), in.positions.end(), origin) - in.positions.begin();
    int at_origin = 0;
    for (std::size_t v = 0; v < r.mesh.provenance.size(); ++v) {
        const Provenance& p = r.mesh.provenance[v];
        if (p.grid != std::array<std::int64_t, 2>{0, 0}) continue;
        ++at_origin;
        EXPECT_EQ(p.kind, QVertexKind::Vertex);
        EXPECT_EQ(p.element, apex);
        EXPECT_EQ(r.mesh.positions[v], origin);
    }
    EXPECT_EQ(at_origin, 1);
}

TEST(Extraction, VertexOfVeryHighValence) {
    // A disk made of one fan of 60,000 thin triangles around its centre (a cone apex, or a
    // pole of a latitude-longitude sphere, looks like this), numbered at random. Every stage
    // walks this one fan; the edge tables sort its 60,000 edges with std::sort rather than by
    // insertion (speed is measured by the benchmarks, not here).
    const int n = 60000;
    Input in;
    in.positions.push_back({0, 0, 0});
    for (int i = 0; i < n; ++i) {
        const double a = 2 * M_PI * i / n;
        in.positions.push_back({6.5 * std::cos(a), 6.5 * std::sin(a), 0});
    }
    for (int i = 0; i < n; ++i) {
        const std::array<int, 3> t{0, 1 + i, 1 + (i + 1) % n};
        in.triangles.push_back(t);
        for (int v : t) in.uvs.push_back({in.positions[v][0], in.positions[v][1]});
    }
    std::mt19937 rng(8);
    shuffle(in, rng); // the centre's edges in random order
    const Result r = extract(in);
    ASSERT_TRUE(r.ok()) << r.error.message;
    EXPECT_EQ(result_inconsistency(in, r), "");
    EXPECT_TRUE(r.check.valid);
    EXPECT_TRUE(r.report.defects.empty());
    expect_the_cells_inside_the_rim(r);
    expect_the_apex_at_the_origin(in, r);
}

TEST(Extraction, RechartShuffleTranslateRotate) {
    const auto layout = cube_layout();
    const Input base = make_map(layout, 3, 4);
    const auto expected = signature(extract_valid(base).mesh);
    std::mt19937 rng(11);
    Input in = base;
    rechart(in, rng);
    shuffle(in, rng);
    translate(in, std::int64_t{1} << 30, -(std::int64_t{1} << 30));
    rotate(in, 3);
    EXPECT_EQ(signature(extract_valid(in).mesh), expected);
    // Shuffling alone must give the identical output (canonical order), byte for byte in memory.
    Input shuffled = base;
    shuffle(shuffled, rng);
    const QuadMesh a = extract_valid(base).mesh, b = extract_valid(shuffled).mesh;
    EXPECT_EQ(a.faces, b.faces);
    EXPECT_EQ(a.positions, b.positions);
}

TEST(Extraction, SolverNoise) {
    const auto layout = icosahedron_layout();
    const Input base = make_map(layout, 2, 3);
    const QuadMesh base_mesh = extract_valid(base).mesh;
    for (double eps : {1e-12, 1e-9, 1e-6}) {
        std::mt19937 rng(3);
        Input in = base;
        add_noise(in, eps, rng);
        const Result r = extract_valid(in);
        EXPECT_TRUE(same_mesh(r.mesh, base_mesh, 1e-4)) << eps;
        EXPECT_GT(r.report.max_sanitization_displacement, 0.0);
        EXPECT_LE(r.report.max_sanitization_displacement, 4 * eps);
    }
}

// --- degeneracies -------------------------------------------------------------------------------

// Options::on_stage hears every stage as it finishes, in pipeline order, at the map's own scale.
TEST(Extraction, StageHookHearsEveryStage) {
    std::vector<std::string> heard;
    std::vector<int> scales;
    Options options;
    options.on_stage = [&](const char* stage, int grid_scale) {
        heard.emplace_back(stage);
        scales.push_back(grid_scale);
    };
    const Result r = extract(make_map(cube_layout(), 3, 4), options);
    ASSERT_TRUE(r.check.valid);
    ASSERT_FALSE(heard.empty());
    EXPECT_EQ(heard.front(), "validate");
    EXPECT_EQ(heard.back(), "check");
    for (const char* stage : {"sanitize", "generate_qvertices", "trace_ports", "extract_faces", "merge_vertices"})
        EXPECT_NE(std::find(heard.begin(), heard.end(), stage), heard.end()) << stage;
    EXPECT_LT(std::find(heard.begin(), heard.end(), "trace_ports") - heard.begin(),
              std::find(heard.begin(), heard.end(), "extract_faces") - heard.begin());
    EXPECT_TRUE(std::all_of(scales.begin(), scales.end(), [](int s) { return s == 1; }));
    // Every stage the report times was heard.
    for (const auto& [name, seconds] : r.report.stage_seconds)
        EXPECT_NE(std::find(heard.begin(), heard.end(), name), heard.end()) << name;
    // And the hook is the caller's only while extract() runs: a later call without one is silent.
    heard.clear();
    (void)extract(make_map(cube_layout(), 3, 4));
    EXPECT_TRUE(heard.empty());
}

TEST(Extraction, CollapsedEdges) {
    const auto layout = torus_layout();
    Input in = make_map(layout, 2, 4);
    insert_collapsed_edge(in, 5, 0);
    insert_collapsed_edge(in, 40, 2);
    const Result r = extract_valid(in);
    EXPECT_EQ(r.report.collapsed_edges, 2);
    EXPECT_EQ(static_cast<std::int64_t>(r.mesh.faces.size()), expected_quads(layout, 2));
}

TEST(Extraction, ZeroAreaTriangles) {
    const auto layout = torus_layout();
    Input in = make_map(layout, 2, 4); // spacing 1/2: midpoints are exact
    insert_zero_area_triangle(in, 7, 0);
    insert_zero_area_triangle(in, 30, 1);
    const Result r = extract_valid(in);
    EXPECT_EQ(r.report.degenerate_triangles, 2);
    EXPECT_EQ(static_cast<std::int64_t>(r.mesh.faces.size()), expected_quads(layout, 2));
}

// --- report, features and given valences ---------------------------------------------------------

TEST(Extraction, ReportCountsAreConsistent) {
    const auto layout = cube_layout();
    const Result r = extract_valid(make_map(layout, 2, 3));
    EXPECT_EQ(r.report.traces_connected * 2 + r.report.traces_into_boundary, r.report.ports);
    EXPECT_EQ(r.report.traces_failed, 0);
    EXPECT_TRUE(r.report.defects.empty());
    EXPECT_EQ(r.report.rung, "as-given");
    EXPECT_FALSE(r.report.stage_seconds.empty());
    // Provenance: every output vertex names an element and a grid point.
    for (const auto& p : r.mesh.provenance) EXPECT_GE(p.element, 0);
}

TEST(Extraction, FeatureEdgesSnapToIsoLines) {
    // Edges of the exact map that lie on integer iso-lines become feature edges; after noise,
    // snapping puts their vertices back on the iso-lines, so grid points on mesh vertices stay
    // on mesh vertices (without snapping, noise moves them into edges and faces).
    const Input exact = make_map(torus_layout(), 2, 3);
    std::vector<std::array<int, 2>> features;
    for (std::size_t f = 0; f < exact.triangles.size(); ++f)
        for (int k = 0; k < 3; ++k) {
            const auto &a = exact.uvs[3 * f + k], &b = exact.uvs[3 * f + (k + 1) % 3];
            for (int axis = 0; axis < 2; ++axis)
                if (a[axis] == b[axis] && std::floor(a[axis]) == a[axis])
                    features.push_back({exact.triangles[f][k], exact.triangles[f][(k + 1) % 3]});
        }
    ASSERT_FALSE(features.empty());
    Input noisy = exact;
    std::mt19937 rng(4);
    add_noise(noisy, 1e-5, rng);
    const Result reference = extract_valid(exact), loose = extract_valid(noisy);
    noisy.feature_edges = features;
    const Result snapped = extract_valid(noisy);
    EXPECT_EQ(snapped.report.qvertices_on_vertices, reference.report.qvertices_on_vertices);
    EXPECT_LT(loose.report.qvertices_on_vertices, reference.report.qvertices_on_vertices);
    EXPECT_TRUE(same_mesh(snapped.mesh, reference.mesh, 1e-3));
}

TEST(Extraction, GivenValencesDecideBranchPoints) {
    // Around a valence-8 vertex the transitions compose to the identity: only the valence tells
    // it is singular (and must be snapped to its grid point). Given valences are used as given.
    const Input exact = make_map(prism_layout(8), 2, 3);
    detail::TriMesh m = detail::make_mesh(exact);
    ASSERT_EQ(detail::build_topology(m, "test").code, ErrorCode::None);
    detail::compute_transitions(m);
    detail::count_valences(m);
    std::vector<int> valences(exact.positions.size(), 4);
    int branch_points = 0;
    for (int v = 0; v < m.num_vertices; ++v) {
        valences[m.input_vertex[v]] = m.map.valence[v];
        branch_points += m.map.valence[v] == 8;
    }
    ASSERT_EQ(branch_points, 2);
    Input noisy = exact;
    std::mt19937 rng(8);
    add_noise(noisy, 1e-7, rng);
    noisy.valences = valences;
    const Result right = extract_valid(noisy);
    for (int& v : noisy.valences) v = v == 8 ? 4 : v; // claim the branch points are regular
    const Result wrong = extract_valid(noisy);
    EXPECT_EQ(right.report.singularities, wrong.report.singularities + 2);
    EXPECT_EQ(right.report.qvertices_on_vertices, wrong.report.qvertices_on_vertices + 2);
}
} // namespace
} // namespace qex::testing
