// The repair's regions: as listed before their fans are made (find_regions, make_fans), and the
// local mend's part of a region round what it left inverted (around_inverted): the free vertices
// within a number of triangle rings of the inverted triangles, their fans as the region has them,
// and the region's triangles round them.
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

// The repair lists its regions first and makes a region's fans only where its attempt is admitted
// (find_regions, make_fans): made, they are what split_regions makes, and before, the region
// holds the same free vertices and triangles, the one the regions are ordered by first.
TEST(FindRegions, ListsWhatSplitRegionsMakesAndMakesTheSameFans) {
    const FoldedRegion fr = torus_map();
    const TriMesh& m = fr.m;
    std::vector<int> distance(static_cast<std::size_t>(m.num_vertices), -1);
    std::vector<int> label(static_cast<std::size_t>(m.num_vertices), -1);
    // Two regions: the free vertices near two far apart vertices, each a ring round it.
    std::vector<int> free;
    for (const int seed : {0, m.num_vertices / 2})
        for (const int v : detail::repair_impl::ring_neighbourhood(m, {seed}, 1, distance)) free.push_back(v);
    std::sort(free.begin(), free.end());
    free.erase(std::unique(free.begin(), free.end()), free.end());
    const std::vector<Region> made = detail::repair_impl::split_regions(m, free, label);
    std::vector<Region> listed = detail::repair_impl::find_regions(m, free, label);
    ASSERT_GE(made.size(), 2u);
    ASSERT_EQ(listed.size(), made.size());
    EXPECT_TRUE(std::all_of(label.begin(), label.end(), [](int l) { return l == -1; })) << "scratch left as found";
    for (std::size_t k = 0; k < made.size(); ++k) {
        EXPECT_EQ(listed[k].faces, made[k].faces) << "region " << k;
        for (std::size_t i = 1; i < listed[k].faces.size(); ++i) { // canonical: by key, ties by index
            const int f = listed[k].faces[i - 1], g = listed[k].faces[i];
            const detail::TriangleKey kf = detail::triangle_key(m, f), kg = detail::triangle_key(m, g);
            EXPECT_TRUE(detail::key_less(kf, kg) || (!detail::key_less(kg, kf) && f < g)) << "region " << k;
        }
        std::vector<int> a = vertices_of(listed[k]), b = vertices_of(made[k]);
        EXPECT_EQ(a.front(), b.front()) << "the smallest key first, region " << k;
        for (const int v : a)
            EXPECT_FALSE(detail::repair_impl::vertex_key(m, v) < detail::repair_impl::vertex_key(m, a.front()));
        EXPECT_TRUE(listed[k].fans.front().corners.empty()) << "listed, not made";
        std::sort(a.begin(), a.end());
        std::sort(b.begin(), b.end());
        EXPECT_EQ(a, b) << "region " << k;
        detail::repair_impl::make_fans(m, listed[k]);
        ASSERT_EQ(listed[k].fans.size(), made[k].fans.size());
        for (std::size_t i = 0; i < made[k].fans.size(); ++i) {
            const auto &x = listed[k].fans[i], &y = made[k].fans[i];
            if (i > 0) // canonical order: by key
                EXPECT_FALSE(detail::repair_impl::vertex_key(m, x.vertex) <
                             detail::repair_impl::vertex_key(m, listed[k].fans[i - 1].vertex));
            const detail::repair_impl::FreeFan own = detail::repair_impl::free_fan(m, x.vertex);
            EXPECT_EQ(x.corners, own.corners);
            EXPECT_EQ(x.length, own.length);
            EXPECT_EQ(x.vertex, y.vertex);
            EXPECT_EQ(x.corners, y.corners);
            EXPECT_EQ(x.length, y.length);
            ASSERT_EQ(x.to_c.size(), y.to_c.size());
            for (std::size_t c = 0; c < x.to_c.size(); ++c) EXPECT_TRUE(x.to_c[c] == y.to_c[c]);
        }
        const std::vector<int> before = listed[k].fans.front().corners;
        detail::repair_impl::make_fans(m, listed[k]); // made once: nothing changes
        EXPECT_EQ(listed[k].fans.front().corners, before);
    }
}

} // namespace
} // namespace qex::testing
