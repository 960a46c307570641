// Valence counting (Algorithm 8): the fan is split into runs of equal orientation and every
// flipped run counts 2*pi plus its (negative) angle sum, which recovers the valence of a
// singularity whose fan lost a full turn to a fold-over (Figure 2 (d)). Beside it the plain signed
// angle sum ("winding valence") is kept: a fold-over next to a regular vertex makes Algorithm 8
// count 8 where the winding valence correctly says 4, so branch points (r = 0 singularities) are
// decided by the winding valence.
#include "pipeline.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

namespace qex::detail {
namespace {

/// A corner of a fan, as its valence needs it.
struct Corner {
    int sign;    ///< orientation of the corner's triangle (exact)
    double y, x; ///< |cross| and dot of the corner's two edges
};

/// A corner's orientation sign and its unsigned inner angle.
using SignedAngle = std::pair<int, double>;

/// The exact orientation sign of triangle f in the parameter domain.
int triangle_sign(const TriMesh& m, int f) { return sign(orient2d(m.uv[3 * f], m.uv[3 * f + 1], m.uv[3 * f + 2])); }

/// The corners of interior vertex v's fan, clockwise. Returns whether every triangle is
/// positive; if so, `approx` is the sum of their approximate angles.
bool gather_corners(const TriMesh& m, int v, const std::vector<signed char>& tri_sign, bool singular_only,
                    std::vector<Corner>& corners, double& approx) {
    corners.clear();
    bool all_positive = true;
    approx = 0.0;
    int h = m.fan_start[v];
    do {
        const Point2& u = m.uv[h];
        const Point2& p = m.uv[TriMesh::next(h)];
        const Point2& w = m.uv[TriMesh::prev(h)];
        const int f = TriMesh::face(h);
        const int s = singular_only ? triangle_sign(m, f) : tri_sign[static_cast<std::size_t>(f)];
        const double ax = p[0] - u[0], ay = p[1] - u[1], bx = w[0] - u[0], by = w[1] - u[1];
        corners.push_back({s, std::abs(ax * by - ay * bx), ax * bx + ay * by});
        all_positive = all_positive && s > 0;
        if (all_positive) approx += approximate_angle(corners.back().y, corners.back().x);
        h = m.cw(h);
    } while (h != m.fan_start[v] && h >= 0);
    return all_positive;
}

/// Every triangle positive (the common case): the valence is the angle sum in quarter turns, and
/// approximate angles decide it whenever their sum is farther from a rounding boundary than their
/// summed error could reach; atan2 would round the same way. Returns whether they decided it.
bool decide_by_approximate_angles(TriMesh& m, int v, double approx, std::size_t corners) {
    const double quarters = 2.0 * approx / M_PI;
    const double k = std::nearbyint(quarters);
    const double reach = 2.0 / M_PI * kApproximateAngleError * static_cast<double>(corners) + 1e-9;
    if (!(0.5 - std::abs(quarters - k) > reach)) return false;
    m.map.winding_valence[v] = static_cast<int>(k);
    m.map.valence[v] = std::abs(m.map.winding_valence[v]);
    return true;
}

/// Degenerate corners join the orientation of the run before them (cyclically). Returns false
/// when every corner is degenerate.
bool join_degenerate_corners(std::vector<SignedAngle>& fan) {
    int last = 0;
    for (const auto& c : fan)
        if (c.first != 0) last = c.first;
    if (last == 0) return false;
    for (auto& c : fan) {
        if (c.first == 0) c.first = last;
        last = c.first;
    }
    return true;
}

/// Algorithm 8's angle sum of a fan of several runs, starting at the run boundary `start`:
/// positive runs count their angle sum, flipped runs 2*pi minus theirs.
double run_angle_sum(const std::vector<SignedAngle>& fan, std::size_t start) {
    double total = 0.0, run = 0.0;
    int run_sign = fan[start].first;
    for (std::size_t i = 0; i < fan.size(); ++i) {
        const auto& c = fan[(start + i) % fan.size()];
        if (c.first != run_sign) {
            total += run_sign < 0 ? 2.0 * M_PI - run : run;
            run = 0.0;
            run_sign = c.first;
        }
        run += c.second;
    }
    total += run_sign < 0 ? 2.0 * M_PI - run : run;
    return total;
}

/// The winding valence and Algorithm 8's valence of v from exact angles (atan2); both stay 4
/// when every triangle of the fan is degenerate. `fan` is scratch.
void count_by_runs(TriMesh& m, int v, const std::vector<Corner>& corners, std::vector<SignedAngle>& fan) {
    fan.clear();
    double winding = 0.0;
    for (const Corner& c : corners) {
        const double angle = std::atan2(c.y, c.x);
        fan.emplace_back(c.sign, angle);
        winding += c.sign < 0 ? -angle : angle;
    }
    if (!join_degenerate_corners(fan)) return; // every triangle degenerate: no valence
    // Rotate so the fan starts at a run boundary, then sum run by run.
    std::size_t start = 0;
    while (start < fan.size() && fan[start].first == fan[(start + fan.size() - 1) % fan.size()].first) ++start;
    m.map.winding_valence[v] = static_cast<int>(std::lround(2.0 * winding / M_PI));
    if (start == fan.size()) { // a single run: the whole fan has one orientation
        if (fan[0].first > 0) {
            m.map.valence[v] = std::abs(m.map.winding_valence[v]);
            return;
        }
        // The whole fan flipped: a fold covering every triangle of it. Its transitions still turn
        // by the signed sum, so once unfolded its angle is a positive number of quarter turns
        // congruent to it: the fewest (a flipped run's angle phi counts as 2*pi*j - phi). Not
        // |winding|: a mirrored fan of -3 quarter turns has transitions that turn by +1, so it
        // unfolds to 1 (or 5), never 3. Whole turns stay as the winding has them (a branch point
        // of 8 stays 8; the winding decides those, see above).
        const int winding = m.map.winding_valence[v], turn = ((winding % 4) + 4) % 4;
        m.map.valence[v] = turn == 0 ? std::max(4, std::abs(winding)) : turn;
        return;
    }
    m.map.valence[v] = static_cast<int>(std::lround(2.0 * run_angle_sum(fan, start) / M_PI));
}

/// The valences of the interior vertices (only the singular ones if `singular_only`), each fan
/// on its own: the parallel loop does not change the result.
void count_fans(TriMesh& m, bool singular_only, const std::vector<signed char>& tri_sign) {
    const auto count = static_cast<std::int64_t>(m.vertex_order.size());
    const int parts = m.parts(3 * m.num_faces());
    for_parts(parts, parts, count, [&](int, std::int64_t begin, std::int64_t end) {
        std::vector<Corner> corners;
        std::vector<SignedAngle> fan;
        for (std::int64_t i = begin; i < end; ++i) {
            const int v = m.vertex_order[static_cast<std::size_t>(i)];
            if (m.fan_start[v] < 0 || m.on_boundary[v]) continue;
            if (singular_only && !m.map.singular[v]) continue;
            double approx = 0.0;
            const bool all_positive = gather_corners(m, v, tri_sign, singular_only, corners, approx);
            if (all_positive && decide_by_approximate_angles(m, v, approx, corners.size())) continue;
            count_by_runs(m, v, corners, fan);
        }
    });
}

} // namespace

std::vector<signed char> triangle_signs(const TriMesh& m) {
    std::vector<signed char> signs(static_cast<std::size_t>(m.num_faces()));
    const int parts = m.parts(3 * m.num_faces());
    for_parts(parts, parts, m.num_faces(), [&](int, std::int64_t begin, std::int64_t end) {
        for (auto f = static_cast<int>(begin); f < end; ++f)
            signs[static_cast<std::size_t>(f)] = static_cast<signed char>(triangle_sign(m, f));
    });
    return signs;
}

double approximate_angle(double y, double x) {
    const double ax = std::abs(x);
    const double hi = std::max(ax, y), lo = std::min(ax, y);
    if (!(hi > 0) || !std::isfinite(hi)) return std::numeric_limits<double>::quiet_NaN();
    // atan on [0, 1] by the minimax polynomial of Abramowitz and Stegun 4.4.49 (|error| <= 1e-5),
    // then the octant is undone.
    const double a = lo / hi, a2 = a * a;
    double r = a * (0.9998660 + a2 * (-0.3302995 + a2 * (0.1801410 + a2 * (-0.0851330 + a2 * 0.0208351))));
    if (y > ax) r = M_PI_2 - r;
    if (x < 0) r = M_PI - r;
    return r;
}

void count_valences(TriMesh& m, bool singular_only) {
    const int nv = m.num_vertices;
    m.map.valence.assign(nv, 4);
    m.map.winding_valence.assign(nv, 4);
    // Each triangle's orientation once, when every fan is counted (a corner's is its triangle's:
    // the exact sign does not change under a cyclic shift of the corners); empty when only the
    // few singular fans are, which take theirs per corner.
    const std::vector<signed char> tri_sign = singular_only ? std::vector<signed char>{} : triangle_signs(m);
    count_fans(m, singular_only, tri_sign);
}

} // namespace qex::detail
