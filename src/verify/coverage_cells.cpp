// The coverage check's required cells (coverage.h): each input triangle owns the cells whose
// reference point lies inside it; a cell it holds whole is required, any other is judged by a
// flood over the triangles across it (positive, far from fold-overs, one chart, no boundary
// across it). A required cell whose corners are not one face's is kept for the reports.
#include "coverage.h"

#include <algorithm>
#include <cstdint>
#include <cmath>
#include <cstdlib>

namespace qex::verify_detail::coverage {
namespace {

/// The closed box [lo, hi] and the closed segment ab meet (separating axes: the box's and the
/// segment's normal).
bool segment_meets_box(const P2& a, const P2& b, const P2& lo, const P2& hi) {
    if (std::max(a[0], b[0]) < lo[0] || std::min(a[0], b[0]) > hi[0] || std::max(a[1], b[1]) < lo[1] ||
        std::min(a[1], b[1]) > hi[1])
        return false;
    const P2 corners[4] = {lo, {hi[0], lo[1]}, hi, {lo[0], hi[1]}};
    bool left = false, right = false;
    for (const P2& c : corners) {
        const double s = cross(a, b, c);
        left = left || s >= 0;
        right = right || s <= 0;
    }
    return left && right;
}

/// A positive triangle's edges as lines: the signed distance of a point inside from each.
struct EdgeLines {
    std::array<P2, 3> from, along;   ///< each edge's start and vector
    std::array<double, 3> inverse{}; ///< 1 / its length (0 for a point)
    explicit EdgeLines(const std::array<P2, 3>& q) {
        for (std::size_t k = 0; k < 3; ++k) {
            from[k] = q[k];
            along[k] = {q[(k + 1) % 3][0] - q[k][0], q[(k + 1) % 3][1] - q[k][1]};
            const double len = norm(along[k][0], along[k][1]);
            inverse[k] = len > 0 ? 1 / len : 0;
        }
    }
    /// Distance from x to the nearest edge's line, positive inside (negative outside).
    double depth(const P2& x) const {
        double d = HUGE_VAL;
        for (std::size_t k = 0; k < 3; ++k)
            d = std::min(d, (along[k][0] * (x[1] - from[k][1]) - along[k][1] * (x[0] - from[k][0])) * inverse[k]);
        return d;
    }
    /// The unit cell centred at x lies inside, farther than `band` from every edge's line.
    bool holds_cell(const P2& x, double band) const {
        for (std::size_t k = 0; k < 3; ++k) {
            const double d = (along[k][0] * (x[1] - from[k][1]) - along[k][1] * (x[0] - from[k][0])) * inverse[k];
            // The corners' distances differ from the centre's by at most this (an affine function).
            const double spread = 0.5 * (std::abs(along[k][0]) + std::abs(along[k][1])) * inverse[k];
            if (!(d - spread > band)) return false;
        }
        return true;
    }
};

} // namespace

CellState Coverage::judge_cell(std::uint32_t t0, const GridPoint& p, RequiredCell& cell, Scratch& scratch) const {
    const GridPoint corners[4] = {p, {p[0] + 1, p[1]}, {p[0] + 1, p[1] + 1}, {p[0], p[1] + 1}};
    cell.cell = {t0, p};
    // The triangles over the cell's interior (shrunk by the band): from the owner across the edges
    // that cross it. Where the map is locally injective over the cell they are connected so.
    scratch.next();
    auto &stamp = scratch.stamp, &queue = scratch.queue;
    auto& to = scratch.to;
    stamp[t0] = scratch.generation;
    to[t0] = Transition{};
    queue.assign(1, t0);
    for (std::size_t head = 0; head < queue.size(); ++head) {
        if (queue.size() > kCellTriangles) return CellState::Unknown;
        const std::uint32_t t = queue[head];
        // The cell in t's chart: its corners carried, the lowest of each coordinate.
        GridPoint lo = map_point(to[t], corners[0]);
        for (std::size_t i = 1; i < 4; ++i) {
            const GridPoint c = map_point(to[t], corners[i]);
            lo = {std::min(lo[0], c[0]), std::min(lo[1], c[1])};
        }
        const std::array<P2, 3> q = uv(t, {static_cast<double>(lo[0]), static_cast<double>(lo[1])});
        // A cone inside the cell or on a side (not at a corner) breaks its grid.
        for (std::size_t k = 0; k < 3; ++k) {
            if (!map_.singular[static_cast<std::size_t>(in_.triangles[t][k])]) continue;
            const P2& x = q[k];
            const bool in_cell =
                x[0] > -claim_reach_ && x[0] < 1 + claim_reach_ && x[1] > -claim_reach_ && x[1] < 1 + claim_reach_;
            const bool at_corner = (std::abs(x[0]) <= claim_reach_ || std::abs(x[0] - 1) <= claim_reach_) &&
                                   (std::abs(x[1]) <= claim_reach_ || std::abs(x[1] - 1) <= claim_reach_);
            if (in_cell && !at_corner) return CellState::Cone;
        }
        const P2 slo{kBoundaryBand, kBoundaryBand}, shi{1 - kBoundaryBand, 1 - kBoundaryBand};
        for (std::size_t k = 0; k < 3; ++k) {
            if (!segment_meets_box(q[k], q[(k + 1) % 3], slo, shi)) continue;
            const std::size_t c = 3 * t + k;
            const std::int64_t o = map_.edges.opposite[c];
            if (o < 0) return map_.edges.partner[c] >= 0 ? CellState::Unknown : CellState::Cut;
            const auto n = static_cast<std::uint32_t>(o / 3);
            if (map_.fold_over[n] || !far_[n]) return CellState::NearFold;
            Transition m;
            if (!compose(map_.edges.across[c], to[t], m)) return CellState::Unknown;
            if (stamp[n] == scratch.generation) {
                if (!same(m, to[n])) return CellState::Cone; // the charts disagree: a cone inside
                continue;
            }
            stamp[n] = scratch.generation;
            to[n] = m;
            queue.push_back(n);
        }
    }
    // Each corner in the flooded triangle nearest to it (the first of equals).
    for (std::size_t i = 0; i < 4; ++i) {
        double best = HUGE_VAL;
        for (const std::uint32_t t : queue) {
            const GridPoint c = map_point(to[t], corners[i]);
            const double d = triangle_distance({0, 0}, uv(t, {static_cast<double>(c[0]), static_cast<double>(c[1])}));
            if (d < best) best = d, cell.corner[i] = {t, c};
        }
        if (!(best <= kCornerReach)) return CellState::Unknown;
    }
    return CellState::Required;
}

bool Coverage::owns(std::uint32_t t, double depth, const P2& x, Scratch& scratch) const {
    if (depth > claim_reach_) return true;
    if (depth < -claim_reach_) return false;
    // Near an edge: the smallest triangle that holds x strictly, else the smallest near it.
    reach_from(t, x, scratch);
    std::uint32_t holder = UINT32_MAX, near = UINT32_MAX;
    for (const auto& [n, y] : scratch.reach) {
        const std::array<P2, 3> p = uv(n, y);
        near = std::min(near, n);
        if (cross(p[0], p[1], {0, 0}) > 0 && cross(p[1], p[2], {0, 0}) > 0 && cross(p[2], p[0], {0, 0}) > 0)
            holder = std::min(holder, n);
    }
    return (holder != UINT32_MAX ? holder : near) == t;
}

std::int64_t Coverage::enumerate(std::uint32_t t, Scratch& scratch, std::vector<Found>& found) const {
    const std::array<P2, 3> q = uv(t, {0, 0});
    const EdgeLines lines(q);
    std::int64_t required = 0;
    // The cells whose reference point lies within the claim reach of its UV box.
    const double u0 = std::floor(std::min({q[0][0], q[1][0], q[2][0]}) - kRefU - claim_reach_);
    const double u1 = std::max({q[0][0], q[1][0], q[2][0]}) + claim_reach_;
    const double v0 = std::floor(std::min({q[0][1], q[1][1], q[2][1]}) - kRefV - claim_reach_);
    const double v1 = std::max({q[0][1], q[1][1], q[2][1]}) + claim_reach_;
    for (double u = u0; u + kRefU <= u1; ++u)
        for (double v = v0; v + kRefV <= v1; ++v) {
            // The triangle owns the cell whose reference point lies inside it.
            const P2 x{u + kRefU, v + kRefV};
            const double depth = lines.depth(x);
            if (depth < -claim_reach_ || !owns(t, depth, x, scratch)) continue;
            Found f;
            const GridPoint lo{static_cast<std::int64_t>(u), static_cast<std::int64_t>(v)};
            if (lines.holds_cell(x, kBoundaryBand)) { // the whole cell inside its owner: its corners there
                f.cell.cell = {t, lo};
                f.cell.corner = {
                    Key{t, lo}, {t, {lo[0] + 1, lo[1]}}, {t, {lo[0] + 1, lo[1] + 1}}, {t, {lo[0], lo[1] + 1}}};
            } else if (judge_cell(t, lo, f.cell, scratch) != CellState::Required) {
                continue;
            }
            ++required;
            f.all = true;
            for (std::size_t i = 0; i < 4; ++i) {
                f.at[i] = claims_at(f.cell.corner[i]);
                f.all = f.all && f.at[i].first != f.at[i].second;
            }
            if (!f.all || face_at(f.at) < 0) found.push_back(f);
        }
    return required;
}

} // namespace qex::verify_detail::coverage
