// Q-vertex generation (Algorithm 3): every integer grid point of the sanitized map becomes a
// q-vertex on the mesh vertex, edge or triangle it lies on, decided by exact predicates.
#include "pipeline.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

namespace qex::detail {
namespace {

/// Barycentric coordinates of x in (a, b, c); only used for embedding, not for decisions.
std::array<double, 3> barycentric_raw(const Point2& x, const Point2& a, const Point2& b, const Point2& c) {
    const double det = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    // A sliver (twice its area at most 2^-20 of the product of two edges' lengths in the max
    // norm) loses its barycentric coordinates to rounding, and the grid point's 3D position with
    // them: computed exactly there.
    const double scale =
        std::max(std::abs(b[0] - a[0]), std::abs(b[1] - a[1])) * std::max(std::abs(c[0] - a[0]), std::abs(c[1] - a[1]));
    if (!(std::abs(det) > std::ldexp(scale, -20))) return barycentric_exact(x, a, b, c);
    const double wb = ((x[0] - a[0]) * (c[1] - a[1]) - (x[1] - a[1]) * (c[0] - a[0])) / det;
    const double wc = ((b[0] - a[0]) * (x[1] - a[1]) - (b[1] - a[1]) * (x[0] - a[0])) / det;
    return {1.0 - wb - wc, wb, wc};
}

} // namespace

std::array<double, 3> barycentric(const TriMesh& m, int f, const Point2& x) {
    std::array<int, 3> c{3 * f, 3 * f + 1, 3 * f + 2};
    std::sort(c.begin(), c.end(), [&](int i, int j) { return m.pos(i) < m.pos(j); });
    const auto w = barycentric_raw(x, m.uv[c[0]], m.uv[c[1]], m.uv[c[2]]);
    std::array<double, 3> out{};
    for (int i = 0; i < 3; ++i) out[c[i] - 3 * f] = w[i];
    return out;
}

namespace {

/// Whether both coordinates of p are integers.
bool is_integer_point(const Point2& p) { return std::floor(p[0]) == p[0] && std::floor(p[1]) == p[1]; }

/// Position from barycentric weights, summed in 3D order of the corners.
std::array<double, 3> embed(const TriMesh& m, int f, const std::array<double, 3>& w) {
    std::array<int, 3> c{0, 1, 2};
    std::sort(c.begin(), c.end(), [&](int i, int j) { return m.pos(3 * f + i) < m.pos(3 * f + j); });
    std::array<double, 3> p{0, 0, 0};
    for (int i : c)
        for (int d = 0; d < 3; ++d) p[d] += w[i] * m.pos(3 * f + i)[d];
    return p;
}

/// Parameter of x on segment [a, b] (for embedding only).
double segment_param(const Point2& x, const Point2& a, const Point2& b) {
    const int ax = std::abs(b[0] - a[0]) >= std::abs(b[1] - a[1]) ? 0 : 1;
    return (x[ax] - a[ax]) / (b[ax] - a[ax]);
}

/// The error for a map with more grid points than Options::max_qvertices, near `element`.
Error too_large(const Options& opt, std::int64_t element) {
    return Error{
        ErrorCode::MapTooLarge,
        "the map has more than " + std::to_string(opt.max_qvertices) + " integer grid points (Options::max_qvertices)",
        element};
}

/// An upper bound on the grid points of the map: the areas of the triangles' grown bounding boxes.
double grid_point_bound(const TriMesh& m) {
    double bound = 0.0;
    for (int f = 0; f < m.num_faces(); ++f) {
        const Point2 &a = m.uv[3 * f], &b = m.uv[3 * f + 1], &c = m.uv[3 * f + 2];
        const double w = std::max({a[0], b[0], c[0]}) - std::min({a[0], b[0], c[0]}) + 1.0;
        const double h = std::max({a[1], b[1], c[1]}) - std::min({a[1], b[1], c[1]}) + 1.0;
        bound += w * h;
    }
    return bound;
}

/// Appends a vertex-q-vertex for every referenced mesh vertex on an integer grid point.
void add_vertex_qvertices(const TriMesh& m, QState& q) {
    q.vertex_qvertex.assign(m.num_vertices, -1);
    for (int v = 0; v < m.num_vertices; ++v) {
        const int c = m.fan_start[v];
        if (c < 0 || !is_integer_point(m.uv[c])) continue;
        q.vertex_qvertex[v] = static_cast<int>(q.qvertices.size());
        std::array<double, 3> w{0, 0, 0};
        w[c % 3] = 1.0;
        q.qvertices.push_back({QVertexKind::Vertex,
                               v,
                               TriMesh::face(c),
                               {static_cast<std::int64_t>(m.uv[c][0]), static_cast<std::int64_t>(m.uv[c][1])},
                               // A vertex glued by collapsing UV-degenerate edges sits at its own input
                               // vertex (the collapse chose it canonically), not at whichever glued
                               // vertex's corner starts its fan.
                               m.vertex_pos(v),
                               w});
    }
}

/// The edge-q-vertices of half-edge h's edge, if h is its canonical half-edge (canonical_half_edge),
/// in h's chart, ascending along the edge's longer axis (trace_ports' qvertex_at searches them so).
void edge_qvertices(const TriMesh& m, int h, std::vector<QVertex>& list) {
    if (canonical_half_edge(m, h) != h) return;
    const Point2& a = m.uv[h];
    const Point2& b = m.uv[TriMesh::next(h)];
    // Possible: a zero-length edge survives where the link condition forbids its collapse
    // (02_collapse.cpp), and the last sanitize round is not followed by a collapse. Its only point
    // is its vertex (a vertex-q-vertex if on the grid); returning keeps the division below safe.
    if (a == b) return;
    const int ax = std::abs(b[0] - a[0]) >= std::abs(b[1] - a[1]) ? 0 : 1; // walk the longer axis
    const double lo = std::ceil(std::min(a[ax], b[ax])), hi = std::floor(std::max(a[ax], b[ax]));
    for (double x = lo; x <= hi; x += 1.0) {
        // The other coordinate of the line at x; if the line hits an integer point there it is
        // within rounding of the computed value. Candidates are confirmed exactly.
        const double t = (x - a[ax]) / (b[ax] - a[ax]);
        const double y = a[1 - ax] + t * (b[1 - ax] - a[1 - ax]);
        const double yr = std::nearbyint(y);
        for (double cand : {yr - 1.0, yr, yr + 1.0}) {
            Point2 p;
            p[ax] = x;
            p[1 - ax] = cand;
            if (p == a || p == b || !on_segment(p, a, b)) continue;
            // Parametrise from the endpoint first in 3D order, so input order does not matter.
            const int f = TriMesh::face(h), k = h % 3;
            const bool swap = m.pos(TriMesh::next(h)) < m.pos(h);
            const double s = swap ? segment_param(p, b, a) : segment_param(p, a, b);
            std::array<double, 3> w{0, 0, 0};
            w[k] = swap ? s : 1.0 - s;
            w[(k + 1) % 3] = swap ? 1.0 - s : s;
            list.push_back({QVertexKind::Edge,
                            h,
                            f,
                            {static_cast<std::int64_t>(p[0]), static_cast<std::int64_t>(p[1])},
                            embed(m, f, w),
                            w});
        }
    }
}

/// The face-q-vertices of triangle f: grid points strictly inside it, if it is not degenerate,
/// ascending by (u, v) (trace_ports' qvertex_at searches them so).
void face_qvertices(const TriMesh& m, int f, std::vector<QVertex>& list) {
    const int s = m.map.face_sign[f];
    if (s == 0) return;
    const Point2 &a = m.uv[3 * f], &b = m.uv[3 * f + 1], &c = m.uv[3 * f + 2];
    const double x0 = std::ceil(std::min({a[0], b[0], c[0]})), x1 = std::floor(std::max({a[0], b[0], c[0]}));
    const double y0 = std::ceil(std::min({a[1], b[1], c[1]})), y1 = std::floor(std::max({a[1], b[1], c[1]}));
    for (double x = x0; x <= x1; x += 1.0)
        for (double y = y0; y <= y1; y += 1.0) {
            const Point2 p{x, y};
            if (sign(orient2d(a, b, p)) != s || sign(orient2d(b, c, p)) != s || sign(orient2d(c, a, p)) != s) continue;
            const auto w = barycentric(m, f, p);
            list.push_back({QVertexKind::Face,
                            f,
                            f,
                            {static_cast<std::int64_t>(x), static_cast<std::int64_t>(y)},
                            embed(m, f, w),
                            w});
        }
}

/// Generates the q-vertices of elements [0, n) in `parts` ranges, one list per range (on
/// `parts` threads), and joins the lists in range order: the q-vertices and their numbering are
/// those of one serial pass. first[e] becomes the index of element e's first q-vertex, first[n]
/// the end. The budget is checked on the joined counts: returns the first element whose
/// q-vertices end beyond it (the element a serial pass would stop at), or -1.
class RangeGenerator {
public:
    RangeGenerator(QState& q, int parts, std::int64_t budget)
        : q_(q), parts_(parts), budget_(budget), found_(static_cast<std::size_t>(parts)) {}

