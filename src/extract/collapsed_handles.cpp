// Collapsed handles: where the map itself forbids a valid mesh at every scale refinement tries.
// A region of the surface whose triangles the map squeezes to almost no UV area, folded onto
// itself, covers no cell: no quad of a mesh that follows the map lies in it, at the map's own
// scale or multiplied by 16. If that region holds a cycle of the surface that no disk of the
// surface bounds (the tube of a handle), every such mesh cuts the cycle and loses the handle.
// Looked for when no attempt at the map's own scale gives a valid mesh; the proof names the
// region first in the report and spares the refinements (extract.cpp).
#include "pipeline.h"
#include "union_find.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <tuple>
#include <utility>

namespace qex::detail {
namespace {

/// The proof covers refinements up to this factor (Options::max_refinement's default and the
/// CLI's largest), or the option where it is larger.
constexpr int kRefinementBound = 16;
int bound(int max_refinement) { return std::max(kRefinementBound, max_refinement); }
/// A triangle is thin when its UV area, times the refinement bound squared, is at most this
/// part of a cell: 1/16384 of a cell at the map's own scale.
constexpr double kThinPart = 1.0 / 64;

// ============================================================================ the surface

/// The input's triangles as the search needs them: who lies across each side, and UV areas.
/// Per input triangle, its UV area in the map as given.
std::vector<double> uv_areas(const Input& in) {
    std::vector<double> area(in.triangles.size());
    for (std::size_t t = 0; t < area.size(); ++t) {
        const auto &p = in.uvs[3 * t], &q = in.uvs[3 * t + 1], &r = in.uvs[3 * t + 2];
        area[t] = 0.5 * ((q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]));
    }
    return area;
}

struct Surface {
    Surface(const Input& in, std::vector<double> areas);
    /// The corner of triangle t at input vertex v.
    int corner_of(int t, int v) const {
        const auto& f = input.triangles[static_cast<std::size_t>(t)];
        return f[0] == v ? 0 : f[1] == v ? 1 : 2;
    }
    int vertex(int t, int k) const { return input.triangles[static_cast<std::size_t>(t)][static_cast<std::size_t>(k)]; }
    int size() const { return static_cast<int>(area.size()); }

