// The scale sweep (issue 12): the paper's six real maps with their UVs multiplied by K, one test
// per map and K. Scaling keeps the fold-overs and the singularities but gives every fold-over K^2
// times more grid cells to cover, so it stresses the repair of fold-overs: the mesh must be
// valid, its topology the input's, and from K = 8 on (fold-overs of many cells) the quad count the
// signed UV area unless the report names where quads were lost. Where the repair cannot re-embed
// a fold-over at scale K, the map with its UVs divided by 2, 4, ... (an integer-grid map again)
// gives the mesh, split back (Options::max_coarsening). K in {2, 4, 8} run by default (label
// scale_sweep); the instantiation LongScaleSweep (K in {16, 32}) is registered with
// -DQEX_LONG_TESTS=ON, label long.
#include "map_transforms.h"
#include "transform_checks.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>
#include <string>
#include <vector>

namespace qex::testing {
namespace {

struct ScaleCase {
    std::string map; ///< in meshes/paper, without "_param.obj"
    std::int64_t k;
};

void PrintTo(const ScaleCase& c, std::ostream* os) { *os << c.map << " x " << c.k; }

std::string case_name(const ::testing::TestParamInfo<ScaleCase>& info) {
    return info.param.map + "_x" + std::to_string(info.param.k);
}

std::vector<ScaleCase> cases(const std::vector<std::int64_t>& ks) {
    std::vector<ScaleCase> out;
    for (const char* map : {"duck_miq_4", "duck_miq_8", "duck_miq_16", "duck_miq_28", "duck_qc_8", "fandisk"})
        for (std::int64_t k : ks) out.push_back({map, k});
    return out;
}

class ScaleSweep : public ::testing::TestWithParam<ScaleCase> {};

TEST_P(ScaleSweep, ValidMeshOfTheScaledArea) {
    const ScaleCase& c = GetParam();
    Input in;
    if (const std::string why = read_real_map("paper", c.map, in); !why.empty()) GTEST_SKIP() << why;
    // Powers of two scale every double exactly: the scaled map is the map, K times larger.
    ASSERT_EQ(transforms::scale_uvs(in, c.k), 0) << "UVs x " << c.k << " is not exact";

    const Result r = extract(in);
    ASSERT_TRUE(r.ok()) << to_string(r.error.code) << ": " << r.error.message;
    const VerifyResult v = verify(in, r.mesh);
    const std::string about = c.map + " x " + std::to_string(c.k) + ": " + summary(r, v);
    std::cout << about << "\n";

    // duck_miq_28 from x8 on was a known failure: its x2 mesh loses 3 quads in folds that neither
    // the repair nor the paper's handling resolve, and split K/2 x K/2 those cells left grid
    // points outside the folds uncovered (the split put vertices on another sheet's preimages,
    // where vertices already lay). It must now be valid like every other case.
    EXPECT_TRUE(r.check.valid) << about << "\nextract's check: " << violations_text(r.check.violations);
    EXPECT_TRUE(v.valid) << about << "\nverify: " << violations_text(v.violations);
    EXPECT_EQ(v.euler, v.input_euler) << about;
    EXPECT_EQ(v.boundary_loops, v.input_boundary_loops) << about;
    EXPECT_EQ(v.components, v.input_components) << about;
    // And the oracle any extractor's mesh faces (`qex check --param`: no provenance, the map's
    // fold-over regions judged on the surface) accepts it: a coarse mesh split K x K must cover
    // the grid points the map covers once as the map's own mesh would.
    QuadMesh bare;
    bare.positions = r.mesh.positions;
    bare.faces = r.mesh.faces;
    bare.grid_scale = r.mesh.grid_scale;
    VerifyOptions located;
    located.fold_regions = true;
    const VerifyResult lv = verify(in, bare, located);
    EXPECT_TRUE(lv.valid) << about << "\nlocated: " << violations_text(lv.violations);
    // A mesh from the map with its UVs divided by K' (the scaled map halves back to an
    // integer-grid map) says so first, and has K'^2 quads per quad of that map.
    const int coarsening = r.report.coarsening;
    if (coarsening > 1) {
        ASSERT_FALSE(r.report.explanations.empty()) << about;
        EXPECT_EQ(r.report.explanations.front().kind, DefectKind::MapCoarsened) << about;
        EXPECT_EQ(r.mesh.faces.size() % static_cast<std::size_t>(coarsening * coarsening), 0u) << about;
        EXPECT_EQ(c.k % coarsening, 0) << about;
    }
    // Never more quads than the signed area (duck_miq_16 x8 had 3,779 for 3,776 at its own scale
    // while near pairs of two clockwise faces, mirror images, were cancelled).
    EXPECT_LE(static_cast<std::int64_t>(r.mesh.faces.size()), v.input_signed_uv_area_rounded) << about;
    if (c.k < 8) return;
    // Fold-overs of this size are the repair's to re-embed: a quad count other than the area
    // must be explained by a loss the report names (not by the scale alone).
    const bool loss_named =
        std::any_of(r.report.explanations.begin(), r.report.explanations.end(), [](const Defect& d) {
            return d.kind == DefectKind::FaceCollapsed || d.kind == DefectKind::GhostFacesCancelled ||
                   d.kind == DefectKind::BoundaryFaceDiscarded || d.kind == DefectKind::FoldOverNotRepaired;
        });
    if (!loss_named) {
        EXPECT_EQ(static_cast<std::int64_t>(r.mesh.faces.size()), v.input_signed_uv_area_rounded) << about;
    }
}

/// A paper map with its UVs x k, coarsened, and moved by each of `moves`: its coarse grid is
/// laid from another origin, and the mesh has the same faces and its positions within `tol`
/// times the diagonal; those a repaired region places within 1% of the median edge length (the
/// owner's bound: the relaxation stops near its minimum, not at it).
void expect_moved_coarsened_map_same(const char* name, int k,
                                     const std::vector<std::pair<std::int64_t, std::int64_t>>& moves, double tol) {
    Input in;
    if (const std::string why = read_real_map("paper", name, in); !why.empty()) GTEST_SKIP() << why;
    ASSERT_EQ(transforms::scale_uvs(in, k), 0);
    const Result base = extract(in);
    ASSERT_TRUE(base.check.valid) << name;
    ASSERT_GT(base.report.coarsening, 1) << name << " x" << k << " no longer needs coarsening: pick another map";
    for (const auto& [dx, dy] : moves) {
        Input moved = in;
        ASSERT_GE(transforms::translate_uvs(moved, dx, dy), 0);
        const Result r = extract(moved);
        ASSERT_TRUE(r.check.valid) << name << " moved by " << dx << " " << dy;
        EXPECT_EQ(r.report.coarsening, base.report.coarsening);
        EXPECT_EQ(mesh_difference(r.mesh, base.mesh, tol * bbox_diagonal(base.mesh.positions),
                                  0.01 * median_edge_length(base.mesh), placed_by_repair(r.mesh, base.mesh)),
                  "")
            << name << " moved by " << dx << " " << dy;
    }
}

TEST(ScaleSweepCoarsening, ACoarsenedMapMovedByACellGivesTheSameMesh) {
    // duck_qc_8 x8 is coarsened (its x4 map split back). Positions within 1e-5 of the diagonal:
    // the repair starts from UVs a few units in the last place apart. The repaired regions'
    // vertices moved by 1.2e-6 of it while the relaxation ended at its minimum (1.5e-5 since it
    // stops near it), at (-65535, 0), where the map's negative x range straddles
    // a power of two and sanitizing truncates fans to twice the step it takes at the map's own
    // origin; a vertex on another sheet would be a quad (1e-2 of it) away.
    expect_moved_coarsened_map_same("duck_qc_8", 8, {{1, 0}, {3, -5}, {-65535, 0}}, 1e-5);
    // duck_miq_28 x8 (its x2 map split back): the map the mesh carries is the coarse one times 4
    // plus the origin, exact only because the repair truncates with a unit of headroom; without
    // it a repaired UV that crosses a power of two rounds, a transition no longer holds exactly,
    // and the split mesh is rejected: x4 moved by (1, 0) gave no valid mesh (x4 is valid at its
    // own scale since near pairs of reversed faces are cancelled).
    expect_moved_coarsened_map_same("duck_miq_28", 8, {{1, 0}, {3, -5}}, 1e-5);
}

INSTANTIATE_TEST_SUITE_P(PaperMaps, ScaleSweep, ::testing::ValuesIn(cases({2, 4, 8})), case_name);
INSTANTIATE_TEST_SUITE_P(LongScaleSweep, ScaleSweep, ::testing::ValuesIn(cases({16, 32})), case_name);

} // namespace
} // namespace qex::testing
