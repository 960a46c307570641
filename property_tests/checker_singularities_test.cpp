// The oracle's round 2 (issue 31) on generated maps: the singularity match (ValenceMismatch,
// SingularityNotCarried) catches a rotated edge wherever it lies, holes are violations of their
// own naming their loop (Hole), an input component without a vertex is named (MissingComponent),
// and qex::check_mesh gives the verdict verify() gives with the oracle's defaults.
#include "mutations.h"
#include "test_support.h"

#include "qex/check.h"

namespace qex::testing {
namespace {

using Index = std::int64_t;

using Case = MutationCase;

TEST(CheckerSingularities, CorrectMeshesMatchTheMapsCones) {
    for (const Case& c : standard_cases()) {
        const VerifyResult v = verify(c.in, c.good);
        EXPECT_TRUE(v.valid) << c.name << ": " << first_message(v);
        EXPECT_EQ(v.map_cones, std::string(c.name) == "cube" ? 8 : 0) << c.name;
        EXPECT_EQ(v.irregular_vertices, v.map_cones) << c.name;
        EXPECT_EQ(v.valences_judged, v.vertices) << c.name; // boundaries along iso-lines: every vertex judged
        EXPECT_EQ(v.undecided_triangles, 0) << c.name;
    }
}

TEST(CheckerSingularities, EveryRotatedEdgeIsAValenceMismatchAtItsFourCorners) {
    // On the cube every face has a cone within a cell, and the faces' own check may be undecided
    // there: the valences are decided all the same, at every edge.
    for (const Case& c :
         {make_case("torus", make_map(torus_layout(), 3, 2)), make_case("cube", make_map(cube_layout(), 3, 3))}) {
        int tried = 0;
        for (std::size_t start = 0; start < c.good.faces.size(); start += 3) {
            const SharedEdge e = shared_edge(c.good, start);
            if (e.a < 0) continue;
            ++tried;
            QuadMesh m = c.good;
            rotate_edge(m, e);
            const VerifyResult v = verify(c.in, m);
            EXPECT_FALSE(v.valid) << c.name;
            // a and b lose a face, the far corners of the two quads gain one: each is named, unless
            // it sits on a cone whose valence it now has (a cube corner of valence 3 gaining one
            // face is named as 4 against 3, so always).
            std::set<Index> named;
            for (const Violation& x : v.violations)
                if (x.kind == ViolationKind::ValenceMismatch) named.insert(x.element);
            EXPECT_TRUE(named.count(e.a) && named.count(e.b)) << c.name << " edge " << e.a << "-" << e.b;
            EXPECT_GE(named.size(), 4u) << c.name;
            EXPECT_EQ(unplaced(v), "");
        }
        EXPECT_GT(tried, 5) << c.name;
    }
}

TEST(CheckerSingularities, AVertexMovedOffACubeCornerLeavesItsConeUncarried) {
    // The corner vertex slid into the middle of a neighbouring quad's edge: the cone carries no
    // vertex, and the slid vertex (3 faces at a regular point) is named.
    const Case c = make_case("cube", make_map(cube_layout(), 3, 3));
    VerifyResult v0 = verify(c.in, c.good);
    ASSERT_TRUE(v0.valid);
    // A vertex of 3 faces: a cube corner.
    std::vector<int> faces(c.good.positions.size(), 0);
    for (const auto& f : c.good.faces)
        for (int x : f) ++faces[static_cast<std::size_t>(x)];
    const auto corner = static_cast<std::size_t>(std::find(faces.begin(), faces.end(), 3) - faces.begin());
    ASSERT_LT(corner, faces.size());
    QuadMesh m = c.good;
    // Halfway to a neighbour along an edge of the mesh (on the cube's flat face: on the surface).
    int other = -1;
    for (const auto& f : c.good.faces)
        for (std::size_t i = 0; i < 4; ++i)
            if (f[i] == static_cast<int>(corner)) other = f[(i + 1) % 4];
    for (int d = 0; d < 3; ++d)
        m.positions[corner][static_cast<std::size_t>(d)] =
            0.5 * (c.good.positions[corner][static_cast<std::size_t>(d)] +
                   c.good.positions[static_cast<std::size_t>(other)][static_cast<std::size_t>(d)]);
    const VerifyResult v = verify(c.in, m);
    EXPECT_FALSE(v.valid);
    EXPECT_EQ(count(v, ViolationKind::SingularityNotCarried), 1u);
    EXPECT_TRUE(names(v, ViolationKind::SingularityNotCarried, PlaceKind::InputVertex, {}));
}

TEST(CheckerSingularities, ADroppedQuadIsAHoleNamingItsLoopAndTriangle) {
    for (const Case& c :
         {make_case("torus", make_map(torus_layout(), 3, 2)), make_case("annulus", make_map(annulus_layout(), 3, 3))}) {
        const std::size_t f = interior_face(c.good, c.good.faces.size() / 2);
        QuadMesh m = c.good;
        const std::vector<Index> loop(m.faces[f].begin(), m.faces[f].end());
        m.faces.erase(m.faces.begin() + static_cast<std::ptrdiff_t>(f));
        const VerifyResult v = verify(c.in, m);
        EXPECT_FALSE(v.valid) << c.name;
        EXPECT_EQ(count(v, ViolationKind::Hole), 1u) << c.name; // the annulus's own two loops are not holes
        EXPECT_TRUE(names(v, ViolationKind::Hole, PlaceKind::Loop, loop)) << c.name;
        bool triangle = false;
        for (const Violation& x : v.violations)
            if (x.kind == ViolationKind::Hole)
                for (const Place& p : x.places)
                    triangle = triangle || (p.kind == PlaceKind::InputTriangle && !p.indices.empty());
        EXPECT_TRUE(triangle) << c.name;
        // Without locating anything, the hole is still named (topology and the input's boundary).
        VerifyOptions topology;
        topology.locate = false;
        EXPECT_TRUE(names(verify(c.in, m, topology), ViolationKind::Hole, PlaceKind::Loop, loop)) << c.name;
    }
}

TEST(CheckerSingularities, AnInputComponentWithoutAVertexIsMissing) {
    // Two tori side by side; the mesh of the first alone.
    const Input a = make_map(torus_layout(), 3, 2);
    Input two = a;
    const auto nv = static_cast<int>(a.positions.size());
    for (const auto& p : a.positions) two.positions.push_back({p[0] + 100, p[1], p[2]});
    for (const auto& t : a.triangles) two.triangles.push_back({t[0] + nv, t[1] + nv, t[2] + nv});
    two.uvs.insert(two.uvs.end(), a.uvs.begin(), a.uvs.end());
    const QuadMesh one = bare(extract(a).mesh);
    const VerifyResult v = verify(two, one);
    EXPECT_FALSE(v.valid);
    ASSERT_EQ(count(v, ViolationKind::MissingComponent), 1u);
    EXPECT_TRUE(
        names(v, ViolationKind::MissingComponent, PlaceKind::InputTriangle, {static_cast<Index>(a.triangles.size())}));
}

TEST(CheckerSingularities, CheckMeshIsVerifyWithTheOraclesDefaults) {
    const Case c = make_case("cube", make_map(cube_layout(), 3, 3));
    QuadMesh m = c.good;
    rotate_edge(m, shared_edge(c.good, 4));
    for (const QuadMesh* mesh : {&c.good, static_cast<const QuadMesh*>(&m)}) {
        const MeshCheck k = check_mesh(c.in, *mesh);
        ASSERT_TRUE(k.map_ok());
        const VerifyResult v = verify(c.in, *mesh);
        EXPECT_EQ(k.verdict.valid, v.valid);
        EXPECT_EQ(k.verdict.violations.size(), v.violations.size());
    }
    EXPECT_TRUE(VerifyOptions{}.fold_regions); // every front end judges fold-over regions so
}

} // namespace
} // namespace qex::testing
