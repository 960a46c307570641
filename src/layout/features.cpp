// qex::quad_feature_edges: the edges of qex's quad mesh that run along the input's feature edges,
// found through the vertices' provenance (qex/layout.h).
#include "qex/layout.h"

#include <algorithm>
#include <cstdint>
#include <iterator>
#include <unordered_map>

namespace qex {
namespace {

std::uint64_t pair_key(int a, int b) {
    return static_cast<std::uint64_t>(std::min(a, b)) << 32 | static_cast<std::uint32_t>(std::max(a, b));
}

/// The input feature edges (their indices) an output vertex lies on: at a vertex, every feature
/// edge there; on an edge, that edge if it is one.
std::vector<int> features_at(const Input& in, const Provenance& p, const std::unordered_map<std::uint64_t, int>& edge,
                             const std::vector<std::vector<int>>& at_vertex) {
    if (p.kind == QVertexKind::Vertex && p.element >= 0 && p.element < static_cast<std::int64_t>(at_vertex.size()))
        return at_vertex[p.element];
    if (p.kind == QVertexKind::Edge && p.element >= 0 && p.element < static_cast<std::int64_t>(in.triangles.size()) &&
        p.local_edge >= 0 && p.local_edge < 3) {
        const auto& t = in.triangles[p.element];
        const auto it = edge.find(pair_key(t[p.local_edge], t[(p.local_edge + 1) % 3]));
        if (it != edge.end()) return {it->second};
    }
    return {};
}

} // namespace

std::vector<std::array<int, 2>> quad_feature_edges(const Input& input, const QuadMesh& mesh) {
    std::unordered_map<std::uint64_t, int> edge;
    std::vector<std::vector<int>> at_vertex(input.positions.size());
    for (std::size_t e = 0; e < input.feature_edges.size(); ++e) {
        const auto [a, b] = input.feature_edges[e];
        if (a < 0 || b < 0 || a >= static_cast<int>(at_vertex.size()) || b >= static_cast<int>(at_vertex.size()))
            continue;
        edge.emplace(pair_key(a, b), static_cast<int>(e));
        at_vertex[a].push_back(static_cast<int>(e));
        at_vertex[b].push_back(static_cast<int>(e));
    }
    std::vector<std::array<int, 2>> out;
    if (edge.empty() || mesh.provenance.size() != mesh.positions.size()) return out;
    std::vector<std::vector<int>> on(mesh.positions.size());
    for (std::size_t v = 0; v < on.size(); ++v) {
        on[v] = features_at(input, mesh.provenance[v], edge, at_vertex);
        std::sort(on[v].begin(), on[v].end());
    }
    for (const auto& f : mesh.faces)
        for (std::size_t k = 0; k < f.size(); ++k) {
            const int a = f[k], b = f[(k + 1) % f.size()];
            if (a < 0 || b < 0 || a >= static_cast<int>(on.size()) || b >= static_cast<int>(on.size()) || a > b)
                continue;
            std::vector<int> both;
            std::set_intersection(on[a].begin(), on[a].end(), on[b].begin(), on[b].end(), std::back_inserter(both));
            if (!both.empty()) out.push_back({a, b});
        }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

} // namespace qex
