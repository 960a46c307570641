// Meshes broken the way real extractors break them, made by mutating qex's own correct outputs
// (without provenance, as `qex check` sees another tool's OBJ): drop a quad, merge two vertices
// at their average, glue a quad to its reverse, pinch two boundary vertices, split a quad into
// triangles, rotate an edge between two quads. Each must be rejected with the right kind of
// violation naming the right place (Violation::places), and every violation must name one.
#include "mutations.h"
#include "test_support.h"

#include <algorithm>
#include <map>
#include <set>

namespace qex::testing {
namespace {

using Index = std::int64_t;

using Case = MutationCase;

TEST(CheckerMutations, CorrectMeshesPass) {
    for (const Case& c : standard_cases()) {
        const VerifyResult v = verify(c.in, c.good);
        EXPECT_TRUE(v.valid) << c.name << ": " << first_message(v);
        // No fold-overs, no cone inside a cell, boundaries on iso-lines: every cell is required,
        // and covered.
        EXPECT_EQ(v.coverage_cells, static_cast<std::int64_t>(c.good.faces.size())) << c.name;
        EXPECT_EQ(v.uncovered_cells + v.uncovered_grid_points, 0) << c.name;
    }
}

TEST(CheckerMutations, DroppedQuadIsAHoleWithItsLoop) {
    for (const Case& c :
         {make_case("torus", make_map(torus_layout(), 3, 2)), make_case("cube", make_map(cube_layout(), 3, 3))}) {
        const std::size_t f = c.good.faces.size() / 2;
        QuadMesh m = c.good;
        const std::vector<int> dropped = m.faces[f];
        m.faces.erase(m.faces.begin() + static_cast<std::ptrdiff_t>(f));
        const VerifyResult v = verify(c.in, m);
        EXPECT_FALSE(v.valid) << c.name;
        const std::vector<Index> loop(dropped.begin(), dropped.end());
        EXPECT_TRUE(names(v, ViolationKind::BoundaryMismatch, PlaceKind::Loop, loop)) << c.name;
        EXPECT_TRUE(names(v, ViolationKind::EulerMismatch, PlaceKind::Loop, loop)) << c.name;
        EXPECT_TRUE(names(v, ViolationKind::CoverageMismatch, PlaceKind::Loop, loop)) << c.name;
        // The faces around the hole: the four that shared an edge with the dropped quad.
        bool faces_named = false;
        for (const Violation& x : v.violations)
            if (x.kind == ViolationKind::BoundaryMismatch)
                for (const Place& p : x.places)
                    faces_named = faces_named || (p.kind == PlaceKind::Face && p.indices.size() == 4);
        EXPECT_TRUE(faces_named) << c.name;
        // And the grid cell no face covers now: exactly the dropped one (the map has no fold-overs).
        std::size_t cells = 0;
        for (const Violation& x : v.violations)
            if (x.kind == ViolationKind::BoundaryMismatch)
                for (const Place& p : x.places) cells += p.kind == PlaceKind::GridCell ? p.indices.size() / 3 : 0;
        EXPECT_EQ(cells, 1u) << c.name;
        // The coverage check names the hole itself: the cell, its corner vertices, its chart.
        EXPECT_TRUE(names(v, ViolationKind::GridCellNotCovered, PlaceKind::Vertex, loop)) << c.name;
        EXPECT_EQ(v.uncovered_cells, 1) << c.name;
        EXPECT_EQ(v.uncovered_grid_points, 0) << c.name;
        EXPECT_EQ(unplaced(v), "") << c.name;
    }
}

TEST(CheckerMutations, MergedVerticesAveragedAreOffTheGrid) {
    // An extractor that merges two vertices it took for copies of one, at their average.
    const Case c = make_case("torus", make_map(torus_layout(), 3, 2));
    const SharedEdge e = shared_edge(c.good, 0);
    ASSERT_GE(e.a, 0);
    QuadMesh m = c.good;
    for (int k = 0; k < 3; ++k)
        m.positions[static_cast<std::size_t>(e.a)][k] =
            0.5 * (m.positions[static_cast<std::size_t>(e.a)][k] + m.positions[static_cast<std::size_t>(e.b)][k]);
    merge_into(m, e.b, e.a);
    const VerifyResult v = verify(c.in, m);
    EXPECT_FALSE(v.valid);
    const bool off = names(v, ViolationKind::NotOnGridPoint, PlaceKind::Vertex, {e.a}) ||
                     names(v, ViolationKind::OffSurface, PlaceKind::Vertex, {e.a});
    EXPECT_TRUE(off) << first_message(v);
    EXPECT_TRUE(names(v, ViolationKind::RepeatedVertex, PlaceKind::Face, {static_cast<Index>(e.f)}));
    EXPECT_TRUE(names(v, ViolationKind::RepeatedVertex, PlaceKind::Face, {static_cast<Index>(e.g)}));
    EXPECT_TRUE(names(v, ViolationKind::UnreferencedVertex, PlaceKind::Vertex, {e.b}));
    // The grid point a left has no vertex now, and b's cells (b still on its grid point, its
    // faces on a) no face.
    EXPECT_GE(v.uncovered_grid_points, 1);
    EXPECT_TRUE(names(v, ViolationKind::GridCellNotCovered, PlaceKind::Vertex, {e.b}));
    EXPECT_EQ(unplaced(v), "");
}

TEST(CheckerMutations, QuadGluedToItsReverseIsAnExtraComponent) {
    for (const Case& c :
         {make_case("torus", make_map(torus_layout(), 3, 2)), make_case("cube", make_map(cube_layout(), 3, 3))}) {
        QuadMesh m = c.good;
        const std::vector<int> src = m.faces[m.faces.size() / 3];
        std::vector<int> copy;
        for (int x : src) {
            copy.push_back(static_cast<int>(m.positions.size()));
            m.positions.push_back(m.positions[static_cast<std::size_t>(x)]);
        }
        const auto f0 = static_cast<Index>(m.faces.size());
        m.faces.push_back(copy);
        m.faces.push_back({copy[3], copy[2], copy[1], copy[0]});
        const VerifyResult v = verify(c.in, m);
        EXPECT_FALSE(v.valid) << c.name;
        EXPECT_TRUE(names(v, ViolationKind::ComponentMismatch, PlaceKind::Face, {f0, f0 + 1})) << c.name;
        EXPECT_TRUE(names(v, ViolationKind::EulerMismatch, PlaceKind::Face, {f0, f0 + 1})) << c.name;
        EXPECT_EQ(unplaced(v), "") << c.name;
    }
    // On the torus (no cones) the reversed quad is also named as no grid cell.
    const Case t = make_case("torus", make_map(torus_layout(), 3, 2));
    QuadMesh m = t.good;
    const std::vector<int> src = m.faces[4];
    const auto n = static_cast<int>(m.positions.size());
    for (int x : src) m.positions.push_back(m.positions[static_cast<std::size_t>(x)]);
    m.faces.push_back({n, n + 1, n + 2, n + 3});
    m.faces.push_back({n + 3, n + 2, n + 1, n});
    EXPECT_TRUE(names(verify(t.in, m), ViolationKind::FaceNotGridCell, PlaceKind::Face,
                      {static_cast<Index>(m.faces.size() - 1)}));
}

TEST(CheckerMutations, PinchedBoundaryVerticesAreNonManifold) {
    const Case c = make_case("annulus", make_map(annulus_layout(), 3, 3));
    ASSERT_TRUE(verify(c.in, c.good).valid);
    // Two vertices of one boundary loop, far apart along it. The boundary sides: a side (a, b) that no other face has as (b, a).
    std::set<std::pair<int, int>> sides;
    for (const auto& f : c.good.faces)
        for (std::size_t i = 0; i < 4; ++i) sides.insert({f[i], f[(i + 1) % 4]});
    std::vector<int> boundary;
    for (const auto& s : sides)
        if (!sides.count({s.second, s.first})) boundary.push_back(s.first);
    ASSERT_GE(boundary.size(), 4u);
    // Walk one loop from its first vertex.
    std::map<int, int> next;
    for (const auto& s : sides)
        if (!sides.count({s.second, s.first})) next[s.first] = s.second;
    std::vector<int> loop{boundary.front()};
    while (next[loop.back()] != loop.front() && loop.size() <= next.size()) loop.push_back(next[loop.back()]);
    ASSERT_GE(loop.size(), 4u);
    const int a = loop[0], b = loop[loop.size() / 2];
    QuadMesh m = c.good;
    merge_into(m, b, a);
    const VerifyResult v = verify(c.in, m);
    EXPECT_FALSE(v.valid);
    EXPECT_TRUE(names(v, ViolationKind::NonManifoldVertex, PlaceKind::Vertex, {a})) << first_message(v);
    EXPECT_TRUE(names(v, ViolationKind::UnreferencedVertex, PlaceKind::Vertex, {b}));
    // The boundary lies on iso-lines: the cells at b are required, and their faces now use a.
    EXPECT_TRUE(names(v, ViolationKind::GridCellNotCovered, PlaceKind::Vertex, {b}));
    EXPECT_EQ(unplaced(v), "");
}

TEST(CheckerMutations, QuadSplitIntoTrianglesIsNamed) {
    const Case c = make_case("cube", make_map(cube_layout(), 3, 3));
    QuadMesh m = c.good;
    const std::size_t f = 7;
    const std::vector<int> q = m.faces[f];
    m.faces[f] = {q[0], q[1], q[2]};
    m.faces.push_back({q[0], q[2], q[3]});
    const VerifyResult v = verify(c.in, m);
    EXPECT_FALSE(v.valid);
    EXPECT_TRUE(names(v, ViolationKind::NotQuad, PlaceKind::Face, {static_cast<Index>(f)}));
    EXPECT_TRUE(names(v, ViolationKind::NotQuad, PlaceKind::Face, {static_cast<Index>(m.faces.size() - 1)}));
    // Its cell has no face: named with its corners and the two triangles in its place.
    const std::vector<Index> corners(q.begin(), q.end());
    EXPECT_TRUE(names(v, ViolationKind::GridCellNotCovered, PlaceKind::Vertex, corners));
    EXPECT_TRUE(names(v, ViolationKind::GridCellNotCovered, PlaceKind::Face,
                      {static_cast<Index>(f), static_cast<Index>(m.faces.size() - 1)}));
    EXPECT_EQ(unplaced(v), "");
}

TEST(CheckerMutations, RotatedEdgeBetweenTwoQuadsIsNoGridCell) {
    const Case c = make_case("torus", make_map(torus_layout(), 3, 2));
    const SharedEdge e = shared_edge(c.good, 3);
    ASSERT_GE(e.a, 0);
    QuadMesh m = c.good;
    rotate_edge(m, e);
    const VerifyResult v = verify(c.in, m);
    EXPECT_FALSE(v.valid);
    EXPECT_TRUE(names(v, ViolationKind::FaceNotGridCell, PlaceKind::Face, {static_cast<Index>(e.f)}));
    EXPECT_TRUE(names(v, ViolationKind::FaceNotGridCell, PlaceKind::Face, {static_cast<Index>(e.g)}));
    EXPECT_EQ(v.euler, v.input_euler); // the topology is intact: only the map sees it
    EXPECT_EQ(unplaced(v), "");
}

TEST(CheckerMutations, CoverageLocatesARotatedEdgeNextToCones) {
    // On the cube every face has a cone within a cell: a face's own check may be undecided there,
    // the coverage check is not. Both cells of the rotated edge are named, with their corners and
    // the two faces in their place, at every edge tried.
    const Case c = make_case("cube", make_map(cube_layout(), 3, 3));
    int tried = 0;
    for (std::size_t start = 0; start < c.good.faces.size(); start += 5) {
        const SharedEdge e = shared_edge(c.good, start);
        if (e.a < 0) continue;
        ++tried;
        QuadMesh m = c.good;
        rotate_edge(m, e);
        const VerifyResult v = verify(c.in, m);
        EXPECT_FALSE(v.valid);
        for (const std::size_t f : {e.f, e.g}) {
            const std::vector<Index> cell(c.good.faces[f].begin(), c.good.faces[f].end());
            EXPECT_TRUE(names(v, ViolationKind::GridCellNotCovered, PlaceKind::Vertex, cell)) << "face " << f;
        }
        EXPECT_TRUE(names(v, ViolationKind::GridCellNotCovered, PlaceKind::Face,
                          {static_cast<Index>(e.f), static_cast<Index>(e.g)}));
        EXPECT_EQ(v.uncovered_cells, 2);
        EXPECT_EQ(unplaced(v), "");
    }
    EXPECT_GT(tried, 5);
}

TEST(CheckerMutations, CoverageNamesAVertexMissingFromItsGridPoint) {
    // A vertex removed with its four faces (the rest renumbered): its grid point is named, with
    // its chart triangle and the four cells around it; the hole's loop is there too.
    const Case c = make_case("torus", make_map(torus_layout(), 3, 2));
    const int gone = c.good.faces[7][2];
    QuadMesh m;
    std::vector<int> index(c.good.positions.size(), -1);
    for (std::size_t i = 0; i < c.good.positions.size(); ++i)
        if (static_cast<int>(i) != gone)
            index[i] = static_cast<int>(m.positions.size()), m.positions.push_back(c.good.positions[i]);
    for (const auto& f : c.good.faces) {
        if (std::find(f.begin(), f.end(), gone) != f.end()) continue;
        std::vector<int> g;
        for (int x : f) g.push_back(index[static_cast<std::size_t>(x)]);
        m.faces.push_back(g);
    }
    ASSERT_EQ(m.faces.size() + 4, c.good.faces.size());
    const VerifyResult v = verify(c.in, m);
    EXPECT_FALSE(v.valid);
    EXPECT_EQ(v.uncovered_grid_points, 1);
    EXPECT_EQ(v.uncovered_cells, 0); // the cells are named at their grid point
    const Violation* point = nullptr;
    for (const Violation& x : v.violations)
        if (x.kind == ViolationKind::GridPointNotCovered) point = &x;
    ASSERT_NE(point, nullptr);
    EXPECT_EQ(element_kind(point->kind), ViolationElement::InputTriangle);
    ASSERT_GE(point->places.size(), 2u);
    EXPECT_EQ(point->places[0].kind, PlaceKind::GridPoint);
    EXPECT_EQ(point->places[0].indices[0], point->element);
    EXPECT_EQ(point->places[1].kind, PlaceKind::GridCell);
    EXPECT_EQ(point->places[1].indices.size(), 4u * 3u);
    EXPECT_EQ(unplaced(v), "");
}

} // namespace
} // namespace qex::testing
