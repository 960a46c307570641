// The topology of a polygon mesh (the output's, and the input's for comparison): edges,
// manifoldness and orientation of every edge and vertex, boundary loops and components.
#include "checker.h"
#include "parallel.h"
#include "union_find.h"

#include <algorithm>
#include <string>

namespace qex::verify_detail {
namespace {

/// Appends a violation when `out` is given (and not full).
void violate(std::vector<Violation>* out, ViolationKind kind, std::string message, std::int64_t element,
             std::vector<Place> places = {}) {
    if (out && out->size() < kMaxListed) out->push_back({kind, std::move(message), element, std::move(places)});
}

/// The faces as flat corner arrays: each corner's face, and the next and previous corner of it.
class Corners {
public:
    Corners(const std::vector<std::size_t>& offset, const std::vector<int>& corner_vertex)
        : offset_(offset), vertex_(corner_vertex) {
        const std::size_t nf = faces();
        // Every face a triangle: then offset[f] == 3f, and corners need no face lookup.
        for (std::size_t f = 0; f < nf && triangles_; ++f) triangles_ = offset[f + 1] - offset[f] == 3;
        face_.resize(triangles_ ? 0 : size());
        for (std::size_t f = 0; f < nf && !triangles_; ++f)
            for (std::size_t c = offset[f]; c < offset[f + 1]; ++c) face_[c] = static_cast<std::int32_t>(f);
    }
    std::size_t faces() const { return offset_.size() - 1; }
    std::size_t size() const { return offset_.back(); }
    /// The vertex at corner c.
    int vertex(std::size_t c) const { return vertex_[c]; }
    std::int64_t face_of(std::size_t c) const { return triangles_ ? static_cast<std::int64_t>(c / 3) : face_[c]; }
    std::size_t next(std::size_t c) const {
        if (triangles_) return c % 3 == 2 ? c - 2 : c + 1;
        const auto f = static_cast<std::size_t>(face_[c]);
        return c + 1 == offset_[f + 1] ? offset_[f] : c + 1;
    }
    std::size_t prev(std::size_t c) const {
        if (triangles_) return c % 3 == 0 ? c + 2 : c - 1;
        const auto f = static_cast<std::size_t>(face_[c]);
        return c == offset_[f] ? offset_[f + 1] - 1 : c - 1;
    }

private:
    const std::vector<std::size_t>& offset_;
    const std::vector<int>& vertex_;
    bool triangles_ = true;
    std::vector<std::int32_t> face_;
};

/// The vertex each corner's outgoing edge ends at.
std::vector<std::int32_t> edge_heads(const Corners& fc, int threads) {
    const std::size_t nc = fc.size();
    std::vector<std::int32_t> head(nc);
    for_range(threads, static_cast<std::int64_t>(nc), [&](std::size_t, std::int64_t begin, std::int64_t end) {
        for (std::int64_t c = begin; c < end; ++c)
            head[static_cast<std::size_t>(c)] = fc.vertex(fc.next(static_cast<std::size_t>(c)));
    });
    return head;
}

/// The corners bucketed by the smaller vertex of their outgoing edge: after the placing pass,
/// bucket v is [begin(v), end[v]). An entry is (larger vertex) << 32 | corner << 1 | direction,
/// the direction 1 when the corner's side runs from the larger vertex (so orientation needs no
/// second look-up).
struct EdgeBuckets {
    std::vector<std::uint32_t> end;
    std::vector<std::uint64_t> entry;
    std::size_t begin(std::size_t v) const { return v == 0 ? 0 : static_cast<std::size_t>(end[v - 1]); }
};

/// The buckets by a counting pass and a placing pass (unsorted within a bucket).
EdgeBuckets bucket_edges(const Corners& fc, const std::vector<std::int32_t>& head, std::size_t num_vertices) {
    const std::size_t nc = fc.size();
    EdgeBuckets b;
    b.end.assign(num_vertices + 1, 0);
    b.entry.resize(nc);
    for (std::size_t c = 0; c < nc; ++c) ++b.end[static_cast<std::size_t>(std::min(fc.vertex(c), head[c])) + 1];
    for (std::size_t v = 0; v < num_vertices; ++v) b.end[v + 1] += b.end[v];
    for (std::size_t c = 0; c < nc; ++c) {
        const int x = fc.vertex(c), y = head[c];
        b.entry[b.end[static_cast<std::size_t>(std::min(x, y))]++] =
            static_cast<std::uint64_t>(static_cast<std::uint32_t>(std::max(x, y))) << 32 |
            static_cast<std::uint32_t>(c) << 1 | (x > y ? 1u : 0u);
    }
    return b;
}

/// The edges matched up: runs of equal (smaller, larger) vertex in the sorted buckets are the
/// undirected edges. twin[c] is the corner whose outgoing edge is the reverse of c's, or -1
/// (boundary, non-manifold, or traversed twice in the same direction).
struct EdgeMatch {
    const Corners& fc;
    EdgeBuckets& buckets;
    std::vector<Violation>* out;
    bool want_pairs;
    std::vector<std::int32_t> twin;
    EdgePairs pair;             ///< empty unless `want_pairs`
    std::vector<char> troubled; ///< per bucket: it has a violation (reported in a second pass)

