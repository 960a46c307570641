// Placement on the given map, for meshes from a relaxed rung of the fallback ladder: every output
// vertex moves onto a preimage of its grid point in the sanitized map as given, so the mesh is
// judged against that map and not against the relaxed one it was extracted from. Also every
// preimage of a grid point such a search finds, for separate_sheets.
#include "chart_search.h"
#include "ladder.h"

#include <algorithm>
#include <cstring>

namespace qex::detail {

const TriMesh* MapGraph::of(const std::vector<std::array<double, 2>>& map) {
    // The same bits: a collapsed corner's NaN equals nothing, itself included.
    const bool same = made_ && map.size() == map_.size() &&
                      (map.empty() || std::memcmp(map.data(), map_.data(), map.size() * sizeof map[0]) == 0);
    if (same) return ok_ ? &graph_ : nullptr;
    made_ = true, map_ = map;
    graph_ = make_mesh(input_);
    ok_ = map.size() == input_.uvs.size() && build_topology(graph_, "input").code == ErrorCode::None;
    if (!ok_) return nullptr;
    graph_.uv = map;
    // Transitions of the map, exact there: rotation from the edge, then the translation.
    compute_transitions(graph_);
    return &graph_;
}

std::int64_t place_on_given_map(MapGraph& graph, const std::vector<std::array<double, 2>>& given, QuadMesh& mesh) {
    const Input& input = graph.input();
    const TriMesh* made = graph.of(given);
    if (!made) return static_cast<std::int64_t>(mesh.positions.size());
    const TriMesh& g = *made;
    ChartSearch search(g);
    std::int64_t unplaced = 0;
    for (std::size_t i = 0; i < mesh.positions.size() && i < mesh.provenance.size(); ++i) {
        Provenance& p = mesh.provenance[i];
        const IPoint grid{p.grid[0], p.grid[1]};
        int found = search.find(p.chart_triangle, grid);
        GridAutomorphism to = found >= 0 ? search.to(found) : GridAutomorphism{};
        if (found < 0) found = search.find_round_singularities(grid, to);
        if (found < 0) {
            ++unplaced;
            continue;
        }
        p = located(input, g, found, to(grid), p.merged);
        mesh.positions[i] = position_of(input, p);
    }
    mesh.map_uvs = given;
    return unplaced;
}

std::vector<std::vector<std::pair<Provenance, std::array<double, 3>>>> preimages(
    MapGraph& graph, const std::vector<std::array<double, 2>>& map, const std::vector<Provenance>& points) {
    std::vector<std::vector<std::pair<Provenance, std::array<double, 3>>>> out(points.size());
    const Input& input = graph.input();
    const TriMesh* made = graph.of(map);
    if (!made) return out;
    const TriMesh& g = *made;
    ChartSearch search(g);
    for (std::size_t i = 0; i < points.size(); ++i) {
        const Provenance& p = points[i];
        for (const auto& [t, q] : search.find_all(p.chart_triangle, {p.grid[0], p.grid[1]})) {
            Provenance at = located(input, g, t, q, p.merged);
            // One preimage per place: a vertex or an edge is held by every triangle round it.
            const std::array<double, 3> x = position_of(input, at);
            if (std::none_of(out[i].begin(), out[i].end(), [&](const auto& seen) { return seen.second == x; }))
                out[i].push_back({std::move(at), x});
        }
    }
    return out;
}

} // namespace qex::detail
