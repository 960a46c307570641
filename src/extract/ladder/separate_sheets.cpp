// Stage separate_sheets (not in the paper): a rung's mesh that the checker rejects may have an
// edge with more than two face sides. Where a fold-over lays several sheets of the surface over
// the same grid cells, a face walk can pass from one sheet to another, and merging the clones it
// meets (Algorithm 7) makes one vertex of two on each end of an edge. Each end is then the corner
// of two fans, joined only at that edge. The edge is cut by splitting an end into one vertex per
// fan: an end that ends no other such edge first (a run of joined edges comes apart from its
// ends inward). The other end's faces then form one fan (where the two ends paired the edge's
// sides differently: a vertex winding twice round its grid point, as a fold-over's branch point
// does) or two, and then it is split too. The grid point has a preimage on each sheet: every
// vertex split takes the one nearest the vertices round its fan. Where the vertices of one split
// would still coincide (the grid point has a single preimage there), the sheets would stay
// joined in space: no candidate is made. Of an edge's two ends, which is tried first (when both
// or neither end another such edge) is the caller's choice; the result is a candidate only, kept
// if the checker accepts it.
#include "ladder.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <map>
#include <numeric>
#include <string>
#include <unordered_map>

namespace qex::detail {
namespace {

using EdgeKey = std::uint64_t;

EdgeKey undirected_key(int a, int b) {
    if (a > b) std::swap(a, b);
    return (static_cast<EdgeKey>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}
int lower_end(EdgeKey key) { return static_cast<int>(key >> 32); }
int upper_end(EdgeKey key) { return static_cast<int>(key & 0xffffffffu); }

/// The edges of more than two face sides, in key order, with their side counts: one sort of
/// every face side's key (no table of all edges).
std::vector<std::pair<EdgeKey, int>> non_manifold_edges(const QuadMesh& mesh) {
    std::vector<EdgeKey> keys;
    for (const std::vector<int>& f : mesh.faces)
        for (std::size_t k = 0; k < f.size(); ++k) keys.push_back(undirected_key(f[k], f[(k + 1) % f.size()]));
    std::sort(keys.begin(), keys.end());
    std::vector<std::pair<EdgeKey, int>> out;
    for (std::size_t i = 0, j = 0; i < keys.size(); i = j) {
        for (j = i + 1; j < keys.size() && keys[j] == keys[i];) ++j;
        if (j - i > 2) out.push_back({keys[i], static_cast<int>(j - i)});
    }
    return out;
}

/// How the corners round an end join into fans (Sides::split): across edges of two face sides,
/// and across each edge of three or four, by one of two pairings of its faces.
struct Joins {
    std::vector<std::pair<std::size_t, std::size_t>> across;
    std::vector<std::array<std::pair<std::size_t, std::size_t>, 2>> first, second;
};

/// Per edge of three or four face sides round an end: the corners whose faces leave the end by
/// it, and those whose faces enter by it.
using Crowded = std::map<int, std::pair<std::vector<std::size_t>, std::vector<std::size_t>>>;

/// The pairings to choose from: two per edge whose leaving and entering faces number two
/// and two, two and one, or one and two.
void add_pairings(const Crowded& crowded, Joins& joins) {
    for (const auto& [w, sides] : crowded) {
        const auto& [out, in] = sides;
        if (joins.first.size() == 4 || out.empty() || in.empty() || out.size() > 2 || in.size() > 2 ||
            out.size() + in.size() < 3)
            continue;
        if (out.size() == 2 && in.size() == 2) {
            joins.first.push_back({{{out[0], in[0]}, {out[1], in[1]}}});
            joins.second.push_back({{{out[0], in[1]}, {out[1], in[0]}}});
        } else { // one face on one side: it joins one of the two on the other (listed twice)
            const std::size_t o1 = out.size() > 1 ? out[1] : out[0], i1 = in.size() > 1 ? in[1] : in[0];
            joins.first.push_back({{{out[0], in[0]}, {out[0], in[0]}}});
            joins.second.push_back({{{o1, i1}, {o1, i1}}});
        }
    }
}

/// The fans of the n corners round an end: the corners joined by `joins`, with one of the two
/// pairings per edge of three or four face sides (a union-find).
class Fans {
public:
    Fans(const Joins& joins, std::size_t n) : joins_(joins), parent_(n), number_(n) {}

    /// The most fans a choice of pairings gives (the first such choice in order), numbered.
    int most() {
        unsigned best = 0;
        for (unsigned choice = 1, most_fans = static_cast<unsigned>(with(0)); choice < (1u << joins_.first.size());
             ++choice)
            if (const auto f = static_cast<unsigned>(with(choice)); f > most_fans) best = choice, most_fans = f;
        return with(best);
    }
    /// The fan of corner i (numbered in the order of the fans' first corners).
    int of(std::size_t i) const { return number_[find(i)]; }

private:
    std::size_t find(std::size_t x) const {
        while (parent_[x] != x) x = parent_[x];
        return x;
    }
    void join(std::size_t a, std::size_t b) {
        a = find(a), b = find(b);
        if (a != b) parent_[std::max(a, b)] = std::min(a, b);
    }
    /// The number of fans with pairing `choice` (bit e: the second pairing of edge e), numbered.
    int with(unsigned choice) {
        std::iota(parent_.begin(), parent_.end(), std::size_t{0});
        for (const auto& [a, b] : joins_.across) join(a, b);
        for (std::size_t e = 0; e < joins_.first.size(); ++e)
            for (const auto& [a, b] : (choice >> e & 1u) ? joins_.second[e] : joins_.first[e])
                if (a != b) join(a, b);
        std::fill(number_.begin(), number_.end(), -1);
        int fans = 0;
        for (std::size_t i = 0; i < number_.size(); ++i)
            if (number_[find(i)] < 0) number_[find(i)] = fans++;
        return fans;
    }

    const Joins& joins_;
    std::vector<std::size_t> parent_;
    std::vector<int> number_;
};

/// The face sides of the edges at the ends of the non-manifold edges, and those ends' face
/// corners, kept up to date as the ends are split (the copies become ends too).
class Sides {
public:
    Sides(QuadMesh& mesh, const std::vector<std::pair<EdgeKey, int>>& edges) : mesh_(mesh) {
        for (const auto& e : edges) {
            corners_.emplace(lower_end(e.first), Corners{});
            corners_.emplace(upper_end(e.first), Corners{});
        }
        for (std::size_t f = 0; f < mesh.faces.size(); ++f)
            for (std::size_t k = 0; k < mesh.faces[f].size(); ++k) {
                const int a = at(f, k), b = at(f, k + 1);
                if (corners_.count(a) || corners_.count(b)) ++count_[undirected_key(a, b)];
                if (const auto it = corners_.find(a); it != corners_.end()) it->second.push_back({f, k});
            }
    }
    int count(EdgeKey key) const {
        const auto it = count_.find(key);
        return it == count_.end() ? 0 : it->second;
    }
    /// Splits end v into one vertex per fan of the faces round it: faces are joined across an
    /// edge (v, w) that one leaves v by and the other enters v by, when that edge has two face
    /// sides; across an edge of three or four, two faces leave v by it or enter by it, and they
    /// are paired so that v has the most fans (pairing faces of two sheets would join them; up
    /// to four such edges, the first best pairing in order). The fan of v's first corner keeps
    /// v; the others get copies (position and provenance), appended in the order of their first
    /// corners. Returns the number of fans.
    int split(int v) {
        const Corners around = corners_.at(v);
        const Joins joins = joins_round(v, around);
        Fans fans(joins, around.size());
        const int count = fans.most();
        if (count < 2) return count;
        hand_out(v, around, fans, count);
        return count;
    }

private:
    using Corners = std::vector<std::pair<std::size_t, std::size_t>>; ///< (face, corner)
    /// Vertex of face f at corner k (mod its size).
    int at(std::size_t f, std::size_t k) const { return mesh_.faces[f][k % mesh_.faces[f].size()]; }
    /// The vertex after corner i of `around` in its face, and the one before it.
    int next(const Corners& around, std::size_t i) const { return at(around[i].first, around[i].second + 1); }
    int prev(const Corners& around, std::size_t i) const {
        return at(around[i].first, around[i].second + mesh_.faces[around[i].first].size() - 1);
    }

    /// How the corners round end v join: across edges of two sides; per edge of three or four,
    /// the faces leaving and entering, paired (add_pairings).
    Joins joins_round(int v, const Corners& around) const {
        const std::size_t n = around.size();
        Joins joins;
        Crowded crowded;
        for (std::size_t i = 0; i < n; ++i) {
            const int w = next(around, i), sides = count(undirected_key(v, w));
            if (sides == 2) {
                for (std::size_t j = 0; j < n; ++j)
                    if (j != i && prev(around, j) == w) joins.across.push_back({i, j});
            } else if (sides == 3 || sides == 4) {
                crowded[w].first.push_back(i);
            }
            if (const int u = prev(around, i), su = count(undirected_key(v, u)); su == 3 || su == 4)
                crowded[u].second.push_back(i);
        }
        add_pairings(crowded, joins);
        return joins;
    }

    /// Gives every fan of v's but the first a copy of v (appended in fan order) and moves the
    /// fan's corners, and the side counts of their edges, to it.
    void hand_out(int v, const Corners& around, const Fans& fans, int count) {
        const int first_copy = static_cast<int>(mesh_.positions.size());
        for (int c = 1; c < count; ++c) {
            mesh_.positions.push_back(mesh_.positions[static_cast<std::size_t>(v)]);
            mesh_.provenance.push_back(mesh_.provenance[static_cast<std::size_t>(v)]);
            corners_.emplace(first_copy + c - 1, Corners{});
        }
        corners_.at(v).clear();
        for (std::size_t i = 0; i < around.size(); ++i) {
            const int fan = fans.of(i);
            const auto [f, k] = around[i];
            const int to = fan == 0 ? v : first_copy + fan - 1;
            corners_.at(to).push_back({f, k});
            if (to == v) continue;
            const int before = prev(around, i), after = next(around, i);
            --count_[undirected_key(v, before)], --count_[undirected_key(v, after)];
            mesh_.faces[f][k] = to;
            ++count_[undirected_key(to, before)], ++count_[undirected_key(to, after)];
        }
    }

    QuadMesh& mesh_;
    std::unordered_map<EdgeKey, int> count_;
    std::map<int, Corners> corners_; ///< per end (and copy)
};

/// The explanation of the edge `key`, of `sides` face sides, cut by the splits `split` (vertex,
/// fans); the grid point is the first vertex's, before it was split.
Defect explain(EdgeKey key, int sides, const std::vector<std::pair<int, int>>& split, const Provenance& where) {
    std::string what;
    for (const auto& [v, fans] : split)
        what += (what.empty() ? "vertex " : " and vertex ") + std::to_string(v) + " into " + std::to_string(fans);
    return {DefectKind::SheetsSeparated,
            "edge (" + std::to_string(lower_end(key)) + ", " + std::to_string(upper_end(key)) + ") had " +
                std::to_string(sides) + " face sides, where merged clones joined sheets of a fold-over: " + what +
                " vertices, one per fan, each on the preimage of its grid point nearest its fan (grid point (" +
                std::to_string(where.grid[0]) + ", " + std::to_string(where.grid[1]) + ") of input triangle " +
                std::to_string(where.chart_triangle) + ")",
            where.chart_triangle,
            -1,
            {where.grid[0], where.grid[1]},
            std::nullopt};
}

/// Each vertex of every group (a vertex split, then its copies: one grid point) moved onto the
/// preimage of its grid point in the mesh's map nearest the mean of the vertices round its fan
/// (those of its group left out): one no other vertex of its group took, if there is one within
/// twice the fan's reach from that mean, else the nearest. False if two vertices of a group
/// coincide then (as they do where no preimage is found, on a mesh without its map).
bool place_on_own_sheets(MapGraph& graph, const std::vector<std::vector<int>>& groups, QuadMesh& mesh) {
    if (groups.empty()) return true;
    std::vector<Provenance> points;
    for (const std::vector<int>& group : groups) points.push_back(mesh.provenance[static_cast<std::size_t>(group[0])]);
    const auto found = preimages(graph, mesh.map_uvs, points);
    std::vector<int> group_of(mesh.positions.size(), -1);
    for (std::size_t g = 0; g < groups.size(); ++g)
        for (const int v : groups[g]) group_of[static_cast<std::size_t>(v)] = static_cast<int>(g);
    // Per vertex of a group: the vertices round it (of other groups).
    std::vector<std::vector<int>> round(mesh.positions.size());
    for (const std::vector<int>& f : mesh.faces)
        for (std::size_t k = 0; k < f.size(); ++k) {
            const auto v = static_cast<std::size_t>(f[k]);
            if (group_of[v] < 0) continue;
            for (const int u : {f[(k + 1) % f.size()], f[(k + f.size() - 1) % f.size()]})
                if (group_of[static_cast<std::size_t>(u)] != group_of[v]) round[v].push_back(u);
        }
    for (std::size_t g = 0; g < groups.size(); ++g) {
        const auto& candidates = found[g];
        std::vector<char> taken(candidates.size(), 0);
        for (const int v : groups[g]) {
            const auto vi = static_cast<std::size_t>(v);
            if (candidates.empty() || round[vi].empty()) continue;
            const Neighbourhood around(mesh.positions, round[vi]);
            std::size_t nearest = 0, nearest_free = candidates.size();
            for (std::size_t c = 0; c < candidates.size(); ++c) {
                const double d = around.distance2(candidates[c].second);
                if (d < around.distance2(candidates[nearest].second)) nearest = c;
                if (!taken[c] && around.near(candidates[c].second) &&
                    (nearest_free == candidates.size() || d < around.distance2(candidates[nearest_free].second)))
                    nearest_free = c;
            }
            const std::size_t best = nearest_free < candidates.size() ? nearest_free : nearest;
            taken[best] = 1;
            mesh.provenance[vi] = candidates[best].first;
            mesh.positions[vi] = candidates[best].second;
        }
        for (std::size_t i = 0; i < groups[g].size(); ++i)
            for (std::size_t j = i + 1; j < groups[g].size(); ++j)
                if (mesh.positions[static_cast<std::size_t>(groups[g][i])] ==
                    mesh.positions[static_cast<std::size_t>(groups[g][j])])
                    return false;
    }
    return true;
}

} // namespace

std::vector<Defect> cut_joined_edges(QuadMesh& mesh, bool larger_end_first, std::vector<std::vector<int>>& groups) {
    groups.clear();
    const auto nv = static_cast<int>(mesh.positions.size());
    if (mesh.provenance.size() != mesh.positions.size()) return {};
    for (const std::vector<int>& f : mesh.faces)
        for (const int v : f)
            if (v < 0 || v >= nv) return {};
    const std::vector<std::pair<EdgeKey, int>> edges = non_manifold_edges(mesh);
    if (edges.empty()) return {};
    Sides sides(mesh, edges);
    const auto ends = [&](std::size_t e) {
        const int lo = lower_end(edges[e].first), hi = upper_end(edges[e].first);
        return larger_end_first ? std::array<int, 2>{hi, lo} : std::array<int, 2>{lo, hi};
    };
    std::vector<std::vector<std::pair<int, int>>> cut(edges.size()); // per edge: (vertex, fans) split for it
    std::vector<Provenance> where(edges.size());                     // per edge: its first split's grid point
    const auto split = [&](std::size_t e, int v) {
        const Provenance before = mesh.provenance[static_cast<std::size_t>(v)];
        const int first_copy = static_cast<int>(mesh.positions.size());
        const int fans = sides.split(v);
        if (fans < 2) return false;
        if (cut[e].empty()) where[e] = before;
        cut[e].push_back({v, fans});
        groups.push_back({v});
        for (int c = first_copy; c < static_cast<int>(mesh.positions.size()); ++c) groups.back().push_back(c);
        return true;
    };
    // While an edge has more than two sides, it is cut at an end that ends no other such edge
    // (whose fans are then its sheets), the first such in order; else at the first end of the
    // first edge. An edge neither of whose ends splits is left (the rounds are bounded).
    std::vector<char> stuck(edges.size(), 0);
    for (std::size_t round = 0; round < 2 * edges.size(); ++round) {
        std::map<int, int> open_at; // per end: how many of its edges have more than two sides
        std::vector<std::size_t> open;
        for (std::size_t e = 0; e < edges.size(); ++e)
            if (!stuck[e] && sides.count(edges[e].first) > 2) {
                open.push_back(e);
                for (const int v : ends(e)) ++open_at[v];
            }
        if (open.empty()) break;
        std::size_t e = open[0];
        int v = ends(e)[0];
        bool lone = false;
        for (std::size_t i = 0; i < open.size() && !lone; ++i)
            for (const int x : ends(open[i]))
                if (!lone && open_at[x] == 1) e = open[i], v = x, lone = true;
        if (!split(e, v) && !split(e, ends(e)[0] == v ? ends(e)[1] : ends(e)[0])) stuck[e] = 1;
    }
    // Every end still the corner of more than one fan is split too (the far end of a cut edge
    // whose two ends paired its sides alike).
    for (std::size_t e = 0; e < edges.size(); ++e)
        for (const int v : ends(e)) (void)split(e, v);
    std::vector<Defect> separated;
    for (std::size_t e = 0; e < edges.size(); ++e)
        if (!cut[e].empty()) separated.push_back(explain(edges[e].first, edges[e].second, cut[e], where[e]));
    return separated;
}

std::vector<Defect> separate_sheets(const Input& input, QuadMesh& mesh, bool larger_end_first) {
    MapGraph graph(input);
    return separate_sheets(graph, mesh, larger_end_first);
}

std::vector<Defect> separate_sheets(MapGraph& graph, QuadMesh& mesh, bool larger_end_first) {
    std::vector<std::vector<int>> groups;
    std::vector<Defect> separated = cut_joined_edges(mesh, larger_end_first, groups);
    if (separated.empty() || !place_on_own_sheets(graph, groups, mesh)) return {};
    return separated;
}

} // namespace qex::detail
