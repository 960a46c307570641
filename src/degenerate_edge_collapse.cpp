// Collapse of edges that have zero length in the parameter domain (Section 3), so that every
// remaining edge determines its transition function. Original 3D positions stay in the corners.
#include "pipeline.h"

#include <numeric>
#include <string>

namespace qex::detail {
namespace {

int find(std::vector<int>& parent, int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
}

} // namespace

Error collapse_degenerate_edges(TriMesh& m, std::int64_t& collapsed) {
    collapsed = 0;
    // Each pass merges the endpoints of every zero-length edge; removing the triangles that became
    // degenerate glues their neighbours, whose shared edges may be of zero length in turn.
    for (int pass = 0; pass < 64; ++pass) {
        const int nf = m.num_faces();
        std::vector<int> parent(m.num_vertices);
        std::iota(parent.begin(), parent.end(), 0);
        std::int64_t found = 0;
        for (int h = 0; h < 3 * nf; ++h) {
            if (m.uv[h] != m.uv[TriMesh::next(h)]) continue;
            const int a = find(parent, m.origin(h)), b = find(parent, m.target(h));
            if (a == b) continue;
            parent[std::max(a, b)] = std::min(a, b);
            ++found;
        }
        if (found == 0) return {};
        collapsed += found;
        // Re-index: keep triangles whose three vertices stay distinct.
        std::vector<int> new_id(m.num_vertices, -1);
        int nv = 0;
        std::vector<int> input_vertex;
        TriMesh out;
        for (int f = 0; f < nf; ++f) {
            std::array<int, 3> t{};
            for (int k = 0; k < 3; ++k) t[k] = find(parent, m.tri[f][k]);
            if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) continue;
            for (int k = 0; k < 3; ++k) {
                if (new_id[t[k]] < 0) {
                    new_id[t[k]] = nv++;
                    input_vertex.push_back(m.input_vertex[t[k]]);
                }
                t[k] = new_id[t[k]];
                out.uv.push_back(m.uv[3 * f + k]);
                out.corner_pos.push_back(m.corner_pos[3 * f + k]);
            }
            out.tri.push_back(t);
            out.input_triangle.push_back(m.input_triangle[f]);
        }
        if (out.tri.empty())
            return {ErrorCode::CollapseFailed, "every triangle is degenerate in the parameter domain", -1};
        out.num_vertices = nv;
        out.input_vertex = std::move(input_vertex);
        m = std::move(out);
        Error e = build_topology(m, "after collapsing UV-degenerate edges");
        if (e.code != ErrorCode::None) {
            e.code = ErrorCode::CollapseFailed;
            return e;
        }
    }
    return {ErrorCode::CollapseFailed, "collapsing UV-degenerate edges did not converge", -1};
}

} // namespace qex::detail
