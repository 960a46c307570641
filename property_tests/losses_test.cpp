// What the report says of a repaired map's losses and of the mesh the repair's look made. Each
// explanation that removed faces says whether a proof backs the fold-over next to it (a valid
// mesh stays valid either way): counted once, naming a fold-over the report explains, and both
// kinds found on a map that has both. A rung that takes its look's mesh reports what that
// mesh's extraction did.
#include "transform_checks.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>

namespace qex::testing {
namespace {

bool removes_faces(DefectKind k) {
    return k == DefectKind::FaceCollapsed || k == DefectKind::GhostFacesCancelled ||
           k == DefectKind::BoundaryFaceDiscarded;
}

/// The input triangle the suffix "next to the fold-over from input triangle N" names, or -1.
std::int64_t named_fold(const std::string& message) {
    const std::string key = "next to the fold-over from input triangle ";
    const std::size_t at = message.find(key);
    return at == std::string::npos ? -1 : std::stoll(message.substr(at + key.size()));
}

TEST(Losses, EachLostFaceSaysWhetherAProofBacksItsFoldOver) {
    // duck_miq_28: 17 quads for an area of 20, folds left both proved (rims short of their
    // singularities) and not (the untangler's failures).
    Input in;
    if (const std::string why = read_real_map("paper", "duck_miq_28", in); !why.empty()) GTEST_SKIP() << why;
    const Result r = extract(in, Options{});
    ASSERT_TRUE(r.ok()) << r.error.message;
    EXPECT_TRUE(r.check.valid);
    std::int64_t removing = 0, proved = 0;
    for (const Defect& d : r.report.explanations) {
        if (!removes_faces(d.kind)) continue;
        ++removing;
        const bool p = d.message.find("which a proof listed before it") != std::string::npos;
        const bool failed = d.message.find("which the repair did not re-embed") != std::string::npos;
        const bool none = d.message.find("no fold-over the repair left") != std::string::npos;
        EXPECT_EQ(int{p} + int{failed} + int{none}, 1) << d.message;
        proved += p;
        if (none) continue;
        // The fold-over it names is one the report explains as left by the repair.
        const std::int64_t fold = named_fold(d.message);
        bool explained = false;
        for (const Defect& e : r.report.explanations)
            explained = explained || (e.kind == DefectKind::FoldOverNotRepaired && e.input_element == fold);
        EXPECT_TRUE(explained) << d.message;
    }
    EXPECT_EQ(r.report.losses_proved + r.report.losses_not_proved, removing);
    EXPECT_EQ(r.report.losses_proved, proved);
    EXPECT_GT(r.report.losses_proved, 0);
    EXPECT_GT(r.report.losses_not_proved, 0);
}

TEST(Losses, NoRepairNoCount) {
    // The paper's handling alone repairs nothing: no loss is matched to a fold-over.
    Input in;
    if (const std::string why = read_real_map("paper", "duck_miq_28", in); !why.empty()) GTEST_SKIP() << why;
    Options o;
    o.repair_fold_overs = false;
    o.fallback_ladder = false;
    const Result r = extract(in, o);
    ASSERT_TRUE(r.ok()) << r.error.message;
    EXPECT_EQ(r.report.losses_proved + r.report.losses_not_proved, 0);
}

/// The rung's mesh from `name` against the map that mesh carries extracted as given: the
/// extraction's counts are the same.
void expect_counts_of_own_map(const char* name) {
    Input in;
    if (const std::string why = read_real_map("paper", name, in); !why.empty()) GTEST_SKIP() << why;
    const Result r = extract(in, Options{});
    ASSERT_TRUE(r.ok()) << r.error.message;
    Input again = in;
    again.uvs = r.mesh.map_uvs;
    Options o;
    o.repair_fold_overs = false;
    o.fallback_ladder = false;
    const Result s = extract(again, o);
    ASSERT_TRUE(s.ok()) << s.error.message;
    EXPECT_EQ(s.mesh.faces.size(), r.mesh.faces.size()) << name;
    const Report &a = r.report, &b = s.report;
    EXPECT_EQ(a.qvertices_on_vertices, b.qvertices_on_vertices) << name;
    EXPECT_EQ(a.qvertices_on_edges, b.qvertices_on_edges) << name;
    EXPECT_EQ(a.qvertices_in_faces, b.qvertices_in_faces) << name;
    EXPECT_EQ(a.ports, b.ports) << name;
    EXPECT_EQ(a.traces, b.traces) << name;
    EXPECT_EQ(a.traces_connected, b.traces_connected) << name;
    EXPECT_EQ(a.faces_traced, b.faces_traced) << name;
    EXPECT_EQ(a.merged_qvertices, b.merged_qvertices) << name;
    EXPECT_EQ(a.collapsed_faces, b.collapsed_faces) << name;
    EXPECT_EQ(a.recovered_edges, b.recovered_edges) << name;
    EXPECT_GT(a.ports, 0) << name;
}

TEST(RepairLook, TheLooksMeshReportsWhatItsExtractionDid) {
    // duck_miq_16: the repair stops at its look before the last ring, and the rung takes the
    // look's mesh and what its extraction reported (ladder.cpp, take_looked, which names those
    // fields one by one). The map the mesh carries, extracted as given, reports the same.
    expect_counts_of_own_map("duck_miq_16");
}

TEST(RepairLook, ALastRingThatChangesNothingKeepsTheLooksExtraction) {
    // duck_qc_8 and duck_miq_28: the look finds fewer quads than the area, the last ring fails
    // on every region it attempts, and the rung takes the look's extraction of the same map
    // (judged by the rung, not by the look).
    expect_counts_of_own_map("duck_qc_8");
    expect_counts_of_own_map("duck_miq_28");
}

} // namespace
} // namespace qex::testing
