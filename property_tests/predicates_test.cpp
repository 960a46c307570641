// The core's predicates against exact rational arithmetic on near-degenerate inputs, the
// packed transition table and the approximate angles of valence counting.
#include "pipeline.h"
#include "predicates.h"

#include <CGAL/Exact_rational.h>
#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace qex::detail {
namespace {

using Q = CGAL::Exact_rational;

int exact_orient(const Point2& a, const Point2& b, const Point2& c) {
    const Q d = (Q(b[0]) - Q(a[0])) * (Q(c[1]) - Q(a[1])) - (Q(b[1]) - Q(a[1])) * (Q(c[0]) - Q(a[0]));
    return CGAL::sign(d);
}

TEST(Predicates, Orient2dMatchesExactRationals) {
    std::mt19937_64 rng(42);
    std::uniform_real_distribution<double> u(-100, 100);
    for (int i = 0; i < 20000; ++i) {
        Point2 a{u(rng), u(rng)}, b{u(rng), u(rng)};
        // c nearly on the line ab: a + t (b - a), nudged by a few ulps.
        const double t = u(rng) / 37.0;
        Point2 c{a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])};
        for (int k = 0; k < (i % 4); ++k) c[k % 2] = std::nextafter(c[k % 2], i % 2 ? 1e300 : -1e300);
        ASSERT_EQ(sign(orient2d(a, b, c)), exact_orient(a, b, c)) << i;
    }
}

TEST(Predicates, Orient2dFilterHoldsAtEveryScale) {
    // The double-precision filter must leave to CGAL every case it cannot decide: near-collinear
    // points scaled from 2^-1000 (products that underflow) to 2^50 (near the 2^52 inputs may
    // reach), translated far from the origin, and with exactly collinear and repeated points.
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int i = 0; i < 40000; ++i) {
        const double scale = std::ldexp(1.0, static_cast<int>(rng() % 1051) - 1000);
        const double shift = i % 3 == 0 ? 0.0 : std::ldexp(u(rng), static_cast<int>(rng() % 52));
        Point2 a{shift + scale * u(rng), shift + scale * u(rng)}, b{shift + scale * u(rng), shift + scale * u(rng)};
        const double t = u(rng) * 3;
        Point2 c{a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])};
        if (i % 5 == 1) c = a;
        for (int k = 0; k < (i % 3); ++k) c[k % 2] = std::nextafter(c[k % 2], i % 2 ? 1e300 : -1e300);
        ASSERT_EQ(sign(orient2d(a, b, c)), exact_orient(a, b, c)) << i;
        ASSERT_EQ(orient2d(a, b, c), orient2d_exact(a, b, c)) << i;
    }
}

TEST(Predicates, SegmentAndTriangleTests) {
    const Point2 a{0, 0}, b{1, 0};
    EXPECT_FALSE(segment_hits_half_open({0, -1}, {0, 1}, a, b)); // only at a: excluded
    EXPECT_TRUE(segment_hits_half_open({1, -1}, {1, 1}, a, b));  // at b: included
    EXPECT_TRUE(segment_hits_half_open({0.5, 0}, {2, 0}, a, b)); // collinear overlap
    EXPECT_FALSE(segment_hits_half_open({-1, 0}, {0, 0}, a, b)); // collinear, touching a only
    EXPECT_TRUE(in_closed_triangle({0.5, 0}, {0, 0}, {1, 0}, {0, 1}));
    EXPECT_TRUE(in_closed_triangle({0.5, 0}, {0, 0}, {0, 1}, {1, 0})); // flipped triangle
    EXPECT_FALSE(in_closed_triangle({0.5, -1e-300}, {0, 0}, {1, 0}, {0, 1}));
    EXPECT_TRUE(on_segment({0.25, 0.25}, {0, 0}, {1, 1}));
    EXPECT_FALSE(on_segment({0.25, 0.2500000000000001}, {0, 0}, {1, 1}));
}

TEST(Transitions, PackedTableKeepsEveryTransitionExactly) {
    // The table keeps rotation and translation in 16 bytes; every rotation, sign and magnitude
    // up to 2^60 (beyond the 2^54 that validated maps reach) must come back unchanged.
    TransitionTable table;
    std::vector<GridAutomorphism> all;
    const std::int64_t big = std::int64_t{1} << 60;
    for (int r = 0; r < 4; ++r)
        for (std::int64_t tx : {std::int64_t{0}, std::int64_t{1}, std::int64_t{-1}, std::int64_t{-7}, big - 1, -big,
                                std::int64_t{1} << 53})
            for (std::int64_t ty : {std::int64_t{0}, std::int64_t{-3}, big, -big, std::int64_t{5}})
                all.push_back({r, tx, ty});
    table.allocate(all.size());
    for (std::size_t i = 0; i < all.size(); ++i) table.set(i, all[i]);
    for (std::size_t i = 0; i < all.size(); ++i) {
        EXPECT_EQ(table[i].r, all[i].r) << i;
        EXPECT_EQ(table[i].tx, all[i].tx) << i;
        EXPECT_EQ(table[i].ty, all[i].ty) << i;
    }
}

TEST(Valences, ApproximateAnglesStayWithinTheirBound) {
    // Valence counting trusts approximate_angle only with kApproximateAngleError per corner.
    // The polynomial's own error is about 1e-5: sampled densely over every direction of the
    // upper half-plane and at magnitudes from 1e-300 to 1e300, it must stay within a fifth of
    // the bound, so the bound keeps a margin.
    double worst = 0.0;
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> turn(0.0, M_PI);
    std::uniform_int_distribution<int> exponent(-300, 300);
    for (int i = 0; i <= 2000000; ++i) {
        const double t = i <= 1000000 ? M_PI * i / 1000000 : turn(rng);
        const double scale = i <= 1000000 ? 1.0 : std::ldexp(1.0, exponent(rng));
        const double y = std::abs(std::sin(t)) * scale, x = std::cos(t) * scale;
        if (!(std::max(y, std::abs(x)) > 0)) continue;
        worst = std::max(worst, std::abs(approximate_angle(y, x) - std::atan2(y, x)));
    }
    EXPECT_LT(worst, kApproximateAngleError / 5) << "largest error " << worst;
    // Axis directions and extreme ratios are exact enough too; zero and non-finite give NaN.
    EXPECT_NEAR(approximate_angle(0.0, 1.0), 0.0, 1e-12);
    EXPECT_NEAR(approximate_angle(1.0, 0.0), M_PI_2, 1e-12);
    EXPECT_NEAR(approximate_angle(0.0, -1.0), M_PI, 1e-12);
    EXPECT_NEAR(approximate_angle(1e-300, 1e300), 0.0, 1e-12);
    EXPECT_TRUE(std::isnan(approximate_angle(0.0, 0.0)));
    EXPECT_TRUE(std::isnan(approximate_angle(1.0, INFINITY)));
}

} // namespace
} // namespace qex::detail