    /// Pairs up the corners of bucket v (sorted); reports its violations when `report`.
    /// Returns the number of edges in it.
    std::int64_t pair_up(std::size_t v, bool report);
    /// The sides of one edge: entries [i, j) of bucket v, all with larger vertex h.
    void pair_edge(std::size_t v, std::uint64_t h, std::size_t i, std::size_t j, bool report);
};

std::int64_t EdgeMatch::pair_up(std::size_t v, bool report) {
    const auto& entry = buckets.entry;
    std::int64_t edges = 0;
    for (std::size_t i = buckets.begin(v), stop = buckets.end[v]; i < stop;) {
        const std::uint64_t h = entry[i] >> 32;
        std::size_t j = i + 1;
        while (j < stop && entry[j] >> 32 == h) ++j;
        ++edges;
        pair_edge(v, h, i, j, report);
        i = j;
    }
    return edges;
}

void EdgeMatch::pair_edge(std::size_t v, std::uint64_t h, std::size_t i, std::size_t j, bool report) {
    const auto& entry = buckets.entry;
    const auto c0 = static_cast<std::uint32_t>(entry[i]) >> 1;
    auto name = [&] { return "(" + std::to_string(v) + ", " + std::to_string(h) + ")"; };
    // The edge and its faces, as the violation's places.
    auto places = [&] {
        std::vector<std::int64_t> faces;
        for (std::size_t k = i; k < j; ++k) faces.push_back(fc.face_of(static_cast<std::uint32_t>(entry[k]) >> 1));
        return std::vector<Place>{{PlaceKind::Edge, {static_cast<std::int64_t>(v), static_cast<std::int64_t>(h)}},
                                  {PlaceKind::Face, std::move(faces)}};
    };
    if (j - i > 2) {
        troubled[v] = 1;
        if (report)
            violate(out, ViolationKind::NonManifoldEdge,
                    "edge " + name() + " has " + std::to_string(j - i) + " incident face sides", fc.face_of(c0),
                    places());
    } else if (j - i == 2) {
        const auto c1 = static_cast<std::uint32_t>(entry[i + 1]) >> 1;
        if (want_pairs) pair[c0] = static_cast<std::int32_t>(c1), pair[c1] = static_cast<std::int32_t>(c0);
        if ((entry[i] & 1) == (entry[i + 1] & 1)) {
            troubled[v] = 1;
            if (report)
                violate(out, ViolationKind::InconsistentOrientation,
                        "edge " + name() + " is traversed twice in the same direction", fc.face_of(c1), places());
        } else {
            twin[c0] = static_cast<std::int32_t>(c1), twin[c1] = static_cast<std::int32_t>(c0);
        }
    }
}

/// Sorts bucket [b, e): insertion sort for short ones.
void sort_bucket(std::uint64_t* b, std::uint64_t* e) {
    if (e - b > 24) {
        std::sort(b, e);
    } else {
        for (std::uint64_t* i = b + 1; i < e; ++i)
            for (std::uint64_t* j = i; j > b && j[0] < j[-1]; --j) std::swap(j[0], j[-1]);
    }
}

/// Sorts and pairs the buckets on all threads; a bucket with a problem is marked, and its
/// violations are written afterwards in bucket order. Returns the number of edges.
std::int64_t match_edges(EdgeMatch& m, std::size_t num_vertices, int threads) {
    const auto nv64 = static_cast<std::int64_t>(num_vertices);
    const int workers = run_parallel(threads, static_cast<std::int64_t>(m.fc.size())) ? threads : 1;
    std::vector<std::int64_t> edges_of(static_cast<std::size_t>(workers), 0);
    share_chunks(workers, nv64, 4096, [&](std::size_t t, const auto& next) {
        for (std::int64_t from = 0, to = 0; next(from, to);)
            for (std::int64_t v = from; v < to; ++v) {
                std::uint64_t* b = m.buckets.entry.data() + m.buckets.begin(static_cast<std::size_t>(v));
                std::uint64_t* e = m.buckets.entry.data() + m.buckets.end[static_cast<std::size_t>(v)];
                sort_bucket(b, e);
                edges_of[t] += m.pair_up(static_cast<std::size_t>(v), false);
            }
    });
    std::int64_t edges = 0;
    for (const std::int64_t n : edges_of) edges += n;
    for (std::size_t v = 0; v < num_vertices; ++v)
        if (m.troubled[v]) m.pair_up(v, true);
    return edges;
}

/// What the corners say of each vertex: whether a face uses it, its corners, its boundary
/// sides (outgoing sides without a twin) and where the first one leads, and the components.
struct VertexCorners {
    std::vector<int> boundary_next, boundary_count, corners;
    std::vector<char> referenced;
    UnionFind components;

