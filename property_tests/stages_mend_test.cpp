// Stage-level unit tests of the ladder: mending a rejected mesh, and the sheets joined at an edge
// separated.
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

/// The first length + 1 corners of a face whose corners have three faces or more and whose rings
/// miss those of `path`'s vertices; empty if there is none.
std::vector<int> path_apart(const QuadMesh& mesh, const std::vector<std::vector<std::size_t>>& around,
                            const std::vector<int>& path, std::size_t length) {
    // Vertices of faces round a vertex: its ring.
    const auto ring = [&](int v) {
        std::set<int> out;
        for (const std::size_t f : around[static_cast<std::size_t>(v)])
            out.insert(mesh.faces[f].begin(), mesh.faces[f].end());
        return out;
    };
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
    return other;
}

/// The mesh with `path` glued onto another path cut apart again, whichever end first: one
/// explanation per edge, the mesh back up to its vertices' names, each path vertex split in two;
/// and separate_sheets refuses, no preimage lying near the other path's fans.
void expect_glued_path_cut(const Input& in, const QuadMesh& mesh, const QuadMesh& glued, const std::vector<int>& path,
                           std::size_t length, bool disk, const std::string& name) {
    for (const bool larger_end_first : {false, true}) {
        const std::string about =
            name + ", " + std::to_string(length) + " edges, larger end first " + std::to_string(larger_end_first);
        QuadMesh cut = glued;
        std::vector<std::vector<int>> groups;
        const std::vector<Defect> separated = detail::cut_joined_edges(cut, larger_end_first, groups);
        ASSERT_EQ(separated.size(), length) << about;
        EXPECT_EQ(separated[0].kind, DefectKind::SheetsSeparated);
        if (length == 1) {
            const int a = path[0], b = path[1];
            EXPECT_NE(
                separated[0].message.find("(" + std::to_string(std::min(a, b)) + ", " + std::to_string(std::max(a, b)) +
                                          ") had " + std::to_string(disk ? 3 : 4) + " face sides"),
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
        // A path of one or two edges glued onto another: the first corners of face 0 (a, b, and
        // g) and those of a face whose corners' rings miss theirs, each corner with three faces or
        // more. Two edges meet at b: a vertex that ends two such edges is split last, once its
        // edges have been cut at their other ends (its own sheet is not torn).
        for (const std::size_t length : {1u, 2u}) {
            const std::vector<int> path(mesh.faces[0].begin(), mesh.faces[0].begin() + length + 1);
            const std::vector<int> other = path_apart(mesh, around, path, length);
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
            expect_glued_path_cut(in, mesh, glued, path, length, disk, layout.name);
        }
    }
}

} // namespace
} // namespace qex::testing
