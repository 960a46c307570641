// Real parametrizations from ../shared (skipped with a message where absent): the paper's six
// maps must extract to valid quad meshes; the 25 MIQ maps must end valid or with located defects.
#include "map_transforms.h"
#include "result_checks.h"
#include "test_support.h"

#include <filesystem>
#include <iostream>

namespace qex::testing {
namespace {

namespace fs = std::filesystem;

std::vector<fs::path> maps(const std::string& sub) {
    std::vector<fs::path> out;
    const fs::path dir = fs::path(QEX_SHARED_DIR) / "meshes" / sub;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir, ec))
        if (e.path().extension() == ".obj") out.push_back(e.path());
    std::sort(out.begin(), out.end());
    return out;
}

TEST(RealMaps, PaperMapsGiveValidQuadMeshes) {
    const auto files = maps("paper");
    if (files.empty()) GTEST_SKIP() << "no maps in " << QEX_SHARED_DIR << "/meshes/paper";
    std::int64_t recovered = 0;
    for (const auto& path : files) {
        Input in;
        ASSERT_TRUE(read_obj(path.string(), in).ok()) << path;
        const Result r = extract(in);
        ASSERT_TRUE(r.ok()) << path << ": " << r.error.message;
        const VerifyResult v = verify(in, r.mesh);
        EXPECT_TRUE(v.valid) << path << ": " << (v.violations.empty() ? "" : v.violations[0].message);
        EXPECT_EQ(result_inconsistency(in, r, &v), "") << path;
        // The oracle for other extractors accepts it too: positions only, located on the raw map.
        // (Not where the repair moved the map: located on the raw map, vertices there are off
        // its grid points. The checker judges them against the repaired map above.)
        if (r.mesh.map_repaired.empty()) {
            QuadMesh bare = r.mesh;
            bare.provenance.clear();
            bare.map_uvs.clear();
            bare.face_uvs.clear();
            const VerifyResult located = verify(in, bare);
            EXPECT_TRUE(located.located);
            EXPECT_TRUE(located.valid) << path << ": "
                                       << (located.violations.empty() ? "" : located.violations[0].message);
        } else {
            // The certificate was checked: every repaired triangle positive in the carried map.
            EXPECT_EQ(v.repaired_triangles, r.report.repaired_triangles) << path;
        }
        // Quad count equals the signed UV area, or the report explains every missing quad.
        const auto quads = static_cast<std::int64_t>(r.mesh.faces.size());
        const auto area = v.input_signed_uv_area_rounded;
        if (quads != area) {
            EXPECT_GT(r.report.flipped_triangles, 0) << path;
            EXPECT_FALSE(r.report.explanations.empty()) << path;
        }
        std::cout << path.filename().string() << ": " << quads << " quads, area " << area << ", "
                  << r.report.explanations.size() << " explanations, " << r.report.recovered_edges
                  << " recovered edges\n";
        recovered += r.report.recovered_edges;
    }
    // The coarse ducks hold the configurations of Figures 2 (d) and 5 (a)/(b): singularities that
    // lost ports inside fold-overs. Their recovery (Section 5.5) must have been needed.
    EXPECT_GT(recovered, 0);
}

TEST(RealMaps, SubdividedDuckGivesTheSameQuadMesh) {
    const fs::path path = fs::path(QEX_SHARED_DIR) / "meshes" / "paper" / "duck_miq_8_param.obj";
    Input in;
    if (!read_obj(path.string(), in).ok()) GTEST_SKIP() << "no " << path;
    const Input twice = subdivide(subdivide(in)); // 1-to-4 twice: the same surface and map
    // The paper's method alone depends on the map, not on its triangulation: the same mesh.
    Options paper;
    paper.repair_fold_overs = false;
    const Result a = extract(in, paper);
    const Result b = extract(twice, paper);
    ASSERT_TRUE(a.check.valid) << a.check.violations.front().message;
    ASSERT_TRUE(b.check.valid) << b.check.violations.front().message;
    // Coordinates are about 10^3: sanitizing a different vertex set moves q-vertices by ~1e-6 relative.
    EXPECT_TRUE(same_mesh(a.mesh, b.mesh, 1e-3));
    // The repair re-embeds the folded regions of each triangulation differently, so only the
    // verdict is the same there; where both are fully repaired, so is the quad count.
    const Result ra = extract(in), rb = extract(twice);
    EXPECT_TRUE(ra.check.valid && rb.check.valid);
    if (ra.report.flipped_after_repair == 0 && rb.report.flipped_after_repair == 0) {
        EXPECT_EQ(ra.mesh.faces.size(), rb.mesh.faces.size());
    }
}

