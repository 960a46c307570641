// The coverage check's required cells (coverage.h): each input triangle owns the cells whose
// reference point lies inside it; a cell it holds whole is required, any other is judged by a
// flood over the triangles across it (positive, far from fold-overs, one chart, no boundary
// across it). A required cell whose corners are not one face's is kept for the reports. The
// same judgement reads the cells round a grid point of the boundary for the singularity match
// (BoundaryCells): a cell there that the boundary cuts may lack its face.
#include "coverage.h"

#include <algorithm>
#include <cstdint>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <utility>
#include <vector>

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

/// The closed triangle q and the closed box [lo, hi] meet (separating axes: the box's two and the
/// triangle's three edge normals; a triangle of no area in doubles by its sides).
bool triangle_meets_box(const std::array<P2, 3>& q, const P2& lo, const P2& hi) {
    for (std::size_t d = 0; d < 2; ++d)
        if (std::max({q[0][d], q[1][d], q[2][d]}) < lo[d] || std::min({q[0][d], q[1][d], q[2][d]}) > hi[d])
            return false;
    const double area = cross(q[0], q[1], q[2]);
    const P2 corners[4] = {lo, {hi[0], lo[1]}, hi, {lo[0], hi[1]}};
    for (std::size_t k = 0; k < 3; ++k) {
        if (area == 0) {
            if (segment_meets_box(q[k], q[(k + 1) % 3], lo, hi)) return true;
            continue;
        }
        bool inside = false; // a corner of the box on the triangle's side of the edge
        for (const P2& c : corners) inside = inside || (area > 0 ? 1 : -1) * cross(q[k], q[(k + 1) % 3], c) >= 0;
        if (!inside) return false;
    }
    return area != 0;
}

/// The cell with lower-left p carried by m: the lowest of its carried corners.
GridPoint carried_cell(const Transition& m, const GridPoint& p) {
    GridPoint lo = map_point(m, p);
    for (const GridPoint& d : {GridPoint{1, 0}, GridPoint{1, 1}, GridPoint{0, 1}}) {
        const GridPoint c = map_point(m, {p[0] + d[0], p[1] + d[1]});
        lo = {std::min(lo[0], c[0]), std::min(lo[1], c[1])};
    }
    return lo;
}