    const Input& input;
    std::vector<int> across;  ///< per side 3t+k (corner k to k+1): the triangle across, -1 on the boundary
    std::vector<double> area; ///< per triangle, its UV area in the map as given
};

Surface::Surface(const Input& in, std::vector<double> areas)
    : input(in), across(3 * in.triangles.size(), -1), area(std::move(areas)) {
    std::vector<std::tuple<int, int, int>> sides; // (smaller vertex, larger vertex, side)
    sides.reserve(across.size());
    for (int t = 0; t < size(); ++t)
        for (int k = 0; k < 3; ++k) {
            const int a = vertex(t, k), b = vertex(t, (k + 1) % 3);
            sides.emplace_back(std::min(a, b), std::max(a, b), 3 * t + k);
        }
    std::sort(sides.begin(), sides.end());
    for (std::size_t i = 0; i + 1 < sides.size(); ++i) {
        const auto [a, b, h] = sides[i];
        const auto [c, d, g] = sides[i + 1];
        if (a != c || b != d) continue;
        across[static_cast<std::size_t>(h)] = g / 3; // a manifold edge: exactly two sides
        across[static_cast<std::size_t>(g)] = h / 3;
    }
}

/// The connected regions (across sides) of the triangles for which `member` holds, each in
/// increasing order; `label` gets each triangle's region (-1 outside them all).
template <class Member>
std::vector<std::vector<int>> regions(const Surface& s, Member member, std::vector<int>& label) {
    label.assign(static_cast<std::size_t>(s.size()), -1);
    std::vector<std::vector<int>> out;
    for (int seed = 0; seed < s.size(); ++seed) {
        if (label[static_cast<std::size_t>(seed)] >= 0 || !member(seed)) continue;
        const int id = static_cast<int>(out.size());
        std::vector<int> region{seed};
        label[static_cast<std::size_t>(seed)] = id;
        for (std::size_t i = 0; i < region.size(); ++i)
            for (int k = 0; k < 3; ++k) {
                const int j = s.across[3 * static_cast<std::size_t>(region[i]) + static_cast<std::size_t>(k)];
                if (j < 0 || label[static_cast<std::size_t>(j)] >= 0 || !member(j)) continue;
                label[static_cast<std::size_t>(j)] = id;
                region.push_back(j);
            }
        std::sort(region.begin(), region.end());
        out.push_back(std::move(region));
    }
    return out;
}

// ============================================================================ a region's topology

/// A connected region's topology: its Euler characteristic with the input's boundary loops in
/// it capped (each a disk added), and its rims (the boundary loops across which the rest of the
/// surface lies). It is a disk when it has one rim and euler 1.
struct Topology {
    std::int64_t euler = 0;
    int rims = 0;
    bool disk() const { return rims == 1 && euler == 1; }
    int genus() const { return static_cast<int>((2 - euler - rims) / 2); }
};


/// The topology of `region` (the triangles whose label is `id`), vertices counted once per fan
/// of the region round them (a region pinched at a vertex counts it twice). `local`: scratch,
/// -1 for every triangle, left so.
Topology topology(const Surface& s, const std::vector<int>& region, const std::vector<int>& label, int id,
                  std::vector<int>& local) {
    const auto inside = [&](int t) { return t >= 0 && label[static_cast<std::size_t>(t)] == id; };
    for (std::size_t i = 0; i < region.size(); ++i) local[static_cast<std::size_t>(region[i])] = static_cast<int>(i);
    UnionFind corners(3 * region.size()); // the region's corners, joined round each vertex
    std::int64_t boundary_sides = 0, inner_sides = 0;
    for (std::size_t i = 0; i < region.size(); ++i)
        for (int k = 0; k < 3; ++k) {
            const int t = region[i], j = s.across[3 * static_cast<std::size_t>(t) + static_cast<std::size_t>(k)];
            if (!inside(j)) {
                ++boundary_sides;
                continue;
            }
            ++inner_sides;
            const int lj = 3 * local[static_cast<std::size_t>(j)], lt = 3 * static_cast<int>(i);
            const auto join = [&](int a, int b) {
                if ((a = corners.find(a)) != (b = corners.find(b))) corners.attach(a, b);
            };
            join(lt + k, lj + s.corner_of(j, s.vertex(t, k)));
            join(lt + (k + 1) % 3, lj + s.corner_of(j, s.vertex(t, (k + 1) % 3)));
        }
    std::int64_t vertices = 0;
    for (int c = 0; c < static_cast<int>(3 * region.size()); ++c) vertices += corners.find(c) == c;
    // The boundary loops: from a side whose far triangle is outside, the next such side starts
    // where it ends, found by turning round that vertex inside the region.
    std::vector<char> seen(3 * region.size(), 0);
    int loops = 0, rims = 0;
    for (std::size_t i = 0; i < region.size(); ++i)
        for (int k = 0; k < 3; ++k) {
            int t = region[i], side = k;
            if (inside(s.across[3 * static_cast<std::size_t>(t) + static_cast<std::size_t>(side)]) ||
                seen[3 * i + static_cast<std::size_t>(k)])
                continue;
            bool rim = false;
            while (!seen[3 * static_cast<std::size_t>(local[static_cast<std::size_t>(t)]) +
                         static_cast<std::size_t>(side)]) {
                seen[3 * static_cast<std::size_t>(local[static_cast<std::size_t>(t)]) +
                     static_cast<std::size_t>(side)] = 1;
                rim = rim || s.across[3 * static_cast<std::size_t>(t) + static_cast<std::size_t>(side)] >= 0;
                const int end = s.vertex(t, (side + 1) % 3);
                side = (side + 1) % 3;
                for (int j = s.across[3 * static_cast<std::size_t>(t) + static_cast<std::size_t>(side)]; inside(j);
                     j = s.across[3 * static_cast<std::size_t>(t) + static_cast<std::size_t>(side)])
                    t = j, side = s.corner_of(j, end);
            }
            ++loops;
            rims += rim;
        }
    for (const int t : region) local[static_cast<std::size_t>(t)] = -1;
    const auto faces = static_cast<std::int64_t>(region.size());
    return {vertices - (boundary_sides + inner_sides / 2) + faces + (loops - rims), rims};
}

// ============================================================================ the proof

/// `region` with every disk of the surface it encloses (a part of the rest that is a disk with
/// one rim, on the region) added, as a label (1 inside) and its topology; rims 0 when that is
/// the whole surface (or a whole component of it).
Topology with_enclosed_disks(const Surface& s, const std::vector<int>& region, std::vector<int>& local) {
    std::vector<int> in(static_cast<std::size_t>(s.size()), 0);
    for (const int t : region) in[static_cast<std::size_t>(t)] = 1;
    std::vector<int> label;
    const auto rest = regions(
        s, [&](int t) { return in[static_cast<std::size_t>(t)] == 0; }, label);
    std::vector<int> filled = region;
    for (std::size_t id = 0; id < rest.size(); ++id)
        if (topology(s, rest[id], label, static_cast<int>(id), local).disk())
            filled.insert(filled.end(), rest[id].begin(), rest[id].end());
    for (const int t : filled) in[static_cast<std::size_t>(t)] = 1;
    return topology(s, filled, in, 1, local);
}

/// A region's vertex graph: its vertices (sorted) and each one's neighbours over its edges.
struct VertexGraph {
    VertexGraph(const Surface& s, const std::vector<int>& region) {
        std::vector<std::pair<int, int>> edges;
        for (const int t : region)
            for (int k = 0; k < 3; ++k) {
                const int a = s.vertex(t, k), b = s.vertex(t, (k + 1) % 3);
                vertices.push_back(a);
                edges.emplace_back(a, b), edges.emplace_back(b, a);
            }
        std::sort(vertices.begin(), vertices.end());
        vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
        std::sort(edges.begin(), edges.end());
        edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
        first.assign(vertices.size() + 1, 0);
        for (const auto& e : edges) ++first[static_cast<std::size_t>(index(e.first)) + 1];
        for (std::size_t v = 0; v < vertices.size(); ++v) first[v + 1] += first[v];
        for (const auto& e : edges) next.push_back(index(e.second)); // edges are sorted by their first end
    }
    int index(int vertex) const {
        return static_cast<int>(std::lower_bound(vertices.begin(), vertices.end(), vertex) - vertices.begin());
    }
    /// Breadth-first from local vertex `from`: the farthest one (the first found at the largest
    /// distance), each vertex's parent in `parent`.
    int farthest(int from, std::vector<int>& parent) const {
        parent.assign(vertices.size(), -1);
        parent[static_cast<std::size_t>(from)] = from;
        std::vector<int> queue{from};
        for (std::size_t i = 0; i < queue.size(); ++i) {
            const auto v = static_cast<std::size_t>(queue[i]);
            for (int e = first[v]; e < first[v + 1]; ++e) {
                const int w = next[static_cast<std::size_t>(e)];
                if (parent[static_cast<std::size_t>(w)] >= 0) continue;
                parent[static_cast<std::size_t>(w)] = queue[i];
                queue.push_back(w);
            }
        }
        return queue.back();
    }
    std::vector<int> vertices, first, next;
};

/// The input vertex the region is round: the middle of a longest shortest path across it (two
/// sweeps of breadth-first search over its edges, from its smallest vertex, then from the end).
std::int64_t centre(const Surface& s, const std::vector<int>& region) {
    const VertexGraph g(s, region);
    std::vector<int> parent;
    const int a = g.farthest(0, parent);
    int v = g.farthest(a, parent);
    std::vector<int> path{v};
    while (v != a) path.push_back(v = parent[static_cast<std::size_t>(v)]);
    return g.vertices[static_cast<std::size_t>(path[path.size() / 2])];
}

} // namespace