// The same map in another vertex, face and corner order gives the identical mesh: byte for byte,
// repaired maps and the paper's handling of what the repair leaves included.
TEST(RealMaps, ShuffledPaperMapsGiveTheIdenticalMesh) {
    const auto files = maps("paper");
    if (files.empty()) GTEST_SKIP() << "no maps in " << QEX_SHARED_DIR << "/meshes/paper";
    for (const auto& path : files) {
        Input in;
        ASSERT_TRUE(read_obj(path.string(), in).ok()) << path;
        Input shuffled = in;
        transforms::shuffle(shuffled, 7); // vertices, triangles and each triangle's corners
        const Result a = extract(in), b = extract(shuffled);
        ASSERT_TRUE(a.check.valid && b.check.valid) << path;
        EXPECT_EQ(a.mesh.positions, b.mesh.positions) << path;
        EXPECT_EQ(a.mesh.faces, b.mesh.faces) << path;
        EXPECT_EQ(a.mesh.face_uvs, b.mesh.face_uvs) << path;
        EXPECT_EQ(a.report.rung, b.report.rung) << path;
    }
}

// A map too coarse for its surface (kitten_miq_10: its handle is about a quad around, and at
// its own scale the mesh loses it) is extracted refined: valid against the map scaled by 2, said
// so in the report, and rejected at its own scale.
TEST(RealMaps, CoarseMapIsRefined) {
    const fs::path path = fs::path(QEX_SHARED_DIR) / "meshes" / "miq-more" / "kitten_miq_10_param.obj";
    Input in;
    if (!read_obj(path.string(), in).ok()) GTEST_SKIP() << "no " << path;
    Options own_scale;
    own_scale.max_refinement = 1;
    const Result at_one = extract(in, own_scale);
    ASSERT_TRUE(at_one.ok());
    EXPECT_FALSE(at_one.check.valid);
    EXPECT_EQ(at_one.mesh.grid_scale, 1);
    const Result r = extract(in);
    ASSERT_TRUE(r.ok());
    ASSERT_TRUE(r.check.valid);
    EXPECT_EQ(r.mesh.grid_scale, 2);
    EXPECT_EQ(r.report.grid_scale, 2);
    EXPECT_EQ(r.report.refinements_tried, 1);
    ASSERT_FALSE(r.report.explanations.empty());
    EXPECT_EQ(r.report.explanations.front().kind, DefectKind::MapRefined);
    EXPECT_EQ(result_inconsistency(in, r), "");
    // The checker judges it against the map scaled by 2, and rejects it against the map itself.
    const VerifyResult v = verify(in, r.mesh);
    EXPECT_TRUE(v.valid) << (v.violations.empty() ? "" : v.violations.front().message);
    QuadMesh unscaled = r.mesh;
    unscaled.grid_scale = 1;
    EXPECT_FALSE(verify(in, unscaled).valid);
    unscaled.grid_scale = 3; // not a power of two
    EXPECT_FALSE(verify(in, unscaled).valid);
    // The scaled map's area is four times the map's, and bounds the quads.
    const VerifyResult v1 = verify(in, at_one.mesh);
    EXPECT_EQ(v.input_signed_uv_area_rounded, 4 * v1.input_signed_uv_area_rounded);
    EXPECT_LE(static_cast<std::int64_t>(r.mesh.faces.size()), v.input_signed_uv_area_rounded);
}

TEST(RealMaps, MiqMapsEndValidOrWithLocatedDefects) {
    const auto files = maps("miq");
    if (files.empty()) GTEST_SKIP() << "no maps in " << QEX_SHARED_DIR << "/meshes/miq";
    int valid = 0;
    for (const auto& path : files) {
        Input in;
        ASSERT_TRUE(read_obj(path.string(), in).ok()) << path;
        const Result r = extract(in);
        if (!r.ok()) {
            // A map the pipeline cannot take: the error must say where.
            EXPECT_GE(r.error.element, 0) << path << ": " << r.error.message;
            continue;
        }
        const VerifyResult v = verify(in, r.mesh);
        // The verdict is the checker's, the checker defects its violations kind for kind, and
        // every defect names a place (result_checks.h).
        EXPECT_EQ(result_inconsistency(in, r, &v), "") << path;
        if (v.valid) {
            ++valid;
            continue;
        }
        // Invalid: every violation names an element, and the report locates defects on the input.
        EXPECT_EQ(r.report.check_violations, static_cast<std::int64_t>(v.violations.size())) << path;
        // Local violations carry the input triangle near them; global ones (Euler characteristic)
        // are named as such.
        EXPECT_FALSE(r.report.defects.empty()) << path;
        std::size_t checker_defects = 0;
        for (const auto& d : r.report.defects) {
            EXPECT_FALSE(d.message.empty());
            // A checker violation keeps its kind; every other defect has none.
            EXPECT_EQ(d.kind == DefectKind::CheckerViolation, d.violation.has_value()) << path << ": " << d.message;
            checker_defects += d.violation.has_value();
            if (d.output_face >= 0) { EXPECT_GE(d.input_element, 0) << path << ": " << d.message; }
            // A global defect names the candidate places: where faces were removed, and the input
            // vertex farthest from the output.
            if (d.violation == ViolationKind::EulerMismatch) {
                EXPECT_NE(d.message.find("farthest from the output is at input vertex"), std::string::npos)
                    << d.message;
            }
        }
        EXPECT_EQ(checker_defects, v.violations.size()) << path;
    }
    std::cout << "MIQ maps: " << valid << "/" << files.size() << " valid\n";
    EXPECT_GE(valid, 24); // the tally recorded in the README; a regression fails here
}

} // namespace
} // namespace qex::testing
