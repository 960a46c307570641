// The quad mesh's half-edges, fans, cut edges and canonical vertex order (quad_topology.h).
#include "quad_topology.h"

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <utility>

namespace qex::layout {
namespace {

/// The half-edges bucketed by their smaller vertex (a counting sort: no comparison sort needed).
struct Buckets {
    std::vector<int> begin, items;
    Buckets(const QuadTopology& t) : begin(t.vertices + 1, 0), items(4 * static_cast<std::size_t>(t.faces)) {
        for (int h = 0; h < 4 * t.faces; ++h) ++begin[std::min(t.from(h), t.to(h)) + 1];
        std::partial_sum(begin.begin(), begin.end(), begin.begin());
        std::vector<int> fill(begin.begin(), begin.end() - 1);
        for (int h = 0; h < 4 * t.faces; ++h) items[fill[std::min(t.from(h), t.to(h))]++] = h;
    }
};

/// Faces must be quads of four distinct vertices in range.
std::string check_faces(const QuadMesh& mesh) {
    const int n = static_cast<int>(mesh.positions.size());
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
        const auto& q = mesh.faces[f];
        if (q.size() != 4) return "face " + std::to_string(f) + " has " + std::to_string(q.size()) + " vertices";
        for (int k = 0; k < 4; ++k) {
            if (q[k] < 0 || q[k] >= n) return "face " + std::to_string(f) + " has a vertex index out of range";
            for (int j = 0; j < k; ++j)
                if (q[j] == q[k]) return "face " + std::to_string(f) + " repeats vertex " + std::to_string(q[k]);
        }
    }
    return "";
}

/// Twins: the half-edges of one edge found in the bucket of its smaller vertex.
std::string pair_twins(QuadTopology& t, const Buckets& buckets) {
    t.twin.assign(4 * static_cast<std::size_t>(t.faces), -1);
    t.cut.assign(t.twin.size(), 0);
    std::vector<char> done(t.twin.size(), 0);
    for (int v = 0; v < t.vertices; ++v)
        for (int i = buckets.begin[v]; i < buckets.begin[v + 1]; ++i) {
            const int a = buckets.items[i], other = std::max(t.from(a), t.to(a));
            if (done[a]) continue;
            int b = -1;
            for (int k = i + 1; k < buckets.begin[v + 1]; ++k) {
                const int c = buckets.items[k];
                if (std::max(t.from(c), t.to(c)) != other) continue;
                if (b >= 0)
                    return "edge of vertices " + std::to_string(v) + " and " + std::to_string(other) +
                           " has more than two faces";
                b = c;
            }
            if (b < 0) {
                t.cut[a] = 1;
                continue;
            }
            if (t.from(a) == t.from(b))
                return "faces " + std::to_string(a / 4) + " and " + std::to_string(b / 4) +
                       " are inconsistently oriented";
            t.twin[a] = b;
            t.twin[b] = a;
            done[b] = 1;
        }
    return "";
}

std::string mark_features(QuadTopology& t, const Buckets& buckets, const LayoutOptions& options) {
    t.feature.assign(t.vertices, 0);
    for (const auto& e : options.feature_edges) {
        const int lo = std::min(e[0], e[1]), hi = std::max(e[0], e[1]);
        bool found = false;
        for (int i = buckets.begin[lo]; i < buckets.begin[lo + 1] && lo != hi; ++i) {
            const int h = buckets.items[i];
            if (std::max(t.from(h), t.to(h)) != hi) continue;
            t.cut[h] = 1;
            found = true;
        }
        if (!found)
            return "feature edge " + std::to_string(e[0]) + " " + std::to_string(e[1]) + " is not an edge of the mesh";
        t.feature[e[0]] = t.feature[e[1]] = 1;
    }
    return "";
}

/// Each vertex's outgoing half-edges in rot() order, from the boundary where it has one.
std::string build_fans(QuadTopology& t) {
    const int halfedges = 4 * t.faces;
    std::vector<int> count(t.vertices + 1, 0), first(t.vertices, -1);
    t.boundary.assign(t.vertices, 0);
    for (int h = 0; h < halfedges; ++h) {
        const int v = t.from(h);
        ++count[v + 1];
        if (first[v] < 0 || (t.twin[h] < 0 && t.twin[first[v]] >= 0)) first[v] = h;
        if (t.twin[h] < 0) t.boundary[v] = t.boundary[t.to(h)] = 1;
    }
    std::partial_sum(count.begin(), count.end(), count.begin());
    t.fan_begin = count;
    t.fan.assign(halfedges, -1);
    for (int v = 0; v < t.vertices; ++v) {
        int o = first[v], k = t.fan_begin[v];
        for (; o >= 0 && k < t.fan_begin[v + 1]; o = t.rot(o)) {
            t.fan[k++] = o;
            if (t.rot(o) == first[v]) break;
        }
        if (k != t.fan_begin[v + 1])
            return "vertex " + std::to_string(v) + " is not manifold (its faces form several fans)";
    }
    return "";
}

} // namespace

std::string build_topology(const QuadMesh& mesh, const LayoutOptions& options, QuadTopology& t) {
    t.mesh = &mesh;
    t.vertices = static_cast<int>(mesh.positions.size());
    t.faces = static_cast<int>(mesh.faces.size());
    if (std::string e = check_faces(mesh); !e.empty()) return e;
    const Buckets buckets(t);
    if (std::string e = pair_twins(t, buckets); !e.empty()) return e;
    for (const auto& e : options.feature_edges)
        if (e[0] < 0 || e[1] < 0 || e[0] >= t.vertices || e[1] >= t.vertices)
            return "feature edge " + std::to_string(e[0]) + " " + std::to_string(e[1]) + " is out of range";
    if (std::string e = mark_features(t, buckets, options); !e.empty()) return e;
    if (std::string e = build_fans(t); !e.empty()) return e;
    std::vector<int> order(t.vertices);
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) {
        return std::make_pair(mesh.positions[a], a) < std::make_pair(mesh.positions[b], b);
    });
    t.rank.assign(t.vertices, 0);
    for (int i = 0; i < t.vertices; ++i) t.rank[order[i]] = i;
    return "";
}

VertexSpokes spokes(const QuadTopology& t, int v) {
    VertexSpokes s;
    const int n = t.valence(v);
    if (n == 0) return s;
    const int* fan = t.fan.data() + t.fan_begin[v];
    // Edge k (0 <= k < n) is fan[k]'s, between faces k-1 and k; a boundary vertex has edge n too.
    std::vector<int> cuts;
    for (int k = 0; k < n; ++k)
        if (t.cut[fan[k]]) cuts.push_back(k);
    const bool open = t.boundary[v] != 0;
    if (open) cuts.push_back(n); // fan[0]'s edge is the first boundary edge, edge n the other
    if (cuts.empty()) {
        s.special = n != 4;
        if (s.special) s.traces.assign(fan, fan + n);
        return s;
    }
    const int sectors = open ? static_cast<int>(cuts.size()) - 1 : static_cast<int>(cuts.size());
    for (int i = 0; i < sectors; ++i) {
        const int a = cuts[i];
        const int b = open || i + 1 < static_cast<int>(cuts.size()) ? cuts[i + 1] : cuts[0] + n;
        if (b - a == 2) continue;
        s.special = true;
        for (int k = a + 1; k < b; ++k) s.traces.push_back(fan[k % n]);
    }
    return s;
}

} // namespace qex::layout
