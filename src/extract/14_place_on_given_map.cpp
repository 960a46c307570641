// Placement on the given map, for meshes from a relaxed rung of the fallback ladder: every output
// vertex moves onto a preimage of its grid point in the sanitized map as given, so the mesh is
// judged against that map and not against the relaxed one it was extracted from.
#include "pipeline.h"

#include <algorithm>
#include <cmath>

namespace qex::detail {
namespace {

/// The search from a vertex's provenance triangle stops once it has listed at least this many triangles.
constexpr std::size_t kMaxSearchTriangles = 4096;

/// Breadth-first search over the live triangles of the given map `g` (its transitions computed),
/// crossing edges with their transitions; edges next to a collapsed triangle are not crossed.
class PreimageSearch {
public:
    explicit PreimageSearch(const TriMesh& g)
        : g_(g), stamp_(static_cast<std::size_t>(g.num_faces()), 0), to_(static_cast<std::size_t>(g.num_faces())) {}
    /// A triangle that holds `grid` (in the chart of triangle `start`): the first positive one
    /// found, else the first flipped one; -1 if none is found or `start` is not a live triangle.
    int find(int start, const IPoint& grid);
    /// The transition from the chart of the last search's start to that of triangle t (listed by it).
    const GridAutomorphism& to(int t) const { return to_[static_cast<std::size_t>(t)]; }

private:
    /// Whether triangle f survived the collapses (its UVs are not NaN).
    bool alive(int f) const { return std::isfinite(g_.uv[3 * f][0]); }
    /// The orientation of triangle t if it is not degenerate and holds `grid` (closed), else 0.
    int holding_sign(int t, const IPoint& grid) const;
    /// Lists t's unlisted live neighbours, with their transitions.
    void list_neighbours(int t);

    const TriMesh& g_;
    std::vector<std::uint32_t> stamp_; ///< per triangle: the search that listed it last
    std::vector<GridAutomorphism> to_; ///< per triangle: chart of the start -> its chart
    std::vector<int> queue_;
    std::uint32_t generation_ = 0;
};

int PreimageSearch::holding_sign(int t, const IPoint& grid) const {
    const Point2 x = to_point(to(t)(grid));
    const Point2 &a = g_.uv[3 * t], &b = g_.uv[3 * t + 1], &c = g_.uv[3 * t + 2];
    const int s = sign(orient2d(a, b, c));
    if (s == 0) return 0;
    const int o0 = sign(orient2d(a, b, x)), o1 = sign(orient2d(b, c, x)), o2 = sign(orient2d(c, a, x));
    const bool inside = (o0 == s || o0 == 0) && (o1 == s || o1 == 0) && (o2 == s || o2 == 0);
    return inside ? s : 0;
}

void PreimageSearch::list_neighbours(int t) {
    // In canonical order (triangle_less), so that which path reaches a triangle first (and so its
    // transition past a singularity), and which preimage is found first, do not depend on the
    // input's order.
    std::array<int, 3> ks{0, 1, 2};
    auto neighbour = [&](int k) { return g_.opp[3 * t + k] < 0 ? -1 : TriMesh::face(g_.opp[3 * t + k]); };
    std::sort(ks.begin(), ks.end(), [&](int a, int b) {
        const int na = neighbour(a), nb = neighbour(b);
        if (na < 0 || nb < 0) return na > nb;
        return triangle_less(g_, na, nb);
    });
    for (const int k : ks) {
        const int o = g_.opp[3 * t + k];
        if (o < 0) continue;
        const int n = TriMesh::face(o);
        if (stamp_[static_cast<std::size_t>(n)] == generation_ || !alive(n)) continue;
        stamp_[static_cast<std::size_t>(n)] = generation_;
        to_[static_cast<std::size_t>(n)] = g_.map.transition[3 * t + k].after(to(t));
        queue_.push_back(n);
    }
}

int PreimageSearch::find(int start, const IPoint& grid) {
    if (start < 0 || start >= g_.num_faces() || !alive(start)) return -1;
    ++generation_;
    queue_.assign(1, start);
    stamp_[static_cast<std::size_t>(start)] = generation_;
    to_[static_cast<std::size_t>(start)] = GridAutomorphism{};
    int found = -1, found_flipped = -1;
    for (std::size_t head = 0; head < queue_.size() && found < 0 && queue_.size() < kMaxSearchTriangles; ++head) {
        const int t = queue_[head];
        const int s = holding_sign(t, grid);
        if (s > 0) found = t;
        if (s < 0 && found_flipped < 0) found_flipped = t;
        list_neighbours(t);
    }
    return found >= 0 ? found : found_flipped;
}

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
    PreimageSearch search(g);
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

} // namespace qex::detail
