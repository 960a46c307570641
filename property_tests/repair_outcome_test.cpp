// The repair names every transition it changed (RepairOutcome::transitions_before, with the value
// before it): the memo that refinements take rebuilds the map's transitions before the repair
// from the map after it (keep_for_refinements) instead of copying them all beforehand.
#include "extract/repair/repair.h"
#include "stages_support.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

namespace qex::testing {
namespace {

using detail::RepairMemo;
using detail::TransitionTable;
using detail::TriMesh;

/// duck_miq_8 sanitized (its four co-located dipoles are merged by the repair); the input is a
/// member because the mesh points at its positions.
class RepairTransitions : public ::testing::Test {
protected:
    void SetUp() override {
        if (const std::string why = read_real_map("paper", "duck_miq_8", in); !why.empty()) GTEST_SKIP() << why;
        m = sanitized(in);
    }
    Input in;
    TriMesh m;
};

TEST_F(RepairTransitions, NamesEveryTransitionItChanged) {
    const TransitionTable before = m.map.transition;
    Report report;
    const detail::RepairOutcome out = detail::repair(m, {}, false, 1, report);
    const std::vector<std::size_t> changed = m.map.transition.differing(before);
    ASSERT_FALSE(changed.empty()) << "no merge stood: the test shows nothing";
    // Listed once each, by half-edge.
    for (std::size_t i = 1; i < out.transitions_before.size(); ++i)
        EXPECT_LT(out.transitions_before[i - 1].first, out.transitions_before[i].first);
    // Every changed one is listed, with the transition it had.
    TransitionTable rebuilt = m.map.transition;
    for (const auto& [h, g] : out.transitions_before) rebuilt.set(static_cast<std::size_t>(h), g);
    EXPECT_TRUE(rebuilt.differing(before).empty());
    for (const std::size_t h : changed)
        EXPECT_TRUE(std::any_of(out.transitions_before.begin(), out.transitions_before.end(),
                                [&](const auto& e) { return static_cast<std::size_t>(e.first) == h; }));
}

TEST_F(RepairTransitions, TheMemoTakesTheConnectivityAsBeforeTheRepair) {
    const TriMesh sanitized_map = m;
    Report report;
    RepairMemo memo;
    memo.filled = true;
    // As repair_into_memo keeps them: the changed half-edges only, with their old transitions.
    for (const auto& [h, g] : detail::repair(m, {}, false, 1, report).transitions_before)
        if (!(m.map.transition[static_cast<std::size_t>(h)] == g)) memo.transitions_before.push_back({h, g});
    ASSERT_FALSE(m.map.transition.differing(sanitized_map.map.transition).empty());
    detail::keep_for_refinements(m, memo);
    EXPECT_TRUE(memo.connectivity);
    EXPECT_TRUE(memo.transitions.differing(sanitized_map.map.transition).empty());
    EXPECT_EQ(memo.tri, sanitized_map.tri);
    EXPECT_EQ(memo.input_triangle, sanitized_map.input_triangle);
    EXPECT_EQ(memo.input_vertex, sanitized_map.input_vertex);
    EXPECT_EQ(memo.corner_vertex, sanitized_map.corner_vertex);
    EXPECT_EQ(m.input_triangle, sanitized_map.input_triangle) << "take_map reads it after the hand-over";
    EXPECT_TRUE(m.tri.empty());
    // Once only: a second hand-over (from the emptied mesh) changes nothing.
    detail::keep_for_refinements(m, memo);
    EXPECT_EQ(memo.tri, sanitized_map.tri);
    // Not into a memo the repair did not fill.
    RepairMemo empty;
    TriMesh again = sanitized_map;
    detail::keep_for_refinements(again, empty);
    EXPECT_FALSE(empty.connectivity);
    EXPECT_EQ(again.tri, sanitized_map.tri);
}

} // namespace
} // namespace qex::testing