    /// `one(element, list)` appends the q-vertices of one element to `list`.
    template <class One>
    int run(int n, std::vector<int>& first, One&& one) {
        first.assign(static_cast<std::size_t>(n) + 1, 0);
        const auto base = static_cast<int>(q_.qvertices.size());
        for_parts(parts_, parts_, n,
                  [&](int part, std::int64_t, std::int64_t) { generate_range(n, part, first, one); });
        return join(n, base, first);
    }

private:
    int lo(int n, int part) const { return static_cast<int>(static_cast<std::int64_t>(n) * part / parts_); }
    int hi(int n, int part) const { return lo(n, part + 1); }

    /// Fills the list of range `part`; first[e] becomes e's first q-vertex in that list.
    template <class One>
    void generate_range(int n, int part, std::vector<int>& first, One& one) {
        auto& list = found_[static_cast<std::size_t>(part)];
        list.clear();
        const int end = hi(n, part);
        for (int e = lo(n, part); e < end; ++e) {
            first[static_cast<std::size_t>(e)] = static_cast<int>(list.size());
            one(e, list);
            // A part alone far over the budget stops early; the joined check reports.
            if (static_cast<std::int64_t>(list.size()) > budget_) {
                for (int rest = e + 1; rest < end; ++rest)
                    first[static_cast<std::size_t>(rest)] = static_cast<int>(list.size());
                break;
            }
        }
    }

