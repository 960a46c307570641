// Stage separate_sheets (not in the paper): a rung's mesh that the checker rejects may have an
// edge with four face sides. Where a fold-over lays several sheets of the surface over the same
// grid cells, a face walk can pass from one sheet to another, and merging the clones it meets
// (Algorithm 7) makes one vertex of two on each end of an edge. Each end is then the corner of two
// fans, joined only at that edge. The edge is cut by splitting one end into one vertex per fan.
// The other end's faces then form one fan (where the two ends paired the edge's sides
// differently: a vertex winding twice round its grid point, as a fold-over's branch point does)
// or two, and then it is split too. The grid point has a preimage on each sheet: every vertex
// split takes the one nearest the vertices round its fan. Which end goes first is the caller's
// choice; the result is a candidate only, kept if the checker accepts it.
#include "pipeline.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <cstdint>
#include <numeric>
#include <string>
#include <unordered_map>

namespace qex::detail {
namespace {

std::uint64_t edge_key(int a, int b) {
    if (a > b) std::swap(a, b);
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

/// The mesh's edges with how many face sides each has, and each vertex's face corners, kept up
/// to date as vertices are split.
class Sides {
public:
    explicit Sides(const QuadMesh& mesh) : mesh_(mesh), corners_(mesh.positions.size()) {
        count_.reserve(2 * mesh.faces.size());
        for (std::size_t f = 0; f < mesh.faces.size(); ++f)
            for (std::size_t k = 0; k < mesh.faces[f].size(); ++k) {
                ++count_[edge_key(at(f, k), at(f, k + 1))];
                corners_[static_cast<std::size_t>(at(f, k))].push_back({f, k});
            }
    }
    int count(int a, int b) const {
        const auto it = count_.find(edge_key(a, b));
        return it == count_.end() ? 0 : it->second;
    }
    /// The edges of more than two face sides, in order.
    std::vector<std::uint64_t> non_manifold() const {
        std::vector<std::uint64_t> keys;
        for (const auto& [key, n] : count_)
            if (n > 2) keys.push_back(key);
        std::sort(keys.begin(), keys.end());
        return keys;
    }
    /// Splits vertex v of `mesh` (the one this was built from) into one vertex per fan of the
    /// faces round it: faces are joined across an edge (v, w) that one leaves v by and the other
    /// enters v by, when that edge has two face sides. The fan of v's first corner keeps v; the
    /// others get copies, appended in the order of their first corners. Returns the number of fans.
    int split(QuadMesh& mesh, int v) {
        const std::vector<std::pair<std::size_t, std::size_t>> around = corners_[static_cast<std::size_t>(v)];
        std::vector<int> parent(around.size());
        std::iota(parent.begin(), parent.end(), 0);
        const auto find = [&](int x) {
            while (parent[static_cast<std::size_t>(x)] != x) x = parent[static_cast<std::size_t>(x)];
            return x;
        };
        for (std::size_t i = 0; i < around.size(); ++i) {
            const int w = at(around[i].first, around[i].second + 1);
            if (count(v, w) != 2) continue;
            for (std::size_t j = 0; j < around.size(); ++j) {
                const auto [f, k] = around[j];
                if (i == j || at(f, k + mesh.faces[f].size() - 1) != w) continue;
                const int a = find(static_cast<int>(i)), b = find(static_cast<int>(j));
                if (a != b) parent[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
            }
        }
        std::vector<int> number(around.size(), -1);
        int fans = 0;
        for (std::size_t i = 0; i < around.size(); ++i) {
            const auto r = static_cast<std::size_t>(find(static_cast<int>(i)));
            if (number[r] < 0) number[r] = fans++;
        }
        if (fans < 2) return fans;
        const int first_copy = static_cast<int>(mesh.positions.size());
        for (int c = 1; c < fans; ++c) {
            mesh.positions.push_back(mesh.positions[static_cast<std::size_t>(v)]);
            if (static_cast<std::size_t>(v) < mesh.provenance.size())
                mesh.provenance.push_back(mesh.provenance[static_cast<std::size_t>(v)]);
            corners_.emplace_back();
        }
        corners_[static_cast<std::size_t>(v)].clear();
        for (std::size_t i = 0; i < around.size(); ++i) {
            const int fan = number[static_cast<std::size_t>(find(static_cast<int>(i)))];
            const auto [f, k] = around[i];
            const std::size_t n = mesh.faces[f].size();
            const int to = fan == 0 ? v : first_copy + fan - 1;
            corners_[static_cast<std::size_t>(to)].push_back({f, k});
            if (to == v) continue;
            const int prev = at(f, k + n - 1), next = at(f, k + 1);
            --count_[edge_key(v, prev)], --count_[edge_key(v, next)];
            mesh.faces[f][k] = to;
            ++count_[edge_key(to, prev)], ++count_[edge_key(to, next)];
        }
        return fans;
    }

private:
    /// Vertex of face f at corner k (mod its size).
    int at(std::size_t f, std::size_t k) const { return mesh_.faces[f][k % mesh_.faces[f].size()]; }

    const QuadMesh& mesh_;
    std::unordered_map<std::uint64_t, int> count_;
    std::vector<std::vector<std::pair<std::size_t, std::size_t>>> corners_;
};

/// The explanation of edge (a, b) cut by splitting its ends as `split` says (vertex, fans).
Defect explain(const QuadMesh& mesh, int a, int b, int sides, const std::vector<std::pair<int, int>>& split) {
    std::string what;
    for (const auto& [v, fans] : split)
        what += (what.empty() ? "vertex " : " and vertex ") + std::to_string(v) + " into " + std::to_string(fans);
    Defect d{DefectKind::SheetsSeparated,
             "edge (" + std::to_string(a) + ", " + std::to_string(b) + ") had " + std::to_string(sides) +
                 " face sides, where merged clones joined sheets of a fold-over: " + what + " vertices, one per fan",
             -1,
             -1,
             {0, 0},
             std::nullopt};
    const int v = split.front().first;
    if (static_cast<std::size_t>(v) < mesh.provenance.size()) {
        const Provenance& p = mesh.provenance[static_cast<std::size_t>(v)];
        d.input_element = p.chart_triangle;
        d.grid = {p.grid[0], p.grid[1]};
        d.message += " (grid point (" + std::to_string(p.grid[0]) + ", " + std::to_string(p.grid[1]) +
                     ") of input triangle " + std::to_string(p.chart_triangle) + ")";
    }
    return d;
}

/// Each vertex of every group (a vertex split, then its copies: one grid point) moved onto the
/// preimage of its grid point in the mesh's map nearest the mean of the vertices round its fan
/// (those of its group left out), one not taken by another of its group where there is one.
/// Vertices keep their place where no preimage is found (a mesh without its map).
void place_on_own_sheets(const Input& input, const std::vector<std::vector<int>>& groups, QuadMesh& mesh) {
    if (groups.empty() || mesh.provenance.size() != mesh.positions.size()) return;
    std::vector<Provenance> points;
    for (const std::vector<int>& group : groups) points.push_back(mesh.provenance[static_cast<std::size_t>(group[0])]);
    const auto found = preimages(input, mesh.map_uvs, points);
    // Per vertex of a group: the summed positions of the vertices round it, and how many.
    std::vector<int> group_of(mesh.positions.size(), -1);
    for (std::size_t g = 0; g < groups.size(); ++g)
        for (const int v : groups[g]) group_of[static_cast<std::size_t>(v)] = static_cast<int>(g);
    std::vector<std::array<double, 3>> sum(mesh.positions.size(), {0, 0, 0});
    std::vector<int> count(mesh.positions.size(), 0);
    for (const std::vector<int>& f : mesh.faces)
        for (std::size_t k = 0; k < f.size(); ++k) {
            const auto v = static_cast<std::size_t>(f[k]);
            if (group_of[v] < 0) continue;
            for (const int u : {f[(k + 1) % f.size()], f[(k + f.size() - 1) % f.size()]}) {
                if (group_of[static_cast<std::size_t>(u)] == group_of[v]) continue;
                for (std::size_t d = 0; d < 3; ++d) sum[v][d] += mesh.positions[static_cast<std::size_t>(u)][d];
                ++count[v];
            }
        }
    for (std::size_t g = 0; g < groups.size(); ++g) {
        const auto& candidates = found[g];
        if (candidates.empty()) continue;
        std::vector<char> taken(candidates.size(), 0);
        for (const int v : groups[g]) {
            const auto vi = static_cast<std::size_t>(v);
            if (count[vi] == 0) continue;
            std::size_t best = candidates.size();
            double best_distance = std::numeric_limits<double>::infinity();
            for (const bool free_only : {true, false}) {
                for (std::size_t c = 0; c < candidates.size(); ++c) {
                    if (free_only && taken[c]) continue;
                    double distance = 0.0;
                    for (std::size_t d = 0; d < 3; ++d) {
                        const double x = candidates[c].second[d] - sum[vi][d] / count[vi];
                        distance += x * x;
                    }
                    if (distance < best_distance) best = c, best_distance = distance;
                }
                if (best < candidates.size()) break;
            }
            if (best == candidates.size()) continue;
            taken[best] = 1;
            mesh.provenance[vi] = candidates[best].first;
            mesh.positions[vi] = candidates[best].second;
        }
    }
}

} // namespace

std::vector<Defect> separate_sheets(const Input& input, QuadMesh& mesh, int end) {
    const auto nv = static_cast<int>(mesh.positions.size());
    for (const std::vector<int>& f : mesh.faces)
        for (const int v : f)
            if (v < 0 || v >= nv) return {};
    Sides sides(mesh);
    std::vector<Defect> separated;
    std::vector<std::vector<int>> groups; // per vertex split: it, then its copies
    for (const std::uint64_t key : sides.non_manifold()) {
        const int lo = static_cast<int>(key >> 32), hi = static_cast<int>(key & 0xffffffffu);
        const int n = sides.count(lo, hi);
        if (n <= 2) continue; // cut already, at a vertex shared with an earlier edge
        std::vector<std::pair<int, int>> split;
        for (const int v : end == 0 ? std::array<int, 2>{lo, hi} : std::array<int, 2>{hi, lo}) {
            const int first_copy = static_cast<int>(mesh.positions.size());
            const int fans = sides.split(mesh, v);
            if (fans < 2) continue;
            split.push_back({v, fans});
            groups.push_back({v});
            for (int c = first_copy; c < static_cast<int>(mesh.positions.size()); ++c) groups.back().push_back(c);
        }
        if (!split.empty()) separated.push_back(explain(mesh, lo, hi, n, split));
    }
    place_on_own_sheets(input, groups, mesh);
    return separated;
}

} // namespace qex::detail
