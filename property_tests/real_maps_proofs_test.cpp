// Real maps from ../shared (skipped with a message where absent): co-located dipoles merged,
// every fold left unrepaired said why and where, and the proofs the repair names placed on the map.

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

/// Solver rounding can snap a dipole's two singularities (valence 5 and 3) onto one grid point with
/// a fold between them, which no fold-free map allows: on fandisk with its UVs x 8 the fold covers
/// cells, and only merging the pair lets the repair re-embed it. The merge is named in the report,
/// the carried map has two singularities fewer (the checker counts them itself), and the mesh is
/// valid with exactly the signed area's quads.
TEST(RealMaps, CoLocatedDipoleIsMergedNamedAndItsFoldRepaired) {
    const auto merged = expect_scaled_map_repaired("fandisk", 8);
    if (!merged) GTEST_SKIP() << "no fandisk in " << QEX_SHARED_DIR;
    ASSERT_FALSE(merged->empty()) << "no dipole merged on fandisk x 8: pick another map";
    for (const Defect& d : *merged) {
        EXPECT_GE(d.input_element, 0);
        EXPECT_NE(d.message.find("valence 5"), std::string::npos) << d.message;
        EXPECT_NE(d.message.find("valence 3"), std::string::npos) << d.message;
    }
}

/// The merge of a co-located dipole changes two singularities' valences, which the user's valences
/// forbid: fandisk x 8 with the valences the pipeline counts on its sanitized map given as the
/// user's is extracted without a merge (the pair stays, and the result says what that leaves),
/// and with the same valences computed instead, with one.
TEST(RealMaps, NoDipoleIsMergedAgainstGivenValences) {
    const fs::path path = fs::path(QEX_SHARED_DIR) / "meshes" / "paper" / "fandisk_param.obj";
    Input in;
    if (!read_obj(path.string(), in).ok()) GTEST_SKIP() << "no " << path;
    ASSERT_EQ(transforms::scale_uvs(in, 8), 0);
    // The valences the repaired rung starts from: counted on the collapsed, sanitized map.
    detail::TriMesh m;
    ASSERT_EQ(detail::validate(in, 1, m).code, ErrorCode::None);
    std::int64_t collapsed = 0;
    ASSERT_EQ(detail::collapse(m, collapsed).code, ErrorCode::None);
    Report report;
    detail::StageTimer timer(report);
    ASSERT_EQ(detail::sanitize_until_stable(m, in, {}, report, timer).code, ErrorCode::None);
    detail::count_valences(m, true);
    std::vector<int> valences(in.positions.size(), 4);
    for (int v = 0; v < m.num_vertices; ++v) valences[m.input_vertex[v]] = m.map.valence[v];
    const auto merges = [](const Result& r) {
        return std::count_if(r.report.explanations.begin(), r.report.explanations.end(),
                             [](const Defect& d) { return d.kind == DefectKind::SingularitiesMerged; });
    };
    const Result computed = first_rung(in); // the merge is the repaired rung's business
    ASSERT_TRUE(computed.ok()) << computed.error.message;
    ASSERT_GT(merges(computed), 0) << "no dipole merged on fandisk x 8: pick another map";
    in.valences = valences;
    const Result given = first_rung(in);
    ASSERT_TRUE(given.ok()) << given.error.message;
    EXPECT_EQ(merges(given), 0);
    // Whatever that leaves, the verdict is the checker's and every defect is located.
    const VerifyResult v = verify(in, given.mesh);
    EXPECT_EQ(result_inconsistency(in, given, &v), "");
    if (!v.valid) { EXPECT_FALSE(given.report.defects.empty()); }
}

