// The untangler's early give-up (solver.cpp, kGiveUpIteration): a run it does not stop is the run
// without it, bit for bit; a run whose first iterations leave much of its region inverted ends
// there, and fails as the run without it does.
#include "extract/repair/regions.h"
#include "extract/repair/solver.h"
#include "stages_support.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <memory>
#include <vector>

namespace qex::testing {
namespace {

using detail::TriMesh;
using detail::repair_impl::Region;

struct Untangling {
    std::unique_ptr<Input> in; ///< the 3D positions m reads (held where a copy does not move them)
    TriMesh m;
    Region r;
};

/// The region of the free vertices within `radius` rings of vertex 0 of a torus map, less those
/// at every `stride`-th place in vertex order (held fixed; stride 0: none), its largest part.
Untangling region_round_vertex_0(int radius, std::size_t stride) {
    Untangling out;
    out.in = std::make_unique<Input>(make_map(torus_layout(), 3, 3));
    out.m = sanitized(*out.in);
    const TriMesh& m = out.m;
    std::vector<int> distance(static_cast<std::size_t>(m.num_vertices), -1);
    std::vector<int> label(static_cast<std::size_t>(m.num_vertices), -1);
    std::vector<int> near = detail::repair_impl::ring_neighbourhood(m, {0}, radius, distance);
    std::sort(near.begin(), near.end());
    std::vector<int> free;
    for (std::size_t i = 0; i < near.size(); ++i)
        if (stride == 0 || i % stride != 0) free.push_back(near[i]);
    std::vector<Region> regions = detail::repair_impl::split_regions(m, free, label);
    EXPECT_FALSE(regions.empty());
    out.r = *std::max_element(regions.begin(), regions.end(),
                              [](const Region& a, const Region& b) { return a.faces.size() < b.faces.size(); });
    return out;
}

/// Moves vertex v (interior: the map is a torus) by (du, dv) in the chart of its canonical corner.
void move_vertex(TriMesh& m, int v, double du, double dv) {
    const detail::repair_impl::FreeFan fan = detail::repair_impl::free_fan(m, v);
    const detail::Point2 at = m.uv[fan.corners[0]];
    detail::repair_impl::place(m, fan, {at[0] + du, at[1] + dv});
}

std::size_t inverted(const TriMesh& m, const Region& r) {
    std::size_t n = 0;
    for (const int f : r.faces) n += !detail::repair_impl::positive(m, f);
    return n;
}

/// untangle_region on a copy of c's map, with the early give-up or without it.
bool untangled(const Untangling& c, bool give_up_early, TriMesh& out) {
    out = c.m;
    detail::repair_impl::Workspace work(out);
    work.give_up_early = give_up_early;
    return detail::repair_impl::untangle_region(out, c.r, work, detail::repair_impl::kPatienceBeforeLastRing);
}

TEST(UntanglerGivesUpEarly, ARunItDoesNotStopIsTheRunWithoutIt) {
    // One vertex pushed a cell and a half across its neighbours: untangled in the first step.
    Untangling c = region_round_vertex_0(3, 0);
    move_vertex(c.m, c.r.fans[c.r.fans.size() / 2].vertex, 1.5, 0.5);
    ASSERT_GT(inverted(c.m, c.r), 0u);
    TriMesh early, late;
    ASSERT_TRUE(untangled(c, true, early));
    ASSERT_TRUE(untangled(c, false, late));
    EXPECT_EQ(inverted(early, c.r), 0u);
    EXPECT_TRUE(early.uv == late.uv) << "the check for giving up changed the run's iterates";
}

TEST(UntanglerGivesUpEarly, AHopelessRunEndsAfterItsFirstIterations) {
    // Every third vertex of the region held fixed and thrown across the grid: the free vertices'
    // links are tangled beyond any placement of theirs, so most triangles stay inverted.
    Untangling c = region_round_vertex_0(4, 3);
    std::vector<char> is_free(static_cast<std::size_t>(c.m.num_vertices), 0);
    for (const auto& fan : c.r.fans) is_free[static_cast<std::size_t>(fan.vertex)] = 1;
    std::vector<int> held;
    for (const int f : c.r.faces)
        for (const int v : c.m.tri[f])
            if (!is_free[static_cast<std::size_t>(v)]) held.push_back(v);
    std::sort(held.begin(), held.end());
    held.erase(std::unique(held.begin(), held.end()), held.end());
    for (std::size_t i = 0; i < held.size(); ++i)
        move_vertex(c.m, held[i], i % 2 ? 2.75 : -2.25, i % 3 ? -1.75 : 2.5);
    ASSERT_GT(inverted(c.m, c.r), c.r.faces.size() / 4) << "the case should start tangled";
    TriMesh early, late;
    const bool early_ok = untangled(c, true, early);
    const bool late_ok = untangled(c, false, late);
    EXPECT_FALSE(late_ok) << "the case should be hopeless";
    EXPECT_EQ(early_ok, late_ok);
    // It stopped elsewhere than the full first step: the give-up took it.
    EXPECT_FALSE(early.uv == late.uv);
    // Only the region's free corners moved, in both runs.
    for (std::size_t k = 0; k < c.m.uv.size(); ++k) {
        const int v = c.m.tri[static_cast<int>(k / 3)][k % 3];
        if (!is_free[static_cast<std::size_t>(v)]) {
            EXPECT_EQ(early.uv[k], c.m.uv[k]) << "corner " << k;
            EXPECT_EQ(late.uv[k], c.m.uv[k]) << "corner " << k;
        }
    }
}

} // namespace
} // namespace qex::testing
