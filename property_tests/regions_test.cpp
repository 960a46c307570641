// The repair's local mend works on the part of a region round what it left inverted
// (around_inverted): the free vertices within a number of triangle rings of the inverted
// triangles, their fans as the region has them, and the region's triangles round them.
#include "extract/repair/regions.h"
#include "stages_support.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <set>
#include <vector>

namespace qex::testing {
namespace {

using detail::TriMesh;
using detail::repair_impl::around_inverted;
using detail::repair_impl::positive;
using detail::repair_impl::Region;

/// The region of the free vertices within 3 rings of vertex 0 of a torus map, with one of its
/// vertices moved far across its neighbours so that triangles round it invert.
struct FoldedRegion {
    std::shared_ptr<const Input> in; ///< the 3D positions m reads
    TriMesh m;
    Region r;
};

/// A torus map's sanitized mesh, beside the input whose positions it reads.
FoldedRegion torus_map() {
    FoldedRegion out;
    out.in = std::make_shared<const Input>(make_map(torus_layout(), 3, 3));
    out.m = sanitized(*out.in);
    return out;
}

FoldedRegion folded_region() {
    FoldedRegion out = torus_map();
    TriMesh& m = out.m;
    std::vector<int> distance(static_cast<std::size_t>(m.num_vertices), -1);
    std::vector<int> label(static_cast<std::size_t>(m.num_vertices), -1);
    std::vector<int> free = detail::repair_impl::ring_neighbourhood(m, {0}, 3, distance);
    std::sort(free.begin(), free.end());
    std::vector<Region> regions = detail::repair_impl::split_regions(m, free, label);
    EXPECT_EQ(regions.size(), 1u);
    out.r = regions.front();
    const detail::repair_impl::FreeFan& moved = out.r.fans[out.r.fans.size() / 2];
    const detail::Point2 at = m.uv[moved.corners[0]];
    detail::repair_impl::place(m, moved, {at[0] + 1.5, at[1] + 0.5});
    return out;
}

/// Whether `part` lists some of `whole`'s elements in `whole`'s order.
bool in_order_within(const std::vector<int>& part, const std::vector<int>& whole) {
    std::size_t at = 0;
    for (const int x : part) {
        while (at < whole.size() && whole[at] != x) ++at;
        if (at == whole.size()) return false;
        ++at;
    }
    return true;
}

std::vector<int> vertices_of(const Region& r) {
    std::vector<int> out;
    for (const auto& fan : r.fans) out.push_back(fan.vertex);
    return out;
}

bool touches(const TriMesh& m, int f, const std::set<int>& vertices) {
    for (const int v : m.tri[f])
        if (vertices.count(v)) return true;
    return false;
}

TEST(AroundInverted, HoldsEveryInvertedTriangleAndOnlyTheRegionsOwn) {
    const FoldedRegion fr = folded_region();
    const TriMesh& m = fr.m;
    std::vector<int> inverted;
    for (const int f : fr.r.faces)
        if (!positive(m, f)) inverted.push_back(f);
    ASSERT_FALSE(inverted.empty()) << "the moved vertex should invert triangles";
    const Region sub = around_inverted(m, fr.r, 2);
    // Every inverted triangle, and only the region's triangles and fans, in the region's order.
    for (const int f : inverted)
        EXPECT_NE(std::find(sub.faces.begin(), sub.faces.end(), f), sub.faces.end()) << "triangle " << f;
    const std::vector<int> some = vertices_of(sub);
    EXPECT_TRUE(in_order_within(sub.faces, fr.r.faces));
    EXPECT_TRUE(in_order_within(some, vertices_of(fr.r)));
    // Its triangles are exactly the region's that touch its free vertices.
    const std::set<int> mine(some.begin(), some.end());
    for (const int f : fr.r.faces) {
        const bool listed = std::find(sub.faces.begin(), sub.faces.end(), f) != sub.faces.end();
        EXPECT_EQ(listed, touches(m, f, mine)) << "triangle " << f;
    }
    EXPECT_LT(sub.fans.size(), fr.r.fans.size()) << "two rings should not take the whole region";
}

TEST(AroundInverted, GrowsWithItsRingsToTheWholeRegion) {
    const FoldedRegion fr = folded_region();
    std::vector<std::size_t> sizes;
    for (const int rings : {0, 1, 2, 4, 64}) {
        const Region sub = around_inverted(fr.m, fr.r, rings);
        sizes.push_back(sub.fans.size());
        const std::vector<int> some = vertices_of(sub);
        const std::set<int> mine(some.begin(), some.end());
        if (rings > 0) { // the fewer rings' vertices are among these
            const Region fewer = around_inverted(fr.m, fr.r, rings / 2);
            for (const auto& fan : fewer.fans) EXPECT_TRUE(mine.count(fan.vertex)) << "rings " << rings;
        }
    }
    EXPECT_TRUE(std::is_sorted(sizes.begin(), sizes.end()));
    EXPECT_LT(sizes.front(), sizes.back());
    EXPECT_EQ(sizes.back(), fr.r.fans.size()) << "enough rings reach every vertex of a connected region";
    // Without an inverted triangle there is nothing to mend.
    FoldedRegion unfolded = torus_map();
    unfolded.r = fr.r;
    EXPECT_TRUE(around_inverted(unfolded.m, unfolded.r, 2).fans.empty());
    EXPECT_TRUE(around_inverted(unfolded.m, unfolded.r, 2).faces.empty());
}

} // namespace
} // namespace qex::testing
