// The chart search (chart_search.h): a breadth-first search over a map's triangles, carrying
// each one's transition from the search's chart, and where a grid point it finds lies on the input.
#include "chart_search.h"

#include <algorithm>
#include <cmath>

namespace qex::detail {
namespace {

/// The orientation of triangle t of `g` if it is not degenerate and holds x (closed), else 0.
int holding_sign(const TriMesh& g, int t, const Point2& x) {
    const Point2 &a = g.uv[3 * t], &b = g.uv[3 * t + 1], &c = g.uv[3 * t + 2];
    // Outside the triangle's bounding box (exact comparisons): outside the triangle. Most of a
    // search's triangles are, and this spares them the four predicates.
    for (std::size_t d = 0; d < 2; ++d)
        if (x[d] < std::min({a[d], b[d], c[d]}) || x[d] > std::max({a[d], b[d], c[d]})) return 0;
    const int s = sign(orient2d(a, b, c));
    if (s == 0) return 0;
    const int o0 = sign(orient2d(a, b, x)), o1 = sign(orient2d(b, c, x)), o2 = sign(orient2d(c, a, x));
    const bool inside = (o0 == s || o0 == 0) && (o1 == s || o1 == 0) && (o2 == s || o2 == 0);
    return inside ? s : 0;
}

/// Triangle t's edges (0..2) in the canonical order of the neighbours across them
/// (triangle_less), boundary edges last: so that which path a search takes to a triangle (and so
/// its transition past a singularity) does not depend on the input's order.
std::array<int, 3> edges_in_canonical_order(const TriMesh& g, int t) {
    std::array<int, 3> ks{0, 1, 2};
    auto neighbour = [&](int k) { return g.opp[3 * t + k] < 0 ? -1 : TriMesh::face(g.opp[3 * t + k]); };
    std::sort(ks.begin(), ks.end(), [&](int a, int b) {
        const int na = neighbour(a), nb = neighbour(b);
        if (na < 0 || nb < 0) return na > nb;
        return triangle_less(g, na, nb);
    });
    return ks;
}

/// Whether triangle (a, b, c) and the open box (lo, hi) share a point, by separating axes: the
/// box's two and the triangle's three edges (a side that only touches separates). A degenerate
/// triangle is judged by its bounding box.
bool meets_open_box(const Point2& a, const Point2& b, const Point2& c, const IPoint& lo, const IPoint& hi) {
    const auto [x0, x1] = std::minmax({a[0], b[0], c[0]});
    const auto [y0, y1] = std::minmax({a[1], b[1], c[1]});
    if (!(x1 > static_cast<double>(lo[0]) && x0 < static_cast<double>(hi[0]) && y1 > static_cast<double>(lo[1]) &&
          y0 < static_cast<double>(hi[1])))
        return false;
    const std::array<Point2, 4> box{{{static_cast<double>(lo[0]), static_cast<double>(lo[1])},
                                     {static_cast<double>(hi[0]), static_cast<double>(lo[1])},
                                     {static_cast<double>(hi[0]), static_cast<double>(hi[1])},
                                     {static_cast<double>(lo[0]), static_cast<double>(hi[1])}}};
    const int s = sign(orient2d(a, b, c));
    if (s == 0) {
        // A segment (or a point, which the boxes' test decided): it misses the open box when the
        // box lies on one closed side of its line.
        const auto [p, q] = std::minmax({a, b, c});
        if (p == q) return true;
        int below = 0, above = 0;
        for (const Point2& x : box) {
            const int o = sign(orient2d(p, q, x));
            below += o<0, above += o> 0;
        }
        return below > 0 && above > 0;
    }
    const std::array<const Point2*, 3> t{&a, &b, &c};
    for (std::size_t e = 0; e < 3; ++e) {
        bool separated = true;
        for (const Point2& p : box) separated = separated && sign(orient2d(*t[e], *t[(e + 1) % 3], p)) * s <= 0;
        if (separated) return false;
    }
    return true;
}

} // namespace

// ============================================================================ the search

int ChartSearch::find(int start, const IPoint& grid) {
    if (start < 0 || start >= g_.num_faces() || !alive(start)) return -1;
    begin();
    enter(start, GridAutomorphism{}, nullptr);
    int found = -1, found_flipped = -1;
    for (std::size_t head = 0; head < queue_.size() && found < 0 && queue_.size() < kMaxSearchTriangles; ++head) {
        const int t = queue_[head];
        const int s = holding_sign(g_, t, to_point(to(t)(grid)));
        if (s > 0) found = t;
        if (s < 0 && found_flipped < 0) found_flipped = t;
        expand(t, nullptr);
    }
    return found >= 0 ? found : found_flipped;
}

int ChartSearch::find_round_singularities(const IPoint& grid, GridAutomorphism& to) const {
    int flipped = -1;
    GridAutomorphism flipped_to;
    for (const int t : queue_) {
        const std::array<std::int8_t, 3>& order = order_[static_cast<std::size_t>(t)];
        for (const std::int8_t k : order) {
            const int o = k < 0 ? -1 : g_.opp[3 * t + k];
            if (o < 0 || !listed(TriMesh::face(o))) continue;
            const int u = TriMesh::face(o);
            const GridAutomorphism other = g_.map.transition[3 * t + k].after(this->to(t));
            if (other == this->to(u)) continue;
            const int s = holding_sign(g_, u, to_point(other(grid)));
            if (s > 0) {
                to = other;
                return u;
            }
            if (s < 0 && flipped < 0) flipped = u, flipped_to = other;
        }
    }
    to = flipped_to;
    return flipped;
}

std::vector<std::pair<int, IPoint>> ChartSearch::find_all(int start, const IPoint& grid) {
    std::vector<std::pair<int, IPoint>> positive, flipped;
    if (start < 0 || start >= g_.num_faces() || !alive(start)) return positive;
    begin();
    enter(start, GridAutomorphism{}, nullptr);
    for (std::size_t head = 0; head < queue_.size() && queue_.size() < kMaxSearchTriangles; ++head) {
        const int t = queue_[head];
        const IPoint q = to(t)(grid);
        const int s = holding_sign(g_, t, to_point(q));
        if (s > 0) positive.push_back({t, q});
        if (s < 0) flipped.push_back({t, q});
        expand(t, nullptr);
    }
    positive.insert(positive.end(), flipped.begin(), flipped.end());
    return positive;
}

bool ChartSearch::cell(const std::vector<std::pair<int, GridAutomorphism>>& seeds, const IPoint& lo, const IPoint& hi) {
    const Box box{lo, hi};
    begin();
    for (const auto& [t, to] : seeds) enter(t, to, &box);
    for (std::size_t head = 0; head < queue_.size(); ++head) {
        if (queue_.size() > kMaxCellTriangles) return false;
        expand(queue_[head], &box);
    }
    return true;
}

std::vector<int> ChartSearch::holders(const IPoint& q) const {
    std::vector<int> positive, flipped;
    for (const int t : queue_) {
        const int s = holding_sign(g_, t, to_point(to(t)(q)));
        if (s > 0) positive.push_back(t);
        if (s < 0) flipped.push_back(t);
    }
    positive.insert(positive.end(), flipped.begin(), flipped.end());
    return positive;
}

bool ChartSearch::alive(int t) const { return std::isfinite(g_.uv[3 * t][0]); }

void ChartSearch::enter(int t, const GridAutomorphism& to, const Box* box) {
    if (t < 0 || listed(t) || !alive(t)) return;
    if (box) {
        // The box in t's chart: a box again (the transition turns by quarter turns).
        const IPoint p = to(box->lo), q = to(box->hi);
        const IPoint l{std::min(p[0], q[0]), std::min(p[1], q[1])}, h{std::max(p[0], q[0]), std::max(p[1], q[1])};
        if (!meets_open_box(g_.uv[3 * t], g_.uv[3 * t + 1], g_.uv[3 * t + 2], l, h)) return;
    }
    stamp_[static_cast<std::size_t>(t)] = generation_;
    to_[static_cast<std::size_t>(t)] = to;
    queue_.push_back(t);
}

void ChartSearch::expand(int t, const Box* box) {
    std::array<std::int8_t, 3>& order = order_[static_cast<std::size_t>(t)];
    if (order[0] < 0) {
        const std::array<int, 3> ks = edges_in_canonical_order(g_, t);
        order = {static_cast<std::int8_t>(ks[0]), static_cast<std::int8_t>(ks[1]), static_cast<std::int8_t>(ks[2])};
    }
    for (const int k : order)
        if (const int o = g_.opp[3 * t + k]; o >= 0)
            enter(TriMesh::face(o), g_.map.transition[3 * t + k].after(to(t)), box);
}

// ============================================================================ a point found

/// The provenance of grid point q (in the chart of triangle `found` of the given map `g`) in
/// that triangle: on a corner, on an edge, or inside.
Provenance located(const Input& input, const TriMesh& g, int found, const IPoint& q, int merged) {
    const Point2 x = to_point(q);
    const Point2* u = &g.uv[3 * found];
    const auto& tri = input.triangles[static_cast<std::size_t>(found)];
    Provenance np;
    np.merged = merged;
    np.chart_triangle = found;
    np.grid = {q[0], q[1]};
    int corner = -1, edge = -1;
    for (int k = 0; k < 3; ++k) {
        if (u[k] == x)
            corner = k;
        else if (sign(orient2d(u[k], u[(k + 1) % 3], x)) == 0)
            edge = k;
    }
    // For the position only (the place is decided above, exactly): in doubles, as generated
    // q-vertices have them, exactly for a sliver.
    std::array<double, 3> w = barycentric(g, found, x);
    if (corner >= 0) {
        np.kind = QVertexKind::Vertex;
        np.element = tri[static_cast<std::size_t>(corner)];
        w = {0, 0, 0};
        w[static_cast<std::size_t>(corner)] = 1;
    } else if (edge >= 0) {
        np.kind = QVertexKind::Edge;
        np.element = found;
        np.local_edge = edge;
        w[static_cast<std::size_t>((edge + 2) % 3)] = 0; // the corner opposite the edge
    } else {
        np.kind = QVertexKind::Face;
        np.element = found;
    }
    np.barycentric = w;
    return np;
}

/// The 3D position of a provenance from located(): the input vertex's own position on a corner,
/// else the barycentric combination of its triangle's corners.
std::array<double, 3> position_of(const Input& input, const Provenance& p) {
    if (p.kind == QVertexKind::Vertex) return input.positions[static_cast<std::size_t>(p.element)];
    const auto& tri = input.triangles[static_cast<std::size_t>(p.chart_triangle)];
    std::array<std::size_t, 3> ks{0, 1, 2}; // summed in 3D order of the corners, not the input's
    std::sort(ks.begin(), ks.end(), [&](std::size_t a, std::size_t b) {
        return input.positions[static_cast<std::size_t>(tri[a])] < input.positions[static_cast<std::size_t>(tri[b])];
    });
    std::array<double, 3> pos{0, 0, 0};
    for (const std::size_t k : ks) {
        const std::array<double, 3>& corner = input.positions[static_cast<std::size_t>(tri[k])];
        for (std::size_t d = 0; d < 3; ++d) pos[d] += p.barycentric[k] * corner[d];
    }
    return pos;
}

} // namespace qex::detail