/// The triangles within `reach` of the grid point g of triangle t's chart, each with the map from
/// t's chart to its own, into `near` (t first): reached from t across the edges within twice the
/// reach of g, as a vertex's claims are. False where two paths carry t's chart differently (the
/// charts round g do not close up), a fold-over lies near, or the flood runs past the claims' budget.
bool near_point(const LocatedMap& map, std::uint32_t t, const GridPoint& g, double reach, Scratch& scratch,
                std::vector<std::pair<std::uint32_t, Transition>>& near) {
    if (map.fold_over[t]) return false;
    scratch.next();
    scratch.stamp[t] = scratch.generation;
    scratch.to[t] = Transition{};
    near.assign(1, {t, Transition{}});
    for (std::size_t head = 0; head < near.size(); ++head) {
        if (near.size() > kClaimTriangles) return false;
        const auto [s, m] = near[head]; // a copy: `near` grows below
        const GridPoint gs = map_point(m, g);
        const std::array<P2, 3> here = corner_uvs(map.in, s, {static_cast<double>(gs[0]), static_cast<double>(gs[1])});
        for (std::size_t k = 0; k < 3; ++k) {
            if (segment_distance({0, 0}, here[k], here[(k + 1) % 3]) > 2 * reach) continue;
            const std::size_t c = 3 * s + k;
            const std::int64_t o = map.edges.opposite[c];
            if (o < 0) continue;
            const auto n = static_cast<std::uint32_t>(o / 3);
            Transition mn;
            if (!compose(map.edges.across[c], m, mn)) return false;
            const GridPoint gn = map_point(mn, g);
            if (!(std::abs(static_cast<double>(gn[0])) < kFarGrid && std::abs(static_cast<double>(gn[1])) < kFarGrid))
                return false;
            const P2 at{static_cast<double>(gn[0]), static_cast<double>(gn[1])};
            if (triangle_distance({0, 0}, corner_uvs(map.in, n, at)) > reach) continue;
            if (map.fold_over[n]) return false;
            if (scratch.stamp[n] == scratch.generation) {
                if (!same(mn, scratch.to[n])) return false;
                continue;
            }
            scratch.stamp[n] = scratch.generation;
            scratch.to[n] = mn;
            near.push_back({n, mn});
        }
    }
    return true;
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

CellState judge_cell(const CellRules& rules, std::uint32_t t0, const GridPoint& p, RequiredCell& cell,
                     Scratch& scratch) {
    const LocatedMap& map = rules.map;
    const double reach = rules.claim_reach;
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
        const std::array<P2, 3> q = corner_uvs(map.in, t, {static_cast<double>(lo[0]), static_cast<double>(lo[1])});
        // A cone inside the cell or on a side (not at a corner) breaks its grid.
        for (std::size_t k = 0; k < 3; ++k) {
            if (!map.singular[static_cast<std::size_t>(map.in.triangles[t][k])]) continue;
            const P2& x = q[k];
            const bool in_cell = x[0] > -reach && x[0] < 1 + reach && x[1] > -reach && x[1] < 1 + reach;
            const bool at_corner = (std::abs(x[0]) <= reach || std::abs(x[0] - 1) <= reach) &&
                                   (std::abs(x[1]) <= reach || std::abs(x[1] - 1) <= reach);
            if (in_cell && !at_corner) return CellState::Cone;
        }
        const P2 slo{rules.band, rules.band}, shi{1 - rules.band, 1 - rules.band};
        for (std::size_t k = 0; k < 3; ++k) {
            if (!segment_meets_box(q[k], q[(k + 1) % 3], slo, shi)) continue;
            const std::size_t c = 3 * t + k;
            const std::int64_t o = map.edges.opposite[c];
            if (o < 0) return map.edges.partner[c] >= 0 ? CellState::Unknown : CellState::Cut;
            const auto n = static_cast<std::uint32_t>(o / 3);
            if (map.fold_over[n] || (rules.far && !(*rules.far)[n])) return CellState::NearFold;
            Transition m;
            if (!compose(map.edges.across[c], to[t], m)) return CellState::Unknown;
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
            const double d = triangle_distance(
                {0, 0}, corner_uvs(map.in, t, {static_cast<double>(c[0]), static_cast<double>(c[1])}));
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
            } else if (judge_cell({map_, &far_, claim_reach_, kBoundaryBand}, t, lo, f.cell, scratch) !=
                       CellState::Required) {
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

namespace qex::verify_detail {

BoundaryCells::BoundaryCells(const LocatedMap& map, double tol)
    : map_(map),
      reach_(std::max(coverage::kClaimReach, tol)),
      band_(std::max(coverage::kBoundaryBand, tol)),
      scratch_(std::make_unique<coverage::Scratch>(map.in.triangles.size())) {}

BoundaryCells::~BoundaryCells() = default;

CellsRound BoundaryCells::round(std::uint32_t t, const GridPoint& g) {
    using coverage::P2;
    CellsRound out;
    std::vector<std::pair<std::uint32_t, Transition>> near;
    if (!coverage::near_point(map_, t, g, reach_, *scratch_, near)) return out;
    // The four cells at g in t's chart (lower-left g - (1, 1) + (i % 2, i / 2)), each with the
    // first triangle near g that meets it farther than the band inside, and its lower-left in that
    // triangle's chart. One chart round a point of the boundary tells its cells apart: its fan is
    // open, and the caller asks for no corner of more than a turn.
    std::array<std::pair<std::uint32_t, GridPoint>, 4> over{};
    std::array<bool, 4> met{false, false, false, false};
    const P2 lo{band_, band_}, hi{1 - band_, 1 - band_};
    for (const auto& [n, m] : near) {
        out.at.push_back({n, map_point(m, g)});
        for (std::size_t i = 0; i < 4; ++i) {
            const GridPoint c = coverage::carried_cell(
                m, {g[0] - 1 + static_cast<std::int64_t>(i % 2), g[1] - 1 + static_cast<std::int64_t>(i / 2)});
            const P2 origin{static_cast<double>(c[0]), static_cast<double>(c[1])};
            if (!met[i] && coverage::triangle_meets_box(coverage::corner_uvs(map_.in, n, origin), lo, hi))
                met[i] = true, over[i] = {n, c};
        }
    }
    out.read = true;
    for (std::size_t i = 0; i < 4; ++i) {
        if (!met[i]) continue;
        ++out.cells;
        coverage::RequiredCell cell;
        out.cut += coverage::judge_cell({map_, nullptr, reach_, band_}, over[i].first, over[i].second, cell,
                                        *scratch_) == coverage::CellState::Cut;
    }
    return out;
}

} // namespace qex::verify_detail