TEST(RealMaps, EveryFoldLeftUnrepairedSaysWhyAndWhere) {
    // duck_miq_16 x8 at its own scale, the repaired rung alone: folds the repair cannot re-embed
    // are named with what the last attempt found (the region, and the triangle left inverted or
    // the vertex that winds wrongly), not only that it failed.
    Input in;
    if (const std::string why = read_real_map("paper", "duck_miq_16", in); !why.empty()) GTEST_SKIP() << why;
    ASSERT_EQ(transforms::scale_uvs(in, 8), 0);
    const Result r = first_rung(in);
    ASSERT_TRUE(r.ok()) << r.error.message;
    ASSERT_GT(r.report.unrepaired_regions, 0) << "duck_miq_16 x8 is repaired now: pick another map";
    int named = 0;
    for (const Defect& d : r.report.explanations) {
        if (d.kind != DefectKind::FoldOverNotRepaired) continue;
        ++named;
        if (d.message.find("all its corners") != std::string::npos) continue; // no region could hold it
        EXPECT_NE(d.message.find(" rings (a region of "), std::string::npos) << d.message;
        const bool inverted = d.message.find("left ") != std::string::npos &&
                              d.message.find("inverted (the first: input triangle ") != std::string::npos;
        const bool winding = d.message.find("winds ") != std::string::npos;
        const bool other = d.message.find("Gauss-Bonnet") != std::string::npos ||
                           d.message.find("area is not positive") != std::string::npos ||
                           d.message.find("larger than") != std::string::npos;
        EXPECT_TRUE(inverted || winding || other) << d.message;
        if (inverted) {
            // The triangle named is one of the input's.
            const std::size_t at = d.message.find("input triangle ", d.message.find("inverted (the first"));
            const int t = std::stoi(d.message.substr(at + 15));
            ASSERT_GE(t, 0);
            ASSERT_LT(static_cast<std::size_t>(t), in.triangles.size());
        }
    }
    EXPECT_EQ(named, r.report.unrepaired_regions);
}

/// duck_miq_28: MIQ rounded singularities onto grid points that the map round them does not
/// wind about (a valence-3 cone whose rings turn -1 quarter turns about its grid point, a
/// valence-5 one whose rings turn 1). No fold-free map keeps such a singularity at its grid
/// point with the rim fixed, so the repair names the proof instead of untangling: the rim's
/// quarter turns differ from the valence by whole turns, and the singularity lies on a grid
/// point in every corner of the raw map.
TEST(RealMaps, ARimShortOfItsSingularitysAngleIsNamedAsTheProof) {
    Input in;
    if (const std::string why = read_real_map("paper", "duck_miq_28", in); !why.empty()) GTEST_SKIP() << why;
    const Result r = first_rung(in);
    ASSERT_TRUE(r.ok()) << r.error.message;
    const std::string key = "its rim turns ";
    int proofs = 0;
    for (const Defect& d : r.report.explanations) {
        if (d.kind != DefectKind::FoldOverNotRepaired) continue;
        for (std::size_t at = d.message.find(key); at != std::string::npos; at = d.message.find(key, at + 1)) {
            int turns = 0, vertex = -1, valence = 0;
            ASSERT_EQ(std::sscanf(d.message.c_str() + at,
                                  "its rim turns %d quarter turns about the grid point of input vertex %d (a "
                                  "singularity of valence %d",
                                  &turns, &vertex, &valence),
                      3)
                << d.message;
            ++proofs;
            EXPECT_NE(turns, valence) << d.message;
            EXPECT_EQ(((turns - valence) % 4 + 4) % 4, 0) << d.message;
            ASSERT_GE(vertex, 0);
            ASSERT_LT(static_cast<std::size_t>(vertex), in.positions.size());
            int corners = 0;
            for (std::size_t c = 0; c < in.uvs.size(); ++c) {
                if (in.triangles[c / 3][c % 3] != vertex) continue;
                ++corners;
                EXPECT_EQ(in.uvs[c][0], std::round(in.uvs[c][0])) << d.message;
                EXPECT_EQ(in.uvs[c][1], std::round(in.uvs[c][1])) << d.message;
            }
            EXPECT_GT(corners, 0);
        }
    }
    EXPECT_GT(proofs, 0) << "no fold of duck_miq_28 is named with a rim short of its singularity";
    // Each is also a typed explanation, placed at the singularity.
    EXPECT_GT(expect_proofs_placed(in, r)[0], 0) << "no RimShortOfSingularity among duck_miq_28's explanations";
}

