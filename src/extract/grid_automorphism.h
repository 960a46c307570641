// Grid automorphisms g(a) = R90^r a + t with integer t: the transition functions of Section 3.1.
// Applied to doubles they are exact as long as the results stay below 2^53 in magnitude.
#pragma once

#include <array>
#include <cstdint>

namespace qex::detail {

using IPoint = std::array<std::int64_t, 2>;
using Point2 = std::array<double, 2>;

struct GridAutomorphism {
    int r = 0; // rotation by r * 90 degrees, 0..3
    std::int64_t tx = 0, ty = 0;

    template <class T>
    static std::array<T, 2> rotate(const std::array<T, 2>& a, int r) {
        switch (r & 3) {
            case 0: return a;
            case 1: return {-a[1], a[0]};
            case 2: return {-a[0], -a[1]};
            default: return {a[1], -a[0]};
        }
    }
    Point2 operator()(const Point2& a) const {
        const Point2 b = rotate(a, r);
        return {b[0] + static_cast<double>(tx), b[1] + static_cast<double>(ty)};
    }
    IPoint operator()(const IPoint& a) const {
        const IPoint b = rotate(a, r);
        return {b[0] + tx, b[1] + ty};
    }
    /// Rotation part only, for directions.
    int rotate_dir(int d) const { return (d + r) & 3; }
    /// (this ∘ g)(a) = this(g(a)).
    GridAutomorphism after(const GridAutomorphism& g) const {
        const IPoint t = rotate(IPoint{g.tx, g.ty}, r);
        return {(r + g.r) & 3, t[0] + tx, t[1] + ty};
    }
    GridAutomorphism inverse() const {
        const int ri = (4 - r) & 3;
        const IPoint t = rotate(IPoint{-tx, -ty}, ri);
        return {ri, t[0], t[1]};
    }
    bool is_identity() const { return r == 0 && tx == 0 && ty == 0; }
    bool operator==(const GridAutomorphism& o) const { return r == o.r && tx == o.tx && ty == o.ty; }
};

/// Unit direction R90^d (1, 0).
inline IPoint unit_dir(int d) { return GridAutomorphism::rotate(IPoint{1, 0}, d); }

inline Point2 to_point(const IPoint& p) { return {static_cast<double>(p[0]), static_cast<double>(p[1])}; }

} // namespace qex::detail
