// Collapse of edges that have zero length in the parameter domain (Section 3), so that every
// remaining edge determines its transition function. Original 3D positions stay in the corners.
// An edge is collapsed only where the link condition holds (the endpoints share no neighbour
// besides the edge's opposite vertices); otherwise the collapse would pinch the surface, and the
// edge is kept: compute_transitions then derives its rotation from the fan of an endpoint.
#include "pipeline.h"
#include "union_find.h"

#include <algorithm>
#include <numeric>
#include <string>

namespace qex::detail {

Error collapse(TriMesh& m, std::int64_t& collapsed) {
    collapsed = 0;
    const int nf = m.num_faces();
    bool any = false;
    for (int h = 0; h < 3 * nf && !any; ++h) any = m.uv[h] == m.uv[TriMesh::next(h)];
    if (!any) return {};
    UnionFind sets(static_cast<std::size_t>(m.num_vertices));
    // Triangles around each (representative) vertex, and whether a triangle is still alive.
    std::vector<std::vector<int>> faces_of(m.num_vertices);
    for (int f = 0; f < nf; ++f)
        for (int k = 0; k < 3; ++k) faces_of[m.tri[f][k]].push_back(f);
    std::vector<char> dead(nf, 0);
    auto corner_of = [&](int f, int k) { return sets.find(m.tri[f][k]); };
    auto neighbours = [&](int v, std::vector<int>& out) {
        out.clear();
        for (int f : faces_of[v]) {
            if (dead[f]) continue;
            for (int k = 0; k < 3; ++k)
                if (const int w = corner_of(f, k); w != v) out.push_back(w);
        }
        std::sort(out.begin(), out.end());
        out.erase(std::unique(out.begin(), out.end()), out.end());
    };
    std::vector<int> na, nb, common, opposite;
    // Zero-length edges appear again when neighbours glue; a few passes reach the fixed point.
    for (bool changed = true; changed;) {
        changed = false;
        for (int h = 0; h < 3 * nf; ++h) {
            const int f = TriMesh::face(h);
            if (dead[f] || m.uv[h] != m.uv[TriMesh::next(h)]) continue;
            const int a = sets.find(m.origin(h)), b = sets.find(m.target(h));
            if (a == b) continue;
            neighbours(a, na);
            neighbours(b, nb);
            common.clear();
            std::set_intersection(na.begin(), na.end(), nb.begin(), nb.end(), std::back_inserter(common));
            opposite.clear();
            for (int g : faces_of[a]) {
                if (dead[g]) continue;
                int has_b = 0, other = -1;
                for (int k = 0; k < 3; ++k) {
                    const int w = corner_of(g, k);
                    if (w == b) has_b = 1;
                    else if (w != a) other = w;
                }
                if (has_b && other >= 0) opposite.push_back(other);
            }
            std::sort(opposite.begin(), opposite.end());
            if (common != opposite) continue; // the collapse would pinch the surface
            // Merge b into a; triangles holding both die.
            sets.attach(b, a);
            for (int g : faces_of[b]) {
                faces_of[a].push_back(g);
                int count_ab = 0;
                for (int k = 0; k < 3; ++k) count_ab += corner_of(g, k) == a;
                if (count_ab > 1) dead[g] = 1;
            }
            faces_of[b].clear();
            ++collapsed;
            changed = true;
        }
    }
    if (collapsed == 0) return {};
    // Re-index: keep live triangles.
    std::vector<int> new_id(m.num_vertices, -1);
    int nv = 0;
    TriMesh out;
    for (int f = 0; f < nf; ++f) {
        if (dead[f]) continue;
        std::array<int, 3> t{};
        for (int k = 0; k < 3; ++k) {
            const int v = corner_of(f, k);
            if (new_id[v] < 0) {
                new_id[v] = nv++;
                out.input_vertex.push_back(m.input_vertex[v]);
            }
            t[k] = new_id[v];
            out.uv.push_back(m.uv[3 * f + k]);
            out.corner_vertex.push_back(m.corner_vertex[3 * f + k]);
        }
        out.tri.push_back(t);
        out.input_triangle.push_back(m.input_triangle[f]);
    }
    if (out.tri.empty())
        return {ErrorCode::CollapseFailed, "every triangle is degenerate in the parameter domain", -1};
    out.num_vertices = nv;
    out.positions = m.positions;
    out.threads = m.threads;
    m = std::move(out);
    Error e = build_topology(m, "after collapsing UV-degenerate edges");
    if (e.code != ErrorCode::None) e.code = ErrorCode::CollapseFailed;
    return e;
}

} // namespace qex::detail
