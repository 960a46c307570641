// The working mesh's map state (transitions, valences, singularities, triangle signs) belongs to
// one connectivity: a collapse replaces the connectivity and empties the map state, and the
// sanitize rounds always end on a map state that describes the mesh, whatever the round cap.
#include "pipeline.h"
#include "test_support.h"

#include <gtest/gtest.h>

namespace qex::testing {
namespace {

/// A torus map with one zero-length UV edge, which the sanitize rounds collapse.
Input map_with_collapsible_edge() {
    Input in = make_map(torus_layout(), 2, 4);
    insert_collapsed_edge(in, 5, 0);
    return in;
}

TEST(MapState, CollapseEmptiesTheMapState) {
    const Input in = map_with_collapsible_edge();
    detail::TriMesh m;
    ASSERT_EQ(detail::validate(in, 1, m).code, ErrorCode::None);
    Report report;
    detail::StageTimer timer(report);
    ASSERT_EQ(detail::sanitize_until_stable(m, in, {}, report, timer, 0).code, ErrorCode::None);
    ASSERT_TRUE(m.map.sized_for(m.num_faces(), m.num_vertices));
    const int faces_before = m.num_faces();
    std::int64_t collapsed = 0;
    ASSERT_EQ(detail::collapse(m, collapsed).code, ErrorCode::None);
    ASSERT_GT(collapsed, 0);
    EXPECT_LT(m.num_faces(), faces_before);
    // The old connectivity's arrays are gone, not left behind at their old sizes.
    EXPECT_EQ(m.map.transition.size(), 0u);
    EXPECT_TRUE(m.map.face_sign.empty());
    EXPECT_TRUE(m.map.singular.empty());
    EXPECT_FALSE(m.map.sized_for(m.num_faces(), m.num_vertices));
}

TEST(MapState, SanitizeRoundsEndOnAMapStateOfTheMesh) {
    // With a cap of 0 the only round must not end with a collapse (the driver used to break
    // after collapsing at the cap and then read the emptied arrays); with larger caps the
    // collapse happens and the next round computes the state again.
    const Input in = map_with_collapsible_edge();
    for (int cap : {0, 1, 2, detail::kMaxSanitizeRounds}) {
        detail::TriMesh m;
        ASSERT_EQ(detail::validate(in, 1, m).code, ErrorCode::None);
        Report report;
        detail::StageTimer timer(report);
        ASSERT_EQ(detail::sanitize_until_stable(m, in, {}, report, timer, cap).code, ErrorCode::None);
        EXPECT_TRUE(m.map.sized_for(m.num_faces(), m.num_vertices)) << "cap " << cap;
        EXPECT_EQ(report.collapsed_edges > 0, cap > 0) << "cap " << cap;
        // Every stage after sanitization reads the state: none may find it stale.
        detail::count_valences(m, true);
        EXPECT_TRUE(m.map.sized_for(m.num_faces(), m.num_vertices)) << "cap " << cap;
    }
}

TEST(MapState, TheMapWithACollapsedEdgeExtractsValid) {
    const Input in = map_with_collapsible_edge();
    const Result r = extract_valid(in);
    EXPECT_GT(r.report.collapsed_edges, 0);
    EXPECT_EQ(static_cast<std::int64_t>(r.mesh.faces.size()), expected_quads(torus_layout(), 2));
}

} // namespace
} // namespace qex::testing