std::vector<CollapsedHandle> find_collapsed_handles(const Input& input, int max_refinement) {
    const double k2 = std::pow(static_cast<double>(bound(max_refinement)), 2);
    std::vector<double> areas = uv_areas(input);
    // A region folded onto itself holds flipped triangles: without a thin one, there is none
    // (and the adjacency is not built).
    if (std::none_of(areas.begin(), areas.end(), [&](double a) { return a < 0.0 && -a * k2 <= kThinPart; })) return {};
    const Surface s(input, std::move(areas));
    std::vector<int> label, local(static_cast<std::size_t>(s.size()), -1);
    const auto thin = regions(
        s, [&](int t) { return std::abs(s.area[static_cast<std::size_t>(t)]) * k2 <= kThinPart; }, label);
    std::vector<CollapsedHandle> out;
    for (std::size_t id = 0; id < thin.size(); ++id) {
        const std::vector<int>& region = thin[id];
        double net = 0.0, all = 0.0;
        for (const int t : region)
            net += s.area[static_cast<std::size_t>(t)], all += std::abs(s.area[static_cast<std::size_t>(t)]);
        // Folded onto itself (at most half of it left signed), and net below one cell at the bound.
        if (!(all > 0.0) || std::abs(net) > 0.5 * all || std::abs(net) * k2 >= 1.0) continue;
        if (topology(s, region, label, static_cast<int>(id), local).disk()) continue;
        const Topology closed = with_enclosed_disks(s, region, local);
        if (closed.rims == 0 || closed.disk()) continue;
        CollapsedHandle h;
        h.vertex = centre(s, region);
        h.triangles.assign(region.begin(), region.end());
        h.signed_uv_area = net;
        h.absolute_uv_area = all;
        h.genus = closed.genus();
        h.rims = closed.rims;
        out.push_back(std::move(h));
    }
    return out;
}

