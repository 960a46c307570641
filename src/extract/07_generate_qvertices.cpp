// Q-vertex generation (Algorithm 3): every integer grid point of the sanitized map becomes a
// q-vertex on the mesh vertex, edge or triangle it lies on, decided by exact predicates.
#include "pipeline.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

namespace qex::detail {
namespace {

bool is_integer_point(const Point2& p) { return std::floor(p[0]) == p[0] && std::floor(p[1]) == p[1]; }

/// Barycentric coordinates of x in (a, b, c); only used for embedding, not for decisions.
std::array<double, 3> barycentric_raw(const Point2& x, const Point2& a, const Point2& b, const Point2& c) {
    const double det = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    // A sliver (area below 2^-20 of the product of two edges) loses its barycentric coordinates
    // to rounding, and the grid point's 3D position with them: computed exactly there.
    const double scale = std::max(std::abs(b[0] - a[0]), std::abs(b[1] - a[1])) *
                         std::max(std::abs(c[0] - a[0]), std::abs(c[1] - a[1]));
    if (!(std::abs(det) > std::ldexp(scale, -20))) return barycentric_exact(x, a, b, c);
    const double wb = ((x[0] - a[0]) * (c[1] - a[1]) - (x[1] - a[1]) * (c[0] - a[0])) / det;
    const double wc = ((b[0] - a[0]) * (x[1] - a[1]) - (b[1] - a[1]) * (x[0] - a[0])) / det;
    return {1.0 - wb - wc, wb, wc};
}

/// Barycentric coordinates of x in triangle f, computed with the corners in 3D order so that
/// the result does not depend on the input's corner order.
std::array<double, 3> barycentric(const TriMesh& m, int f, const Point2& x) {
    std::array<int, 3> c{3 * f, 3 * f + 1, 3 * f + 2};
    std::sort(c.begin(), c.end(), [&](int i, int j) { return m.pos(i) < m.pos(j); });
    const auto w = barycentric_raw(x, m.uv[c[0]], m.uv[c[1]], m.uv[c[2]]);
    std::array<double, 3> out{};
    for (int i = 0; i < 3; ++i) out[c[i] - 3 * f] = w[i];
    return out;
}

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

} // namespace

Error generate_qvertices(const TriMesh& m, const Options& opt, QState& q) {
    const int nf = m.num_faces();
    q.qvertices.clear();
    auto too_large = [&](std::int64_t element) {
        return Error{ErrorCode::MapTooLarge,
                     "the map has more than " + std::to_string(opt.max_qvertices) +
                         " integer grid points (Options::max_qvertices)",
                     element};
    };
    // Cheap bound first, so an absurd map is rejected before any loop runs long.
    double bound = 0.0;
    for (int f = 0; f < nf; ++f) {
        const Point2 &a = m.uv[3 * f], &b = m.uv[3 * f + 1], &c = m.uv[3 * f + 2];
        const double w = std::max({a[0], b[0], c[0]}) - std::min({a[0], b[0], c[0]}) + 1.0;
        const double h = std::max({a[1], b[1], c[1]}) - std::min({a[1], b[1], c[1]}) + 1.0;
        bound += w * h;
    }
    if (bound > 4.0 * static_cast<double>(opt.max_qvertices) + 1e6) return too_large(-1);

    // Vertex-q-vertices.
    q.vertex_qvertex.assign(m.num_vertices, -1);
    for (int v = 0; v < m.num_vertices; ++v) {
        const int c = m.fan_start[v];
        if (c < 0 || !is_integer_point(m.uv[c])) continue;
        q.vertex_qvertex[v] = static_cast<int>(q.qvertices.size());
        std::array<double, 3> w{0, 0, 0};
        w[c % 3] = 1.0;
        q.qvertices.push_back({QVertexKind::Vertex, v, TriMesh::face(c),
                               {static_cast<std::int64_t>(m.uv[c][0]), static_cast<std::int64_t>(m.uv[c][1])},
                               m.pos(c), w});
    }
    // Edge- and face-q-vertices. Ranges of half-edges (then of triangles) are generated on all
    // threads into their own lists, which are joined in range order: the q-vertices and their
    // numbering are those of one serial pass. The budget is checked on the joined counts and
    // names the element a serial pass would stop at.
    const int parts = m.parallel(3 * nf) ? std::max(1, m.threads) : 1;
    std::vector<std::vector<QVertex>> found(static_cast<std::size_t>(parts));
    // Generates the q-vertices of elements [0, n) with `one(element, list)`; first[e] becomes
    // the index of element e's first q-vertex, first[n] the end. Returns the first element whose
    // q-vertices end beyond the budget, or -1.
    auto generate = [&](int n, std::vector<int>& first, auto&& one) {
        first.assign(static_cast<std::size_t>(n) + 1, 0);
        const auto base = static_cast<int>(q.qvertices.size());
#if defined(_OPENMP)
#pragma omp parallel for schedule(static, 1) num_threads(parts) if (parts > 1)
#endif
        for (int part = 0; part < parts; ++part) {
            auto& list = found[static_cast<std::size_t>(part)];
            list.clear();
            const int lo = static_cast<int>(static_cast<std::int64_t>(n) * part / parts);
            const int hi = static_cast<int>(static_cast<std::int64_t>(n) * (part + 1) / parts);
            for (int e = lo; e < hi; ++e) {
                first[static_cast<std::size_t>(e)] = static_cast<int>(list.size());
                one(e, list);
                // A part alone far over the budget stops early; the joined check below reports.
                if (static_cast<std::int64_t>(list.size()) > opt.max_qvertices) {
                    for (int rest = e + 1; rest < hi; ++rest) first[static_cast<std::size_t>(rest)] = static_cast<int>(list.size());
                    break;
                }
            }
        }
        std::int64_t at = base;
        for (int part = 0; part < parts; ++part) {
            const int lo = static_cast<int>(static_cast<std::int64_t>(n) * part / parts);
            const int hi = static_cast<int>(static_cast<std::int64_t>(n) * (part + 1) / parts);
            const auto& list = found[static_cast<std::size_t>(part)];
            for (int e = lo; e < hi; ++e) {
                const std::int64_t global = at + first[static_cast<std::size_t>(e)];
                const std::int64_t end = e + 1 < hi ? at + first[static_cast<std::size_t>(e) + 1] : at + static_cast<std::int64_t>(list.size());
                first[static_cast<std::size_t>(e)] = static_cast<int>(std::min<std::int64_t>(global, INT32_MAX));
                if (end > opt.max_qvertices) return e;
            }
            at += static_cast<std::int64_t>(list.size());
            q.qvertices.insert(q.qvertices.end(), list.begin(), list.end());
        }
        first[static_cast<std::size_t>(n)] = static_cast<int>(q.qvertices.size());
        return -1;
    };
    // Edge-q-vertices: on each edge, in the chart of its smaller half-edge.
    const int bad_edge = generate(3 * nf, q.edge_first, [&](int h, std::vector<QVertex>& list) {
        if (m.opp[h] >= 0 && m.opp[h] < h) return;
        const Point2& a = m.uv[h];
        const Point2& b = m.uv[TriMesh::next(h)];
        if (a == b) return; // cannot happen after collapsing; keeps the division below safe
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
                list.push_back({QVertexKind::Edge, h, f, {static_cast<std::int64_t>(p[0]), static_cast<std::int64_t>(p[1])},
                                embed(m, f, w), w});
            }
        }
    });
    if (bad_edge >= 0) return too_large(m.input_triangle[TriMesh::face(bad_edge)]);
    // Face-q-vertices: strictly inside a non-degenerate triangle.
    const int bad_face = generate(nf, q.face_first, [&](int f, std::vector<QVertex>& list) {
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
                list.push_back({QVertexKind::Face, f, f, {static_cast<std::int64_t>(x), static_cast<std::int64_t>(y)},
                                embed(m, f, w), w});
            }
    });
    if (bad_face >= 0) return too_large(m.input_triangle[bad_face]);
    return {};
}

} // namespace qex::detail
