// The core's predicates against exact rationals on near-degenerate inputs: any disagreement aborts.
#include "fuzz_input.h"
#include "predicates.h"

#include <CGAL/Exact_rational.h>

#include <cmath>
#include <cstdlib>

using namespace qex::detail;
using Q = CGAL::Exact_rational;

namespace {
int exact_orient(const Point2& a, const Point2& b, const Point2& c) {
    return CGAL::sign((Q(b[0]) - Q(a[0])) * (Q(c[1]) - Q(a[1])) - (Q(b[1]) - Q(a[1])) * (Q(c[0]) - Q(a[0])));
}
bool exact_on_segment(const Point2& x, const Point2& p, const Point2& q) {
    return exact_orient(p, q, x) == 0 && std::min(p[0], q[0]) <= x[0] && x[0] <= std::max(p[0], q[0]) &&
           std::min(p[1], q[1]) <= x[1] && x[1] <= std::max(p[1], q[1]);
}
double bounded(double x) { return std::isfinite(x) && std::abs(x) < 1e100 ? x : 0.5; }
} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    qex::fuzz::Bytes b(data, size);
    const bool raw = b.byte() & 1;
    Point2 a, p, c;
    if (raw) {
        a = {bounded(b.raw_double()), bounded(b.raw_double())};
        p = {bounded(b.raw_double()), bounded(b.raw_double())};
        c = {bounded(b.raw_double()), bounded(b.raw_double())};
    } else {
        // c near the line (a, p), nudged by a few ulps.
        a = {b.unit() * 100, b.unit() * 100};
        p = {std::floor(b.unit() * 100), std::floor(b.unit() * 100)};
        const double t = b.unit() * 3;
        c = {a[0] + t * (p[0] - a[0]), a[1] + t * (p[1] - a[1])};
        for (int i = b.range(0, 4); i > 0; --i) c[i & 1] = std::nextafter(c[i & 1], (b.byte() & 1) ? 1e300 : -1e300);
    }
    if (sign(orient2d(a, p, c)) != exact_orient(a, p, c)) std::abort();
    if (on_segment(c, a, p) != exact_on_segment(c, a, p)) std::abort();
    return 0;
}
