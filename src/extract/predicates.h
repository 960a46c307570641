// The one place where geometric decisions are taken: exact orientation tests (CGAL's filtered
// predicates, implemented in predicates.cpp so that CGAL stays in a single translation unit).
#pragma once

#include <array>

namespace qex::detail {

using Point2 = std::array<double, 2>;

enum class Orientation : signed char { Negative = -1, Collinear = 0, Positive = 1 };

/// Sign of det(b - a, c - a), exactly, by CGAL's filtered predicate.
Orientation orient2d_exact(const Point2& a, const Point2& b, const Point2& c);

/// Sign of det(b - a, c - a), exactly. The determinant in doubles decides wherever its rounding
/// error, bounded as Shewchuk bounds it (Adaptive Precision Floating-Point Arithmetic, 1997: his
/// first error bound, (3 + 16 eps) eps of the two products' magnitudes), cannot change its sign;
/// elsewhere, and where the products could have underflowed, CGAL decides. The differences'
/// signs are exact (a rounded difference is zero only when it is), so products of opposite signs
/// decide at once.
inline Orientation orient2d(const Point2& a, const Point2& b, const Point2& c) {
    const double left = (a[0] - c[0]) * (b[1] - c[1]), right = (a[1] - c[1]) * (b[0] - c[0]);
    const double det = left - right;
    double sum;
    if (left > 0.0) {
        if (right <= 0.0) return det > 0.0 ? Orientation::Positive : orient2d_exact(a, b, c);
        sum = left + right;
    } else if (left < 0.0) {
        if (right >= 0.0) return det < 0.0 ? Orientation::Negative : orient2d_exact(a, b, c);
        sum = -left - right;
    } else {
        return orient2d_exact(a, b, c);
    }
    // 2^-53 (3 + 16 2^-53); sums below 2^-900 may hold underflowed products.
    constexpr double kBound = (3.0 + 16.0 * 0x1p-53) * 0x1p-53;
    if (sum > 0x1p-900) {
        if (det > kBound * sum) return Orientation::Positive;
        if (-det > kBound * sum) return Orientation::Negative;
    }
    return orient2d_exact(a, b, c);
}

inline int sign(Orientation o) { return static_cast<int>(o); }

/// Exact test: does the closed segment [p, q] intersect the half-open segment (a, b]?
bool segment_hits_half_open(const Point2& p, const Point2& q, const Point2& a, const Point2& b);

/// Exact test: is x on the closed segment [p, q]?
bool on_segment(const Point2& x, const Point2& p, const Point2& q);

/// Exact test: is x in the closed triangle (a, b, c) of any orientation (a segment or point if degenerate)?
bool in_closed_triangle(const Point2& x, const Point2& a, const Point2& b, const Point2& c);

/// Barycentric coordinates of x in triangle (a, b, c), computed exactly and rounded at the end
/// (for slivers, where double arithmetic loses them); thirds if the triangle is degenerate.
std::array<double, 3> barycentric_exact(const Point2& x, const Point2& a, const Point2& b, const Point2& c);

} // namespace qex::detail
