// Placement on the given map, for meshes from a relaxed rung of the fallback ladder: every output
// vertex moves onto a preimage of its grid point in the sanitized map as given, so the mesh is
// judged against that map and not against the relaxed one it was extracted from.
#include "pipeline.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <set>

namespace qex::detail {
namespace {

/// The orientation of triangle t of `g` if it is not degenerate and holds x (closed), else 0.
int holding_sign(const TriMesh& g, int t, const Point2& x) {
    const Point2 &a = g.uv[3 * t], &b = g.uv[3 * t + 1], &c = g.uv[3 * t + 2];
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

/// Breadth-first search over the live triangles of the given map `g` (its transitions computed),
/// crossing edges with their transitions (not edges next to a collapsed triangle), each
/// triangle's neighbours in canonical order; every listed triangle carries the transition from
/// the search's chart to its own.
class ChartSearch {
public:
    explicit ChartSearch(const TriMesh& g)
        : g_(g), stamp_(static_cast<std::size_t>(g.num_faces()), 0), to_(static_cast<std::size_t>(g.num_faces())) {}

    /// A triangle that holds `grid` (in the chart of triangle `start`): the first positive one
    /// found, else the first flipped one; -1 if none is found or `start` is not a live triangle.
    int find(int start, const IPoint& grid) {
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

    /// Every triangle the search lists (up to its budget) that holds `grid` (in the chart of
    /// triangle `start`), each with `grid` in its own chart: the positive ones in the order
    /// listed, then the flipped ones.
    std::vector<std::pair<int, IPoint>> find_all(int start, const IPoint& grid) {
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

    /// Lists the triangles of a grid cell, the open box (lo, hi) in the seeds' chart: those that
    /// meet it and are reached from the seeds through such triangles. Kept inside the cell, the
    /// search cannot wind round a singularity at one of its corners into another sheet. False
    /// past the budget.
    bool cell(const std::vector<std::pair<int, GridAutomorphism>>& seeds, const IPoint& lo, const IPoint& hi) {
        const Box box{lo, hi};
        begin();
        for (const auto& [t, to] : seeds) enter(t, to, &box);
        for (std::size_t head = 0; head < queue_.size(); ++head) {
            if (queue_.size() > kMaxCellTriangles) return false;
            expand(queue_[head], &box);
        }
        return true;
    }
    bool listed(int t) const { return stamp_[static_cast<std::size_t>(t)] == generation_; }
    /// The transition from the chart of the last search's start to that of triangle t (listed by it).
    const GridAutomorphism& to(int t) const { return to_[static_cast<std::size_t>(t)]; }
    const std::vector<int>& triangles() const { return queue_; }

    /// Every listed triangle that holds q (the search's chart): positive ones first, in order.
    std::vector<int> holders(const IPoint& q) const {
        std::vector<int> positive, flipped;
        for (const int t : queue_) {
            const int s = holding_sign(g_, t, to_point(to(t)(q)));
            if (s > 0) positive.push_back(t);
            if (s < 0) flipped.push_back(t);
        }
        positive.insert(positive.end(), flipped.begin(), flipped.end());
        return positive;
    }

private:
    static constexpr std::size_t kMaxSearchTriangles = 4096; ///< find() stops listing here
    static constexpr std::size_t kMaxCellTriangles = std::size_t{1} << 16;
    struct Box {
        IPoint lo, hi;
    };

    /// Whether triangle t survived the collapses (its UVs are not NaN).
    bool alive(int t) const { return std::isfinite(g_.uv[3 * t][0]); }
    void begin() {
        ++generation_;
        queue_.clear();
    }
    /// Lists t, reached with transition `to`, unless it is listed, collapsed, or (with a box)
    /// misses the box.
    void enter(int t, const GridAutomorphism& to, const Box* box) {
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
    /// Lists t's neighbours, in canonical order, so that which path reaches a triangle first (and
    /// so its transition past a singularity), and which preimage is found first, do not depend on
    /// the input's order.
    void expand(int t, const Box* box) {
        for (const int k : edges_in_canonical_order(g_, t))
            if (const int o = g_.opp[3 * t + k]; o >= 0)
                enter(TriMesh::face(o), g_.map.transition[3 * t + k].after(to(t)), box);
    }

    const TriMesh& g_;
    std::vector<std::uint32_t> stamp_; ///< per triangle: the search that listed it last
    std::vector<GridAutomorphism> to_; ///< per triangle: chart of the start -> its chart
    std::vector<int> queue_;           ///< the listed triangles, in the order listed
    std::uint32_t generation_ = 0;
};

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
    std::array<double, 3> w = barycentric_exact(x, u[0], u[1], u[2]); // a rare path: exact
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

} // namespace

std::int64_t place_on_given_map(const Input& input, const std::vector<std::array<double, 2>>& given, QuadMesh& mesh) {
    TriMesh g = make_mesh(input);
    if (build_topology(g, "input").code != ErrorCode::None) return static_cast<std::int64_t>(mesh.positions.size());
    g.uv = given;
    // Transitions of the given (sanitized) map, exact there: rotation from the edge, then the
    // translation.
    compute_transitions(g);
    ChartSearch search(g);
    std::int64_t unplaced = 0;
    for (std::size_t i = 0; i < mesh.positions.size() && i < mesh.provenance.size(); ++i) {
        Provenance& p = mesh.provenance[i];
        const IPoint grid{p.grid[0], p.grid[1]};
        const int found = search.find(p.chart_triangle, grid);
        if (found < 0) {
            ++unplaced;
            continue;
        }
        p = located(input, g, found, search.to(found)(grid), p.merged);
        mesh.positions[i] = position_of(input, p);
    }
    mesh.map_uvs = given;
    return unplaced;
}

std::vector<std::vector<std::pair<Provenance, std::array<double, 3>>>> preimages(
    const Input& input, const std::vector<std::array<double, 2>>& map, const std::vector<Provenance>& points) {
    std::vector<std::vector<std::pair<Provenance, std::array<double, 3>>>> out(points.size());
    TriMesh g = make_mesh(input);
    if (map.size() != input.uvs.size() || build_topology(g, "input").code != ErrorCode::None) return out;
    g.uv = map;
    compute_transitions(g);
    ChartSearch search(g);
    for (std::size_t i = 0; i < points.size(); ++i) {
        const Provenance& p = points[i];
        for (const auto& [t, q] : search.find_all(p.chart_triangle, {p.grid[0], p.grid[1]})) {
            Provenance at = located(input, g, t, q, p.merged);
            // One preimage per place: a vertex or an edge is held by every triangle round it.
            const std::array<double, 3> x = position_of(input, at);
            if (std::none_of(out[i].begin(), out[i].end(), [&](const auto& seen) { return seen.second == x; }))
                out[i].push_back({std::move(at), x});
        }
    }
    return out;
}

} // namespace qex::detail

// ============================================================================ a coarse mesh, split

namespace qex::detail {
namespace {

/// The triangles a provenance's grid point is on, each with the transition from the chart of
/// its triangle `chart_triangle` to its own: that triangle; with the neighbour across the edge;
/// or the vertex's whole fan, walked clockwise. Empty if a triangle of it was collapsed away.
std::vector<std::pair<int, GridAutomorphism>> triangles_at(const TriMesh& g, const Provenance& p) {
    std::vector<std::pair<int, GridAutomorphism>> at;
    const int t0 = p.chart_triangle;
    if (p.kind == QVertexKind::Face) return {{t0, GridAutomorphism{}}};
    if (p.kind == QVertexKind::Edge) {
        const int h = 3 * t0 + p.local_edge, o = g.opp[h];
        at.push_back({t0, GridAutomorphism{}});
        if (o >= 0) at.push_back({TriMesh::face(o), g.map.transition[h]});
        return at;
    }
    // The fan from its first corner, then re-based on t0's chart.
    const int v = p.element;
    GridAutomorphism to_h, to_t0;
    bool seen = false;
    for (int h = g.fan_start[v], n = 0; h >= 0 && n < g.fan_size[v]; h = g.cw(h), ++n) {
        if (!std::isfinite(g.uv[h][0])) return {};
        at.push_back({TriMesh::face(h), to_h});
        if (TriMesh::face(h) == t0 && !seen) to_t0 = to_h, seen = true;
        to_h = g.map.transition[h].after(to_h);
    }
    if (!seen) return {};
    const GridAutomorphism back = to_t0.inverse();
    for (auto& [t, to] : at) to = to.after(back);
    // In an order that does not depend on the input's (fan_start does).
    std::sort(at.begin(), at.end(), [&](const auto& x, const auto& y) { return triangle_less(g, x.first, y.first); });
    return at;
}

/// Where the cell search has a corner of the cell (provenance p, its triangles `at`:
/// triangles_at): 1 when grid point q (seeds' chart) is on the corner's vertex, edge or
/// triangle, at its grid point there; -1 when the search holds one of
/// those triangles with q elsewhere; 0 when it holds none (a fold can keep a corner's own
/// triangles out of the cell).
int corner_found(const ChartSearch& search, const Provenance& p,
                 const std::vector<std::pair<int, GridAutomorphism>>& at, const IPoint& q) {
    const IPoint expected{p.grid[0], p.grid[1]};
    int found = 0;
    for (const auto& [t, to] : at)
        if (search.listed(t)) {
            if (search.to(t)(q) == to(expected)) return 1;
            found = -1;
        }
    return found;
}

/// A coarse face's cell on the given map: the triangles it covers (listed by `search`), and how
/// its local frame lies in their chart.
struct CellFrame {
    std::array<int, 4> corners; ///< the face's vertices, from the corner the frame is anchored at
    IPoint origin, e1, e2;      ///< that corner's grid point (times k), the sides' unit steps
    int turn = 0;               ///< quarter turns from the face's local frame to the chart
    int start = -1;             ///< a triangle the search started from, and the transition
    GridAutomorphism to_start;  ///< from the chart of the points to its chart
    /// Grid point (i, j) of the split cell (0..k each), in the chart of the search's start.
    IPoint point(int i, int j) const {
        const IPoint off = GridAutomorphism::rotate(IPoint{i * e1[0] + j * e2[0], i * e1[1] + j * e2[1]}, turn);
        return {origin[0] + off[0], origin[1] + off[1]};
    }
};

/// Finds face f's cell anchored at its corner `a`, for splitting it into k x k: the start and
/// quarter turn under which the cell's triangles hold the most of its other corners where the
/// coarse mesh has them, and none elsewhere. On success, `search` lists that cell.
bool find_cell(const TriMesh& g, const std::vector<Provenance>& provenance, const std::vector<int>& face,
               const std::vector<std::array<std::int64_t, 2>>& uv, int a, int k, ChartSearch& search,
               CellFrame& frame) {
    for (int i = 0; i < 4; ++i)
        frame.corners[static_cast<std::size_t>(i)] = face[static_cast<std::size_t>((a + i) % 4)];
    const auto at = [&](int i) { return uv[static_cast<std::size_t>((a + i) % 4)]; };
    frame.e1 = {at(1)[0] - at(0)[0], at(1)[1] - at(0)[1]};
    frame.e2 = {at(3)[0] - at(0)[0], at(3)[1] - at(0)[1]};
    const Provenance& p0 = provenance[static_cast<std::size_t>(frame.corners[0])];
    frame.origin = {p0.grid[0], p0.grid[1]};
    // Where the search starts: the triangle of the corner (with the neighbour across its edge);
    // on a vertex, each triangle of its fan on its own (their charts, walked round a
    // singularity, differ by its turn: together they would mix two sheets of the cell).
    const std::vector<std::pair<int, GridAutomorphism>> around = triangles_at(g, p0);
    std::vector<std::vector<std::pair<int, GridAutomorphism>>> starts;
    if (p0.kind == QVertexKind::Vertex)
        for (const auto& seed : around) starts.push_back({seed});
    else if (!around.empty())
        starts.push_back(around);
    const auto run = [&](std::size_t start, int r) {
        frame.turn = r;
        const IPoint lo = frame.point(0, 0), hi = frame.point(k, k);
        return search.cell(starts[start], {std::min(lo[0], hi[0]), std::min(lo[1], hi[1])},
                           {std::max(lo[0], hi[0]), std::max(lo[1], hi[1])}) &&
               !search.triangles().empty();
    };
    // Where the other corners are (their triangles, with transitions), walked once.
    std::array<std::vector<std::pair<int, GridAutomorphism>>, 3> corner_at;
    for (std::size_t j = 0; j < 3; ++j)
        corner_at[j] = triangles_at(g, provenance[static_cast<std::size_t>(frame.corners[j + 1])]);
    int best = 0, turn = -1;
    std::size_t from = 0;
    for (std::size_t start = 0; start < starts.size(); ++start)
        for (int r = 0; r < 4; ++r) {
            if (!run(start, r)) continue;
            int matched = 0;
            bool contradicted = false;
            const std::array<std::pair<int, int>, 3> ij{{{k, 0}, {k, k}, {0, k}}};
            for (std::size_t j = 0; j < 3; ++j) {
                const Provenance& pj = provenance[static_cast<std::size_t>(frame.corners[j + 1])];
                const int found = corner_found(search, pj, corner_at[j], frame.point(ij[j].first, ij[j].second));
                matched += found > 0;
                contradicted = contradicted || found < 0;
            }
            // Starts in one sector find the same cell (their charts differ by the singularity's
            // turn about the corner, and so do their quarter turns): the first is taken.
            if (!contradicted && matched > best) best = matched, turn = r, from = start;
        }
    if (turn < 0 || !run(from, turn)) return false;
    frame.start = starts[from][0].first;
    frame.to_start = starts[from][0].second;
    return true;
}

} // namespace

bool split_onto_map(const Input& input, const std::vector<std::array<double, 2>>& map, const QuadMesh& coarse, int k,
                    const IPoint& origin, QuadMesh& out) {
    TriMesh g = make_mesh(input);
    if (build_topology(g, "input").code != ErrorCode::None) return false;
    g.uv = map;
    compute_transitions(g);
    ChartSearch search(g), wide(g);
    const auto nv = coarse.positions.size();
    if (coarse.provenance.size() != nv || coarse.face_uvs.size() != coarse.faces.size() || k < 2) return false;
    out = QuadMesh{};
    out.map_uvs = map;
    out.map_repaired = coarse.map_repaired;
    // The coarse vertices, on the same elements: their grid points times k, from the origin.
    out.provenance.reserve(nv);
    for (std::size_t v = 0; v < nv; ++v) {
        const Provenance& p = coarse.provenance[v];
        if (p.chart_triangle < 0 || p.chart_triangle >= g.num_faces()) return false;
        out.provenance.push_back(
            located(input, g, p.chart_triangle, {p.grid[0] * k + origin[0], p.grid[1] * k + origin[1]}, p.merged));
        out.positions.push_back(position_of(input, out.provenance.back()));
    }
    // Where vertices lie (a new vertex takes a preimage where none lies yet, if it has one).
    std::set<std::array<double, 3>> placed(out.positions.begin(), out.positions.end());
    // Per coarse edge (its vertices, smaller first): the first of its k - 1 new vertices,
    // numbered from the smaller vertex on.
    std::map<std::pair<int, int>, int> side_first;
    std::vector<int> at(static_cast<std::size_t>((k + 1) * (k + 1)));
    for (std::size_t f = 0; f < coarse.faces.size(); ++f) {
        const std::vector<int>& face = coarse.faces[f];
        if (face.size() != 4 || coarse.face_uvs[f].size() != 4) return false;
        // Anchored at a corner inside a triangle if it has one, else on an edge, else on a vertex
        // (the fewer triangles round the anchor, the fewer starts).
        std::array<int, 4> anchors{0, 1, 2, 3};
        std::stable_sort(anchors.begin(), anchors.end(), [&](int x, int y) {
            const auto rank = [](QVertexKind kind) {
                return kind == QVertexKind::Face ? 0 : kind == QVertexKind::Edge ? 1 : 2;
            };
            return rank(out.provenance[static_cast<std::size_t>(face[static_cast<std::size_t>(x)])].kind) <
                   rank(out.provenance[static_cast<std::size_t>(face[static_cast<std::size_t>(y)])].kind);
        });
        CellFrame frame;
        bool found = false;
        for (std::size_t n = 0; n < 4 && !found; ++n)
            found = find_cell(g, out.provenance, face, coarse.face_uvs[f], anchors[n], k, search, frame);
        if (!found) return false;
        const std::array<int, 4>& c = frame.corners;
        // A free preimage is taken only near the cell: within twice its corners' spread of
        // their mean (a grid point found round a singularity can lie across the surface).
        const Neighbourhood cell(out.positions, c);
        const auto usable = [&](const std::array<double, 3>& x) { return !placed.count(x) && cell.near(x); };
        auto place = [&](int i, int j) -> int {
            const IPoint q = frame.point(i, j);
            // A preimage of q inside the cell where no vertex lies yet (a fold-over can give the
            // grid point several, one another sheet's, where a vertex is), else the first.
            std::optional<Provenance> first, free_one;
            for (const int t : search.holders(q)) {
                Provenance p = located(input, g, t, search.to(t)(q), 1);
                if (!first) first = p;
                if (usable(position_of(input, p))) {
                    free_one = std::move(p);
                    break;
                }
            }
            // A fold can cut the cell's triangles in parts: the one that holds q is not reached
            // inside the cell. It is searched for from the start, unbounded, then from the
            // cell's triangles, until a free preimage is found.
            const auto beyond = [&](int s0, const IPoint& from) {
                for (const auto& [u, at_u] : wide.find_all(s0, from)) {
                    Provenance p = located(input, g, u, at_u, 1);
                    if (!first) first = p;
                    if (usable(position_of(input, p))) {
                        free_one = std::move(p);
                        return;
                    }
                }
            };
            // Once some preimage is known, a free one is looked for from at most four more
            // starts (each search lists up to 4096 triangles: a cell of a thousand triangles
            // with no free preimage would otherwise cost a hundred searches per vertex).
            if (!free_one) beyond(frame.start, frame.to_start(q));
            for (std::size_t n = 0, tries = 0; !free_one && n < search.triangles().size() && (!first || tries < 4);
                 n += 8, tries += first ? 1 : 0)
                beyond(search.triangles()[n], search.to(search.triangles()[n])(q));
            if (!first) return -1;
            out.provenance.push_back(free_one ? *free_one : *first);
            out.positions.push_back(position_of(input, out.provenance.back()));
            placed.insert(out.positions.back());
            return static_cast<int>(out.positions.size()) - 1;
        };
        // The vertex at (i, j), 0..k each, of the split cell.
        auto slot = [&](int i, int j) -> int& { return at[static_cast<std::size_t>(j * (k + 1) + i)]; };
        slot(0, 0) = c[0], slot(k, 0) = c[1], slot(k, k) = c[2], slot(0, k) = c[3];
        // The sides, each from its first corner to its second, and the (i, j) of step s along it.
        const std::array<std::array<int, 2>, 4> ends{{{c[0], c[1]}, {c[1], c[2]}, {c[3], c[2]}, {c[0], c[3]}}};
        const auto step = [k](int side, int s) {
            return side == 0   ? std::pair{s, 0}
                   : side == 1 ? std::pair{k, s}
                   : side == 2 ? std::pair{s, k}
                               : std::pair{0, s};
        };
        for (int side = 0; side < 4; ++side) {
            const int a = ends[static_cast<std::size_t>(side)][0], b = ends[static_cast<std::size_t>(side)][1];
            const auto key = std::minmax(a, b);
            // A side's new vertices are numbered from its smaller corner, so the face across it
            // finds them in that order.
            const auto it = side_first.find(key);
            if (it != side_first.end()) {
                for (int s = 1; s < k; ++s) {
                    const auto [i, j] = step(side, s);
                    slot(i, j) = it->second + (a < b ? s : k - s) - 1;
                }
                continue;
            }
            side_first.emplace(key, static_cast<int>(out.positions.size()));
            for (int t = 1; t < k; ++t) {
                const auto [i, j] = step(side, a < b ? t : k - t);
                if ((slot(i, j) = place(i, j)) < 0) return false;
            }
        }
        for (int j = 1; j < k; ++j)
            for (int i = 1; i < k; ++i)
                if ((slot(i, j) = place(i, j)) < 0) return false;
        for (int j = 0; j < k; ++j)
            for (int i = 0; i < k; ++i) {
                out.faces.push_back({slot(i, j), slot(i + 1, j), slot(i + 1, j + 1), slot(i, j + 1)});
                std::vector<std::array<std::int64_t, 2>> local;
                for (const auto& [di, dj] : {std::pair{0, 0}, std::pair{1, 0}, std::pair{1, 1}, std::pair{0, 1}})
                    local.push_back({(i + di) * frame.e1[0] + (j + dj) * frame.e2[0],
                                     (i + di) * frame.e1[1] + (j + dj) * frame.e2[1]});
                out.face_uvs.push_back(std::move(local));
            }
    }
    return true;
}

} // namespace qex::detail
