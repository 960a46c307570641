// Each explanation that removed faces says whether a proof backs the fold-over next to it (a
// valid mesh stays valid either way): counted once, naming a fold-over the report explains, and
// both kinds found on a map that has both.
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

} // namespace
} // namespace qex::testing
