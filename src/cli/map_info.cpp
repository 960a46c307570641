// The analysis behind `qex info` and `qex draw` (see map_info.h).
#include "map_info.h"

#include "io/checked_int.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>

namespace qex::cli {
namespace {

// The UVs are validated (finite, below 2^52; times a grid scale of at most 64 for `qex check
// --svg`): the grid points of a UV always fit in 64 bits, and no clamp bites.
using io_detail::clamped_int;

/// Union-find over `n` elements.
struct Components {
    std::vector<int> parent;
    explicit Components(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
    int find(int x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    }
    void unite(int a, int b) { parent[find(a)] = find(b); }
};

std::int64_t edge_key(int a, int b) { return static_cast<std::int64_t>(a) << 32 | static_cast<std::uint32_t>(b); }

/// Directed half-edge (a, b) -> 3 * triangle + corner of a.
std::unordered_map<std::int64_t, int> half_edges(const Input& in) {
    std::unordered_map<std::int64_t, int> he;
    he.reserve(3 * in.triangles.size());
    for (std::size_t t = 0; t < in.triangles.size(); ++t)
        for (int k = 0; k < 3; ++k)
            he.emplace(edge_key(in.triangles[t][k], in.triangles[t][(k + 1) % 3]), static_cast<int>(3 * t + k));
    return he;
}

double uv_area(const std::array<double, 2>& a, const std::array<double, 2>& b, const std::array<double, 2>& c) {
    return 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
}

/// The topology: edges, boundary half-edges (no twin), components, boundary loops, Euler
/// characteristic and genus. Returns which vertices are on the boundary.
std::vector<bool> add_topology(const Input& in, const std::unordered_map<std::int64_t, int>& he, MapInfo& info) {
    const std::size_t nv = in.positions.size();
    std::vector<int> boundary_next(nv, -1); // boundary half-edge from a vertex: its target
    std::vector<bool> on_boundary(nv, false);
    Components vertex_sets(nv);
    std::int64_t half_boundary = 0;
    for (const auto& t : in.triangles)
        for (int k = 0; k < 3; ++k) {
            const int a = t[k], b = t[(k + 1) % 3];
            vertex_sets.unite(a, b);
            if (!he.count(edge_key(b, a))) {
                ++half_boundary;
                boundary_next[a] = b;
                on_boundary[a] = on_boundary[b] = true;
            }
        }
    info.edges = (static_cast<std::int64_t>(he.size()) + half_boundary) / 2;
    info.euler = info.vertices - info.edges + info.triangles;
    std::vector<bool> seen(nv, false);
    std::vector<std::int64_t> loops_of(nv, 0), euler_of(nv, 0);
    for (std::size_t v = 0; v < nv; ++v) {
        if (boundary_next[v] < 0 || seen[v]) continue;
        ++info.boundary_loops;
        ++loops_of[vertex_sets.find(static_cast<int>(v))];
        for (int x = static_cast<int>(v); x >= 0 && !seen[x]; x = boundary_next[x]) seen[x] = true;
    }
    for (std::size_t v = 0; v < nv; ++v) {
        const int root = vertex_sets.find(static_cast<int>(v));
        if (root == static_cast<int>(v)) ++info.components;
        ++euler_of[root];
    }
    for (const auto& t : in.triangles) ++euler_of[vertex_sets.find(t[0])];
    for (const auto& [key, h] : he) { // each edge once: from its smaller end, or a boundary one
        const int a = static_cast<int>(key >> 32), b = static_cast<int>(key & 0xffffffff);
        if (a < b || !he.count(edge_key(b, a))) --euler_of[vertex_sets.find(a)];
    }
    for (std::size_t v = 0; v < nv; ++v)
        if (vertex_sets.find(static_cast<int>(v)) == static_cast<int>(v))
            info.genus += (2 - euler_of[v] - loops_of[v]) / 2;
    return on_boundary;
}

/// Orientation and area of every triangle; fold-over regions across shared edges.
void add_fold_regions(const Input& in, const std::unordered_map<std::int64_t, int>& he, MapInfo& info) {
    const std::size_t nt = in.triangles.size();
    info.orientation = uv_orientations(in);
    std::vector<double> area(nt);
    for (std::size_t t = 0; t < nt; ++t) {
        const auto* uv = &in.uvs[3 * t];
        area[t] = uv_area(uv[0], uv[1], uv[2]);
        info.signed_uv_area += area[t];
        if (info.orientation[t] < 0) ++info.flipped;
        if (info.orientation[t] == 0) ++info.degenerate;
    }
    Components folds(nt);
    for (const auto& [key, h] : he) {
        const auto twin = he.find(edge_key(static_cast<int>(key & 0xffffffff), static_cast<int>(key >> 32)));
        if (twin == he.end()) continue;
        const int s = h / 3, t = twin->second / 3;
        if (info.orientation[s] <= 0 && info.orientation[t] <= 0) folds.unite(s, t);
    }
    info.region_of.assign(nt, -1);
    std::vector<int> region_of_root(nt, -1);
    for (std::size_t t = 0; t < nt; ++t) {
        if (info.orientation[t] > 0) continue;
        int& r = region_of_root[folds.find(static_cast<int>(t))];
        if (r < 0) {
            r = static_cast<int>(info.fold_regions.size());
            info.fold_regions.emplace_back();
            info.fold_regions.back().grid_lo = {INT64_MAX, INT64_MAX};
            info.fold_regions.back().grid_hi = {INT64_MIN, INT64_MIN};
        }
        info.region_of[t] = r;
        FoldRegion& region = info.fold_regions[r];
        region.triangles.push_back(static_cast<int>(t));
        region.uv_area += area[t];
        for (int k = 0; k < 3; ++k)
            for (int c = 0; c < 2; ++c) {
                const double x = in.uvs[3 * t + k][c];
                region.grid_lo[c] = std::min(region.grid_lo[c], clamped_int<std::int64_t>(std::floor(x)));
                region.grid_hi[c] = std::max(region.grid_hi[c], clamped_int<std::int64_t>(std::ceil(x)));
            }
    }
}

/// Singularities: interior vertices whose fan's signed UV angles sum to other than a full turn
/// (needs the orientations of add_fold_regions).
void add_singularities(const Input& in, const std::vector<bool>& on_boundary, MapInfo& info) {
    const std::size_t nt = in.triangles.size(), nv = in.positions.size();
    std::vector<double> angle(nv, 0.0);
    std::vector<int> first_corner(nv, -1);
    std::vector<bool> in_fold(nv, false);
    for (std::size_t t = 0; t < nt; ++t)
        for (int k = 0; k < 3; ++k) {
            const auto& a = in.uvs[3 * t + k];
            const auto& b = in.uvs[3 * t + (k + 1) % 3];
            const auto& c = in.uvs[3 * t + (k + 2) % 3];
            const double ux = b[0] - a[0], uy = b[1] - a[1], wx = c[0] - a[0], wy = c[1] - a[1];
            const int v = in.triangles[t][k];
            angle[v] += std::atan2(ux * wy - uy * wx, ux * wx + uy * wy);
            if (first_corner[v] < 0) first_corner[v] = static_cast<int>(3 * t + k);
            if (info.orientation[t] <= 0) in_fold[v] = true;
        }
    for (std::size_t v = 0; v < nv; ++v) {
        if (on_boundary[v] || first_corner[v] < 0) continue;
        int valence = clamped_int<int>(std::round(angle[v] / (0.5 * M_PI)));
        // A folded fan winds back on itself (a vertex on a fold line sums to about 0): only the
        // fan's rotation, the angle modulo a full turn, is known there. Take the valence closest
        // to 4 with that rotation (3, 4, 5 or 6).
        if (in_fold[v]) valence = 3 + ((valence - 3) % 4 + 4) % 4;
        if (valence == 4) continue;
        Singularity s;
        s.vertex = static_cast<int>(v);
        s.valence = valence;
        s.triangle = first_corner[v] / 3;
        const auto& uv = in.uvs[first_corner[v]];
        s.grid = {clamped_int<std::int64_t>(std::round(uv[0])), clamped_int<std::int64_t>(std::round(uv[1]))};
        s.in_fold = in_fold[v];
        info.singularities.push_back(s);
    }
}

} // namespace

MapInfo analyse_map(const Input& in) {
    MapInfo info;
    info.vertices = static_cast<std::int64_t>(in.positions.size());
    info.triangles = static_cast<std::int64_t>(in.triangles.size());
    const auto he = half_edges(in);
    const std::vector<bool> on_boundary = add_topology(in, he, info);
    add_fold_regions(in, he, info);
    add_singularities(in, on_boundary, info);
    return info;
}

Error add_sanitized(const Input& input, int threads, MapInfo& info) {
    Options options;
    options.threads = threads;
    options.fallback_ladder = false;
    const Result r = extract(input, options);
    if (!r.ok()) return r.error;
    info.sanitized = true;
    info.max_sanitization_displacement = r.report.max_sanitization_displacement;
    info.sanitized_singularities = r.report.singularities;
    const auto& map = r.mesh.map_uvs;
    const std::size_t nt = input.triangles.size();
    if (map.size() != 3 * nt) return {};
    // Charts: live triangles joined across edges whose two ends have the same UVs on both sides.
    const auto live = [&](std::size_t t) { return !std::isnan(map[3 * t][0]); };
    Components charts(nt);
    const auto he = half_edges(input);
    for (const auto& [key, h] : he) {
        const auto twin = he.find(edge_key(static_cast<int>(key & 0xffffffff), static_cast<int>(key >> 32)));
        if (twin == he.end()) continue;
        const int s = h / 3, t = twin->second / 3, ks = h % 3, kt = twin->second % 3;
        if (!live(s) || !live(t)) continue;
        // half-edge s: corner ks -> ks+1; its twin in t: corner kt -> kt+1 (the same ends, reversed)
        if (map[3 * s + ks] == map[3 * t + (kt + 1) % 3] && map[3 * s + (ks + 1) % 3] == map[3 * t + kt])
            charts.unite(s, t);
    }
    // Singular vertices sit on grid points of the sanitized map: take them from there.
    for (Singularity& s : info.singularities) {
        const auto& tri = input.triangles[s.triangle];
        const int k = tri[0] == s.vertex ? 0 : tri[1] == s.vertex ? 1 : 2;
        if (live(s.triangle))
            s.grid = {clamped_int<std::int64_t>(std::round(map[3 * s.triangle + k][0])),
                      clamped_int<std::int64_t>(std::round(map[3 * s.triangle + k][1]))};
    }
    info.charts = 0;
    for (std::size_t t = 0; t < nt; ++t)
        if (live(t) && charts.find(static_cast<int>(t)) == static_cast<int>(t)) ++info.charts;
    return {};
}

} // namespace qex::cli
