// The input map's signed UV area, rounded to an integer exactly: the number of unit cells a
// fold-over-free closed map holds, which the located mode compares with the face count.
#include "checker.h"

#include <CGAL/Exact_rational.h>

#include <cmath>
#include <limits>
#include <string>

namespace qex::verify_detail {
namespace {

using Rational = CGAL::Exact_rational;

/// The signed area as a double sum (half the sum of the triangles' doubled areas) with a
/// rigorous bound on its rounding error: 8 machine epsilons times the summed magnitudes of the
/// products and of the partial sums (a few epsilons each would do), halved with the sum.
struct AreaSum {
    double approx = 0.0, bound = 0.0;
    bool finite = true;
};

AreaSum double_area(const Input& input) {
    AreaSum s;
    for (std::size_t f = 0; f < input.triangles.size(); ++f) {
        const auto &a = input.uvs[3 * f], &b = input.uvs[3 * f + 1], &c = input.uvs[3 * f + 2];
        const double t = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        s.finite = s.finite && std::isfinite(t);
        s.approx += t;
        s.bound += std::abs(b[0] - a[0]) * std::abs(c[1] - a[1]) + std::abs(b[1] - a[1]) * std::abs(c[0] - a[0]) +
                   std::abs(s.approx);
    }
    s.bound *= 8 * std::numeric_limits<double>::epsilon();
    s.approx *= 0.5;
    s.bound *= 0.5;
    return s;
}

/// The signed area in exact rationals.
Rational exact_area(const Input& input) {
    Rational area = 0;
    for (std::size_t f = 0; f < input.triangles.size(); ++f) {
        const auto &a = input.uvs[3 * f], &b = input.uvs[3 * f + 1], &c = input.uvs[3 * f + 2];
        area += (Rational(b[0]) - Rational(a[0])) * (Rational(c[1]) - Rational(a[1])) -
                (Rational(b[1]) - Rational(a[1])) * (Rational(c[0]) - Rational(a[0]));
    }
    area /= 2;
    return area;
}

/// `area` rounded to the nearest integer, halves upwards (towards +infinity), decided exactly:
/// lo = floor(area), then lo + 1 when the fraction area - lo is at least 1/2.
std::int64_t round_half_up(const Rational& area) {
    Rational lo = Rational(std::floor(CGAL::to_double(area)));
    while (lo > area) lo -= 1;
    while (lo + 1 <= area) lo += 1;
    const Rational frac = area - lo;
    return static_cast<std::int64_t>(CGAL::to_double(lo)) + (frac >= Rational(1, 2) ? 1 : 0);
}

} // namespace

std::vector<char> uv_degenerate_triangles(const Input& input) {
    std::vector<char> out(input.triangles.size(), 0);
    for (std::size_t f = 0; f < input.triangles.size(); ++f) {
        const auto &a = input.uvs[3 * f], &b = input.uvs[3 * f + 1], &c = input.uvs[3 * f + 2];
        const double left = (b[0] - a[0]) * (c[1] - a[1]), right = (b[1] - a[1]) * (c[0] - a[0]);
        // Shewchuk's bound for the orientation in doubles: past it the sign is the exact one.
        const double bound = 3.3306690738754716e-16 * (std::abs(left) + std::abs(right));
        if (std::isfinite(left - right) && std::abs(left - right) > bound) continue;
        if (!std::isfinite(a[0] + a[1] + b[0] + b[1] + c[0] + c[1])) continue;
        const Rational twice = (Rational(b[0]) - Rational(a[0])) * (Rational(c[1]) - Rational(a[1])) -
                               (Rational(b[1]) - Rational(a[1])) * (Rational(c[0]) - Rational(a[0]));
        out[f] = twice == 0;
    }
    return out;
}

void signed_uv_area(const Input& input, VerifyResult& r) {
    // The double sum decides the rounding when its error bound keeps it off every half; exact
    // rationals decide it only when the bound does not. The display shows the double sum, or
    // the exact area rounded to a double when the rationals were needed.
    AreaSum s = double_area(input);
    const double nearest = std::nearbyint(s.approx);
    if (s.finite && std::abs(s.approx - nearest) + s.bound < 0.5) {
        r.input_signed_uv_area_rounded = static_cast<std::int64_t>(nearest);
    } else if (s.finite) {
        const Rational area = exact_area(input);
        s.approx = CGAL::to_double(area);
        r.input_signed_uv_area_rounded = round_half_up(area);
    }
    r.input_signed_uv_area = std::to_string(s.approx);
}

} // namespace qex::verify_detail
