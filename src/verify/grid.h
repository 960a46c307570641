// The checker's grid helpers: THE quarter-turn rotation of the checker (for integer grid points
// and for doubles alike) and the corners of a triangle. The extractor has its own
// (src/extract/grid_automorphism.h): the checker includes nothing of the extractor.
#pragma once

#include <array>
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

/// Corner k of triangle t is corner 3t + k: the next corner of the same triangle (k + 1 mod 3).
inline std::size_t next_corner(std::size_t c) { return c - c % 3 + (c % 3 + 1) % 3; }

/// The previous corner of the same triangle (k + 2 mod 3).
inline std::size_t prev_corner(std::size_t c) { return c - c % 3 + (c % 3 + 2) % 3; }

} // namespace qex::verify_detail
