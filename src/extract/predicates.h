// The one place where geometric decisions are taken: exact orientation tests (CGAL's filtered
// predicates, implemented in predicates.cpp so that CGAL stays in a single translation unit).
#pragma once

#include <array>

namespace qex::detail {

using Point2 = std::array<double, 2>;

enum class Orientation : signed char { Negative = -1, Collinear = 0, Positive = 1 };

/// Sign of det(b - a, c - a), exactly.
Orientation orient2d(const Point2& a, const Point2& b, const Point2& c);

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
