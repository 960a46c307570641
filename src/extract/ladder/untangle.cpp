// Fold-over untangling: a fallback for maps whose fold-overs defeat the paper's local handling.
// Regular interior vertices within `rings` of a flipped or degenerate triangle (UV area <= 0) are
// moved to the average of their neighbours (uniform Laplacian, Gauss-Seidel), expressed through
// the exact transitions, so the map keeps its transitions and singularities; only the folded
// region moves. Run before sanitization, which re-truncates the moved coordinates.
#include "ladder.h"

#include <algorithm>
#include <cmath>

namespace qex::detail {
namespace {

/// Whether triangle f's UV area is <= 0 (exact): flipped or degenerate, what untangling targets.
bool flipped_or_degenerate(const TriMesh& m, int f) {
    return sign(orient2d(m.uv[3 * f], m.uv[3 * f + 1], m.uv[3 * f + 2])) <= 0;
}

/// Marks the vertices of flipped or degenerate triangles in `active` and returns how many such
/// triangles there are.
std::int64_t mark_flipped_or_degenerate(const TriMesh& m, std::vector<char>& active) {
    std::int64_t count = 0;
    for (int f = 0; f < m.num_faces(); ++f)
        if (flipped_or_degenerate(m, f)) {
            ++count;
            for (int k = 0; k < 3; ++k) active[m.tri[f][k]] = 1;
        }
    return count;
}

/// Grows the `active` vertices by `rings` rings of neighbours.
void grow_rings(const TriMesh& m, int rings, std::vector<char>& active) {
    for (int r = 0; r < rings; ++r) {
        std::vector<char> grown = active;
        for (int h = 0; h < 3 * m.num_faces(); ++h)
            if (active[m.origin(h)]) grown[m.target(h)] = 1;
        active.swap(grown);
    }
}

/// The relaxed vertices' fans, fixed while the sweeps run (only UVs move): per vertex its
/// corners, from the one whose next vertex comes first in 3D (so the sums below do not depend
/// on the input's order), and the transitions from the first corner's chart to each corner's and
/// back.
struct Fans {
    std::vector<std::size_t> start{0};
    std::vector<int> corner;
    std::vector<GridAutomorphism> to_c, from_c;
};

/// Adds interior vertex v's fan to `fans` unless v is singular (its fan's transitions do not
/// compose to the identity, or its winding valence is 8 or more): singular vertices stay.
void add_fan(const TriMesh& m, int v, Fans& fans) {
    const std::size_t first = fans.corner.size();
    for (int h = m.fan_start[v], n = 0; h >= 0 && n < m.fan_size[v]; h = m.cw(h), ++n) fans.corner.push_back(h);
    const auto fan = fans.corner.begin() + static_cast<std::ptrdiff_t>(first);
    std::rotate(fan,
                std::min_element(fan, fans.corner.end(),
                                 [&](int a, int b) { return m.pos(TriMesh::next(a)) < m.pos(TriMesh::next(b)); }),
                fans.corner.end());
    const std::size_t n = fans.corner.size() - first;
    std::vector<GridAutomorphism> to_c(n);
    for (std::size_t i = 1; i < n; ++i)
        to_c[i] = m.map.transition[fan[static_cast<std::ptrdiff_t>(i - 1)]].after(to_c[i - 1]);
    const GridAutomorphism loop = m.map.transition[fans.corner.back()].after(to_c[n - 1]);
    if (!loop.is_identity() || std::abs(m.map.winding_valence[v]) >= 8) {
        fans.corner.resize(first);
        return;
    }
    for (const GridAutomorphism& g : to_c) fans.to_c.push_back(g), fans.from_c.push_back(g.inverse());
    fans.start.push_back(fans.corner.size());
}

/// Moves the k-th vertex of `fans` to the average of its neighbours, each mapped into the chart
/// of its first corner, and writes it to every corner through the transitions.
void relax_vertex(TriMesh& m, const Fans& fans, std::size_t k) {
    const std::size_t b = fans.start[k], e = fans.start[k + 1];
    double sx = 0.0, sy = 0.0;
    for (std::size_t i = b; i < e; ++i) {
        const Point2 p = fans.from_c[i](m.uv[TriMesh::next(fans.corner[i])]);
        sx += p[0];
        sy += p[1];
    }
    const auto n = static_cast<double>(e - b);
    const Point2 u0{sx / n, sy / n};
    for (std::size_t i = b; i < e; ++i) m.uv[fans.corner[i]] = fans.to_c[i](u0);
}

} // namespace

std::int64_t untangle(TriMesh& m, int rings, int iterations) {
    const int nv = m.num_vertices, nf = m.num_faces();
    std::vector<char> active(nv, 0);
    if (mark_flipped_or_degenerate(m, active) == 0) return 0;
    grow_rings(m, rings, active);
    // Gauss-Seidel sweeps in 3D order of the vertices, not the input's.
    std::vector<int> order;
    for (int v = 0; v < nv; ++v)
        if (active[v] && !m.on_boundary[v] && m.fan_start[v] >= 0) order.push_back(v);
    const auto& positions = *m.positions;
    std::sort(order.begin(), order.end(), [&](int a, int b) {
        const auto &pa = positions[static_cast<std::size_t>(m.input_vertex[a])],
                   &pb = positions[static_cast<std::size_t>(m.input_vertex[b])];
        return pa != pb ? pa < pb : a < b;
    });
    Fans fans;
    for (const int v : order) add_fan(m, v, fans);
    for (int it = 0; it < iterations; ++it)
        for (std::size_t k = 0; k + 1 < fans.start.size(); ++k) relax_vertex(m, fans, k);
    // The triangles still flipped or degenerate.
    std::int64_t remaining = 0;
    for (int f = 0; f < nf; ++f) remaining += flipped_or_degenerate(m, f);
    return remaining;
}

} // namespace qex::detail