Defect collapsed_handle_defect(const Input& input, const CollapsedHandle& h, int max_refinement) {
    const int k = bound(max_refinement);
    std::int64_t at = -1; // the first of its triangles round the vertex
    std::string first;
    for (const std::int64_t t : h.triangles) {
        const auto& f = input.triangles[static_cast<std::size_t>(t)];
        if (at < 0 && (f[0] == h.vertex || f[1] == h.vertex || f[2] == h.vertex)) at = t;
        if (first.size() < 60) first += (first.empty() ? "" : ", ") + std::to_string(t);
    }
    char areas[200];
    std::snprintf(areas, sizeof areas,
                  "each below 1/%.0f of a cell, have a signed UV area of %.3g cells and an absolute one of %.3g (x%d: "
                  "%.3g net)",
                  64.0 * k * k, h.signed_uv_area, h.absolute_uv_area, k, h.signed_uv_area * k * k);
    return {DefectKind::MapCollapsesHandle,
            "the map collapses a handle of the surface round input vertex " + std::to_string(h.vertex) + ": its " +
                std::to_string(h.triangles.size()) + " triangles (input triangles " + first +
                (h.triangles.size() > 8 ? ", ..." : "") + "), " + areas +
                ", folded onto themselves; with the disks they enclose they form a region of genus " +
                std::to_string(h.genus) + " with " + std::to_string(h.rims) +
                " rims, which holds a cycle no disk of the surface bounds: no quad mesh that follows the map keeps "
                "it, at any scale up to x" +
                std::to_string(k),
            at,
            -1,
            {0, 0},
            std::nullopt};
}

} // namespace qex::detail
