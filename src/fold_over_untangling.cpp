// Fold-over untangling: a fallback for maps whose fold-overs defeat the paper's local handling.
// Regular interior vertices within `rings` of a flipped or degenerate triangle are moved to the
// average of their neighbours (uniform Laplacian, Gauss-Seidel), expressed through the exact
// transitions, so the map keeps its transitions and singularities; only the folded region moves.
// Run before sanitization, which re-truncates the moved coordinates.
#include "pipeline.h"

#include <algorithm>
#include <cmath>

namespace qex::detail {

std::int64_t untangle_fold_overs(TriMesh& m, int rings, int iterations) {
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
            for (std::size_t i = 1; i < n; ++i) to_c[i] = m.transition[fan[i - 1]].after(to_c[i - 1]);
            const GridAutomorphism loop = m.transition[fan[n - 1]].after(to_c[n - 1]);
            if (!loop.is_identity() || std::abs(m.winding_valence[v]) >= 8) continue; // singular: pinned
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

namespace qex::detail {

std::int64_t place_on_given_map(const Input& input, const std::vector<std::array<double, 2>>& given, QuadMesh& mesh) {
    TriMesh g = make_mesh(input);
    if (build_topology(g, "input").code != ErrorCode::None) return static_cast<std::int64_t>(mesh.positions.size());
    g.uv = given;
    const int nf = g.num_faces();
    auto alive = [&](int f) { return std::isfinite(g.uv[3 * f][0]); };
    // Transitions of the given (sanitized) map, exact there: rotation from the edge, then the
    // translation. Edges next to a collapsed triangle are not crossed.
    compute_transitions(g);
    std::vector<std::uint32_t> stamp(static_cast<std::size_t>(nf), 0);
    std::vector<GridAutomorphism> to(static_cast<std::size_t>(nf));
    std::vector<int> queue;
    std::uint32_t generation = 0;
    std::int64_t unplaced = 0;
    for (std::size_t i = 0; i < mesh.positions.size() && i < mesh.provenance.size(); ++i) {
        Provenance& p = mesh.provenance[i];
        const int start = p.chart_triangle;
        if (start < 0 || start >= nf || !alive(start)) {
            ++unplaced;
            continue;
        }
        ++generation;
        queue.assign(1, start);
        stamp[static_cast<std::size_t>(start)] = generation;
        to[static_cast<std::size_t>(start)] = GridAutomorphism{};
        int found = -1, found_flipped = -1;
        for (std::size_t head = 0; head < queue.size() && found < 0 && queue.size() < 4096; ++head) {
            const int t = queue[head];
            const IPoint q = to[static_cast<std::size_t>(t)](IPoint{p.grid[0], p.grid[1]});
            const Point2 x{static_cast<double>(q[0]), static_cast<double>(q[1])};
            const Point2 &a = g.uv[3 * t], &b = g.uv[3 * t + 1], &c = g.uv[3 * t + 2];
            const int s = sign(orient2d(a, b, c));
            if (s != 0) {
                const int o0 = sign(orient2d(a, b, x)), o1 = sign(orient2d(b, c, x)), o2 = sign(orient2d(c, a, x));
                const bool inside = (o0 == s || o0 == 0) && (o1 == s || o1 == 0) && (o2 == s || o2 == 0);
                if (inside && s > 0) found = t;
                if (inside && s < 0 && found_flipped < 0) found_flipped = t;
            }
            for (int k = 0; k < 3; ++k) {
                const int o = g.opp[3 * t + k];
                if (o < 0) continue;
                const int n = TriMesh::face(o);
                if (stamp[static_cast<std::size_t>(n)] == generation || !alive(n)) continue;
                stamp[static_cast<std::size_t>(n)] = generation;
                to[static_cast<std::size_t>(n)] = g.transition[3 * t + k].after(to[static_cast<std::size_t>(t)]);
                queue.push_back(n);
            }
        }
        if (found < 0) found = found_flipped;
        if (found < 0) {
            ++unplaced;
            continue;
        }
        // The grid point in the found triangle: on a corner, on an edge, or inside.
        const IPoint q = to[static_cast<std::size_t>(found)](IPoint{p.grid[0], p.grid[1]});
        const Point2 x{static_cast<double>(q[0]), static_cast<double>(q[1])};
        const Point2* u = &g.uv[3 * found];
        const auto& tri = input.triangles[static_cast<std::size_t>(found)];
        Provenance np;
        np.merged = p.merged;
        np.chart_triangle = found;
        np.grid = {q[0], q[1]};
        int corner = -1, edge = -1;
        for (int k = 0; k < 3; ++k) {
            if (u[k] == x) corner = k;
            else if (sign(orient2d(u[k], u[(k + 1) % 3], x)) == 0) edge = k;
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
        std::array<double, 3> pos{0, 0, 0};
        for (int k = 0; k < 3; ++k)
            for (int d = 0; d < 3; ++d)
                pos[static_cast<std::size_t>(d)] += w[static_cast<std::size_t>(k)] * input.positions[static_cast<std::size_t>(tri[static_cast<std::size_t>(k)])][static_cast<std::size_t>(d)];
        if (corner >= 0) pos = input.positions[static_cast<std::size_t>(np.element)];
        mesh.positions[i] = pos;
        p = np;
    }
    mesh.map_uvs = given;
    return unplaced;
}

} // namespace qex::detail
