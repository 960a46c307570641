// Placement on the given map, for meshes from a relaxed rung of the fallback ladder: every output
// vertex moves onto a preimage of its grid point in the sanitized map as given, so the mesh is
// judged against that map and not against the relaxed one it was extracted from.
#include "pipeline.h"

#include <algorithm>
#include <cmath>

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
                to[static_cast<std::size_t>(n)] = g.map.transition[3 * t + k].after(to[static_cast<std::size_t>(t)]);
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