/// decimated-knight_miq_18: a flipped triangle whose three corners are singularities (solver
/// rounding crowds its 92 singularities onto 502 vertices). No fold-free map keeps them at their
/// grid points, and the report says so with the triangle, at the map's own scale and on the
/// best-effort mesh of its map refined (its grid point then at that scale).
TEST(RealMaps, AFoldBetweenThreeSingularitiesIsNamedAsTheProof) {
    Input in;
    if (const std::string why = read_real_map("miq-more", "decimated-knight_miq_18", in); !why.empty())
        GTEST_SKIP() << why;
    EXPECT_GT(expect_proofs_placed(in, first_rung(in))[1], 0) << "no FoldPinnedBySingularities at its own scale";
    Options refined;
    refined.max_refinement = 2;
    refined.best_effort = true;
    const Result r = extract(in, refined);
    ASSERT_TRUE(r.ok()) << r.error.message;
    ASSERT_EQ(r.mesh.grid_scale, 2) << "the best effort is no longer the map refined x2: pick another case";
    EXPECT_GT(expect_proofs_placed(in, r)[1], 0) << "no FoldPinnedBySingularities on the refined mesh";
}

/// decimated-knight_miq_18 gives no valid mesh as extracted at any scale: at x2 one hole is left,
/// whose rim passes singularities with folded fans round the fold between pinned singularities,
/// and lays out in no grid. The last resort fills it from its rim, and the mesh is valid: the
/// checker accepts it with its provenance and without (as `qex check --param` judges it, at its
/// grid scale), the proof of the fold and the filled hole are explained, and the quads added are
/// those the explanation counts. Without the last resort the map ends invalid.
TEST(RealMaps, AHoleRoundAFoldBetweenPinnedSingularitiesIsFilledAsTheLastResort) {
    Input in;
    if (const std::string why = read_real_map("miq-more", "decimated-knight_miq_18", in); !why.empty())
        GTEST_SKIP() << why;
    Options no_last_resort;
    no_last_resort.fill_holes = false;
    const Result plain = extract(in, no_last_resort);
    ASSERT_TRUE(plain.ok()) << plain.error.message;
    EXPECT_FALSE(plain.check.valid) << "valid without the last resort: pick another case";
    const Result r = extract(in);
    ASSERT_TRUE(r.ok()) << r.error.message;
    ASSERT_TRUE(r.check.valid) << (r.check.violations.empty() ? "" : r.check.violations[0].message);
    EXPECT_GT(r.mesh.grid_scale, 1);
    EXPECT_EQ(result_inconsistency(in, r), "");
    EXPECT_GT(expect_proofs_placed(in, r)[1], 0) << "no FoldPinnedBySingularities beside the filled hole";
    int filled = 0, holes = 0;
    for (const Defect& d : r.report.explanations) {
        if (d.kind != DefectKind::HoleFilled) continue;
        ++holes;
        int quads = 0;
        const std::size_t at = d.message.find("filled with ");
        ASSERT_NE(at, std::string::npos) << d.message;
        ASSERT_EQ(std::sscanf(d.message.c_str() + at, "filled with %d quad", &quads), 1) << d.message;
        filled += quads;
    }
    EXPECT_GT(holes, 0);
    // The mesh without the last resort at that scale, refined alone, lacks exactly those quads.
    Options at_scale = no_last_resort;
    at_scale.max_refinement = r.mesh.grid_scale;
    at_scale.best_effort = true;
    const Result unfilled = extract(in, at_scale);
    ASSERT_EQ(unfilled.mesh.grid_scale, r.mesh.grid_scale) << "the best effort is at another scale: pick another case";
    EXPECT_EQ(r.mesh.faces.size(), unfilled.mesh.faces.size() + static_cast<std::size_t>(filled));
    EXPECT_EQ(r.mesh.positions, unfilled.mesh.positions);
    QuadMesh bare;
    bare.positions = r.mesh.positions;
    bare.faces = r.mesh.faces;
    bare.grid_scale = r.mesh.grid_scale;
    const VerifyResult located = verify(in, bare);
    EXPECT_TRUE(located.valid) << (located.violations.empty() ? "" : located.violations[0].message);
    // The same mesh whatever the input's order (the patch is chosen on the canonical numbering).
    Input shuffled = in;
    transforms::shuffle(shuffled, 11);
    const Result s = extract(shuffled);
    ASSERT_TRUE(s.ok()) << s.error.message;
    EXPECT_EQ(s.mesh.faces, r.mesh.faces);
    EXPECT_EQ(s.mesh.positions, r.mesh.positions);
}

