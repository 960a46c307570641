// Fold-over untangling: a fallback for maps whose fold-overs defeat the paper's local handling.
// Regular interior vertices within `rings` of a flipped or degenerate triangle are moved to the
// average of their neighbours (uniform Laplacian, Gauss-Seidel), expressed through the exact
// transitions, so the map keeps its transitions and singularities; only the folded region moves.
// Run before sanitization, which re-truncates the moved coordinates.
#include "pipeline.h"

#include <algorithm>
#include <cmath>

namespace qex::detail {

std::int64_t untangle(TriMesh& m, int rings, int iterations) {
    const int nv = m.num_vertices, nf = m.num_faces();
    auto flipped = [&](int f) {
        return sign(orient2d(m.uv[3 * f], m.uv[3 * f + 1], m.uv[3 * f + 2])) <= 0;
    };
    std::vector<char> active(nv, 0);
    std::int64_t bad = 0;
    for (int f = 0; f < nf; ++f)
        if (flipped(f)) {
            ++bad;
            for (int k = 0; k < 3; ++k) active[m.tri[f][k]] = 1;
        }
    if (bad == 0) return 0;
    for (int r = 0; r < rings; ++r) {
        std::vector<char> grown = active;
        for (int h = 0; h < 3 * nf; ++h)
            if (active[m.origin(h)]) grown[m.target(h)] = 1;
        active.swap(grown);
    }
    std::vector<int> fan;
    std::vector<GridAutomorphism> to_c;
    for (int it = 0; it < iterations; ++it) {
        for (int v = 0; v < nv; ++v) {
            if (!active[v] || m.on_boundary[v] || m.fan_start[v] < 0) continue;
            fan.clear();
            for (int h = m.fan_start[v], n = 0; h >= 0 && n < m.fan_size[v]; h = m.cw(h), ++n) fan.push_back(h);
            const std::size_t n = fan.size();
            to_c.assign(n, GridAutomorphism{});
            for (std::size_t i = 1; i < n; ++i) to_c[i] = m.map.transition[fan[i - 1]].after(to_c[i - 1]);
            const GridAutomorphism loop = m.map.transition[fan[n - 1]].after(to_c[n - 1]);
            if (!loop.is_identity() || std::abs(m.map.winding_valence[v]) >= 8) continue; // singular: pinned
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
    }
    std::int64_t remaining = 0;
    for (int f = 0; f < nf; ++f) remaining += flipped(f);
    return remaining;
}


} // namespace qex::detail
