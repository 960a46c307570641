// The checker's grid helpers: THE quarter-turn rotation of the checker (for integer grid points
// and for doubles alike), an exact sum test, and the corners of a triangle. The extractor has its own
// (src/extract/grid_automorphism.h): the checker includes nothing of the extractor.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>

namespace qex::verify_detail {

/// `p` turned about the origin by r quarter turns counter-clockwise (r taken mod 4, so 4 - r
/// undoes r). Only negations and swaps: exact for integers and doubles.
template <class T>
std::array<T, 2> rotate_quarter(const std::array<T, 2>& p, int r) {
    switch (r & 3) {
        case 0: return p;
        case 1: return {-p[1], p[0]};
        case 2: return {-p[0], -p[1]};
        default: return {p[1], -p[0]};
    }
}

/// Exactly x + y == z? Knuth's TwoSum gives the rounding error of x + y without error
/// (round-to-nearest, no contraction: the build uses -ffp-contract=off); the rounded sum must be
/// z and its error zero.
inline bool sums_exactly(double x, double y, double z) {
    const double s = x + y;
    const double bb = s - x;
    const double err = (x - (s - bb)) + (y - bb);
    return s == z && err == 0.0;
}

/// The signed angle at u from the direction to p to the direction to w (a flat corner is half a
/// turn: atan2 would take the sign of a zero).
inline double signed_angle(const std::array<double, 2>& u, const std::array<double, 2>& p,
                           const std::array<double, 2>& w) {
    const double ax = p[0] - u[0], ay = p[1] - u[1], bx = w[0] - u[0], by = w[1] - u[1];
    const double cross = ax * by - ay * bx, dot = ax * bx + ay * by;
    if (cross == 0.0) return dot < 0.0 ? M_PI : 0.0;
    return std::atan2(cross, dot);
}

/// Corner k of triangle t is corner 3t + k: the next corner of the same triangle (k + 1 mod 3).
inline std::size_t next_corner(std::size_t c) { return c - c % 3 + (c % 3 + 1) % 3; }

/// The previous corner of the same triangle (k + 2 mod 3).
inline std::size_t prev_corner(std::size_t c) { return c - c % 3 + (c % 3 + 2) % 3; }

} // namespace qex::verify_detail