/// decimated-knight_miq_18 with its UVs x5 (no power of two: refinement cannot halve back to the
/// x2 that the last resort makes valid): its repaired rung joins two sheets at an edge round the
/// hole, and another rung has fewer violations. The last resort takes the first rung whose mesh
/// lost only topology, separates the sheets and fills the hole: valid at that scale, both cuts and
/// filling explained, judged without provenance too; without the last resort, invalid.
TEST(RealMaps, TheLastResortSeparatesSheetsBeforeItFillsAHole) {
    Input in;
    if (const std::string why = read_real_map("miq-more", "decimated-knight_miq_18", in); !why.empty())
        GTEST_SKIP() << why;
    (void)transforms::scale_uvs(in, 5); // rounded where x5 is inexact, as igm_transform rounds
    Options no_last_resort;
    no_last_resort.fill_holes = false;
    no_last_resort.max_refinement = 1;
    EXPECT_FALSE(extract(in, no_last_resort).check.valid) << "valid without the last resort: pick another case";
    Options own_scale;
    own_scale.max_refinement = 1;
    const Result r = extract(in, own_scale);
    ASSERT_TRUE(r.ok()) << r.error.message;
    ASSERT_TRUE(r.check.valid) << (r.check.violations.empty() ? "" : r.check.violations[0].message);
    EXPECT_EQ(r.mesh.grid_scale, 1);
    EXPECT_EQ(result_inconsistency(in, r), "");
    std::vector<DefectKind> mended;
    for (const Defect& d : r.report.explanations)
        if (d.kind == DefectKind::SheetsSeparated || d.kind == DefectKind::HoleFilled) mended.push_back(d.kind);
    ASSERT_FALSE(mended.empty());
    EXPECT_EQ(mended.front(), DefectKind::SheetsSeparated);
    EXPECT_EQ(mended.back(), DefectKind::HoleFilled);
    expect_bare_valid(in, r.mesh, "decimated-knight_miq_18 x5");
}

/// kitten_miq_10 is valid with its map refined x2, and the repair of its own scale, reused there,
/// leaves a rim short of its singularity: the proof is named on the refined map.
TEST(RealMaps, AProofOfARefinedMeshIsPlacedAtItsScale) {
    Input in;
    if (const std::string why = read_real_map("miq-more", "kitten_miq_10", in); !why.empty()) GTEST_SKIP() << why;
    const Result r = extract(in);
    ASSERT_TRUE(r.ok()) << r.error.message;
    ASSERT_TRUE(r.check.valid);
    ASSERT_GT(r.mesh.grid_scale, 1) << "kitten_miq_10 is valid at its own scale now: pick another map";
    EXPECT_GT(expect_proofs_placed(in, r)[0], 0) << "no RimShortOfSingularity on kitten_miq_10 refined";
}

/// Regions the repair's room certificate refuses are proofs too, named where a fold-over's region
/// has no fold-free map: on duck_miq_28 (angles that miss whole turns among several
/// singularities) and face_miq_10 (a region of negative signed UV area, a vertex whose triangles
/// outside leave it no room), placed, stated, and before the folds they back.
TEST(RealMaps, ARegionTheRoomCertificateRefusesIsNamedAsTheProof) {
    int regions = 0, areas = 0, vertices = 0;
    for (const auto& [folder, name] : {std::pair<const char*, const char*>{"paper", "duck_miq_28"},
                                       std::pair<const char*, const char*>{"miq-more", "face_miq_10"}}) {
        Input in;
        if (const std::string why = read_real_map(folder, name, in); !why.empty()) GTEST_SKIP() << why;
        const Result r = first_rung(in);
        ASSERT_TRUE(r.ok()) << r.error.message;
        const std::array<int, 4> count = expect_proofs_placed(in, r);
        regions += count[2];
        areas += count[3];
        for (const Defect& d : r.report.explanations)
            vertices += d.kind == DefectKind::AnglesLeaveNoRoom && d.message.rfind("input vertex ", 0) == 0;
        EXPECT_GT(count[2] + count[3], 0) << name << ": no region proved";
    }
    EXPECT_GT(regions, 0) << "no AnglesLeaveNoRoom";
    EXPECT_GT(areas, 0) << "no RegionAreaNotPositive";
    EXPECT_GT(vertices, 0) << "no AnglesLeaveNoRoom at a vertex";
}

} // namespace
} // namespace qex::testing
