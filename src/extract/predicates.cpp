// Exact predicates, the only translation unit of the core that includes CGAL.
#include "predicates.h"

#include "qex/extract.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Exact_rational.h>

#include <algorithm>

namespace qex::detail {
namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using KPoint = Kernel::Point_2;

KPoint k(const Point2& p) { return KPoint(p[0], p[1]); }

// Points are compared coordinate-wise in doubles: comparisons of doubles are exact.
bool between(double x, double lo, double hi) { return std::min(lo, hi) <= x && x <= std::max(lo, hi); }
} // namespace

Orientation orient2d_exact(const Point2& a, const Point2& b, const Point2& c) {
    switch (CGAL::orientation(k(a), k(b), k(c))) {
        case CGAL::LEFT_TURN: return Orientation::Positive;
        case CGAL::RIGHT_TURN: return Orientation::Negative;
        default: return Orientation::Collinear;
    }
}

bool on_segment(const Point2& x, const Point2& p, const Point2& q) {
    // The box test first: it is exact too, and it spares most calls the orientation test.
    return between(x[0], p[0], q[0]) && between(x[1], p[1], q[1]) && orient2d(p, q, x) == Orientation::Collinear;
}

bool in_closed_triangle(const Point2& x, const Point2& a, const Point2& b, const Point2& c) {
    const int s = sign(orient2d(a, b, c));
    if (s == 0) return on_segment(x, a, b) || on_segment(x, b, c) || on_segment(x, c, a);
    const int s0 = sign(orient2d(a, b, x)), s1 = sign(orient2d(b, c, x)), s2 = sign(orient2d(c, a, x));
    return s0 * s >= 0 && s1 * s >= 0 && s2 * s >= 0;
}

bool segment_hits_half_open(const Point2& p, const Point2& q, const Point2& a, const Point2& b) {
    const int op = sign(orient2d(a, b, p)), oq = sign(orient2d(a, b, q));
    if (op * oq > 0) return false;
    if (op == 0 && oq == 0) {
        // Collinear: compare along the dominant axis of (a, b); the overlap must hold a point != a.
        const int ax = std::abs(b[0] - a[0]) >= std::abs(b[1] - a[1]) ? 0 : 1;
        const double dir = b[ax] > a[ax] ? 1.0 : -1.0;
        // Parametrise by t = dir * (x - a[ax]); segment (a, b] is t in (0, |b - a|].
        const double t0 = dir * (p[ax] - a[ax]), t1 = dir * (q[ax] - a[ax]);
        const double lo = std::max(std::min(t0, t1), 0.0);
        const double hi = std::min(std::max(t0, t1), dir * (b[ax] - a[ax]));
        if (lo > hi) return false;
        return hi > 0.0; // overlap [lo, hi] contains a point other than a (t = 0)
    }
    const int oa = sign(orient2d(p, q, a)), ob = sign(orient2d(p, q, b));
    if (oa * ob > 0) return false;
    // The unique intersection point is a itself exactly when a lies on the line of [p, q].
    if (oa == 0) return false;
    return true;
}

std::array<double, 3> barycentric_exact(const Point2& x, const Point2& a, const Point2& b, const Point2& c) {
    using Q = CGAL::Exact_rational;
    const Q ax(a[0]), ay(a[1]), bx(b[0]), by(b[1]), cx(c[0]), cy(c[1]), px(x[0]), py(x[1]);
    const Q det = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
    if (det == 0) return {1.0 / 3, 1.0 / 3, 1.0 / 3};
    const Q wb = ((px - ax) * (cy - ay) - (py - ay) * (cx - ax)) / det;
    const Q wc = ((bx - ax) * (py - ay) - (by - ay) * (px - ax)) / det;
    return {CGAL::to_double(Q(1) - wb - wc), CGAL::to_double(wb), CGAL::to_double(wc)};
}

} // namespace qex::detail

namespace qex {

std::vector<std::int8_t> uv_orientations(const Input& input) {
    std::vector<std::int8_t> out(input.triangles.size(), 0);
    for (std::size_t t = 0; t < out.size() && 3 * t + 2 < input.uvs.size(); ++t)
        out[t] = static_cast<std::int8_t>(
            detail::sign(detail::orient2d(input.uvs[3 * t], input.uvs[3 * t + 1], input.uvs[3 * t + 2])));
    return out;
}

} // namespace qex