    /// Appends the lists to q.qvertices in range order, making first[] global; checks the budget.
    int join(int n, int base, std::vector<int>& first) {
        std::int64_t at = base;
        for (int part = 0; part < parts_; ++part) {
            const int end = hi(n, part);
            const auto& list = found_[static_cast<std::size_t>(part)];
            for (int e = lo(n, part); e < end; ++e) {
                const std::int64_t global = at + first[static_cast<std::size_t>(e)];
                const std::int64_t last = e + 1 < end ? at + first[static_cast<std::size_t>(e) + 1]
                                                      : at + static_cast<std::int64_t>(list.size());
                first[static_cast<std::size_t>(e)] = static_cast<int>(std::min<std::int64_t>(global, INT32_MAX));
                if (last > budget_) return e;
            }
            at += static_cast<std::int64_t>(list.size());
            q_.qvertices.insert(q_.qvertices.end(), list.begin(), list.end());
        }
        first[static_cast<std::size_t>(n)] = static_cast<int>(q_.qvertices.size());
        return -1;
    }

    QState& q_;
    int parts_;
    std::int64_t budget_;
    std::vector<std::vector<QVertex>> found_;
};

} // namespace

Error generate_qvertices(const TriMesh& m, const Options& opt, QState& q) {
    const int nf = m.num_faces();
    q.qvertices.clear();
    // Cheap bound first, so an absurd map is rejected before any loop runs long.
    if (grid_point_bound(m) > 4.0 * static_cast<double>(opt.max_qvertices) + 1e6) return too_large(opt, -1);
    add_vertex_qvertices(m, q);
    // Edge- and face-q-vertices: ranges of half-edges (then of triangles) on all threads.
    RangeGenerator generate(q, m.parts(3 * nf), opt.max_qvertices);
    const int bad_edge =
        generate.run(3 * nf, q.edge_first, [&](int h, std::vector<QVertex>& list) { edge_qvertices(m, h, list); });
    if (bad_edge >= 0) return too_large(opt, m.input_triangle[TriMesh::face(bad_edge)]);
    const int bad_face =
        generate.run(nf, q.face_first, [&](int f, std::vector<QVertex>& list) { face_qvertices(m, f, list); });
    if (bad_face >= 0) return too_large(opt, m.input_triangle[bad_face]);
    return {};
}

} // namespace qex::detail
