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

/// Moves interior vertex v to the average of its neighbours unless it is singular (its fan's
/// transitions do not compose to the identity, or its winding valence is 8 or more).
/// `fan` and `to_c` are scratch.
void relax_vertex(TriMesh& m, int v, std::vector<int>& fan, std::vector<GridAutomorphism>& to_c) {
    fan.clear();
    for (int h = m.fan_start[v], n = 0; h >= 0 && n < m.fan_size[v]; h = m.cw(h), ++n) fan.push_back(h);
    // Start at the corner whose next vertex comes first in 3D: the sums below then do not depend
    // on the input's order.
    std::rotate(fan.begin(),
                std::min_element(fan.begin(), fan.end(),
                                 [&](int a, int b) { return m.pos(TriMesh::next(a)) < m.pos(TriMesh::next(b)); }),
                fan.end());
    const std::size_t n = fan.size();
    // to_c[i]: chart of fan[0] -> chart of fan[i].
    to_c.assign(n, GridAutomorphism{});
    for (std::size_t i = 1; i < n; ++i) to_c[i] = m.map.transition[fan[i - 1]].after(to_c[i - 1]);
    const GridAutomorphism loop = m.map.transition[fan[n - 1]].after(to_c[n - 1]);
    if (!loop.is_identity() || std::abs(m.map.winding_valence[v]) >= 8) return; // singular: pinned
    // Average of the neighbours, each mapped into the chart of fan[0].
    double sx = 0.0, sy = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        const Point2 p = to_c[i].inverse()(m.uv[TriMesh::next(fan[i])]);
        sx += p[0];
        sy += p[1];
    }
    const Point2 u0{sx / static_cast<double>(n), sy / static_cast<double>(n)};
    for (std::size_t i = 0; i < n; ++i) m.uv[fan[i]] = to_c[i](u0);
}

} // namespace

std::int64_t untangle(TriMesh& m, int rings, int iterations) {
    const int nv = m.num_vertices, nf = m.num_faces();
    std::vector<char> active(nv, 0);
    if (mark_flipped_or_degenerate(m, active) == 0) return 0;
    grow_rings(m, rings, active);
    std::vector<int> fan;
    std::vector<GridAutomorphism> to_c;
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
    for (int it = 0; it < iterations; ++it)
        for (const int v : order) relax_vertex(m, v, fan, to_c);
    // The triangles still flipped or degenerate.
    std::int64_t remaining = 0;
    for (int f = 0; f < nf; ++f) remaining += flipped_or_degenerate(m, f);
    return remaining;
}

} // namespace qex::detail
