// The repair's regions: the fans of free vertices, regions and their canonical orders, and the
// regions found round the fold-overs (regions.h).
#include "extract/repair/regions.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numeric>
#include <utility>

namespace qex::detail::repair_impl {
namespace {

/// x's bits as an unsigned integer in x's order (the two zeros alike; x is finite).
std::uint64_t ordered_bits(double x) {
    std::uint64_t u = 0;
    const double y = x + 0.0; // -0.0 becomes +0.0
    std::memcpy(&u, &y, sizeof u);
    return (u >> 63) != 0 ? ~u : u | (std::uint64_t{1} << 63);
}

/// Triangles in an order that does not depend on the input's: by their corners' 3D positions
/// from the canonical base on.
void sort_canonically(const TriMesh& m, std::vector<int>& faces) {
    // The keys once, then the faces sorted by them (ties by index): moving 4-byte indices, not
    // 76-byte pairs, took a quarter off the last rings' region building (duck_miq_28). Beside each
    // index its key's first coordinate, as bits in its order: most comparisons end there, without
    // reading the 72-byte keys (the order is key_less's).
    std::vector<TriangleKey> keys(faces.size());
    std::vector<std::pair<std::uint64_t, std::uint32_t>> order(faces.size());
    for (std::size_t i = 0; i < faces.size(); ++i) {
        keys[i] = triangle_key(m, faces[i]);
        order[i] = {ordered_bits(keys[i][0][0]), static_cast<std::uint32_t>(i)};
    }
    std::sort(order.begin(), order.end(), [&](const auto& x, const auto& y) {
        if (x.first != y.first) return x.first < y.first;
        const std::uint32_t a = x.second, b = y.second;
        if (key_less(keys[a], keys[b])) return true;
        return !key_less(keys[b], keys[a]) && faces[a] < faces[b];
    });
    std::vector<int> sorted(faces.size());
    for (std::size_t i = 0; i < faces.size(); ++i) sorted[i] = faces[order[i].second];
    faces.swap(sorted);
}

} // namespace

// ============================================================================ a free vertex

FreeFan free_fan(const TriMesh& m, int v) {
    FreeFan fan;
    fan.vertex = v;
    // Started at the canonical corner sanitize starts the fan at too (the vertex is interior).
    walk_fan_corners(m, v, true, fan.corners, fan.to_c);
    const std::vector<int>& walk = fan.corners;
    const std::size_t n = walk.size();
    double sum = 0.0;
    for (const int c : walk) {
        const Vec2 &p = m.uv[c], &q = m.uv[TriMesh::next(c)];
        sum += std::hypot(q[0] - p[0], q[1] - p[1]);
    }
    fan.length = sum / static_cast<double>(n);
    return fan;
}

std::vector<int> fan_in_3d_order(const TriMesh& m, int v) {
    std::vector<int> fan;
    for (int h = m.fan_start[v], n = 0; h >= 0 && n < m.fan_size[v]; h = m.cw(h), ++n) fan.push_back(h);
    const auto first = std::min_element(fan.begin(), fan.end(), [&](int a, int b) {
        if (m.pos(TriMesh::next(a)) != m.pos(TriMesh::next(b)))
            return m.pos(TriMesh::next(a)) < m.pos(TriMesh::next(b));
        return m.pos(TriMesh::prev(a)) < m.pos(TriMesh::prev(b));
    });
    std::rotate(fan.begin(), first, fan.end());
    return fan;
}

void place(TriMesh& m, const FreeFan& fan, const Vec2& x) {
    const Vec2 t = truncated_for_fan(m, fan.corners, fan.to_c, x, 1.0);
    for (std::size_t i = 0; i < fan.corners.size(); ++i) m.uv[fan.corners[i]] = fan.to_c[i](t);
}

// ============================================================================ a region

std::vector<Point2> region_uvs(const TriMesh& m, const Region& r) {
    std::vector<Point2> uvs;
    for (const FreeFan& fan : r.fans)
        for (const int c : fan.corners) uvs.push_back(m.uv[c]);
    return uvs;
}

void restore_region_uvs(TriMesh& m, const Region& r, const std::vector<Point2>& uvs) {
    std::size_t i = 0;
    for (const FreeFan& fan : r.fans)
        for (const int c : fan.corners) m.uv[c] = uvs[i++];
}

VertexKey vertex_key(const TriMesh& m, int v) {
    VertexKey k{m.pos(m.fan_start[v]), m.input_vertex[v]};
    for (int h = m.fan_start[v], n = 0; h >= 0 && n < m.fan_size[v]; h = m.cw(h), ++n)
        if (m.pos(h) < k.pos) k.pos = m.pos(h);
    return k;
}

// ============================================================================ finding the regions

std::vector<char> pinned_vertices(const TriMesh& m, const std::vector<std::array<int, 2>>& feature_edges) {
    std::vector<char> pinned(static_cast<std::size_t>(m.num_vertices), 0);
    for (int v = 0; v < m.num_vertices; ++v) pinned[v] = m.fan_start[v] < 0 || m.on_boundary[v] || m.map.singular[v];
    if (!feature_edges.empty()) {
        std::vector<char> on_feature;
        for (const auto& fe : feature_edges)
            for (const int x : fe)
                if (x >= 0) {
                    if (static_cast<std::size_t>(x) >= on_feature.size()) on_feature.resize(x + 1, 0);
                    on_feature[static_cast<std::size_t>(x)] = 1;
                }
        for (int v = 0; v < m.num_vertices; ++v) {
            const auto iv = static_cast<std::size_t>(m.input_vertex[v]);
            if (iv < on_feature.size() && on_feature[iv]) pinned[v] = 1;
        }
    }
    return pinned;
}

std::vector<int> ring_neighbourhood(const TriMesh& m, const std::vector<int>& seeds, int radius,
                                    std::vector<int>& distance) {
    std::vector<int> reached;
    for (const int v : seeds)
        if (distance[v] < 0) distance[v] = 0, reached.push_back(v);
    for (std::size_t i = 0; i < reached.size(); ++i) {
        const int v = reached[i];
        if (distance[v] >= radius) continue;
        for (int h = m.fan_start[v], n = 0; h >= 0 && n < m.fan_size[v]; ++n) {
            for (const int w : {m.target(h), m.origin(TriMesh::prev(h))})
                if (distance[w] < 0) distance[w] = distance[v] + 1, reached.push_back(w);
            h = m.cw(h);
        }
    }
    for (const int v : reached) distance[v] = -1;
    return reached;
}

std::vector<Region> find_regions(const TriMesh& m, const std::vector<int>& free, std::vector<int>& label) {
    std::vector<Region> regions;
    std::vector<char> listed(static_cast<std::size_t>(m.num_faces()), 0); // per triangle: in the region's list
    for (const int v : free) label[v] = -2; // free, unassigned
    for (const int start : free) {
        if (label[start] != -2) continue;
        const int id = static_cast<int>(regions.size());
        Region& r = regions.emplace_back();
        std::vector<int> stack{start};
        label[start] = id;
        while (!stack.empty()) {
            const int v = stack.back();
            stack.pop_back();
            r.fans.emplace_back().vertex = v;
            for (int h = m.fan_start[v], n = 0; h >= 0 && n < m.fan_size[v]; h = m.cw(h), ++n) {
                for (const int w : {m.target(h), m.origin(TriMesh::prev(h))})
                    if (label[w] == -2) label[w] = id, stack.push_back(w);
                char& once = listed[static_cast<std::size_t>(TriMesh::face(h))];
                if (!once) once = 1, r.faces.push_back(TriMesh::face(h));
            }
        }
        for (const int f : r.faces) listed[static_cast<std::size_t>(f)] = 0;
        // Listed once each; their order is then the keys' alone (ties by index).
        sort_canonically(m, r.faces);
        // The smallest key first: the regions are ordered by it.
        std::size_t first = 0;
        VertexKey least = vertex_key(m, r.fans[0].vertex);
        for (std::size_t i = 1; i < r.fans.size(); ++i)
            if (const VertexKey k = vertex_key(m, r.fans[i].vertex); k < least) least = k, first = i;
        std::swap(r.fans[0], r.fans[first]);
    }
    for (const int v : free) label[v] = -1;
    return regions;
}

void make_fans(const TriMesh& m, Region& r) {
    if (r.fans.empty() || !r.fans[0].corners.empty()) return; // an interior vertex has corners
    std::vector<std::pair<VertexKey, int>> keyed;
    keyed.reserve(r.fans.size());
    for (const FreeFan& fan : r.fans) keyed.push_back({vertex_key(m, fan.vertex), fan.vertex});
    std::sort(keyed.begin(), keyed.end());
    for (std::size_t i = 0; i < keyed.size(); ++i) r.fans[i] = free_fan(m, keyed[i].second);
}

std::vector<Region> split_regions(const TriMesh& m, const std::vector<int>& free, std::vector<int>& label) {
    std::vector<Region> regions = find_regions(m, free, label);
    for (Region& r : regions) make_fans(m, r);
    return regions;
}

namespace {

/// The triangles `bad` (ascending) split by `pinned`: those with a free vertex, and the others.
void split_by_pinned(const TriMesh& m, const std::vector<char>& pinned, const std::vector<int>& bad,
                     std::vector<int>& repairable, std::vector<int>& stuck) {
    repairable.clear();
    stuck.clear();
    for (const int f : bad) {
        const auto& t = m.tri[f];
        (pinned[t[0]] && pinned[t[1]] && pinned[t[2]] ? stuck : repairable).push_back(f);
    }
}

} // namespace

void bad_triangles(const TriMesh& m, const std::vector<char>& pinned, std::vector<int>& repairable,
                   std::vector<int>& stuck) {
    std::vector<int> bad;
    for (int f = 0; f < m.num_faces(); ++f)
        if (!positive(m, f)) bad.push_back(f);
    split_by_pinned(m, pinned, bad, repairable, stuck);
}

void split_again(const TriMesh& m, const std::vector<char>& pinned, std::vector<int>& repairable,
                 std::vector<int>& stuck) {
    std::vector<int> bad = std::move(repairable);
    bad.insert(bad.end(), stuck.begin(), stuck.end());
    std::sort(bad.begin(), bad.end());
    split_by_pinned(m, pinned, bad, repairable, stuck);
}

std::vector<std::vector<int>> triangle_groups(const TriMesh& m, const std::vector<int>& faces) {
    std::vector<int> parent(faces.size());
    std::iota(parent.begin(), parent.end(), 0);
    auto find = [&](int x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    };
    std::vector<int> owner(static_cast<std::size_t>(m.num_vertices), -1);
    for (std::size_t i = 0; i < faces.size(); ++i)
        for (const int v : m.tri[faces[i]]) {
            if (owner[v] >= 0) parent[find(static_cast<int>(i))] = find(owner[v]);
            owner[v] = static_cast<int>(i);
        }
    std::vector<std::vector<int>> groups;
    std::vector<int> group_of(faces.size(), -1);
    for (std::size_t i = 0; i < faces.size(); ++i) {
        const int root = find(static_cast<int>(i));
        if (group_of[root] < 0) group_of[root] = static_cast<int>(groups.size()), groups.emplace_back();
        groups[group_of[root]].push_back(faces[i]);
    }
    return groups;
}

Region around_inverted(const TriMesh& m, const Region& r, int rings) {
    std::vector<std::pair<int, std::size_t>> fan_of; // (vertex, its fan in r), sorted
    for (std::size_t i = 0; i < r.fans.size(); ++i) fan_of.emplace_back(r.fans[i].vertex, i);
    std::sort(fan_of.begin(), fan_of.end());
    std::vector<char> in(r.fans.size(), 0);
    const auto fan = [&](int v) {
        const auto it = std::lower_bound(fan_of.begin(), fan_of.end(), std::make_pair(v, std::size_t{0}));
        return it != fan_of.end() && it->first == v ? it->second : r.fans.size();
    };
    const auto touches = [&](int f, const std::vector<char>& marked) {
        for (const int v : m.tri[f])
            if (const std::size_t i = fan(v); i < in.size() && marked[i]) return true;
        return false;
    };
    const auto take = [&](int f, std::vector<char>& marked) {
        for (const int v : m.tri[f])
            if (const std::size_t i = fan(v); i < in.size()) marked[i] = 1;
    };
    for (const int f : r.faces)
        if (!positive(m, f)) take(f, in);
    for (int ring = 0; ring < rings; ++ring) {
        std::vector<char> next = in;
        for (const int f : r.faces)
            if (touches(f, in)) take(f, next);
        in.swap(next);
    }
    Region sub;
    for (std::size_t i = 0; i < r.fans.size(); ++i)
        if (in[i]) sub.fans.push_back(r.fans[i]);
    for (const int f : r.faces)
        if (touches(f, in)) sub.faces.push_back(f);
    return sub;
}

} // namespace qex::detail::repair_impl