    VertexCorners(const Corners& fc, const std::vector<std::int32_t>& head, const std::vector<std::int32_t>& twin,
                  std::size_t num_vertices)
        : boundary_next(num_vertices, -1),
          boundary_count(num_vertices, 0),
          corners(num_vertices, 0),
          referenced(num_vertices, 0),
          components(num_vertices) {
        for (std::size_t c = 0; c < fc.size(); ++c) {
            const int a = fc.vertex(c), b = head[c];
            referenced[a] = 1;
            ++corners[a];
            if (fc.next(c) > c) components.unite(a, b); // a face's last side joins nothing new
            if (twin[c] < 0) {
                ++boundary_count[a];
                if (boundary_next[a] < 0) boundary_next[a] = b;
            }
        }
    }
};

/// The vertices in the order of their first corners (vertex numbering may have no locality at all).
std::vector<std::int32_t> vertices_by_first_corner(const Corners& fc, std::size_t num_vertices) {
    std::vector<std::int32_t> order;
    order.reserve(num_vertices);
    std::vector<char> listed(num_vertices, 0);
    for (std::size_t c = 0; c < fc.size(); ++c) {
        const auto v = static_cast<std::size_t>(fc.vertex(c));
        if (!listed[v]) listed[v] = 1, order.push_back(static_cast<std::int32_t>(v));
    }
    return order;
}

/// Per vertex: its faces form a single fan. From a corner, cross its outgoing edge to the twin's
/// face; the corner there follows the twin. A boundary vertex's walk starts at a corner whose
/// incoming side has no twin. Each vertex's fan on all threads, in `order`.
std::vector<char> single_fans(const Corners& fc, const std::vector<std::int32_t>& twin, const std::vector<int>& corners,
                              const std::vector<std::int32_t>& order, int threads) {
    const std::size_t nv = corners.size();
    std::vector<std::int32_t> start(nv, -1);
    for (std::size_t c = 0; c < fc.size(); ++c) {
        const int v = fc.vertex(c);
        if (start[v] < 0 || twin[fc.prev(c)] < 0) start[v] = static_cast<std::int32_t>(c);
    }
    std::vector<char> single(nv, 0);
    const auto listed = static_cast<std::int64_t>(order.size());
    // Split as the corners are: parallel from as many corners as the other loops' elements.
    const int split = run_parallel(threads, static_cast<std::int64_t>(fc.size())) ? threads : 1;
    share_chunks(split, listed, (listed + split - 1) / split, [&](std::size_t, const auto& next) {
        for (std::int64_t from = 0, to = 0; next(from, to);)
            for (std::int64_t i = from; i < to; ++i) {
                const auto v = static_cast<std::size_t>(order[static_cast<std::size_t>(i)]);
                if (start[v] < 0) continue;
                std::size_t c = static_cast<std::size_t>(start[v]);
                int seen = 0;
                do {
                    ++seen;
                    if (twin[c] < 0) break;
                    c = fc.next(static_cast<std::size_t>(twin[c]));
                } while (c != static_cast<std::size_t>(start[v]) && seen <= corners[v]);
                single[v] = seen == corners[v];
            }
    });
    return single;
}

/// Boundary loops: follow the boundary sides from each vertex not yet on a loop.
std::int64_t count_boundary_loops(const std::vector<int>& boundary_next) {
    std::int64_t loops = 0;
    std::vector<char> used(boundary_next.size(), 0);
    for (std::size_t v = 0; v < boundary_next.size(); ++v) {
        if (boundary_next[v] < 0 || used[v]) continue;
        ++loops;
        for (int x = static_cast<int>(v); x >= 0 && !used[x]; x = boundary_next[x]) used[x] = 1;
    }
    return loops;
}

/// The manifold vertices: one boundary side at most, and the faces around one fan.
void check_vertices(const Corners& fc, const std::vector<std::int32_t>& twin, VertexCorners& vc,
                    std::vector<Violation>* out, int threads, std::vector<char>* single_fan_out) {
    const std::size_t nv = vc.corners.size();
    for (std::size_t v = 0; v < nv; ++v)
        if (vc.boundary_count[v] > 1)
            violate(out, ViolationKind::NonManifoldVertex,
                    "vertex " + std::to_string(v) + " has " + std::to_string(vc.boundary_count[v]) + " boundary fans",
                    static_cast<std::int64_t>(v));
    const std::vector<std::int32_t> order = vertices_by_first_corner(fc, nv);
    std::vector<char> single = single_fans(fc, twin, vc.corners, order, threads);
    for (const std::int32_t vi : order) {
        const auto v = static_cast<std::size_t>(vi);
        if (!single[v])
            violate(out, ViolationKind::NonManifoldVertex,
                    "the faces around vertex " + std::to_string(v) + " do not form a single fan",
                    static_cast<std::int64_t>(v));
    }
    if (single_fan_out) *single_fan_out = std::move(single);
}

} // namespace

Topology analyse(std::size_t num_vertices, const std::vector<std::size_t>& offset,
                 const std::vector<int>& corner_vertex, std::vector<Violation>* out, int threads, EdgePairs* pairs_out,
                 std::vector<char>* single_fan_out) {
    const Corners fc(offset, corner_vertex);
    const std::vector<std::int32_t> head = edge_heads(fc, threads);
    EdgeBuckets buckets = bucket_edges(fc, head, num_vertices);
    EdgeMatch m{fc,
                buckets,
                out,
                pairs_out != nullptr,
                std::vector<std::int32_t>(fc.size(), -1),
                {},
                std::vector<char>(num_vertices, 0)};
    if (pairs_out) m.pair.assign(fc.size(), -1);
    Topology t;
    t.edges = match_edges(m, num_vertices, threads);
    std::vector<std::uint64_t>().swap(buckets.entry);
    VertexCorners vc(fc, head, m.twin, num_vertices);
    check_vertices(fc, m.twin, vc, out, threads, single_fan_out);
    t.boundary_loops = count_boundary_loops(vc.boundary_next);
    for (std::size_t v = 0; v < num_vertices; ++v) {
        if (!vc.referenced[v]) continue;
        ++t.vertices;
        if (vc.components.find(static_cast<int>(v)) == static_cast<int>(v)) ++t.components;
    }
    t.faces = static_cast<std::int64_t>(fc.faces());
    if (pairs_out) *pairs_out = std::move(m.pair);
    return t;
}

} // namespace qex::verify_detail
